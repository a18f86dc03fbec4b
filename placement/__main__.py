"""Command line: ``python -m placement`` (also installed as ``placement``).

    placement --robot orthoglide --path examples/rect.yaml    best and worst placements, gain
    placement --robot orthoglide --path rect.yaml --at x=0,y=0,z=0,phi=0    one placement
    placement --robot orthoglide --path a.yaml b.yaml --html scene.html    3-D scene in one page
    placement map --robot orthoglide --path rect.yaml --grid x=-120:60:41,y=-120:60:41 --out map.npz
    placement robots                                           list the built-in robots
    placement check ROBOT                                      describe a robot, prove its model exact

Exit codes: 0 success, 1 a physics check failed, 2 bad input or no feasible placement (the
message says what and where).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

from placement.checks import check_robot
from placement.evaluation import Evaluator
from placement.exceptions import PlacementError
from placement.frames import ANGLES, VARIABLES, placed_task
from placement.kinematics import joint_trajectory
from placement.optimize import SearchSettings, default_space, optimize_placement
from placement.path import Timing, ToolPath, load_path
from placement.report import (REGENERATION_TEXT, detail_json, format_detail, format_result, write_atomically,
                              write_json, write_trace)
from placement.sweep import sweep
from placement.visualize import AT_COLOR, BEST_COLOR, WORST_COLOR, Scene
from placement.energy import REGENERATION_MODES
from placement.robot import Robot, builtin_robots, load_robot
from placement.sidecar import BallScrew

SUBCOMMANDS = ("robots", "check", "map")


class UsageError(PlacementError):
    """A command-line option has a value it cannot take."""


def add_sampling_options(parser: argparse.ArgumentParser) -> None:
    """Options that override how a path file is timed and sampled (see configured_path)."""
    parser.add_argument("--timing", choices=("paper", "realistic"), help="override the path file's timing law")
    parser.add_argument("--max-acceleration", type=float, metavar="M_S2",
                        help="tool acceleration bound of the realistic timing law (m/s^2)")
    parser.add_argument("--max-jerk", type=float, metavar="M_S3", help="tool jerk bound of the realistic timing law (m/s^3)")
    parser.add_argument("--time-step", type=float, metavar="S", help="path sampling step (s; default: the path file's)")


def build_parser() -> argparse.ArgumentParser:
    """The parser of the main job: place a path on a robot."""
    parser = argparse.ArgumentParser(
        prog="placement", description="Find where to place a tool path in a robot's workspace so that the "
        "actuators draw the least electric energy while every limit holds.",
        epilog="Other commands: 'placement robots' lists the built-in robots; 'placement check ROBOT' describes "
               "a robot and proves its dynamic model exact.")
    parser.add_argument("--robot", required=True, help="built-in robot name or path to a robot sidecar YAML")
    parser.add_argument("--path", required=True, nargs="+", help="path file(s) (YAML), e.g. examples/rect.yaml")
    direction = parser.add_mutually_exclusive_group()
    direction.add_argument("--minimize", action="store_true", help="only search the least-energy placement")
    direction.add_argument("--maximize", action="store_true", help="only search the most-energy placement")
    parser.add_argument("--at", metavar="x=..,y=..,phi=..",
                        help="evaluate one placement instead of searching (mm and deg unless a value ends in m or rad)")
    parser.add_argument("--free", metavar="x,y,z,phi",
                        help="free placement variables (default: the robot's, e.g. x,y,z,phi for the Orthoglide)")
    parser.add_argument("--fix", metavar="z=0,theta=0", help="values of fixed variables (mm, deg; default 0)")
    parser.add_argument("--regen", choices=REGENERATION_MODES, default="clip",
                        help="what happens to braking energy (default: clip, no regeneration)")
    add_sampling_options(parser)
    parser.add_argument("--seed", type=int, default=0, help="random seed of the search (default 0)")
    parser.add_argument("--generations", type=int, default=SearchSettings.max_generations, metavar="N",
                        help=f"most generations of the global search (default {SearchSettings.max_generations})")
    parser.add_argument("--population", type=int, default=SearchSettings.population, metavar="N",
                        help=f"population of the global search (default {SearchSettings.population})")
    parser.add_argument("--json", metavar="FILE", help="write the results as JSON (SI units)")
    parser.add_argument("--trace", metavar="FILE",
                        help="write a per-sample CSV trace of the placement given by --at, else of the best one")
    parser.add_argument("--html", metavar="FILE", help="write a 3-D scene (robot, workspace, best and worst paths, "
                        "robot animated along the first path) as a self-contained HTML page")
    parser.add_argument("--show", action="store_true", help="serve the 3-D scene live on this machine and print its URL")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def build_command_parser() -> argparse.ArgumentParser:
    """The parser of the 'robots' and 'check' commands."""
    parser = argparse.ArgumentParser(prog="placement")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    commands.add_parser("robots", help="list the built-in robots")
    check = commands.add_parser("check", help="describe a robot and prove its dynamic model exact")
    check.add_argument("robot", help="built-in robot name or path to a sidecar YAML file")
    check.add_argument("--samples", type=int, default=100, help="samples of the check trajectory (default 100)")
    energy_map = commands.add_parser("map", help="energy map over a grid of placements (saved as .npz)")
    energy_map.add_argument("--robot", required=True, help="built-in robot name or sidecar YAML")
    energy_map.add_argument("--path", required=True, help="path file (YAML)")
    energy_map.add_argument("--grid", required=True, metavar="x=-120:60:41,y=-120:60:41",
                            help="swept variables: name=start:stop:count, in mm and degrees")
    energy_map.add_argument("--fix", metavar="z=0,phi=0", help="values of the other variables (mm, deg; default 0)")
    energy_map.add_argument("--regen", choices=REGENERATION_MODES, default="clip", help="regeneration mode")
    add_sampling_options(energy_map)
    energy_map.add_argument("--workers", type=int, help="worker processes (default: every core)")
    energy_map.add_argument("--out", required=True, help="the map file to write (.npz; reload with SweepResult.load)")
    energy_map.add_argument("--png", help="also draw the map (two variables) as PNG and SVG")
    energy_map.add_argument("--html", help="also draw the feasible placements as coloured points in a 3-D scene")
    energy_map.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def describe(robot: Robot) -> str:
    """A human-readable summary of a loaded robot."""
    model = robot.model
    point = sum(c.kind == "point" for c in robot.closures)
    lines = [f"{robot.name}: {robot.sidecar.description}",
             f"  files: {robot.sidecar_path} + {robot.urdf_path.name}",
             f"  joints: {model.nv} ({len(robot.actuators)} actuated); closures: {len(robot.closures)} "
             f"({point} point, {len(robot.closures) - point} weld)",
             f"  end effector: frame '{model.frames[robot.end_effector_frame_id].name}', {robot.task} task; "
             f"kinematics: {'closed-form plug-in ' + robot.sidecar.kinematics_plugin if robot.closed_form else 'generic solver'}",
             f"  gravity: {list(robot.sidecar.gravity_m_s2)} m/s^2",
             "  actuators:"]
    for a in robot.actuators:
        unit, mass = ("m", "kg") if a.prismatic else ("rad", "kg m^2")
        text = (f"    {a.joint:<20s} [{a.position_min:.6f}, {a.position_max:.6f}] {unit}, "
                f"|speed| <= {a.velocity_max:g} {unit}/s")
        if a.drive is not None:
            t = a.drive.transmission
            ratio = f"ball screw {t.lead_m * 1e3:g} mm" if isinstance(t, BallScrew) else f"gear {t.ratio:g}:1"
            text += f", {ratio}, motor {a.drive.motor.max_torque_Nm:g} N m max, reflected inertia {a.reflected_inertia:.4g} {mass}"
        lines.append(text)
    workspace = robot.sidecar.workspace
    if workspace is not None:
        lines.append(f"  workspace: box {np.round(workspace.min_m, 6).tolist()} .. {np.round(workspace.max_m, 6).tolist()} m"
                     + (f"; points {', '.join(workspace.points_m)}" if workspace.points_m else ""))
    estimated = sum(text.startswith("EST") for text in robot.sidecar.sources.values())
    lines.append(f"  sources: {len(robot.sidecar.sources)} entries, {estimated} estimated (EST)")
    return "\n".join(lines)


def run_check(robot_name: str, samples: int) -> int:
    """Load, describe and check one robot; returns the exit code."""
    robot = load_robot(robot_name)
    print(describe(robot))
    report = check_robot(robot, samples)
    print(f"  physics check on a demonstration trajectory around the reference ({report.samples} samples):")
    print(f"    closure residual            {report.closure_gap:.1e} (m, rad)")
    if report.solver_gap is not None:
        print(f"    closed form vs generic      {report.solver_gap:.1e} (m, rad)")
    print(f"    forward dynamics round trip {report.forward_error:.1e} (joint acceleration error)")
    print(f"    power balance               {report.power_error_W:.1e} W of {report.peak_power_W:.3g} W peak")
    print(f"    peak efforts                {np.round(report.peak_effort, 3).tolist()}")
    print("  result: " + ("exact to round-off" if report.passed else "FAILED: the model is not consistent"))
    return 0 if report.passed else 1


def parse_values(text: str, option: str) -> dict[str, float]:
    """'x=10,phi=30' -> SI values; lengths in mm and angles in deg unless suffixed m / rad."""
    values = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, _, raw = item.partition("=")
        name = name.strip()
        if name not in VARIABLES or not raw:
            raise UsageError(f"{option}: expected name=value with names from {', '.join(VARIABLES)}, got '{item}'")
        angle = name in ANGLES
        units = {"rad": 1.0, "deg": np.pi / 180} if angle else {"mm": 1e-3, "m": 1.0}
        unit = next((u for u in sorted(units, key=len, reverse=True) if raw.strip().endswith(u)), None)
        number = raw.strip()[: -len(unit)] if unit else raw.strip()
        try:
            values[name] = float(number) * units[unit or ("deg" if angle else "mm")]
        except ValueError:
            raise UsageError(f"{option}: '{raw}' is not a number for {name}") from None
        if not np.isfinite(values[name]):
            raise UsageError(f"{option}: {name} must be a finite number, got '{raw}'")
    return values


def configured_path(args: argparse.Namespace, file: str) -> ToolPath:
    """A path file with the command line's timing overrides."""
    path = load_path(file)
    overrides = (args.timing, args.max_acceleration, args.max_jerk)
    if any(value is not None for value in overrides):
        timing = path.timing
        try:
            timing = Timing(mode=args.timing if args.timing is not None else timing.mode,
                            max_acceleration_m_s2=(args.max_acceleration if args.max_acceleration is not None
                                                   else timing.max_acceleration_m_s2),
                            max_jerk_m_s3=args.max_jerk if args.max_jerk is not None else timing.max_jerk_m_s3)
        except ValueError as error:
            problem = error.errors()[0]
            field = {"max_acceleration_m_s2": "--max-acceleration", "max_jerk_m_s3": "--max-jerk"}.get(
                str(problem["loc"][0]) if problem["loc"] else "", "--timing")
            raise UsageError(f"{field}: {problem['msg'].removeprefix('Value error, ')}; the realistic timing law "
                             "needs --max-acceleration and --max-jerk > 0, or both in the path file") from None
        path = dataclasses.replace(path, timing=timing)
    if args.time_step is not None and not args.time_step > 0:
        raise UsageError("--time-step must be > 0 s")
    return path


