"""Robots as data: a URDF (spanning tree) and its sidecar built into a validated :class:`Robot`.

Building checks every name against the URDF, the physical sense of every number, that each loop
closure closes at the reference configuration, that the actuated joints are exactly the
mechanism's degrees of freedom, and that its physics is plausible (no moving link without inertia:
:mod:`placement.robot.plausibility`). Errors name the file and the field. The kinematics checks and the
tool's mounting follow in :func:`placement.workshop.load.robot_from_sidecar`, which
:func:`placement.workshop.load.load_robot` calls.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
from pydantic import BaseModel

from placement.robot.closures import closure_jacobian, closure_residuals
from placement.robot.exceptions import RobotFileError
from placement.robot.formats import SIDECAR_NAME, DescriptionOptions, is_gepetto
from placement.robot.mjcf import is_mjcf, mjcf_model, read_mjcf
from placement.robot.model import Actuator, Closure, Robot
from placement.robot.plausibility import check_plausible
from placement.robot.plugins import load_plugin, make_closed_form
from placement.robot.sidecar import Actuator as ActuatorSpec
from placement.robot.sidecar import Sidecar
from placement.robot.tool import add_tool_frame, find_frame
from placement.robot.urdf import UrdfContents, pinocchio_model, read_urdf, resolve_urdf, urdf_limits_missing
from placement.robot.xacro import expand_xacro, is_xacro

CLOSURE_TOLERANCE_M = 1e-6
PRISMATIC_JOINTS = ("JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned")
RENAMED_APART = "#joint"  # appended to a joint named as a link while Pinocchio reduces the model (a name no URDF gives)


def build_robot(path: Path, sidecar: Sidecar, *, check_closures: bool = True, allow_massless: bool = False,
                options: DescriptionOptions = DescriptionOptions()) -> Robot:
    """A robot from a validated sidecar held in memory (one generated from a URDF, say), before its kinematics
    are checked and its tool mounted (:func:`placement.workshop.load.robot_from_sidecar` does both).

    Args:
        path: Where the sidecar stands: its folder resolves a relative URDF, and errors name it.
        sidecar: The sidecar.
        check_closures: Whether the loops must close at the reference configuration (and the actuated
            joints parametrise the closed-loop motion); without, the robot is only fit for
            :mod:`placement.workshop.assemble` to close its loops, and its physics is not checked.
        allow_massless: Load a robot with moving links without inertia or actuated joints without an effort bound,
            with a warning (:func:`placement.robot.plausibility.check_plausible`); else it is refused.
        options: Package folders and xacro arguments beyond the sidecar's (the command line's).

    Raises:
        RobotFileError: The sidecar disagrees with its URDF, or the physics is implausible (the message names
            ``path`` and field).
    """
    package_paths = (*options.package_paths, *((path.parent / folder).resolve() for folder in sidecar.package_paths))
    urdf_path = resolve_urdf(path, sidecar.urdf)
    if is_xacro(urdf_path):
        urdf_path = expand_xacro(urdf_path, {**sidecar.xacro_args, **options.xacro_args}, package_paths, path, "urdf")
    full, urdf = _description(path, sidecar, urdf_path)
    model = _lock_joints(full, path, sidecar.locked_joints)
    plugin = load_plugin(path, sidecar.kinematics_plugin)
    model.gravity = pin.Motion(np.array(sidecar.gravity_m_s2), np.zeros(3))
    robot = Robot(
        name=sidecar.name,
        sidecar_path=path,
        urdf_path=urdf_path,
        model=model,
        closures=tuple(_closure(model, path, i, c.name, c.type, c.frames) for i, c in enumerate(sidecar.closures)),
        actuators=tuple(_actuator(model, path, sidecar, i, is_mjcf(urdf_path)) for i in range(len(sidecar.actuators))),
        end_effector_frame_id=add_tool_frame(model, sidecar.end_effector, _frame_id(
            model, path, "end_effector.frame", sidecar.end_effector.frame)),
        task=sidecar.end_effector.task,
        reference_q=_reference_q(model, path, sidecar.reference_configuration, sidecar.locked_joints),
        plugin=plugin,
        closed_form=make_closed_form(plugin, model, path),
        sidecar=sidecar,
        package_paths=package_paths,
    )
    for actuator in robot.actuators:
        model.armature[actuator.v_index] += actuator.reflected_inertia
    _check_joint_springs(path, sidecar, model)
    _check_link_springs(path, robot)
    _check_sources(path, sidecar, urdf.names)
    if check_closures:
        _check_closed_at_reference(robot)
        _check_mobility(robot)
        robot.massless_links = check_plausible(robot, urdf, allow_massless=allow_massless)
    return robot


def _description(path: Path, sidecar: Sidecar, description: Path) -> tuple[pin.Model, UrdfContents]:
    """The model of the description file (a URDF, or an MJCF by its suffix) and what loading reads of it, with the
    sidecar's ``links`` (a URDF's only: an MJCF's inertias are its ``<inertial>`` elements)."""
    if is_mjcf(description):
        if sidecar.links:
            name = next(iter(sidecar.links))
            raise RobotFileError(path, f"links.{name}", f"{description.name} is an MJCF: give body '{name}' its "
                                 "<inertial> there (mass, pos, fullinertia); the sidecar's links replace a URDF's")
        model = mjcf_model(description)
        return model, read_mjcf(description, model)
    urdf = read_urdf(description, sidecar.links)
    for name in sidecar.links:
        if name not in urdf.names["link"]:
            raise RobotFileError(path, f"links.{name}", f"no link '{name}' in {description.name}")
    return pinocchio_model(description, sidecar.links), urdf


