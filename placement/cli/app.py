"""The workbench in the browser: ``placement app --robot NAME --path FILE [--cell FILE] [--port N]``.

Serves a page on this machine (127.0.0.1, unless ``--host`` says otherwise, with a warning) where
the path's placement is dragged or typed and read live, searched, and the robot played along it
(:mod:`placement.app.page`); prints its address and serves until Enter is pressed or the input ends.
"""

from __future__ import annotations

import argparse
import sys

from placement.cli.common import (
    configured_path,
    job_options,
    load_robot_argument,
    margin_option,
    massless_option,
    model_options,
    placement_options,
    sampling_options,
    seed_option,
    serve_until_stopped,
    whole_number,
)
from placement.cli.exceptions import UsageError
from placement.distribution import WORKBENCH, require
from placement.placing.values import parse_free, parse_values
from placement.search.optimize import SearchSettings
from placement.search.space import default_space


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The ``app`` subcommand's options."""
    parser = commands.add_parser("app", help="the workbench: drag, read, search and play a placement in the browser",
                                 description="Serve the workbench page: the robot, its workspace and the placed "
                                             "path with a gizmo, live and exact readings, searches, the motion.",
                                 parents=[job_options(), massless_option(), placement_options(), model_options(),
                                          sampling_options(), margin_option(), seed_option()])
    parser.add_argument("--port", type=whole_number(0, 65535), default=0,
                        help="port to serve on (default: the first free one from 8080)")
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to serve on (default 127.0.0.1: this machine only)")
    parser.add_argument("--allow-origin", action="append", default=[], metavar="ORIGIN",
                        help="a further origin (scheme://host:port) whose pages may use the workbench, e.g. behind a "
                             "proxy; repeatable. By default only the workbench's own page on a loopback name "
                             "(127.0.0.1, localhost, [::1]) with the printed ?token= may (docs/howto/use_the_workbench.md)")


def start(args: argparse.Namespace):  # -> placement.app.page.Workbench (viser loads only here)
    """Build the bench and serve its page; returns the workbench (its ``url``, ``close()``)."""
    require(WORKBENCH)  # before any work: the [app] extra's packages, or a message naming the extra
    from placement.app.evaluations import Bench, Choices  # the [app] extra's modules: imported only here
    from placement.app.guard import allowed_origin
    from placement.app.page import Workbench

    origins = tuple(allowed_origin(origin) for origin in args.allow_origin)
    if not args.host.strip():
        raise UsageError("--host: expected an address, got ''")
    if not (args.host == "localhost" or args.host.startswith("127.") or args.host == "::1"):
        print(f"warning: --host {args.host}: the workbench is served to every machine that can reach this address",
              file=sys.stderr)
    robot = load_robot_argument(args.robot, args, args.cell)
    if robot.workpiece_frame is not None:
        raise UsageError(f"robot '{robot.name}' carries the workpiece on a chain (workpiece_frame: {robot.workpiece_frame}): "
                         "the workbench places the path in the base frame and does not cover a workpiece that moves "
                         f"yet; search with 'placement --robot {args.robot} --path {args.path}' and see its motion "
                         "with --html")
    if robot.redundant_joints:
        held = " ".join(f"--lock {joint}=VALUE" for joint in robot.redundant_joints)
        raise UsageError(f"robot '{robot.name}' has joints profiled along the path ({', '.join(robot.redundant_joints)}), "
                         f"which the search places beside x, y, z, phi, theta, psi; the workbench places those six "
                         f"only: hold the profiled joints ({held}), or search them with 'placement --robot "
                         f"{args.robot} --path {args.path}'")
    path = configured_path(args, args.path)
    free, bounds = parse_free(args.free, "--free") if args.free is not None else (None, {})
    space = default_space(robot, free=free, fixed=parse_values(args.fix or "", "--fix"), bounds=bounds,
                          half_turn=path.half_turn_symmetric())
    bench = Bench(robot, path, space=space, time_step_s=args.time_step,
                  choices=Choices(objective=args.objective, regeneration=args.regen),
                  search=SearchSettings(seed=args.seed), margin=args.margin / 100)
    try:
        return Workbench(bench, host=args.host, port=args.port, origins=origins)
    except OSError as error:
        bench.close()
        raise UsageError(f"--host/--port: cannot serve on '{args.host}': {error.strerror or error}") from None


def run(args: argparse.Namespace) -> int:
    """Serve the workbench until Enter is pressed, or, with no input (in the background), until interrupted."""
    workbench = start(args)
    print(f"workbench at {workbench.url} (press Enter or Ctrl-C to stop)", flush=True)
    try:
        serve_until_stopped()
    finally:
        workbench.close()
    return 0
