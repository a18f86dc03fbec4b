"""The 'map' command: the objective over a grid of placements, saved as .npz, drawn as PNG or 3-D.

    placement map --robot orthoglide --path rect.yaml --grid x=-120:60:41,y=-120:60:41 [--out map.npz] [--png map.png]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
from tqdm import tqdm

from placement.cli.common import (
    check_outputs,
    configured_path,
    job_options,
    load_robot_argument,
    margin_option,
    massless_option,
    model_options,
    require_features,
    robot_files,
    run_options,
    sampling_options,
)
from placement.cli.exceptions import UsageError
from placement.contract.objective import quantity, wording
from placement.distribution import CLUSTER, PLOTS, SCENE
from placement.evaluation.evaluator import EvaluatorSettings
from placement.evaluation.parallel import cluster, scheduler_address
from placement.output.report import write_atomically
from placement.placing.transform import ANGLES, VARIABLES, placement_pose
from placement.placing.values import parse_values
from placement.search.sweep import sweep

MAX_GRID_POINTS = 1_000_000


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'map' subcommand's options."""
    energy_map = commands.add_parser("map", help="map of the objective over a grid of placements (saved as .npz)",
                                     parents=[job_options(), massless_option(), model_options(), sampling_options(),
                                              margin_option(),
                                              run_options(workers="worker processes (default: every core)")])
    energy_map.add_argument("--grid", required=True, metavar="x=-120:60:41,y=-120:60:41",
                            help="swept variables: name=start:stop:count, in mm and degrees")
    energy_map.add_argument("--fix", metavar="z=0,phi=0", help="values of the other variables (mm, deg; default 0)")
    energy_map.add_argument("--out", help="the map file to write (.npz; reload with SweepResult.load); at least one "
                                          "of --out, --png and --html")
    energy_map.add_argument("--png", help="also draw the map (two variables) as PNG and SVG")
    energy_map.add_argument("--html", help="also draw the feasible placements as coloured points in a 3-D scene")


def parse_grid(text: str) -> dict[str, np.ndarray]:
    """'x=-120:60:41,phi=-90:90:37' -> {name: values (SI)}; mm and degrees."""
    axes: dict[str, np.ndarray] = {}
    points = 1
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, _, spec = item.partition("=")
        parts = spec.split(":")
        if name not in VARIABLES or len(parts) != 3:
            raise UsageError(f"--grid: expected name=start:stop:count (mm or deg), got '{item[:40]}'")
        if name in axes:
            raise UsageError(f"--grid: {name} is given twice")
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        except ValueError:
            raise UsageError(f"--grid: '{spec[:40]}' is not start:stop:count") from None
        if not (np.isfinite(start) and np.isfinite(stop)):
            raise UsageError(f"--grid: the start and stop of {name} must be finite numbers")
        if count < 2:
            raise UsageError(f"--grid: {name} needs at least 2 points")
        points *= count
        if points > MAX_GRID_POINTS:
            raise UsageError(f"--grid: more than {MAX_GRID_POINTS:,} placements; use fewer points")
        scale = np.pi / 180 if name in ANGLES else 1e-3
        axes[name] = np.linspace(start, stop, count) * scale
        if not np.isfinite(axes[name]).all():
            raise UsageError(f"--grid: the values of {name} overflow; give a sensible range")
    if not axes:
        raise UsageError("--grid: give at least one variable")
    return axes


def run(args: argparse.Namespace) -> int:
    """The 'map' command: a map of the objective over a grid of placements."""
    if not (args.out or args.png or args.html):
        raise UsageError("map: give what to write: --out (the map, .npz), --png (a figure) or --html (a scene)")
    out = None if not args.out else args.out if args.out.endswith(".npz") else f"{args.out}.npz"  # numpy's suffix
    check_outputs(("--out", out), ("--png", args.png), ("--html", args.html),
                  inputs=(args.path, *robot_files(args.robot, args.cell)))
    axes = parse_grid(args.grid)
    fixed = parse_values(args.fix or "", "--fix")
    clash = sorted(set(axes) & set(fixed))
    if clash:
        raise UsageError(f"--fix: {', '.join(clash)} is also swept by --grid")
    if args.png and len(axes) != 2:
        raise UsageError(f"--png draws maps over exactly two variables; --grid gives {len(axes)}")
    require_features((args.png, PLOTS), (args.html, SCENE), (scheduler_address(args.scheduler), CLUSTER))
    robot = load_robot_argument(args.robot, args, args.cell)
    path = configured_path(args, args.path)
    total = int(np.prod([len(v) for v in axes.values()]))
    with cluster(scheduler_address(args.scheduler)) as remote, \
            tqdm(desc="mapping", total=total, unit=" placement", disable=args.quiet, file=sys.stderr, leave=False) as bar:
        evaluation = EvaluatorSettings(objective=args.objective, regeneration=args.regen, time_step_s=args.time_step,
                                       workers=args.workers, margin=args.margin / 100)
        result = sweep(robot, path, axes, fixed, evaluation=evaluation, progress=bar.update,
                       executor=remote.executor if remote else None)
    if out:
        result.save(out)
    feasible = result.value[result.feasible]
    words = wording(args.objective)
    print(f"{total} placements of {path.name} on {robot.name}: {len(feasible)} feasible"
          + (f", {words.subject} {feasible.min():.4f} to {quantity(feasible.max(), words.unit)}" if len(feasible) else "")
          + (f"; written to {out}" if out else ""))
    if args.png:
        from placement.output.plots import map_figure, save  # the [viz] extra (matplotlib, meshcat): imported only here

        save(map_figure(result, f"{path.name}: {words.subject} ({args.regen})"), str(args.png).removesuffix(".png"))
        print(f"figure written to {args.png} (and .svg)")
    if args.html:
        from placement.output.scene import Scene  # the [viz] extra (matplotlib, meshcat): imported only here

        scene = Scene(robot)
        scene.add_workspace()
        keep = result.feasible.ravel()
        origins = placement_pose(result.placements()[keep], robot.plane)[1]
        scene.add_value_points(origins, result.value.ravel()[keep], words.subject)
        write_atomically(args.html, scene.html(f"{robot.name}: {words.subject} map of {path.name}"))
        print(f"scene written to {args.html}")
    return 0