def check_outputs(*pairs: tuple[str, str | None]) -> None:
    """Every output file must be writable before hours of work are spent: (option, file) pairs."""
    for option, file in pairs:
        if file is None:
            continue
        target = Path(file)
        if target.is_dir():
            raise UsageError(f"{option}: '{file}' is a folder, expected a file name")
        if not target.absolute().parent.is_dir():
            raise UsageError(f"{option}: the folder of '{file}' does not exist")
        if not os.access(target.absolute().parent, os.W_OK) or (target.exists() and not os.access(target, os.W_OK)):
            raise UsageError(f"{option}: '{file}' cannot be written")


def place_one(robot: Robot, path: ToolPath, args: argparse.Namespace) -> tuple[dict, dict, str | None]:
    """Search (or evaluate --at) one path and print its report.

    Returns:
        The JSON document, the details to draw ({"best"|"worst"|"at": PlacementDetail}), and the
        reason when no placement is feasible.
    """
    samples = path.sample(args.time_step)
    print(f"{path.name} on {robot.name}: {len(path.segments)} segment(s), {path.length_m * 1e3:.1f} mm, "
          f"feed {path.feed_m_s:g} m/s, {path.timing.mode} timing, {len(samples)} samples over "
          f"{samples.t_s[-1]:.3f} s; energy: {REGENERATION_TEXT[args.regen]}")
    document: dict = {"robot": robot.name, "path": path.name, "regeneration": args.regen,
                      "timing": path.timing.mode, "samples": len(samples)}
    if args.at is not None:
        given = parse_values(args.at, "--at")
        detail = Evaluator(robot, path, args.regen, args.time_step).detail(
            np.array([given.get(name, 0.0) for name in VARIABLES]))
        print("\n" + format_detail("placement given by --at", robot, detail))
        document["at"] = detail_json(robot, detail)
        problem = None
        if not detail.reachable:
            problem = f"the placement given by --at leaves the robot's reach ({len(detail.unreachable_samples)} samples)"
        elif not detail.feasible:
            worst = min(detail.margins, key=lambda m: m.margin)
            problem = f"the placement given by --at breaks the {worst.kind} ({worst.where})"
        return document, {"at": detail} if detail.reachable else {}, problem
    free = tuple(n.strip() for n in args.free.split(",")) if args.free else None
    space = default_space(robot, free=free, fixed=parse_values(args.fix or "", "--fix"),
                          half_turn=path.half_turn_symmetric())
    print(f"search: {', '.join(space.free)} free; seed {args.seed}")
    if args.generations < 1 or args.population < 1:
        raise UsageError("--generations and --population must be at least 1")
    settings = SearchSettings(seed=args.seed, max_generations=args.generations, population=args.population)
    directions = 1 if args.minimize or args.maximize else 2
    with tqdm(desc="searching", total=directions * settings.max_generations, unit=" generation",
              disable=args.quiet, file=sys.stderr, leave=False) as bar:
        result = optimize_placement(robot, path, space=space, regeneration=args.regen,
                                    minimize_energy=not args.maximize, maximize_energy=not args.minimize,
                                    time_step_s=args.time_step, settings=settings, progress=bar.update)
    print("\n" + format_result(robot, result))
    details = {}
    for key, optimum in (("best", result.best), ("worst", result.worst)):
        if optimum is not None:
            document[key] = detail_json(robot, optimum.detail, optimum)
            details[key] = optimum.detail
    if result.gain is not None:
        document["gain"] = result.gain
    if result.infeasible:
        document["infeasible"] = result.infeasible
    return document, details, result.infeasible


