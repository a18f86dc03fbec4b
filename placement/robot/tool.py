"""The tool: its tip, a frame added to the Pinocchio model, and its body, a mass the robot carries.

A sidecar's ``end_effector.offset_m`` and ``end_effector.rpy_rad`` place a tool tip on any frame
(a flange, a wrist link) without editing the URDF: the tip becomes a new frame of the model, on
the same joint as the named frame, and it is the tip that follows the path.

A tool body (a spindle: a sidecar's or a cell's ``tool``) is rigid with its mount frame, so its
inertia adds to the body of that frame's parent joint: inverse dynamics then includes the tool's
weight and inertial wrench, exactly as if the URDF had the tool as a fixed link.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pinocchio as pin

from placement.cell.cell_file import Posed, ToolBody
from placement.cell.exceptions import CellFileError
from placement.exceptions import InputFileError
from placement.robot.exceptions import RobotFileError
from placement.robot.model import Robot
from placement.robot.sidecar import EndEffector

TIP_SUFFIX = "_tool_tip"


def tool_offset(end_effector: EndEffector) -> pin.SE3 | None:
    """The tool tip's placement in the named frame, or None when the sidecar gives no offset.

    Args:
        end_effector: The sidecar's end-effector section: ``offset_m`` (m, in the named frame) and
            ``rpy_rad`` (roll, pitch, yaw about fixed x, y, z, rad).

    Returns:
        The rigid transform from the named frame to the tip (m).
    """
    if end_effector.offset_m is None and end_effector.rpy_rad is None:
        return None
    roll, pitch, yaw = end_effector.rpy_rad or (0.0, 0.0, 0.0)
    return pin.SE3(pin.rpy.rpyToMatrix(roll, pitch, yaw), np.array(end_effector.offset_m or (0.0, 0.0, 0.0)))


def add_tool_frame(model: pin.Model, end_effector: EndEffector, frame_id: int) -> int:
    """Add the tool tip frame to ``model`` (in place) when the sidecar gives an offset.

    The tip is an operational frame on the named frame's parent joint, at the named frame's
    placement composed with the offset, called NAME_tool_tip (NAME_tool_tip_2, ... if taken).

    Args:
        model: The Pinocchio model (gains a frame).
        end_effector: The sidecar's end-effector section.
        frame_id: Id of the named frame (``end_effector.frame``).

    Returns:
        The id of the frame that follows the path: the tip's, else ``frame_id`` unchanged.
    """
    offset = tool_offset(end_effector)
    if offset is None:
        return frame_id
    base = model.frames[frame_id]
    name, count = f"{base.name}{TIP_SUFFIX}", 1
    while model.existFrame(name):
        count += 1
        name = f"{base.name}{TIP_SUFFIX}_{count}"
    tip = pin.Frame(name, base.parentJoint, frame_id, base.placement * offset, pin.FrameType.OP_FRAME)
    return int(model.addFrame(tip, False))


def find_frame(model: pin.Model, name: str) -> int | None:
    """The id of the frame called ``name``: a link first, then a fixed joint, then a joint (a URDF may give a
    link and a joint one name), then another frame (an MJCF's site); None if there is none."""
    for kind in (pin.FrameType.BODY, pin.FrameType.FIXED_JOINT, pin.FrameType.JOINT, pin.FrameType.OP_FRAME):
        if model.existFrame(name, kind):
            return int(model.getFrameId(name, kind))
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
    name = tool.frame if tool.frame is not None else robot.mount_frame
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
        The robot with the tool's mass, and following the path with the tool's tip when it has one
        (a new frame, TOOLNAME_tip); every other field is shared with ``robot``.

    Raises:
        InputFileError: The mount frame is unknown (see :func:`tool_mount`).
    """
    joint, joint_M_tool = tool_mount(robot, tool, source if source is not None else robot.sidecar_path)
    model = pin.Model(robot.model)
    model.inertias[joint] = model.inertias[joint] + joint_M_tool.act(tool_inertia(tool))
    if tool.tip is None:
        return dataclasses.replace(robot, model=model)
    name = tool.frame if tool.frame is not None else robot.mount_frame
    mount = find_frame(model, name)
    tip = pin.Frame(f"{tool.name}_tip", joint, mount, joint_M_tool * pose_placement(tool.tip), pin.FrameType.OP_FRAME)
    return dataclasses.replace(robot, model=model, end_effector_frame_id=int(model.addFrame(tip, False)))


def unmount_tool(robot: Robot, tool: ToolBody, source: Path | None = None) -> Robot:
    """A copy of the robot without the mass of a tool :func:`mount_tool` gave it (exact to rounding), following
    the path again with the frame it followed before the tool's tip."""
    joint, joint_M_tool = tool_mount(robot, tool, source if source is not None else robot.sidecar_path)
    model = pin.Model(robot.model)
    model.inertias[joint] = model.inertias[joint] - joint_M_tool.act(tool_inertia(tool))
    end_effector = robot.end_effector_frame_id
    if tool.tip is not None:
        end_effector = int(model.frames[end_effector].parentFrame)
    return dataclasses.replace(robot, model=model, end_effector_frame_id=end_effector)
