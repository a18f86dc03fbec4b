"""Command line: ``python -m placement`` (also installed as ``placement``).

    placement --robot orthoglide --path examples/rect.yaml    the main job (:mod:`placement.cli.place`)
    placement map ...                                          a map of the objective (:mod:`placement.cli.map`)
    placement feed ...                                         energy and time per part against feed
    placement check ROBOT                                      describe a robot, prove its model exact
    placement assemble ROBOT [--near J=V,...] [--write]        close the loops of a robot exported open
    placement robots                                           list the robots
    placement calibrate ROBOT --log LOG --fit NAMES            fit drive constants to measurements
    placement study --robots A,B --paths P Q --out study.csv   every path on every robot, one table
    placement export RESULT.json --to kuka [--out FILE]        a placement as a controller's work frame
    placement app --robot orthoglide --path rect.yaml          the workbench in the browser (:mod:`placement.cli.app`)

Exit codes: 0 success, 1 a physics check failed, 2 bad input or no feasible placement (the
message says what and where), 130 interrupted. ``--debug`` anywhere on the line shows the
traceback of an unexpected error instead of its one-line summary.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings

from placement.cli import app, assemble, calibrate, check, export, feed, place, robots, study
from placement.cli import map as map_command
from placement.cli.memory import keep_freed_memory
from placement.distribution import version
from placement.exceptions import PlacementError

SUBCOMMANDS = {"robots": robots, "check": check, "map": map_command, "feed": feed, "calibrate": calibrate,
               "assemble": assemble, "study": study, "export": export, "app": app}


def build_command_parser() -> argparse.ArgumentParser:
    """The parser of the subcommands."""
    parser = argparse.ArgumentParser(prog="placement")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in SUBCOMMANDS.values():
        module.add_parser(commands)
    return parser


def main_parser() -> argparse.ArgumentParser:
    """The main job's parser, its help closing with every command in one line each, ``--version`` and ``--debug``."""
    parser = place.build_parser()
    commands = argparse.ArgumentParser(prog="placement").add_subparsers()
    for module in SUBCOMMANDS.values():
        module.add_parser(commands)
    lines = [f"  {action.dest:<10s} {action.help}" for action in commands._choices_actions]
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.epilog = "\n".join(["commands (placement COMMAND --help for each):", *lines, "",
                                "  --version  print the version and exit",
                                "  --debug    anywhere on the line: the traceback of an unexpected error instead of "
                                "its one-line summary"])
    return parser


def _format_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                    line: str | None = None) -> str:
    """placement's own warnings as the command line's other ``warning: ...`` lines; others as Python shows them."""
    if category.__module__.startswith("placement."):
        return f"warning: {message}\n"
    return PYTHON_FORMAT(message, category, filename, lineno, line)


PYTHON_FORMAT = warnings.formatwarning


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code.

    The command line owns its process, so it tunes it: freed memory is kept for the next batch
    (:func:`placement.cli.memory.keep_freed_memory`), in this process and in the workers it forks. The library
    never changes a host program's process-wide state.
    """
    keep_freed_memory()
    warnings.formatwarning = _format_warning
    try:
        return _main(sys.argv[1:] if argv is None else list(argv))
    finally:
        warnings.formatwarning = PYTHON_FORMAT


def _main(argv: list[str]) -> int:
    """:func:`main` on the arguments ``argv``."""
    debug = "--debug" in argv
    argv = [arg for arg in argv if arg != "--debug"]
    if not debug:  # numpy's overflow warnings on absurd input: the results and limits say what went wrong
        warnings.simplefilter("ignore", RuntimeWarning)
    try:
        if argv and not argv[0].startswith("-") and argv[0] not in SUBCOMMANDS:
            print(f"error: unknown command '{argv[0][:40]}': expected one of {', '.join(SUBCOMMANDS)}, or options "
                  "for the main job (--robot, --path, ...; see --help)", file=sys.stderr)
            return 2
        if argv and argv[0] in SUBCOMMANDS:
            args = build_command_parser().parse_args(argv)
            return SUBCOMMANDS[args.command].run(args)
        if "--version" in argv:
            print(f"placement {version()}")
            return 0
        return place.run(main_parser().parse_args(argv))
    except PlacementError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader of the output stopped early (| head): not an error of the command
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # the exit's flush has nowhere to fail
        return 141  # as a shell reports a command that SIGPIPE ended
    except OSError as error:  # a file could not be written after all (disk full, ...)
        print(f"error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as error:  # the last resort: a one-line message, never a traceback by default
        if debug:
            raise
        text = " ".join(str(error).split())[:300]
        print(f"error: unexpected {type(error).__name__}: {text} (run again with --debug to see where)",
              file=sys.stderr)
        return 2