def _lock_joints(model: pin.Model, path: Path, locked: dict[str, float]) -> pin.Model:
    """The model with the ``locked`` joints held at their values (a gripper's fingers, say)."""
    if not locked:
        return model
    q = pin.neutral(model)
    ids = []
    for name, value in locked.items():
        joint_id = _joint_id(model, path, f"locked_joints.{name}", name)
        low, high = model.lowerPositionLimit[model.joints[joint_id].idx_q], model.upperPositionLimit[model.joints[joint_id].idx_q]
        if not (low <= value <= high or urdf_limits_missing(model, joint_id)):
            raise RobotFileError(path, f"locked_joints.{name}", f"{value} is outside the joint's limits [{low}, {high}]")
        q[model.joints[joint_id].idx_q] = value
        ids.append(joint_id)
    try:
        return reduced_model(model, ids, q)
    except ValueError as error:
        raise RobotFileError(path, "locked_joints", str(error)) from None


def reduced_model(model: pin.Model, joint_ids: list[int], q: np.ndarray) -> pin.Model:
    """The model with joints ``joint_ids`` held at ``q`` (``pin.buildReducedModel``). Pinocchio needs the names of the
    frames it makes unique, which a description that gives a link (an MJCF's body) and a joint one name breaks (the
    SO-101's ``gripper``): such joints are renamed apart while it builds, and their names given back after.

    Raises:
        ValueError: Pinocchio refuses, with its reason.
    """
    frame_names = [frame.name for frame in model.frames]
    shared = {name for name in frame_names if frame_names.count(name) > 1}
    if not shared:
        return _reduced(model, joint_ids, q)
    apart = pin.Model(model)
    for j in range(1, apart.njoints):
        if apart.names[j] in shared:
            apart.names[j] += RENAMED_APART
    for i, frame in enumerate(apart.frames):
        if frame.type == pin.FrameType.JOINT and frame.name in shared:
            apart.frames[i].name = frame.name + RENAMED_APART
    reduced = _reduced(apart, joint_ids, q)
    for j in range(1, reduced.njoints):
        reduced.names[j] = reduced.names[j].removesuffix(RENAMED_APART)
    for i, frame in enumerate(reduced.frames):
        reduced.frames[i].name = frame.name.removesuffix(RENAMED_APART)
    return reduced


def _reduced(model: pin.Model, joint_ids: list[int], q: np.ndarray) -> pin.Model:
    """``pin.buildReducedModel``, its refusal a ValueError that says so."""
    try:
        return pin.buildReducedModel(model, joint_ids, q)
    except ValueError as error:
        raise ValueError(f"Pinocchio cannot hold these joints: {str(error)[:200]}") from None


def _frame_id(model: pin.Model, path: Path, field: str, name: str) -> int:
    """Frame id of a link (preferred) or joint called ``name``."""
    frame_id = find_frame(model, name)
    if frame_id is None:
        raise RobotFileError(path, field, f"no frame '{name}' in the URDF (links and joints are frames)")
    return frame_id


