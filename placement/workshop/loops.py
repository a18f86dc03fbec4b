"""Closed-loop robots given as a description file, their sidecar estimated: ``--robot FILE --tool FRAME``.

Two conventions say where a description's loops close, so that no hand-written ``robot.yaml`` is needed:

- an MJCF's ``<equality><connect>`` and ``<weld>`` (:mod:`placement.robot.mjcf`), its actuated joints those its
  actuators drive;
- a URDF exported by onshape-to-robot, whose links ``closing_NAME_1`` and ``closing_NAME_2`` must coincide (a
  point closure, :func:`placement.robot.urdf.closing_pairs`); the URDF does not say which joints are actuated, so
  they are estimated: the joints on the base link (a parallel mechanism's motors sit on its base), else the
  joints whose name does not contain ``passive``, provided they number the mechanism's degrees of freedom.

The rest is estimated as for a Gepetto ``robot.yaml`` (:mod:`placement.workshop.gepetto`), each estimate marked EST
under ``sources``: the drives from the effort and speed bounds (:func:`placement.workshop.gepetto.estimated_drive`;
an MJCF's speed, which it never gives, ``JOINT_SPEED_RAD_S`` or ``JOINT_SPEED_M_S``; its armature the rotor's
inertia through the gear and its damping and friction loss the drive's friction), a position task for ``--tool``,
gravity along the base's -z, the reference configuration the description's zero posture (where an MJCF's loops
close by definition), else the loops closed there by :func:`placement.workshop.assemble.assemble`, the joints that
spin freely locked (:func:`placement.workshop.assemble.internal_freedoms`), and the workspace from what the
actuators reach (:func:`placement.workshop.gepetto.estimated_workspace`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
from pydantic import ValidationError

from placement.exceptions import listed
from placement.robot.build import PRISMATIC_JOINTS
from placement.robot.closures import closure_residuals
from placement.robot.exceptions import ExampleRobotError
from placement.robot.mjcf import MjcfJoint
from placement.robot.sidecar import Sidecar
from placement.robot.tool import find_frame
from placement.robot.urdf import urdf_limits_missing
from placement.workshop.assemble import CLOSED_TOLERANCE, assemble, internal_freedoms, reference_values
from placement.workshop.gepetto import GRAVITY_M_S2, estimated_drive, estimated_workspace
from placement.workshop.load import robot_from_sidecar

JOINT_SPEED_RAD_S = np.pi  # a joint speed where an MJCF gives none: 180 deg/s, a UR's rated speed
JOINT_SPEED_M_S = 0.5  # a prismatic joint's where an MJCF gives none
PASSIVE = "passive"  # onshape-to-robot exports name the joints no motor drives so, by habit


@dataclass(frozen=True)
class LoopDescription:
    """What a description file says of a closed-loop robot.

    Attributes:
        kind: "MJCF" or "URDF", for messages and sources.
        model: Its model (the loops' frames in it), effort and speed bounds 0 where it gives none.
        closures: The sidecar's ``closures`` entries (name, type, frames).
        actuated: The actuated joints, in order.
        actuated_from: Where ``actuated`` comes from, a sources entry ("DERIVED: ..." or "EST: ...").
        joints: An MJCF's joints' armature and friction, by name (None for a URDF).
        start: The joints not at 0 in the posture the file places its bodies in (an MJCF's qpos0), m or rad.
    """

    kind: str
    model: pin.Model
    closures: list[dict[str, Any]]
    actuated: list[str]
    actuated_from: str
    joints: dict[str, MjcfJoint] | None = None
    start: dict[str, float] = field(default_factory=dict)


def loop_sidecar(path: Path, tool: str | None, description: LoopDescription) -> Sidecar:
    """The estimated sidecar of a closed-loop robot described by ``path``, ``tool`` following the path (rules: module
    docstring).

    Raises:
        ExampleRobotError: No tool or an unknown one, no actuator, or a joint whose drive cannot be estimated.
        RobotFileError, AssemblyError: The loops do not close, or the actuators do not determine the mechanism.
    """
    model = description.model
    if tool is None or find_frame(model, tool) is None:
        frames = [f.name for f in model.frames if f.type in (pin.FrameType.BODY, pin.FrameType.OP_FRAME)]
        said = f"has no frame '{tool[:40]}'" if tool is not None else "needs --tool FRAME, the frame that follows the path"
        raise ExampleRobotError(f"{path}: {said}; its links and frames: {', '.join(frames)}")
    if not description.actuated:
        raise ExampleRobotError(f"{path}: the {description.kind} names no actuated joint; write a sidecar "
                                "(docs/adding_a_robot.md)")
    sources = {"closures": f"DERIVED: the {description.kind}'s loops", "actuators": description.actuated_from,
               "gravity_m_s2": "EST: the description's -z is down",
               "end_effector": "EST: --tool, a position task"}
    document: dict[str, Any] = {
        "name": description_name(path), "urdf": str(path),
        "description": f"{path.name}, tool {tool}: closed loops, drives and workspace estimated",
        "gravity_m_s2": list(GRAVITY_M_S2), "end_effector": {"frame": tool, "task": "position"},
        "closures": description.closures, "actuators": [], "drives": {}, "sources": sources,
        "reference_configuration": dict(description.start)}
    _refuse_unbounded(path, description)
    for i, joint in enumerate(description.actuated):
        _actuator(path, description, i, joint, document)
    robot = robot_from_sidecar(path, _validated(path, document), check_closures=False)
    data = robot.model.createData()
    if np.abs(closure_residuals(robot, data, robot.reference_q)).max(initial=0.0) < CLOSED_TOLERANCE:
        q, reference = robot.reference_q, dict(description.start)
        sources["reference_configuration"] = ("DERIVED: the posture the description places its bodies in, where its "
                                              "loops close")
    else:
        assembly = assemble(robot)
        q, reference = assembly.q, reference_values(robot, assembly)
        sources["reference_configuration"] = ("DERIVED: the loops closed by placement's solver from the posture the "
                                              "description places its bodies in")
    locks = internal_freedoms(robot, q)
    document["reference_configuration"] = {name: value for name, value in reference.items() if name not in locks}
    if locks:
        document["locked_joints"] = locks
        sources["locked_joints"] = "EST: joints that spin freely with the actuators held, locked where they stand"
    robot = robot_from_sidecar(path, _validated(path, document))
    document.update(estimated_workspace(robot, sources))
    return _validated(path, document)


def description_name(path: Path) -> str:
    """A robot's name from its description file: the file's stem, or its folder's name for a file called ``robot``
    (as onshape-to-robot and Gepetto write them)."""
    stem = path.name.removesuffix(path.suffix).removesuffix(".urdf")
    return (path.resolve().parent.name if stem == "robot" else stem)[:80] or "robot"


def _refuse_unbounded(path: Path, description: LoopDescription) -> None:
    """Refuse actuated joints whose effort nothing bounds, naming every one, and where their bound goes.

    Raises:
        ExampleRobotError: Some actuated joint has no effort bound (its drive cannot be estimated).
    """
    model = description.model
    unbounded = [joint for joint in description.actuated if model.existJointName(joint)
                 and not 0 < model.effortLimit[model.joints[model.getJointId(joint)].idx_v] < np.inf]
    if not unbounded:
        return
    where = ("(onshape-to-robot's exports give their position actuators a kp only) or give each actuator a forcerange "
             "in a copy of the file" if description.kind == "MJCF" else "or give each joint <limit effort=...> in a "
             "copy of the file")
    raise ExampleRobotError(f"{path}: nothing bounds the effort of actuated joint(s) {listed(unbounded, 8)}, so their "
                            f"drives cannot be estimated: give each its servo's peak torque (N m; N for a sliding "
                            f"joint) with --effort JOINT=VALUE, e.g. --effort {unbounded[0]}=1.5 {where}; or write a "
                            "sidecar (docs/adding_a_robot.md)")


def _actuator(path: Path, description: LoopDescription, i: int, joint: str, document: dict[str, Any]) -> None:
    """Add actuator ``i`` and its estimated drive to ``document`` (rules: module docstring)."""
    model, sources = description.model, document["sources"]
    if not model.existJointName(joint):
        raise ExampleRobotError(f"{path}: actuated joint '{joint}' is not a movable joint of the model")
    j = model.getJointId(joint)
    v, prismatic = model.joints[j].idx_v, model.joints[j].shortname() in PRISMATIC_JOINTS
    effort, speed = float(model.effortLimit[v]), float(model.velocityLimit[v])
    name = joint.replace(".", "_")
    actuator: dict[str, Any] = {"joint": joint, "drive": name}
    if not 0 < speed < np.inf:
        speed = JOINT_SPEED_M_S if prismatic else JOINT_SPEED_RAD_S
        actuator["velocity_max"] = speed
        sources[f"actuators.{i}.velocity_max"] = f"EST: the {description.kind} gives no speed limit; a typical joint speed"
    if urdf_limits_missing(model, j) and not prismatic:
        actuator.update(position_min=-np.pi, position_max=np.pi)
        for field in ("position_min", "position_max"):
            sources[f"actuators.{i}.{field}"] = f"EST: the {description.kind} gives no limits; a full turn"
    drive, text = estimated_drive(effort, speed, prismatic, origin=f"the {description.kind}'s")
    given = description.joints.get(joint) if description.joints is not None else None
    if given is not None and given.armature > 0:
        ratio = (2 * np.pi / drive["transmission"]["lead_m"]) if prismatic else drive["transmission"]["ratio"]
        drive["motor"]["rotor_inertia_kg_m2"] = given.armature / ratio**2
        text += f"; rotor inertia DERIVED from the MJCF's armature {given.armature:g}"
    if given is not None and (given.frictionloss > 0 or given.damping > 0):
        drive["friction"] = {"coulomb": given.frictionloss, "viscous": given.damping}
        sources[f"drives.{name}.friction"] = (f"DERIVED: the MJCF's joint frictionloss {given.frictionloss:g} "
                                              f"(Coulomb) and damping {given.damping:g} (viscous)")
    document["actuators"].append(actuator)
    document["drives"][name] = drive
    sources[f"drives.{name}.motor"] = f"EST: {text}"
    sources[f"drives.{name}.transmission"] = f"EST: {text.split(',')[0]}, to reach the joint's speed"


def _validated(path: Path, document: dict[str, Any]) -> Sidecar:
    try:
        return Sidecar.model_validate(document)
    except ValidationError as error:
        problem = error.errors()[0]
        raise ExampleRobotError(f"{path}: cannot estimate {'.'.join(map(str, problem['loc']))}: {problem['msg']}; "
                                "write a sidecar (docs/adding_a_robot.md)") from None
