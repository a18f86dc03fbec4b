"""The 'study' command: every path on every robot, one table.

    placement study --robots orthoglide,ur5 --paths examples/rect.yaml examples/circle.yaml --out study.csv
        [--cell FILE] [--objective NAME] [--regen MODE] [--timing LAW] [--time-step S]
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
from collections.abc import Sequence
from dataclasses import asdict

from tqdm import tqdm

from placement.cli.common import (
    cell_option,
    check_outputs,
    configured_path,
    load_robot_argument,
    massless_option,
    model_options,
    require_features,
    robot_files,
    run_options,
    sampling_options,
    seed_option,
    whole_number,
)
from placement.cli.exceptions import UsageError
from placement.contract.objective import OBJECTIVES
from placement.distribution import CLUSTER
from placement.evaluation.evaluator import EvaluatorSettings
from placement.evaluation.parallel import cluster, scheduler_address
from placement.output.report import write_atomically
from placement.search.optimize import SearchSettings
from placement.search.study import StudyRow, run_study


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'study' subcommand's options."""
    command = commands.add_parser("study", help="search every path on every robot and write one table",
                                  parents=[cell_option(), massless_option(), model_options(), sampling_options(), seed_option(),
                                           run_options(workers="searches run at once on this machine (default: every "
                                                               "core)")])
    command.add_argument("--robots", required=True, metavar="A,B",
                         help="robots, comma-separated: names or sidecar YAML files")
    command.add_argument("--paths", required=True, nargs="+", metavar="FILE", help="path files (YAML)")
    command.add_argument("--out", required=True, metavar="FILE.csv",
                         help="the table (CSV; also FILE.parquet when pyarrow is installed)")
    command.add_argument("--generations", type=whole_number(1, 100_000), default=SearchSettings.max_generations,
                         metavar="N", help=f"most generations of each search (default {SearchSettings.max_generations})")


def run(args: argparse.Namespace) -> int:
    """Search every pair, print the table, write it; exit 2 when some pair has no feasible placement."""
    if not args.out.endswith(".csv"):
        raise UsageError(f"--out: expected a file name ending in .csv, got '{args.out[:60]}'")
    names = [name.strip() for name in args.robots.split(",") if name.strip()]
    if not names:
        raise UsageError("--robots: expected robot names or sidecar files, comma-separated")
    check_outputs(("--out", args.out), ("--out", args.out.removesuffix(".csv") + ".parquet"),
                  inputs=(*args.paths, *(file for name in names for file in robot_files(name, args.cell))))
    OBJECTIVES.get(args.objective)  # an unknown name is refused before any robot is loaded
    require_features((scheduler_address(args.scheduler), CLUSTER))
    robots = [load_robot_argument(name, args, args.cell) for name in names]
    paths = [configured_path(args, file) for file in args.paths]
    settings = SearchSettings(seed=args.seed, max_generations=args.generations)
    evaluation = EvaluatorSettings(objective=args.objective, regeneration=args.regen, time_step_s=args.time_step)
    with cluster(scheduler_address(args.scheduler)) as remote, \
            tqdm(desc="studying", total=len(robots) * len(paths), unit=" search", disable=args.quiet,
                 file=sys.stderr, leave=False) as bar:
        rows = run_study(robots, paths, evaluation=evaluation, settings=settings,
                         executor=remote.executor if remote else None, workers=args.workers, progress=bar.update)
    print(format_table(rows))
    written = write_table(rows, args.out)
    print(f"\nwritten to {' and '.join(written)}")
    return 0 if all(row.feasible for row in rows) else 2


def format_table(rows: Sequence[StudyRow]) -> str:
    """The study as a text table, one line per (robot, path) pair; for an objective other than energy, its values at
    the best and worst placements come first, and the gain is the objective's."""
    fastest = any(not math.isnan(row.fastest_cycle_time_s) for row in rows)
    ranked = next((row.objective for row in rows if row.objective != "energy"), None)
    unit = f" {OBJECTIVES.get(ranked).unit}".rstrip() if ranked else ""
    lines = [f"{'robot':<14s}{'path':<34s}" + (f"{'best' + unit:>12s}{'worst' + unit:>12s}" if ranked else "")
             + f"{'best J':>10s}{'worst J':>10s}{'gain':>8s}{'time s':>9s}"
             + (f"{'fastest s':>10s}" if fastest else "") + "  feasible"]
    for row in rows:
        gain = "" if math.isnan(row.gain) else f"{row.gain * 100:.1f} %"
        objective = "".join(f"{'' if math.isnan(v) else f'{v:.5g}':>12s}" for v in (row.best_value, row.worst_value))
        values = "".join(f"{'' if math.isnan(v) else f'{v:.4f}':>10s}" for v in (row.best_energy_J, row.worst_energy_J))
        verdict = "yes" if row.feasible else f"no: {row.reason}"
        quickest = f"{row.fastest_cycle_time_s:>10.4f}" if fastest else ""
        lines.append(f"{row.robot[:13]:<14s}{row.path[:33]:<34s}{objective if ranked else ''}{values}{gain:>8s}"
                     f"{row.cycle_time_s:>9.3f}{quickest}  {verdict}")
    return "\n".join(([f"ranked by {ranked}; the gain is its own"] if ranked else []) + lines)


def write_table(rows: Sequence[StudyRow], csv_path: str) -> list[str]:
    """Write the rows as CSV, and beside it as Parquet when pyarrow is installed; returns the files written."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(StudyRow.__dataclass_fields__))
    writer.writeheader()
    writer.writerows(asdict(row) for row in rows)
    write_atomically(csv_path, buffer.getvalue())
    try:
        import pyarrow as arrow
        import pyarrow.parquet as parquet
    except ImportError:
        return [csv_path]
    parquet_path = csv_path.removesuffix(".csv") + ".parquet"
    parquet.write_table(arrow.Table.from_pylist([asdict(row) for row in rows]), parquet_path)
    return [csv_path, parquet_path]