def _joint_id(model: pin.Model, path: Path, field: str, name: str, locked: dict[str, float] | None = None) -> int:
    if locked and name in locked:
        raise RobotFileError(path, field, f"joint '{name}' is locked (locked_joints): it cannot also move")
    if not model.existJointName(name):
        movable = [n for n in model.names[1:]]
        raise RobotFileError(path, field, f"no movable joint '{name}' in the URDF; movable joints: {movable}")
    joint_id = model.getJointId(name)
    if model.joints[joint_id].nv != 1 or model.joints[joint_id].nq != 1:
        raise RobotFileError(path, field, f"joint '{name}' must be revolute or prismatic (one coordinate)")
    return joint_id


def _closure(model: pin.Model, path: Path, i: int, name: str, kind: str, frames: tuple[str, str]) -> Closure:
    first, second = (_frame_id(model, path, f"closures.{i}.frames.{k}", f) for k, f in enumerate(frames))
    return Closure(name=name, kind=kind, frame_ids=(first, second))


def _actuator(model: pin.Model, path: Path, sidecar: Sidecar, i: int, mjcf: bool) -> Actuator:
    spec = sidecar.actuators[i]
    joint_id = _joint_id(model, path, f"actuators.{i}.joint", spec.joint, sidecar.locked_joints)
    q_index, v_index = model.joints[joint_id].idx_q, model.joints[joint_id].idx_v
    lower = spec.position_min if spec.position_min is not None else model.lowerPositionLimit[q_index]
    upper = spec.position_max if spec.position_max is not None else model.upperPositionLimit[q_index]
    velocity = spec.velocity_max if spec.velocity_max is not None else model.velocityLimit[v_index]
    missing = [f"actuators.{i}.{field}" for field in ("position_min", "position_max") if getattr(spec, field) is None]
    if missing and urdf_limits_missing(model, joint_id):
        unit = "m" if model.joints[joint_id].shortname() in PRISMATIC_JOINTS else "rad"
        raise RobotFileError(path, missing[0], f"joint '{spec.joint}' has no limits in the URDF: set "
                             f"{' and '.join(missing)} in the sidecar ({unit})")
    if not lower < upper:
        raise RobotFileError(path, f"actuators.{i}.position_min", f"must be below position_max ({lower} >= {upper})")
    if not velocity > 0:
        unit = "m/s" if model.joints[joint_id].shortname() in PRISMATIC_JOINTS else "rad/s"
        given = ("the MJCF gives no speed limits" if mjcf else f"joint '{spec.joint}' has velocity limit {velocity:g} "
                 f"in the URDF (urdf.joint.{spec.joint}.limit.velocity)")
        raise RobotFileError(path, f"actuators.{i}.velocity_max", f"{given}: set actuators.{i}.velocity_max in "
                             f"the sidecar ({unit}), expected > 0")
    drive = sidecar.drives[spec.drive] if spec.drive else None
    return Actuator(joint=spec.joint, q_index=q_index, v_index=v_index, position_min=float(lower),
                    position_max=float(upper), velocity_max=float(velocity), drive=drive,
                    drive_name=spec.drive if drive else None,
                    acceleration_max=spec.acceleration_max,
                    reflected_inertia=drive.reflected_inertia if drive else 0.0,
                    prismatic=model.joints[joint_id].shortname() in PRISMATIC_JOINTS,
                    own_stiffness=spec.stiffness)


def _check_joint_springs(path: Path, sidecar: Sidecar, model: pin.Model) -> None:
    """Each spring of ``joint_springs`` names a passive joint of the model (an actuator's is its ``stiffness``)."""
    actuated = {spec.joint: i for i, spec in enumerate(sidecar.actuators)}
    for name in sidecar.joint_springs:
        _joint_id(model, path, f"joint_springs.{name}", name, sidecar.locked_joints)
        if name in actuated:
            raise RobotFileError(path, f"joint_springs.{name}", f"joint '{name}' is actuated: give its stiffness as "
                                 f"actuators.{actuated[name]}.stiffness")


