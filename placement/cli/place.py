"""The main job: place one or more paths on a robot, report the best and worst placements.

    placement --robot orthoglide --path examples/rect.yaml    best and worst placements, gain
    placement --robot orthoglide --path rect.yaml --at x=0,y=0,z=0,phi=0    one placement
    placement --robot orthoglide --path a.yaml b.yaml --html scene.html    3-D scene in one page
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from tqdm import tqdm

from placement.cli.common import (
    check_outputs,
    compile_noticed,
    configured_path,
    job_options,
    load_robot_argument,
    margin_option,
    massless_option,
    model_options,
    non_negative,
    placement_options,
    positive_number,
    require_features,
    robot_files,
    run_options,
    sampling_options,
    seed_option,
    serve_until_stopped,
    whole_number,
)
from placement.cli.exceptions import UsageError
from placement.cli.front import parse_members, parse_objectives, place_front
from placement.contract.objective import OBJECTIVES, wording
from placement.distribution import CLUSTER, FRONTS, PLOTS, SCENE
from placement.dynamics.inverse import TreeDynamics
from placement.dynamics.tree_rnea import touch_tree_kernels
from placement.energy.regeneration import REGENERATION
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.evaluation.parallel import Cluster, cluster, scheduler_address
from placement.evaluation.results import PlacementDetail
from placement.limits.collision import closest_points
from placement.limits.workspace import workspace_misfit
from placement.output.palette import AT_COLOR, BEST_COLOR, WORST_COLOR, path_color
from placement.output.report import (
    detail_json,
    format_detail,
    format_gap,
    format_result,
    format_uncertainty,
    gap_json,
    job_document,
    results_lines,
    tolerance_json,
    uncertainty_json,
    write_atomically,
    write_json,
    write_trace,
)
from placement.path.samples import PathSamples
from placement.path.toolpath import ToolPath
from placement.placing.profiles import length_variables, redundant_defaults, redundant_variables
from placement.placing.transform import VARIABLES
from placement.placing.values import parse_free, parse_values, unsuffixed_lengths
from placement.robot.model import Robot
from placement.robot.plausibility import massless_note
from placement.search.gap import BUDGET, optimality_gap
from placement.search.optimize import Optimum, PlacementResult, SearchSettings, optimize_placement
from placement.search.plausibility import feed_warnings, length_warnings
from placement.search.space import PlacementSpace, default_space
from placement.search.uncertainty import energy_uncertainty

if TYPE_CHECKING:  # the scene's modules (meshcat, trimesh: the [viz] extra) load only for --html and --show
    from placement.output.scene import Scene  # the [viz] extra (matplotlib, meshcat): imported only here


def build_parser() -> argparse.ArgumentParser:
    """The parser of the main job: place a path on a robot."""
    parser = argparse.ArgumentParser(
        prog="placement", description="Find where to place a tool path in a robot's workspace so that the "
        "actuators draw the least electric energy while every limit holds.",  # the commands: cli.main_parser
        parents=[job_options(several_paths=True), massless_option(), placement_options(), model_options(),
                 sampling_options(), margin_option(), seed_option(), run_options()])
    direction = parser.add_mutually_exclusive_group()
    direction.add_argument("--minimize", action="store_true",
                           help="only search the placement of least objective (the best for energy)")
    direction.add_argument("--maximize", action="store_true",
                           help="only search the placement of most objective (the worst for energy)")
    parser.add_argument("--at", metavar="x=..,y=..,phi=..",
                        help="evaluate one placement instead of searching (mm and deg unless a value ends in m or rad)")
    parser.add_argument("--at-json", metavar="RESULT.json",
                        help="evaluate the placement of a result written by --json (its best, or --which)")
    parser.add_argument("--which", choices=("best", "worst", "at"), default=None,
                        help="with --at-json: which placement of the result (default best)")
    parser.add_argument("--strict", action="store_true",
                        help="refuse (exit 2) what would only be warned about: a feed or a length whose size "
                             "suggests another unit")
    parser.add_argument("--generations", type=whole_number(1, 100_000), default=SearchSettings.max_generations,
                        metavar="N",
                        help=f"most generations of the global search (default {SearchSettings.max_generations})")
    parser.add_argument("--population", type=whole_number(1, 10_000), default=SearchSettings.population, metavar="N",
                        help=f"population of the global search (default {SearchSettings.population})")
    parser.add_argument("--objectives", metavar="A,B[,C]",
                        help="search the Pareto front of two or three objectives instead of one (names as for "
                             "--objective, e.g. energy,dexterity)")
    parser.add_argument("--members", metavar="knee,energy,3",
                        help="with --objectives: the front members to detail and draw (knee, an objective's end, "
                             "or a member number; default: the knee and every end)")
    parser.add_argument("--png", metavar="FILE", help="with --objectives: plot the front in FILE (PNG) and beside it as "
                        "SVG; without, on a robot with redundant joints (a track, a positioner, a seven-axis arm's "
                        "joint): plot each one's profile along the path at the placement reported (--at, else the best)")
    parser.add_argument("--rest", type=non_negative, default=0.0, metavar="S",
                        help="rest between passes (s), holding the path's end pose, for the duty cycle's cycles per "
                             "hour (default 0: back to back)")
    parser.add_argument("--within", type=positive_number, default=1.0, metavar="PERCENT",
                        help="the tolerance box around each optimum keeps the objective within PERCENT of it "
                             "(default 1)")
    parser.add_argument("--error-bars", action="store_true",
                        help="vary the drives' constants over ranges from their source status (EST ±20 %%, "
                             "CALIBRATED ±5 %%, published ±2 %%) and give the best and worst energies and the gain with "
                             "intervals (first order, checked by sampling) and the share of draws in which another "
                             "basin wins (energy objective; see docs/howto/certainty.md)")
    parser.add_argument("--gap", type=whole_number(100, 10_000_000), nargs="?", const=BUDGET, default=None,
                        metavar="N",
                        help="bound the best feasible objective from below by a branch and bound over the box on N "
                             f"evaluations (default {BUDGET}) and give the optimality gap, best found − lower bound: "
                             "an estimate from sampled derivative bounds times a safety factor, not a proof "
                             "(see docs/howto/certainty.md)")
    parser.add_argument("--json", metavar="FILE", help="write the results as JSON (SI units)")
    parser.add_argument("--trace", metavar="FILE",
                        help="write a per-sample CSV trace of the placement given by --at, else of the best one")
    parser.add_argument("--html", metavar="FILE", help="write a 3-D scene (robot, workspace, best and worst paths, "
                        "robot animated along the first path) as a self-contained HTML page")
    parser.add_argument("--show", action="store_true",
                        help="serve the 3-D scene on this machine (127.0.0.1) and print its address")
    parser.add_argument("--show-host", metavar="ADDRESS", default="127.0.0.1",
                        help="serve --show on this address instead (0.0.0.0: every network the machine is on)")
    return parser


def at_json(file: str, which: str, extra: tuple[str, ...] = ()) -> dict[str, float]:
    """The placement (SI) of a result written by --json: its ``which`` entry ("best", "worst" or "at"), or, for a
    document of several paths, the first path's."""
    try:
        document = json.loads(Path(file).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as error:
        raise UsageError(f"--at-json: cannot read {file}: {error}") from None
    if isinstance(document, dict) and isinstance(document.get("paths"), list) and document["paths"]:
        document = document["paths"][0]
    entry = document.get(which) if isinstance(document, dict) else None
    placement = entry.get("placement") if isinstance(entry, dict) else None
    if not isinstance(placement, dict) or set(placement) - set(VARIABLES + extra) or not all(
            isinstance(v, int | float) and not isinstance(v, bool) and np.isfinite(v) for v in placement.values()):
        raise UsageError(f"--at-json: {file} has no '{which}.placement' with finite numbers for "
                         f"{', '.join(VARIABLES + extra)} (write it with --json)")
    return {name: float(value) for name, value in placement.items()}


def warn(lines: list[str], strict: bool) -> None:
    """Print plausibility warnings, one line each on stderr; with ``strict``, refuse them (exit 2)."""
    for line in lines:
        print(f"warning: {line}", file=sys.stderr)
    if strict and lines:
        raise UsageError(f"--strict: {len(lines)} warning(s) above")


def feed_words(path: ToolPath) -> str:
    """The path's feed, or the range of a G-code program's feeds and its rapid feed, or a timed pose list's."""
    if path.timed is not None:
        return f"timed by its pose list (mean speed {path.feed_m_s:.4g} m/s)"
    feeds = sorted({path.speed_m_s(segment) for segment in path.segments if not segment.rapid})
    words = f"feed {feeds[0]:g} m/s" if len(feeds) == 1 else f"feeds {feeds[0]:.4g} to {feeds[-1]:.4g} m/s"
    return words + (f", rapids {path.rapid_feed_m_s:g} m/s" if path.rapid_feed_m_s is not None else "")


def timing_words(path: ToolPath, samples: PathSamples) -> str:
    """The timing law and sampling, as the report's first line says them."""
    if path.timing.mode == "optimal":
        return (f"optimal timing (as fast as the robot allows at each placement; {samples.t_s[-1]:.3f} s at the feed "
                f"throughout), {len(samples)} samples along the path")
    return f"{path.timing.mode} timing, {len(samples)} samples over {samples.t_s[-1]:.3f} s"


def place_one(robot: Robot, path: ToolPath, args: argparse.Namespace,
              remote: Cluster | None = None) -> tuple[dict, dict, str | None]:
    """Search (or evaluate --at) one path and print its report; ``remote`` runs the search on a Dask cluster.

    Returns:
        The JSON document, the details to draw ({"best"|"worst"|"at": PlacementDetail}), and the
        reason when no placement is feasible.
    """
    samples = path.sample(args.time_step)
    objective = OBJECTIVES.get(args.objective)
    print(f"{path.name} on {robot.name}: {len(path.segments)} segment(s), {path.length_m * 1e3:.1f} mm, "
          f"{feed_words(path)}, {timing_words(path, samples)}; energy: {REGENERATION.get(args.regen).description}"
          + ("" if args.objective == "energy" else f"; objective: {objective.title} ({args.objective})"))
    note = massless_note(robot)
    if note is not None:
        print(f"note: {note}")
    dynamics, optimal = TreeDynamics(robot.model), path.timing.mode == "optimal"
    if dynamics.tree is not None and (dynamics.compiled_efforts or optimal):
        compile_noticed(lambda: touch_tree_kernels(dynamics.compiled_efforts, optimal), "the dynamics",
                        "a few seconds")
    evaluation = EvaluatorSettings(objective=args.objective, regeneration=args.regen, time_step_s=args.time_step,
                                   workers=remote.threads if remote else None, margin=args.margin / 100)
    document = job_document(robot, path, evaluation, len(samples))
    if "plane" in document:
        print(plane_line(document["plane"]))
    if args.at is not None or args.at_json is not None:
        knots = redundant_variables(robot)
        given = (parse_values(args.at, "--at", knots, length_variables(robot)) if args.at is not None
                 else at_json(args.at_json, args.which or "best", knots))
        if not given:
            raise UsageError("--at: give at least one value, e.g. --at x=0,phi=30")
        option = "--at" if args.at is not None else f"--at-json {args.at_json}"
        values = {**redundant_defaults(robot), **given}  # a knot not given: the reference configuration's value
        detail = Evaluator(robot, path, evaluation).detail(np.array([values.get(name, 0.0) for name in VARIABLES + knots]))
        print("\n" + format_detail(f"placement given by {option}", robot, detail, rest_s=args.rest))
        document["at"] = detail_json(robot, detail, rest_s=args.rest)
        problem = None
        if not detail.reachable:
            problem = (f"the placement given by {option} leaves the robot's reach "
                       f"({len(detail.unreachable_samples)} samples)")
        elif not detail.feasible:
            worst = min(detail.margins, key=lambda m: m.margin)
            problem = (f"the placement given by {option} breaks the {worst.kind} ({worst.where})" if worst.margin < 0
                       else f"the placement given by {option} comes within the {args.margin:g} % margin of the "
                            f"{worst.kind} ({worst.where}: {worst.margin * 100:.2f} %)")
        return document, {"at": detail} if detail.reachable else {}, problem
    knots = redundant_variables(robot)
    lengths = length_variables(robot)
    free, bounds = parse_free(args.free, "--free", knots, lengths) if args.free is not None else (None, {})
    if free is not None and set(free) <= set(knots):  # only redundant variables: bounds on top of the defaults
        free = None
    space = default_space(robot, free=free, fixed=parse_values(args.fix or "", "--fix", knots, lengths), bounds=bounds,
                          half_turn=path.half_turn_symmetric())
    misfit = misfit_line(robot, samples, space)
    if misfit is not None:
        return document, {}, misfit
    kept = f"; every limit keeps a {args.margin:g} % margin" if args.margin else ""
    print(f"search: {', '.join(space.free)} free; seed {args.seed}{kept}")
    lower = objective.better == "lower"
    settings = SearchSettings(seed=args.seed, max_generations=args.generations, population=args.population,
                              best=not (args.maximize if lower else args.minimize),
                              worst=not (args.minimize if lower else args.maximize), box_within=args.within / 100)
    if args.objectives:
        front_document, details, infeasible = place_front(robot, path, space, args, evaluation, settings, remote)
        document.update(front_document)
        return document, details, infeasible
    with tqdm(desc="searching", total=(settings.best + settings.worst) * settings.max_generations,
              unit=" generation", disable=args.quiet, file=sys.stderr, leave=False) as bar:
        result = optimize_placement(robot, path, space=space, evaluation=evaluation, settings=settings,
                                    progress=bar.update, announce=lambda e: bar.write(duration_line(e), sys.stdout),
                                    executor=remote.executor if remote else None)
    boxes = {key: optimum.tolerance for key, optimum in (("best", result.best), ("worst", result.worst))
             if optimum is not None and optimum.tolerance is not None}
    print("\n" + format_result(robot, result, args.rest, boxes))
    details = {}
    for key, optimum in (("best", result.best), ("worst", result.worst)):
        if optimum is not None:
            document[key] = detail_json(robot, optimum.detail, optimum, args.rest)
            if key in boxes:
                document[key]["tolerance"] = tolerance_json(boxes[key])
            details[key] = optimum.detail
    if result.gain is not None:
        document["gain"] = result.gain
    if args.error_bars:
        document["uncertainty"] = error_bars(robot, path, evaluation, result)
    if args.gap is not None and result.best is not None:
        document["optimality_gap"] = bound_gap(robot, path, evaluation, space, result.best, args.gap, args.seed)
    if result.infeasible:
        document["infeasible"] = result.infeasible
    return document, details, result.infeasible


def error_bars(robot: Robot, path: ToolPath, evaluation: EvaluatorSettings, result: PlacementResult) -> dict | None:
    """Print the error bars of a search's energies (--error-bars, :mod:`placement.search.uncertainty`) and return
    them as JSON, or say why there are none (None)."""
    if evaluation.objective != "energy" or result.best is None and result.worst is None:
        print("\nerror bars: given for the energy objective's optima only")
        return None
    best, worst = (None if o is None else o.detail.placement for o in (result.best, result.worst))
    others = np.array([b.placement for b in result.best.basins]) if result.best is not None else None
    uncertainty = energy_uncertainty(robot, path, dataclasses.replace(evaluation, workers=1), best, worst, others)
    print("\n" + format_uncertainty(uncertainty))
    return uncertainty_json(uncertainty)


def bound_gap(robot: Robot, path: ToolPath, evaluation: EvaluatorSettings, space: PlacementSpace, best: Optimum,
              budget: int, seed: int) -> dict:
    """Print the optimality gap of the best placement (--gap, :mod:`placement.search.gap`) and return it as JSON."""
    with Evaluator(robot, path, evaluation) as evaluator:
        gap = optimality_gap(evaluator, space, evaluator.objective.sign, best.detail.value, budget, seed=seed)
    unit = " J" if evaluation.objective == "energy" else ""
    print("\n" + format_gap(gap, unit))
    return gap_json(gap)


def misfit_line(robot: Robot, samples: PathSamples, space: PlacementSpace) -> str | None:
    """Why the path cannot fit in the robot's workspace box at any placement the search may take, before searching;
    None when it may fit, or when the box is not the robot's or the placement may tilt (not checked then)."""
    workspace = robot.workspace
    tilted = {"theta", "psi"} & set(space.free) or np.any(space.fixed[4:6] != 0)
    if workspace is None or robot.plane is not None or tilted:
        return None
    if "phi" in space.free:
        k = space.free.index("phi")
        turns = (float(space.lower[k]), float(space.upper[k]))
    else:
        turns = (float(space.fixed[3]), float(space.fixed[3]))
    origin = [space.fixed[:3].copy(), space.fixed[:3].copy()]  # where the search may put the path's origin
    for k, name in enumerate(space.free):
        if name in ("x", "y", "z"):
            axis = "xyz".index(name)
            origin[0][axis], origin[1][axis] = space.lower[k], space.upper[k]
    return workspace_misfit(workspace.min_m, workspace.max_m, samples.position_m, turns,
                            (origin[0].tolist(), origin[1].tolist()))


def duration_line(seconds: float) -> str:
    """What the search will take (``seconds``, s), said before it starts."""
    if seconds >= 60:
        return f"search: about {seconds / 60:.1f} min"
    return f"search: about {max(1.0, seconds):.0f} s"


def plane_line(plane: dict[str, list[float]]) -> str:
    """One line saying in which plane a planar robot's placements are read (see :func:`describe_plane`)."""
    def vector(values: list[float]) -> str:
        return "[" + ", ".join(f"{v:.4g}" for v in np.where(np.abs(values) < 1e-15, 0.0, values)) + "]"

    return (f"plane (sidecar placement.plane): normal {vector(plane['normal'])} through {vector(plane['point_m'])} m; "
            f"placements are read in it: x along {vector(plane['x_axis'])}, y along {vector(plane['y_axis'])}, "
            "phi about the normal, z = theta = psi = 0")


def draw(scene: Scene, robot: Robot, index: int, details: dict, name: str, several: bool) -> None:
    """Add one path's placements to the scene; animate the robot along the first path's.

    One path: the best, worst and ``--at`` placements in three colours (front members in the palette's next
    ones). Several paths (``several``): one colour per path, named in the legend, its best solid and its worst
    dashed. On a robot whose workpiece rides on a chain, the paths are drawn on the workpiece, moving with it.
    """

    words = wording(next(iter(details.values())).objective) if details else None
    best, worst = (f"{words.best} {words.subject}", f"{words.worst} {words.subject}") if words else ("", "")
    if several:
        for key, detail in details.items():
            scene.add_path(f"{index}_{key.replace(' ', '_')}", detail.tool_position_m, path_color(index), name,
                           dashed=key == "worst", configuration=detail.configuration)
        solid = [label for key, label in (("best", best), ("at", "--at")) if key in details]
        styles = ([f"solid: {', '.join(solid)}"] if solid else []) + ([f"dashed: {worst}"] if "worst" in details else [])
        if styles:
            scene.add_note(", ".join(styles))
    else:
        colors = {"best": (BEST_COLOR, best), "worst": (WORST_COLOR, worst), "at": (AT_COLOR, "--at")}
        for number, (key, detail) in enumerate(details.items()):
            color, label = colors.get(key, (path_color(3 + number), key))
            scene.add_path(f"{index}_{key.replace(' ', '_')}", detail.tool_position_m, color, label,
                           configuration=detail.configuration)
    moving = details.get("at") or details.get("best") or details.get("knee") or details.get("worst")
    if index == 0 and moving is not None and moving.reachable:
        scene.animate(moving.configuration, moving.samples.t_s)
        nearest = min((m for m in moving.margins if m.kind == "collision"), key=lambda m: m.margin, default=None)
        if nearest is not None:
            first, second = closest_points(robot, moving.configuration[nearest.sample], nearest.where)
            scene.add_nearest(str(index), first, second, f"nearest: {nearest.where}, {nearest.value * 1e3:.1f} mm "
                              f"at t = {moving.samples.t_s[nearest.sample]:.3f} s")


def show(page: str, host: str) -> None:
    """Serve the scene's page until Enter is pressed (or the input ends)."""
    if not host.strip():
        raise UsageError("--show-host: expected an address, got ''")
    if not (host == "localhost" or host.startswith("127.") or host == "::1"):
        print(f"warning: --show-host {host}: the scene is served to every machine that can reach this address",
              file=sys.stderr)
    from placement.output.scene import PageServer  # the [viz] extra (matplotlib, meshcat): imported only here

    try:
        server = PageServer(page, host)
    except OSError as error:
        raise UsageError(f"--show-host: cannot serve on '{host}': {error.strerror or error}") from None
    print(f"\nviewer at {server.url} (press Enter or Ctrl-C to stop)")
    try:
        serve_until_stopped()
    finally:
        server.close()


def write_profiles(file: str, robot: Robot, detail: PlacementDetail, path_name: str) -> None:
    """Plot the redundant joints' profiles of a placement in ``file`` (PNG) and beside it as SVG."""
    from placement.output.plots import profiles_figure, save  # the [viz] extra (matplotlib, meshcat): imported only here

    save(profiles_figure(robot, detail, f"{path_name} on {robot.name}: redundant joints along the path"),
         str(file).removesuffix(".png"))
    print(f"profiles written to {file} (and .svg)")


def check_front_options(args: argparse.Namespace, robot: Robot) -> None:
    """--objectives excludes the single-objective options; --members needs it, and --png without it a robot with
    redundant joints (their profiles)."""
    if args.png and len(args.path) > 1:
        raise UsageError("--png: give a single --path")
    if args.objectives is None:
        if args.members is not None:
            raise UsageError("--members goes with --objectives (a Pareto front)")
        if args.png is not None and not robot.redundant_joints:
            raise UsageError(f"--png plots a Pareto front (with --objectives) or the redundant joints' profiles, and "
                             f"robot '{robot.name}' has none")
        return
    objectives = parse_objectives(args.objectives)
    if args.members is not None:
        parse_members(args.members, objectives)
    if args.at is not None or args.at_json is not None or args.minimize or args.maximize or args.objective != "energy":
        raise UsageError("--objectives searches a Pareto front: give it without --at, --minimize, --maximize or "
                         "--objective")


def run(args: argparse.Namespace) -> int:
    """The main job; returns the exit code."""
    robot = load_robot_argument(args.robot, args, args.cell)
    if args.trace and len(args.path) > 1:
        raise UsageError("--trace: give a single --path")
    if args.at is not None and args.at_json is not None:
        raise UsageError("--at and --at-json each give the placement: give one")
    if args.which is not None and args.at_json is None:
        raise UsageError("--which goes with --at-json")
    if (args.at is not None or args.at_json is not None) and (args.fix or args.free or args.minimize or args.maximize):
        raise UsageError("--at evaluates one placement: give every value in --at, without --fix, --free, "
                         "--minimize or --maximize")
    for option, text in (("--at", args.at), ("--fix", args.fix)):
        if text is not None:
            parse_values(text, option, redundant_variables(robot), length_variables(robot))  # its errors first
            warn(length_warnings(robot, option, unsuffixed_lengths(text, length_variables(robot))), args.strict)
    check_front_options(args, robot)
    check_outputs(("--json", args.json), ("--trace", args.trace), ("--html", args.html),
                  ("--png", args.png),
                  inputs=(*args.path, *robot_files(args.robot, args.cell)))
    require_features((args.html or args.show, SCENE), (args.png, PLOTS), (args.objectives, FRONTS),
                     (scheduler_address(args.scheduler), CLUSTER))
    scene = None
    if args.html or args.show:
        from placement.output.scene import Scene  # the [viz] extra (matplotlib, meshcat): imported only here

        scene = Scene(robot)
    if scene:
        scene.add_workspace()
    documents, failures = [], []
    with cluster(scheduler_address(args.scheduler)) as remote:
        for index, file in enumerate(args.path):
            if index:
                print()
            path = configured_path(args, file)
            warn(feed_warnings(robot, path, f"{file}: feed_m_s"), args.strict)
            document, details, infeasible = place_one(robot, path, args, remote)
            documents.append(document)
            if infeasible:
                failures.append(f"{file}: {infeasible}")
                document["infeasible"] = infeasible
            if scene:
                draw(scene, robot, index, details, document["path"], len(args.path) > 1)
                scene.add_results(([""] if index else []) + results_lines(document))
            traced = details.get("at") or details.get("best") or details.get("worst")
            if args.trace and traced is not None:
                write_trace(args.trace, robot, traced)
            if args.png and args.objectives is None and traced is not None:
                write_profiles(args.png, robot, traced, document["path"])
    if args.json:
        write_json(args.json, documents[0] if len(documents) == 1 else {"robot": robot.name, "paths": documents})
    if scene:
        title = documents[0]["path"] if len(documents) == 1 else f"{len(documents)} paths"
        page = scene.html(f"{robot.name}: {title}")
        if args.html:
            write_atomically(args.html, page)
            print(f"\nscene written to {args.html} (open it in a browser; no server needed)")
        if args.show:
            show(page, args.show_host)
    for failure in failures:
        print(f"error: {'' if args.at is not None or args.at_json else 'no feasible placement: '}{failure}",
              file=sys.stderr)
    return 2 if failures else 0
