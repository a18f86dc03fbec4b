"""Plausibility rules: inputs that are valid but whose size suggests a unit mistake.

Each rule returns warnings (one line each, naming the field and the likely unit); the caller
decides whether to print them or refuse the input (the command line's ``--strict``).
"""

from __future__ import annotations

import numpy as np

from placement.path.path_file import MM_PER_MIN
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot

SPAN_FOR_MM = 0.1  # m: a robot whose workspace spans this much is read in mm; a length under 1 mm there is odd


def feed_warnings(robot: Robot, path: ToolPath, field: str = "feed_m_s") -> list[str]:
    """A feed above every prismatic joint's top speed (m/s), which no placement can run: a value in mm/min?

    Args:
        robot: The robot (only its prismatic joints' top speeds are compared: the tool of a
            Cartesian or parallel machine moves at about their speed).
        path: The path, at its feed.
        field: How the feed was given, for the message.

    Returns:
        The warnings (empty when the feed is plausible, or the robot has no prismatic actuator).
    """
    speeds = [a.velocity_max for a in robot.actuators if a.prismatic]
    if not speeds or path.feed_m_s <= max(speeds):
        return []
    feed, top = path.feed_m_s, max(speeds)
    return [f"{field} {feed:g} m/s is above every joint's top speed ({top:g} m/s): a value in mm/min? "
            f"{feed:g} mm/min = {feed * MM_PER_MIN:.4g} m/s"]


def length_warnings(robot: Robot, option: str, unsuffixed_mm: dict[str, float]) -> list[str]:
    """Lengths read in mm (given without a unit) that are under 1 mm on a robot whose workspace spans at least
    SPAN_FOR_MM: metres typed without ``m``?

    Args:
        robot: The robot (its workspace box's largest side is its span; none, no warning).
        option: The option or field the values come from, for the message.
        unsuffixed_mm: The lengths given without a unit, by placement variable, in mm.

    Returns:
        One warning per suspicious value.
    """
    workspace = robot.workspace
    if workspace is None:
        return []
    span = float(np.max(np.subtract(workspace.max_m, workspace.min_m)))
    if span < SPAN_FOR_MM:
        return []
    return [f"{option} {name}={value:g} is read as {value:g} mm, but {robot.name}'s workspace spans {span * 1e3:.0f} mm: "
            f"metres? write {name}={value:g}m ({value * 1e3:g} mm)"
            for name, value in unsuffixed_mm.items() if 0 < abs(value) < 1]