def _check_link_springs(path: Path, robot: Robot) -> None:
    """Each spring of ``link_springs`` names a link of the model outside every closed loop."""
    model = robot.model
    for name in robot.sidecar.link_springs:
        field = f"link_springs.{name}"
        if not model.existBodyName(name):
            raise RobotFileError(path, field, f"no link '{name}' in the URDF")
        joint = model.frames[model.getBodyId(name)].parentJoint
        for closure in robot.closures:  # a loop wholly beyond the link moves with it; one it closes on is not covered
            beyond = [joint in model.supports[model.frames[f].parentJoint] for f in closure.frame_ids]
            if any(beyond) and not all(beyond):
                raise RobotFileError(path, field, f"link '{name}' is in the closed loop {closure.name}: a link spring "
                                     "is covered outside loops only; give the loop's compliance as joint_springs on "
                                     "its passive joints")


def _reference_q(model: pin.Model, path: Path, values: dict[str, float], locked: dict[str, float]) -> np.ndarray:
    q = pin.neutral(model)
    for name, value in values.items():
        joint_id = _joint_id(model, path, f"reference_configuration.{name}", name, locked)
        q[model.joints[joint_id].idx_q] = value
    return q


def _check_sources(path: Path, sidecar: Sidecar, names: dict[str, set[str]]) -> None:
    """Every key under ``sources`` must name a sidecar field or a URDF link or joint (``names`` by kind)."""
    for key in sidecar.sources:
        parts = key.split(".")
        if len(parts) == 2 and parts[0] == "actuators" and parts[1] in ActuatorSpec.model_fields:
            continue  # one source for that field of every actuator
        if parts[0] == "urdf":
            if len(parts) < 3 or parts[1] not in names or parts[2] not in names[parts[1]]:
                raise RobotFileError(path, f"sources.{key}", "expected 'urdf.link.NAME...' or 'urdf.joint.NAME...' "
                                     "naming a link or joint of the URDF")
            continue
        node: Any = sidecar
        for part in parts:
            if isinstance(node, (list, tuple)) and part.isdigit() and int(part) < len(node):
                node = node[int(part)]
            elif isinstance(node, dict) and part in node:
                node = node[part]
            elif isinstance(node, BaseModel) and part in type(node).model_fields:
                node = getattr(node, part)
            else:
                raise RobotFileError(path, f"sources.{key}", "names no field of this sidecar (use dotted paths "
                                     "such as drives.NAME.motor.resistance_ohm, or urdf.link.NAME)")


def _check_closed_at_reference(robot: Robot) -> None:
    data = robot.model.createData()
    residuals = closure_residuals(robot, data, robot.reference_q)
    start = 0
    for i, closure in enumerate(robot.closures):
        gap = float(np.linalg.norm(residuals[start:start + closure.dimension]))
        start += closure.dimension
        if gap > CLOSURE_TOLERANCE_M:
            field, fix = f"closures.{i}", f"'python -m placement assemble {robot.sidecar_path}' closes the loops"
            if is_gepetto(robot.sidecar_path):
                folder = robot.sidecar_path.parent
                field, fix = f"closed_loop.{i}", (f"'python -m placement assemble {folder} --write' closes the loops "
                                                  f"and writes them to {folder / SIDECAR_NAME}")
            raise RobotFileError(robot.sidecar_path, field, f"closure '{closure.name}' does not close at "
                                 f"reference_configuration: gap {gap:.3g} (m and rad), expected below "
                                 f"{CLOSURE_TOLERANCE_M}; {fix}")