def draw(scene: Scene, robot: Robot, index: int, details: dict) -> None:
    """Add one path's placements to the scene; animate the robot along the first path's."""
    colors = {"best": (BEST_COLOR, "least energy"), "worst": (WORST_COLOR, "most energy"), "at": (AT_COLOR, "--at")}
    for key, detail in details.items():
        scene.add_path(f"{index}_{key}", detail.tool_position_m, *colors[key])
    moving = details.get("at") or details.get("best") or details.get("worst")
    if index == 0 and moving is not None and moving.reachable:
        task, _ = placed_task(robot, moving.samples, moving.placement[None])
        scene.animate(joint_trajectory(robot, task).q, moving.samples.t_s)


def run_placement(args: argparse.Namespace) -> int:
    """The main job; returns the exit code."""
    robot = load_robot(args.robot)
    if args.trace and len(args.path) > 1:
        raise UsageError("--trace: give a single --path")
    if args.at is not None and (args.fix or args.free or args.minimize or args.maximize):
        raise UsageError("--at evaluates one placement: give every value in --at, without --fix, --free, "
                         "--minimize or --maximize")
    check_outputs(("--json", args.json), ("--trace", args.trace), ("--html", args.html))
    scene = Scene(robot, live=args.show) if args.html or args.show else None
    if scene:
        scene.add_workspace()
    documents, failures = [], []
    try:
        for index, file in enumerate(args.path):
            if index:
                print()
            document, details, infeasible = place_one(robot, configured_path(args, file), args)
            documents.append(document)
            if infeasible:
                failures.append(f"{file}: {infeasible}")
                document["infeasible"] = infeasible
            if scene:
                draw(scene, robot, index, details)
            if args.trace and details:
                write_trace(args.trace, robot, details.get("at") or details.get("best") or details.get("worst"))
        if args.json:
            write_json(args.json, documents[0] if len(documents) == 1 else {"robot": robot.name, "paths": documents})
        if args.html:
            title = documents[0]["path"] if len(documents) == 1 else f"{len(documents)} paths"
            write_atomically(args.html, scene.html(f"{robot.name}: {title}"))
            print(f"\nscene written to {args.html} (open it in a browser; no server needed)")
        if args.show:
            print(f"\nviewer at {scene.url()} (press Enter to stop)")
            try:
                input()
            except EOFError:
                pass
    finally:
        if scene:
            scene.close()
    for failure in failures:
        print(f"error: {'' if args.at is not None else 'no feasible placement: '}{failure}", file=sys.stderr)
    return 2 if failures else 0


