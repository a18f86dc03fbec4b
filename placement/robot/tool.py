"""The tool tip: a frame fixed at an offset from a frame of the URDF, added to the Pinocchio model.

A sidecar's ``end_effector.offset_m`` and ``end_effector.rpy_rad`` place a tool tip on any frame
(a flange, a wrist link) without editing the URDF: the tip becomes a new frame of the model, on
the same joint as the named frame, and it is the tip that follows the path.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

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