def _check_mobility(robot: Robot) -> None:
    """The actuated joints must parametrise the closed-loop motion exactly."""
    data = robot.model.createData()
    jacobian = closure_jacobian(robot, data, robot.reference_q)
    nv = robot.model.nv
    rank = np.linalg.matrix_rank(jacobian, tol=1e-9) if jacobian.size else 0
    passive = np.setdiff1d(np.arange(nv), robot.actuated_v_indices)
    passive_rank = np.linalg.matrix_rank(jacobian[:, passive], tol=1e-9) if jacobian.size else 0
    if passive_rank != len(passive):
        raise RobotFileError(robot.sidecar_path, "actuators", _free_joints_text(robot, jacobian, nv - rank))
    if nv - rank != len(robot.actuators):
        raise RobotFileError(robot.sidecar_path, "actuators",
                             f"the closures leave {nv - rank} degree(s) of freedom at reference_configuration, "
                             f"and the {len(robot.actuators)} actuated joint(s) must determine all "
                             f"{len(passive)} passive ones")
    needed, planar = _task_freedoms(robot)
    needed += _check_redundancy(robot)
    if not robot.closures and len(robot.actuators) < needed:
        hint = ("use a position task or unlock joints" if robot.task == "pose" else
                "unlock joints" if planar else "unlock joints, or declare the plane of a planar arm (placement.plane)")
        raise RobotFileError(robot.sidecar_path, "end_effector.task",
                             f"a serial robot with {len(robot.actuators)} actuated joints cannot follow a {planar}"
                             f"{robot.task} task of {needed}: {hint}")
    if len(robot.actuators) > needed:
        raise RobotFileError(robot.sidecar_path, "locked_joints",
                             f"the robot has {len(robot.actuators)} degrees of freedom for a {planar}{robot.task} task "
                             f"of {needed}: lock {len(robot.actuators) - needed} joint(s) so that the path determines "
                             "the motion, or name them under redundancy.joints so that the search profiles them")
    if planar and not robot.closures:
        _check_moves_in_plane(robot)


def _check_redundancy(robot: Robot) -> int:
    """The redundant joints (``redundancy.joints``), which the task's rows prescribe too: how many, each an
    actuated joint of a robot without closures, named once."""
    names = robot.redundant_joints
    actuated = {actuator.joint for actuator in robot.actuators}
    for i, name in enumerate(names):
        if name not in actuated:
            raise RobotFileError(robot.sidecar_path, f"redundancy.joints.{i}", f"'{name}' is not an actuated joint: "
                                 f"expected one of {', '.join(sorted(actuated))}")
        if names.count(name) > 1:
            raise RobotFileError(robot.sidecar_path, f"redundancy.joints.{i}", f"'{name}' is named twice")
    if robot.tool_spin and robot.task != "pose":
        raise RobotFileError(robot.sidecar_path, "redundancy.spin", "the tool's spin is a variable of pose tasks only")
    if names and robot.closures:
        raise RobotFileError(robot.sidecar_path, "redundancy", "redundant joints are resolved on serial robots only "
                             "(this one has closures): lock them under locked_joints")
    _check_workpiece_frame(robot)
    return len(names)


def _check_workpiece_frame(robot: Robot) -> None:
    """The workpiece's frame (``workpiece_frame``) is a frame of the model on a chain of profiled joints only: the
    path then fixes the tool relative to it, and the profiles fix where it is."""
    name = robot.workpiece_frame
    if name is None:
        return
    model = robot.model
    if not model.existFrame(name) or name == robot.mount_frame:
        raise RobotFileError(robot.sidecar_path, "workpiece_frame", f"'{name}' is not a frame of the model apart from "
                             "the end effector's: expected the link or fixed joint the workpiece is clamped to")
    if robot.closures:
        raise RobotFileError(robot.sidecar_path, "workpiece_frame", "a workpiece on a chain needs a serial robot (this "
                             "one has closures)")
    moving = [model.names[j] for j in list(model.supports[model.frames[model.getFrameId(name)].parentJoint])[1:]]
    unprofiled = [joint for joint in moving if joint not in robot.redundant_joints]
    if unprofiled:
        raise RobotFileError(robot.sidecar_path, "workpiece_frame", f"'{name}' is moved by {', '.join(unprofiled)}, "
                             "which redundancy.joints does not profile: name them there, or lock them")


def _task_freedoms(robot: Robot) -> tuple[int, str]:
    """The degrees of freedom the task asks for, and "planar " when a declared plane makes it 2 (else "").

    A position task in a declared plane (``placement.plane``) asks for the 2 in-plane coordinates.
    """
    if robot.task == "position" and robot.plane is not None:
        return 2, "planar "
    return robot.task_dimension, ""


