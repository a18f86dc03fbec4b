"""--lock JOINT=VALUE and --knots N: hold joints of any robot, and set the knots of a redundant robot's profiles; a
robot whose placement variables --free, --fix or --at name ``spin`` gets its tool's spin as one."""

from __future__ import annotations

import argparse

import numpy as np

from placement.cli.exceptions import UsageError
from placement.placing.profiles import SPIN
from placement.robot.formats import DescriptionOptions
from placement.robot.model import Robot
from placement.robot.sidecar import MAX_KNOTS
from placement.workshop.load import edit_redundancy

PRISMATIC_SHORTNAMES = ("JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned")


def add_redundancy_options(options: argparse.ArgumentParser) -> None:
    """Add --lock and --knots to a parser."""
    options.add_argument("--lock", action="append", default=[], metavar="JOINT=VALUE",
                         help="hold a joint at a value (deg, or mm for a prismatic joint, unless it ends in rad or m; "
                              "repeatable), as the sidecar's locked_joints would: e.g. --lock panda_joint3=0 gives "
                              "the six-axis Panda")
    options.add_argument("--knots", type=int, default=None, metavar="N",
                         help=f"knots of each redundant joint's profile along the path (1 to {MAX_KNOTS}; 1: a "
                              "constant; default: the sidecar's redundancy.knots); the knots are placement variables "
                              "JOINT@K, searched, given to --at and --fix in deg (mm for a prismatic joint such as a "
                              "track)")


def apply_redundancy_options(robot: Robot, args: argparse.Namespace, options: DescriptionOptions) -> Robot:
    """The robot with the --lock joints held and --knots knots (the robot itself without either).

    Raises:
        UsageError: A --lock that is not JOINT=VALUE with a number, or --knots out of range or for a robot without
            redundant joints.
    """
    texts, knots = getattr(args, "lock", None) or [], getattr(args, "knots", None)
    spin = not robot.tool_spin and _names_spin(args)
    if not texts and knots is None and not spin:
        return robot
    if knots is not None and not 1 <= knots <= MAX_KNOTS:
        raise UsageError(f"--knots: expected a whole number from 1 to {MAX_KNOTS}, got {knots}")
    locks = {name: value for name, value in (_lock(robot, text) for text in texts)}
    if knots is not None and not [name for name in robot.redundant_joints if name not in locks]:
        raise UsageError(f"--knots: robot '{robot.name}' has no redundant joint left to profile (its sidecar's "
                         "redundancy.joints, less the --lock ones)")
    return edit_redundancy(robot, locks, knots, spin=spin, allow_massless=bool(getattr(args, "allow_massless", False)),
                           options=options)


def _names_spin(args: argparse.Namespace) -> bool:
    """Whether --free, --fix or --at names the variable ``spin``."""
    texts = [getattr(args, option, None) or "" for option in ("free", "fix", "at")]
    return any(item.partition("=")[0].strip() == SPIN for text in texts for item in text.split(","))


def _lock(robot: Robot, text: str) -> tuple[str, float]:
    """'panda_joint3=0' -> (joint, value in m or rad)."""
    name, equals, raw = (part.strip() for part in text.partition("="))
    if not equals or not name or not raw:
        raise UsageError(f"--lock: expected JOINT=VALUE, e.g. --lock panda_joint3=0, got '{text[:60]}'")
    model = robot.model
    if not model.existJointName(name) or model.getJointId(name) == 0:
        movable = ", ".join(list(model.names)[1:])
        raise UsageError(f"--lock: robot '{robot.name}' has no movable joint '{name[:40]}'; expected one of {movable}")
    prismatic = model.joints[model.getJointId(name)].shortname() in PRISMATIC_SHORTNAMES
    units = {"mm": 1e-3, "m": 1.0} if prismatic else {"deg": np.pi / 180, "rad": 1.0}
    unit = next((u for u in sorted(units, key=len, reverse=True) if raw.endswith(u)), None)
    try:
        value = float(raw[: -len(unit)] if unit else raw) * units[unit or ("mm" if prismatic else "deg")]
    except ValueError:
        raise UsageError(f"--lock: '{raw[:40]}' is not a number for {name}") from None
    if not np.isfinite(value):
        raise UsageError(f"--lock: {name} must be a finite number, got '{raw[:40]}'")
    return name, value
