"""The 'robots' command: the robots known by name, built-in and installed, without loading them."""

from __future__ import annotations

import argparse

from placement.workshop.catalog import ERD_FORM, robot_description, robot_names


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'robots' subcommand (no options)."""
    commands.add_parser("robots", help="list the robots known by name")


def run(args: argparse.Namespace) -> int:
    """Print one line per robot: its name and the description in its sidecar; then the erd: form."""
    for name in robot_names():
        print(f"{name:<14s} {robot_description(name)}")
    print(f"{ERD_FORM + 'NAME':<14s} any serial arm of example-robot-data, with --tool FRAME (drives and workspace "
          "estimated)")
    return 0
