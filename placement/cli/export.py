"""The 'export' command: a placement of a result file as the work frame a controller takes.

    placement export result.json --to kuka [--out base.src] [--which best|worst|at]
"""

from __future__ import annotations

import argparse

from placement.cli.common import check_outputs
from placement.output.export import FORMATS, WHICH, read_work_frame
from placement.output.report import write_atomically


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'export' subcommand's options."""
    command = commands.add_parser("export", help="write a placement of a --json result as a controller's work frame "
                                  "(G-code G54/G68, ABB wobjdata, KUKA BASE_DATA, UR pose, Fanuc user frame)")
    command.add_argument("result", help="the JSON file the main job's --json wrote (one path)")
    command.add_argument("--to", required=True, choices=tuple(FORMATS), help="the controller's format")
    command.add_argument("--out", metavar="FILE", help="write to FILE (default: print)")
    command.add_argument("--which", choices=WHICH, default="best",
                         help="which placement of the file (default best; at: the --at placement)")


def run(args: argparse.Namespace) -> int:
    """Print or write the placement in the format asked for."""
    check_outputs(("--out", args.out), inputs=(args.result,))
    text = FORMATS[args.to](read_work_frame(args.result, args.which))
    if args.out:
        write_atomically(args.out, text)
        print(f"{args.to} work frame written to {args.out}")
    else:
        print(text, end="")
    return 0
