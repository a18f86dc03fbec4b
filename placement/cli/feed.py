"""The 'feed' command: energy per part against time per part as the feed rate changes.

    placement feed --robot orthoglide --path rect.yaml --at x=0,y=0 --feeds 0.2:1.2:11 [--png FILE]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from placement.cli.common import (
    check_outputs,
    configured_path,
    job_options,
    load_robot_argument,
    massless_option,
    regeneration_option,
    require_features,
    robot_files,
    sampling_options,
)
from placement.cli.exceptions import UsageError
from placement.distribution import PLOTS
from placement.energy.regeneration import REGENERATION
from placement.evaluation.evaluator import EvaluatorSettings
from placement.placing.transform import VARIABLES
from placement.placing.values import parse_values
from placement.search.feed import feed_study

MAX_FEEDS = 1000
MAX_FEED_M_S = 100.0


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'feed' subcommand's options."""
    command = commands.add_parser("feed", help="energy and time per part against the feed rate, at one placement",
                                  parents=[job_options(), massless_option(), regeneration_option(), sampling_options()])
    command.add_argument("--at", required=True, metavar="x=..,y=..,phi=..",
                         help="the placement (mm and deg unless a value ends in m or rad)")
    command.add_argument("--feeds", required=True, metavar="START:STOP:COUNT", help="feed rates in m/s, e.g. 0.2:1.2:11")
    command.add_argument("--png", help="also draw energy per part against time per part (PNG and SVG)")


def parse_feeds(text: str) -> np.ndarray:
    """'0.2:1.2:11' -> feed rates (m/s)."""
    parts = text.split(":")
    try:
        start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
    except (ValueError, IndexError):
        raise UsageError(f"--feeds: expected START:STOP:COUNT in m/s, got '{text[:40]}'") from None
    if len(parts) != 3 or not (0 < start <= MAX_FEED_M_S and 0 < stop <= MAX_FEED_M_S) or not 1 <= count <= MAX_FEEDS:
        raise UsageError(f"--feeds: expected feeds from 0 to {MAX_FEED_M_S:g} m/s and 1 to {MAX_FEEDS} of them, "
                         f"got '{text[:40]}'")
    return np.linspace(start, stop, count)


def run(args: argparse.Namespace) -> int:
    """Print the table (and draw the figure) of time and energy per part against feed."""
    check_outputs(("--png", args.png), inputs=(args.path, *robot_files(args.robot, args.cell)))
    require_features((args.png, PLOTS))
    feeds = parse_feeds(args.feeds)
    given = parse_values(args.at, "--at")
    robot = load_robot_argument(args.robot, args, args.cell)
    path = configured_path(args, args.path)
    study = feed_study(robot, path, np.array([given.get(name, 0.0) for name in VARIABLES]), feeds,
                       EvaluatorSettings(regeneration=args.regen, time_step_s=args.time_step))
    print(f"{path.name} on {robot.name}, {path.timing.mode} timing, energy: {REGENERATION.get(args.regen).description}")
    width = max(16, *map(len, study.speed_bound))
    print(f"  {'feed m/s':>9s} {'reached m/s':>12s} {'time/part s':>12s} {'energy/part J':>14s} {'mean power W':>13s}"
          f"  {'speed bounded by':<{width}s}  limits")
    for k, feed in enumerate(study.feeds_m_s):
        state = "hold" if study.feasible[k] else f"BROKEN: {study.binding[k]}"
        print(f"  {feed:9.3f} {study.top_speed_m_s[k]:12.3f} {study.time_s[k]:12.4f} {study.energy_J[k]:14.4f} "
              f"{study.energy_J[k] / study.time_s[k]:13.2f}  {study.speed_bound[k]:<{width}s}  {state}")
    if args.png:
        from placement.output.plots import feed_figure, save  # the [viz] extra (matplotlib, meshcat): imported only here

        save(feed_figure(study, f"{path.name} on {robot.name}"), str(args.png).removesuffix(".png"))
        print(f"figure written to {args.png} (and .svg)")
    if not study.feasible.any():
        print(f"error: no feed keeps every limit at this placement ({study.binding[0]} at the first)", file=sys.stderr)
        return 2
    return 0
