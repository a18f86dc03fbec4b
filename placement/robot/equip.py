"""A robot at work in a cell: the tool it carries there, and the cell it knows.

The tool's mass is mounted by :mod:`placement.robot.tool`; a cell's tool replaces the sidecar's.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from placement.cell.cell_file import Cell, ToolBody
from placement.robot.model import Robot
from placement.robot.tool import mount_tool, unmount_tool


def tool_of(robot: Robot, cell: Cell | None) -> tuple[ToolBody, Path] | None:
    """The tool body the robot carries, and the file that declares it: the cell's tool, else the sidecar's.

    A cell equips the robot for a job, so its tool replaces the one in the robot's sidecar.
    """
    if cell is not None and cell.tool is not None:
        return cell.tool, cell.path
    if robot.tool is not None:
        return robot.tool, robot.sidecar_path
    return None


def equip(robot: Robot, cell: Cell | None) -> Robot:
    """The robot at work in ``cell``: carrying the cell's tool instead of its sidecar's, and knowing its cell.

    A robot loaded from a sidecar with a ``tool`` already carries that tool's mass; a cell with a
    tool replaces it. The cell's distances then become a limit (:mod:`placement.limits.collision`).

    Args:
        robot: The robot, as loaded.
        cell: The cell (None: the robot as it is, without a cell).
    """
    if cell is None:
        return robot
    if cell.tool is not None:
        if robot.tool is not None:
            robot = unmount_tool(robot, robot.tool)
        robot = mount_tool(robot, cell.tool, cell.path)
    return dataclasses.replace(robot, cell=cell)