def _check_moves_in_plane(robot: Robot) -> None:
    """A serial arm declaring a plane must move its end effector in that plane at the reference configuration."""
    data = robot.model.createData()
    jacobian = pin.computeFrameJacobian(robot.model, data, robot.reference_q, robot.end_effector_frame_id,
                                        pin.LOCAL_WORLD_ALIGNED)[:3]
    plane = robot.plane
    assert plane is not None  # _task_freedoms found it
    normal = np.asarray(plane.normal) / np.linalg.norm(plane.normal)
    off_plane = float(np.abs(normal @ jacobian).max(initial=0.0))
    scale = float(np.abs(jacobian).max(initial=0.0))
    if off_plane > 1e-6 * scale or np.linalg.matrix_rank(jacobian, tol=1e-9 * max(scale, 1e-300)) < 2:
        raise RobotFileError(robot.sidecar_path, "placement.plane",
                             f"the end effector of this planar arm must move in the plane of normal "
                             f"[{', '.join(f'{c:g}' for c in plane.normal)}] at reference_configuration, along 2 "
                             f"independent directions; its velocity leaves the plane by up to {off_plane:.3g} m/s per "
                             "unit joint rate: give a normal along the arm's revolute joint axes, or a "
                             "reference_configuration away from a singular posture")


def joints_to_lock(robot: Robot, jacobian: np.ndarray) -> tuple[list[str], list[str]]:
    """The passive joints the actuated ones leave free, and one joint of each group that moves together.

    The joints that move with the actuators held are the passive ones with a part in the null
    space of the passive closure Jacobian. Going through them in model order, a joint is proposed
    for ``locked_joints`` when locking it (dropping its column) lowers that null space's
    dimension, until none is left: one joint of each group of joints that move together.

    Args:
        robot: The robot.
        jacobian: Its closure Jacobian (closure rows, nv) at the configuration considered.

    Returns:
        The names of the free passive joints, and of those to lock, both in model order (both
        empty when the actuated joints determine the passive ones).
    """
    passive = np.setdiff1d(np.arange(robot.model.nv), robot.actuated_v_indices)
    columns = jacobian[:, passive]
    rank = int(np.linalg.matrix_rank(columns, tol=1e-9)) if columns.size else 0
    null_basis = np.linalg.svd(columns)[2][rank:].T if columns.size else np.eye(len(passive))
    moving = [int(v) for v, row in zip(passive, null_basis) if np.abs(row).max(initial=0.0) > 1e-9]
    kept, locked = list(passive), []
    for v in moving:
        if _nullity(jacobian[:, [k for k in kept if k != v]]) < _nullity(jacobian[:, kept]):
            kept.remove(v)
            locked.append(v)
        if _nullity(jacobian[:, kept]) == 0:
            break
    return ([_joint_name_of_velocity(robot.model, v) for v in moving],
            [_joint_name_of_velocity(robot.model, v) for v in locked])


def _free_joints_text(robot: Robot, jacobian: np.ndarray, freedoms: int) -> str:
    """Why the actuated joints leave passive joints free: which ones move, and which to lock (:func:`joints_to_lock`)."""
    moving, locked = joints_to_lock(robot, jacobian)
    shown = ", ".join(moving[:12]) + (", ..." if len(moving) > 12 else "")
    proposal = ", ".join(f"{name}: {_reference_text(robot, name)}" for name in locked)
    return (f"the closures leave {freedoms} degree(s) of freedom at reference_configuration for the "
            f"{len(robot.actuators)} actuated joint(s): with these held, joint(s) {shown} still move (a rod spinning "
            f"about its own axis, say); actuate or lock one joint of each group that moves together, e.g. add to the "
            f"sidecar's locked_joints: {{{proposal}}} (the values at reference_configuration); 'placement assemble "
            "--write' locks them for you")


def _nullity(matrix: np.ndarray) -> int:
    """Dimension of the null space of ``matrix`` (its columns less its rank)."""
    if matrix.shape[1] == 0:
        return 0
    return matrix.shape[1] - (int(np.linalg.matrix_rank(matrix, tol=1e-9)) if matrix.size else 0)


def _joint_name_of_velocity(model: pin.Model, v: int) -> str:
    """The name of the joint that velocity index ``v`` belongs to."""
    return next(model.names[j] for j in range(1, model.njoints)
                if model.joints[j].idx_v <= v < model.joints[j].idx_v + model.joints[j].nv)


def _reference_text(robot: Robot, name: str) -> str:
    """Joint ``name``'s value at the reference configuration (m or rad), as YAML that reads back exactly."""
    value = float(robot.reference_q[robot.model.joints[robot.model.getJointId(name)].idx_q])
    return "0.0" if value == 0.0 else repr(value)
