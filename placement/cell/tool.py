"""A tool body on the robot: where it is mounted, and a robot that carries its mass.

The tool is rigid with its mount frame, so its inertia adds to the body of that frame's parent
joint: inverse dynamics then includes the tool's weight and inertial wrench, exactly as if the URDF
had the tool as a fixed link.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pinocchio as pin

from placement.cell.schema import Cell, Posed, ToolBody
from placement.exceptions import CellFileError, InputFileError, RobotFileError
from placement.robot.load import find_frame
from placement.robot.model import Robot


def tool_of(robot: Robot, cell: Cell | None) -> tuple[ToolBody, Path] | None:
    """The tool body the robot carries, and the file that declares it: the cell's tool, else the sidecar's.

    A cell equips the robot for a job, so its tool replaces the one in the robot's sidecar.
    """
    if cell is not None and cell.tool is not None:
        return cell.tool, cell.path
    if robot.sidecar.tool is not None:
        return robot.sidecar.tool, robot.sidecar_path
    return None


def pose_placement(pose: Posed) -> pin.SE3:
    """The rigid transform of a pose (``xyz_m``, ``rpy_rad``): from the pose's frame to the enclosing one."""
    return pin.SE3(pin.rpy.rpyToMatrix(*pose.rpy_rad), np.array(pose.xyz_m, dtype=float))


def tool_mount(robot: Robot, tool: ToolBody, source: Path) -> tuple[int, pin.SE3]:
    """The joint that carries the tool, and the tool frame's placement in that joint's frame.

    Args:
        robot: The robot.
        tool: The tool body.
        source: The file that declares the tool (errors name it).

    Raises:
        InputFileError: The mount frame is not a frame of the robot (a CellFileError when ``source``
            is a cell file, a RobotFileError when it is the robot's sidecar).
    """
    name = tool.frame if tool.frame is not None else robot.sidecar.end_effector.frame
    frame_id = find_frame(robot.model, name)
    if frame_id is None:
        raise declaring_file_error(robot, source)(source, "tool.frame", f"no frame '{name[:80]}' in robot "
                                                  f"'{robot.name}' to mount the tool on (links and joints are frames)")
    frame = robot.model.frames[frame_id]
    return int(frame.parentJoint), frame.placement * pose_placement(tool)


def declaring_file_error(robot: Robot, source: Path) -> type[InputFileError]:
    """The error naming ``source``: a RobotFileError for the robot's sidecar, a CellFileError for a cell file."""
    return RobotFileError if source == robot.sidecar_path else CellFileError


def tool_inertia(tool: ToolBody) -> pin.Inertia:
    """The tool's spatial inertia in the tool frame (kg, m, kg·m²)."""
    return pin.Inertia(float(tool.mass_kg), np.array(tool.com_m, dtype=float), tool.inertia_matrix)


def mount_tool(robot: Robot, tool: ToolBody, source: Path | None = None) -> Robot:
    """A copy of the robot whose model carries the tool's inertia (the original is left unchanged).

    The tool's inertia, moved to its mount joint's frame, adds to that joint's body:
    ``model.inertias[joint] += joint_M_tool · inertia``.

    Args:
        robot: The robot.
        tool: The tool body (mount frame, pose, mass, centre of mass, inertia).
        source: The file that declares the tool, for errors (default: the robot's sidecar).

    Returns:
        The robot with the tool's mass; every other field is shared with ``robot``.

    Raises:
        InputFileError: The mount frame is unknown (see :func:`tool_mount`).
    """
    joint, joint_M_tool = tool_mount(robot, tool, source if source is not None else robot.sidecar_path)
    model = pin.Model(robot.model)
    model.inertias[joint] = model.inertias[joint] + joint_M_tool.act(tool_inertia(tool))
    return dataclasses.replace(robot, model=model)