def parse_grid(text: str) -> dict[str, np.ndarray]:
    """'x=-120:60:41,phi=-90:90:37' -> {name: values (SI)}; mm and degrees."""
    axes = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, _, spec = item.partition("=")
        parts = spec.split(":")
        if name not in VARIABLES or len(parts) != 3:
            raise UsageError(f"--grid: expected name=start:stop:count (mm or deg), got '{item}'")
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        except ValueError:
            raise UsageError(f"--grid: '{spec}' is not start:stop:count") from None
        if count < 2:
            raise UsageError(f"--grid: {name} needs at least 2 points")
        scale = np.pi / 180 if name in ANGLES else 1e-3
        axes[name] = np.linspace(start, stop, count) * scale
    if not axes:
        raise UsageError("--grid: give at least one variable")
    return axes


def run_map(args: argparse.Namespace) -> int:
    """The 'map' command: an energy map over a grid of placements."""
    robot = load_robot(args.robot)
    check_outputs(("--out", args.out), ("--png", args.png), ("--html", args.html))
    path = configured_path(args, args.path)
    axes = parse_grid(args.grid)
    fixed = parse_values(args.fix or "", "--fix")
    total = int(np.prod([len(v) for v in axes.values()]))
    with tqdm(desc="mapping", total=total, unit=" placement", disable=args.quiet, file=sys.stderr, leave=False) as bar:
        result = sweep(robot, path, axes, fixed, regeneration=args.regen, time_step_s=args.time_step,
                       workers=args.workers, progress=bar.update)
    result.save(args.out)
    feasible = result.energy_J[result.feasible]
    print(f"{total} placements of {path.name} on {robot.name}: {len(feasible)} feasible"
          + (f", energy {feasible.min():.4f} to {feasible.max():.4f} J" if len(feasible) else "")
          + f"; written to {args.out}")
    if args.png:
        if len(axes) != 2:
            raise UsageError("--png draws maps over exactly two variables")
        from placement.plots import map_figure, save

        save(map_figure(result, f"{path.name}: energy ({args.regen})"), str(args.png).removesuffix(".png"))
        print(f"figure written to {args.png} (and .svg)")
    if args.html:
        scene = Scene(robot)
        scene.add_workspace()
        placements = np.tile(result.fixed, (result.energy_J.size, 1))
        for name, grid in zip(result.variables, np.meshgrid(*result.axes, indexing="ij")):
            placements[:, VARIABLES.index(name)] = grid.ravel()
        keep = result.feasible.ravel()
        scene.add_energy_points(placements[keep, :3], result.energy_J.ravel()[keep])
        write_atomically(args.html, scene.html(f"{robot.name}: energy map of {path.name}"))
        print(f"scene written to {args.html}")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    argv = sys.argv[1:] if argv is None else argv
    try:
        if argv and argv[0] in SUBCOMMANDS:
            args = build_command_parser().parse_args(argv)
            if args.command == "robots":
                for name in builtin_robots():
                    print(f"{name:<14s} {load_robot(name).sidecar.description}")
                return 0
            if args.command == "map":
                return run_map(args)
            return run_check(args.robot, args.samples)
        return run_placement(build_parser().parse_args(argv))
    except PlacementError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except OSError as error:  # a file could not be written after all (disk full, ...)
        print(f"error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
