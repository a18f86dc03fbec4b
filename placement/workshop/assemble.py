"""Close the loops of a closed-loop robot exported with them open (``placement assemble``).

A CAD export leaves a sidecar's ``reference_configuration`` a little off: loop gaps of
centimetres, passive angles off by radians. :func:`assemble` starts from that configuration
(optionally overridden) and solves the closure equations (:mod:`placement.robot.closures`) by
Levenberg–Marquardt, first with the actuated joints held at their start values so that only
passive joints move, then, if that fails, with every joint free. It reports how far the closed
configuration is from a singularity, and :func:`write_reference_configuration` rewrites the
sidecar's ``reference_configuration`` block in place, leaving the rest of the file as it was.

Units: joint values in m (prismatic) or rad (revolute); closure gaps in m (points) and rad
(orientations of welds).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin
import yaml

from placement.kinematics.generic import null_space_basis
from placement.robot.build import joints_to_lock
from placement.robot.closures import LWA, closure_jacobian, closure_residuals
from placement.robot.exceptions import AssemblyError
from placement.robot.model import Robot
from placement.robot.urdf import urdf_limits_missing
from placement.workshop.gepetto import URDF_NAME, YAML_NAME, sidecar_beside, sidecar_text
from placement.workshop.load import robot_from_sidecar, write_if_it_loads

CLOSED_TOLERANCE = 1e-10  # largest gap (m, rad) at which a loop counts as closed
MAX_ITERATIONS = 500
MAX_STEP = 0.5  # largest joint step of one iteration (m or rad)
ZERO_SNAP = 1e-14  # joint values this small (m, rad) are written as 0.0
SINGULAR_SIGMA = 1e-9  # passive closure Jacobian singular at or below this smallest singular value (m or rad per m or rad)


@dataclass(frozen=True)
class ClosureGap:
    """How far one closure is from closed.

    Attributes:
        name: The closure's name in the sidecar.
        position_m: Distance between the two frames' origins (m).
        angle_rad: Angle between the two frames' orientations (rad); None for a point closure.
    """

    name: str
    position_m: float
    angle_rad: float | None

    @property
    def largest(self) -> float:
        """The larger of the position (m) and angle (rad) gaps."""
        return max(self.position_m, self.angle_rad or 0.0)


@dataclass(frozen=True)
class Assembly:
    """A closed configuration and what it says about the mechanism.

    Attributes:
        q: The closed configuration (Pinocchio order; m or rad).
        start_q: The configuration the solver started from.
        gaps_before: Gaps of every closure at ``start_q``.
        gaps_after: Gaps of every closure at ``q``.
        actuated_held: True when only the passive joints moved.
        iterations: Levenberg–Marquardt iterations spent (both attempts).
        passive_sigma_min: Smallest singular value of the closure Jacobian's passive columns (m or
            rad of gap per m or rad of joint motion); near 0 the passive joints are near a singular,
            uncertain assembly.
        task_condition: Condition number of the map from actuated joint rates to end-effector
            velocity (task rows); 1 is isotropic, large is near a singularity of the actuators; inf
            when the passive joints are singular (``passive_sigma_min`` at most ``SINGULAR_SIGMA``).
    """

    q: np.ndarray
    start_q: np.ndarray
    gaps_before: tuple[ClosureGap, ...]
    gaps_after: tuple[ClosureGap, ...]
    actuated_held: bool
    iterations: int
    passive_sigma_min: float
    task_condition: float


def start_configuration(robot: Robot, near: dict[str, float] | None = None) -> np.ndarray:
    """The sidecar's reference configuration with the ``near`` joints set to their values.

    Args:
        robot: The robot (loaded with its loops possibly open).
        near: {joint name: value (m or rad)} overriding the reference configuration.

    Raises:
        AssemblyError: A name is not a one-coordinate movable joint of the model.
    """
    q = robot.reference_q.copy()
    for name, value in (near or {}).items():
        index = joint_q_index(robot, name)
        if index is None:
            raise AssemblyError(f"unknown joint '{name[:40]}': expected one of {', '.join(movable_joints(robot))}")
        q[index] = value
    return q


def movable_joints(robot: Robot) -> list[str]:
    """Names of the model's one-coordinate (revolute or prismatic) joints, in model order."""
    model = robot.model
    return [model.names[i] for i in range(1, model.njoints) if model.joints[i].nq == 1 and model.joints[i].nv == 1]


def joint_q_index(robot: Robot, name: str) -> int | None:
    """Configuration index of a one-coordinate joint called ``name``, or None."""
    if name not in movable_joints(robot):
        return None
    return int(robot.model.joints[robot.model.getJointId(name)].idx_q)


def closure_gaps(robot: Robot, data: pin.Data, q: np.ndarray) -> tuple[ClosureGap, ...]:
    """Gap of every closure at ``q``: position (m) and, for welds, angle (rad)."""
    residuals = closure_residuals(robot, data, q)
    gaps, start = [], 0
    for closure in robot.closures:
        part = residuals[start:start + closure.dimension]
        start += closure.dimension
        angle = float(np.linalg.norm(part[3:])) if closure.kind == "weld" else None
        gaps.append(ClosureGap(closure.name, float(np.linalg.norm(part[:3])), angle))
    return tuple(gaps)


def exact_closure_jacobian(robot: Robot, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """Jacobian (rows, nv) of :func:`closure_residuals` at ``q``, exact also far from closed.

    :func:`closure_jacobian` gives the rows of a weld's orientation gap ``log3(R1 R2^T)`` as
    ``w1 - w2``, exact only where the gap is zero. Here they are ``Jlog3(R) (R^T w1 - w2)``
    with ``R = R1 R2^T``, ``w1, w2`` the frames' angular-velocity Jacobians in the world frame,
    so that Newton steps stay right for orientation gaps of radians.
    """
    jacobian = closure_jacobian(robot, data, q)
    row = 0
    for closure in robot.closures:
        if closure.kind == "weld":
            m1, m2 = (data.oMf[i] for i in closure.frame_ids)
            w1, w2 = (pin.getFrameJacobian(robot.model, data, i, LWA)[3:] for i in closure.frame_ids)
            rotation = m1.rotation @ m2.rotation.T
            jacobian[row + 3:row + 6] = pin.Jlog3(rotation) @ (rotation.T @ w1 - w2)
        row += closure.dimension
    return jacobian


def _solve(robot: Robot, data: pin.Data, q: np.ndarray, free_v: np.ndarray) -> tuple[np.ndarray, int]:
    """Levenberg–Marquardt (Nielsen's damping update) on the closure residuals, moving ``free_v`` only.

    Returns:
        The configuration of least residual found, and the iterations spent.
    """
    model = robot.model
    residual = closure_residuals(robot, data, q)
    cost = float(residual @ residual)
    damping, growth = -1.0, 2.0
    for iteration in range(1, MAX_ITERATIONS + 1):
        if np.abs(residual).max(initial=0.0) < CLOSED_TOLERANCE * 1e-3:
            return q, iteration - 1
        jacobian = exact_closure_jacobian(robot, data, q)[:, free_v]
        normal, gradient = jacobian.T @ jacobian, jacobian.T @ residual
        if damping < 0:
            damping = 1e-3 * max(float(np.diag(normal).max(initial=0.0)), 1e-12)
        while True:
            step = -np.linalg.solve(normal + damping * np.eye(len(free_v)), gradient)
            longest = np.abs(step).max(initial=0.0)
            if longest > MAX_STEP:
                step *= MAX_STEP / longest
            v = np.zeros(model.nv)
            v[free_v] = step
            trial = pin.integrate(model, q, v)
            trial_residual = closure_residuals(robot, data, trial)
            trial_cost = float(trial_residual @ trial_residual)
            predicted = -(2 * step @ gradient + step @ normal @ step)
            if trial_cost < cost and predicted > 0:
                ratio = (cost - trial_cost) / predicted
                damping *= max(1 / 3, 1 - (2 * ratio - 1) ** 3)
                growth = 2.0
                q, residual, cost = trial, trial_residual, trial_cost
                break
            damping *= growth
            growth *= 2
            if damping > 1e20 or longest < 1e-16:  # no step lowers the residual: a local minimum
                return q, iteration
    return q, MAX_ITERATIONS


def singularity_measures(robot: Robot, data: pin.Data, q: np.ndarray) -> tuple[float, float]:
    """Smallest singular value of the passive closure Jacobian, and the condition of the task map."""
    jacobian = closure_jacobian(robot, data, q)
    actuated = robot.actuated_v_indices
    passive = np.setdiff1d(np.arange(robot.model.nv), actuated)
    j_passive = jacobian[:, passive]
    if len(passive) == 0:
        sigma_min = np.inf
    elif j_passive.shape[0] < len(passive):
        sigma_min = 0.0  # fewer equations than passive joints: they are not determined
    else:
        sigma_min = float(np.linalg.svd(j_passive, compute_uv=False)[-1])
    if sigma_min <= SINGULAR_SIGMA:  # the actuators do not determine the passive joints: no task map
        return sigma_min, np.inf
    basis, _, _ = null_space_basis(robot, jacobian)
    task = pin.getFrameJacobian(robot.model, data, robot.end_effector_frame_id, LWA)[:robot.task_dimension]
    return sigma_min, float(np.linalg.cond(task @ basis))


def assemble(robot: Robot, near: dict[str, float] | None = None) -> Assembly:
    """Close the robot's loops from its reference configuration (see the module's docstring).

    Args:
        robot: A closed-loop robot, possibly loaded with its loops open.
        near: {joint: value (m or rad)} overriding the reference configuration at the start.

    Returns:
        The closed configuration, with the gaps before and after and the singularity measures.

    Raises:
        AssemblyError: The robot has no closures, a ``near`` joint is unknown, or no
            configuration near the start closes every loop (the message names the worst closure
            and its gap).
    """
    if not robot.closures:
        raise AssemblyError(f"robot '{robot.name}' has no loop closures: nothing to assemble")
    multiple = [robot.model.names[i] for i in range(1, robot.model.njoints) if robot.model.joints[i].nq != 1]
    if multiple:
        raise AssemblyError(f"assemble handles one-coordinate joints only; joint '{multiple[0]}' has "
                            f"{robot.model.joints[robot.model.getJointId(multiple[0])].nq} coordinates")
    data = robot.model.createData()
    start = start_configuration(robot, near)
    before = closure_gaps(robot, data, start)
    passive = np.setdiff1d(np.arange(robot.model.nv), robot.actuated_v_indices)
    q, iterations = _solve(robot, data, start, passive)
    after = closure_gaps(robot, data, q)
    held = max(gap.largest for gap in after) < CLOSED_TOLERANCE
    if not held:
        q_all, more = _solve(robot, data, start, np.arange(robot.model.nv))
        iterations += more
        after_all = closure_gaps(robot, data, q_all)
        if max(gap.largest for gap in after_all) <= max(gap.largest for gap in after):
            q, after = q_all, after_all
    worst = max(after, key=lambda gap: gap.largest)
    if worst.largest >= CLOSED_TOLERANCE:
        angle = f", angle gap {worst.angle_rad:.3g} rad" if worst.angle_rad is not None else ""
        raise AssemblyError(f"{robot.name}: closure '{worst.name}' cannot close near the start configuration: the solver stops "
                            f"at a gap of {worst.position_m:.3g} m{angle} (it started at "
                            f"{max(gap.largest for gap in before):.3g} m or rad); check the link lengths, or start "
                            "elsewhere with --near")
    sigma_min, condition = singularity_measures(robot, data, q)
    return Assembly(q=q, start_q=start, gaps_before=before, gaps_after=after, actuated_held=held,
                    iterations=iterations, passive_sigma_min=sigma_min, task_condition=condition)


def internal_freedoms(robot: Robot, q: np.ndarray) -> dict[str, float]:
    """Joints to lock so that the actuated joints determine the passive ones, at their values in ``q``.

    A weld closure between two links that each end in a revolute joint about the same axis (as a
    CAD export cuts a loop at a pin) leaves the pair free to spin together: a motion no actuator
    drives and that moves neither the end effector nor any closure. Such a freedom is locked by
    holding one joint of the group that moves with it (:func:`placement.robot.build.joints_to_lock`),
    which changes neither the tool's motion nor the loads the actuators carry. A free motion that
    moves the end effector is a missing actuator, not something to lock: then nothing is proposed.

    Args:
        robot: The robot, its loops closed at ``q``.
        q: A closed configuration (Pinocchio order; m or rad).

    Returns:
        {joint: value at ``q`` (m or rad)}, in model order; empty when the actuated joints determine
        the passive ones, or when a free motion moves the end effector.
    """
    data = robot.model.createData()
    jacobian = closure_jacobian(robot, data, q)
    passive = np.setdiff1d(np.arange(robot.model.nv), robot.actuated_v_indices)
    columns = jacobian[:, passive]
    rank = int(np.linalg.matrix_rank(columns, tol=1e-9)) if columns.size else 0
    if rank == len(passive):
        return {}
    free = np.linalg.svd(columns)[2][rank:].T if columns.size else np.eye(len(passive))
    task = pin.getFrameJacobian(robot.model, data, robot.end_effector_frame_id, LWA)[:robot.task_dimension]
    scale = max(float(np.abs(task).max(initial=0.0)), 1e-300)
    if np.abs(task[:, passive] @ free).max(initial=0.0) > 1e-9 * scale:
        return {}
    _, locked = joints_to_lock(robot, jacobian)
    model = robot.model
    return {name: _snapped(float(q[model.joints[model.getJointId(name)].idx_q])) for name in locked}


def locked_robot(robot: Robot, reference: dict[str, float], locks: dict[str, float]) -> Robot:
    """``robot`` with the ``locks`` joints held at their values and ``reference`` as its reference configuration.

    Raises:
        RobotFileError: Pinocchio cannot hold these joints (see :func:`placement.robot.build.reduced_model`).
    """
    sidecar = robot.edited_sidecar(locked_joints={**robot.locked_joints, **locks}, reference_configuration=reference)
    return robot_from_sidecar(robot.sidecar_path, sidecar, check_closures=False)


def _snapped(value: float) -> float:
    """``value``, or 0.0 when its magnitude is below ``ZERO_SNAP``."""
    return 0.0 if abs(value) < ZERO_SNAP else value


def reference_values(robot: Robot, assembly: Assembly) -> dict[str, float]:
    """The joints to write as ``reference_configuration`` (m or rad).

    Every joint the sidecar's ``reference_configuration`` names, in its order, then every passive
    joint, then any actuated joint whose value differs from the sidecar's (0 when it names none),
    whether ``--near`` set it or the solver moved it; values below ``ZERO_SNAP`` become 0.0.
    """
    actuated = {a.joint for a in robot.actuators}
    names = list(robot.reference_configuration)
    for name in movable_joints(robot):
        index = joint_q_index(robot, name)
        changed = index is not None and assembly.q[index] != robot.reference_q[index]
        if name not in names and (name not in actuated or changed):
            names.append(name)
    values = {}
    for name in names:
        index = joint_q_index(robot, name)
        values[name] = _snapped(float(assembly.q[index])) if index is not None else 0.0
    return values


def outside_limits(robot: Robot, values: dict[str, float]) -> list[str]:
    """Joints of a configuration (``values``: {joint: value (m or rad)}, as :func:`reference_values` gives them)
    outside their limits: an actuator's, else the URDF's, none when the URDF gives none."""
    actuators = {a.joint: a for a in robot.actuators}
    warnings = []
    for name, value in values.items():
        joint_id = robot.model.getJointId(name)
        if name in actuators:
            low, high = actuators[name].position_min, actuators[name].position_max
        elif urdf_limits_missing(robot.model, joint_id):
            continue
        else:
            index = robot.model.joints[joint_id].idx_q
            low, high = float(robot.model.lowerPositionLimit[index]), float(robot.model.upperPositionLimit[index])
        if not low <= value <= high:
            warnings.append(f"joint '{name}' is at {value:.6g}, outside its limits [{low:.6g}, {high:.6g}]")
    return warnings


def _number(value: float) -> str:
    """A float as YAML that reads back as the same float (PyYAML needs a dot before an exponent)."""
    text = repr(float(value))
    mantissa, e, exponent = text.partition("e")
    if e and "." not in mantissa:
        text = f"{mantissa}.0e{exponent}"
    return text


def _key(name: str) -> str:
    """A joint name as a YAML key (quoted when YAML would read it otherwise)."""
    return yaml.safe_dump([name], default_flow_style=True, width=10_000).strip()[1:-1]


def reference_block(values: dict[str, float]) -> str:
    """The ``reference_configuration:`` YAML block of ``values`` (m or rad), ending with a newline."""
    return "reference_configuration:\n" + "".join(f"  {_key(name)}: {_number(v)}\n" for name, v in values.items())


def write_reference_configuration(path: Path, values: dict[str, float], locks: dict[str, float] | None = None,
                                  reason: str = "") -> Robot:
    """Replace the ``reference_configuration`` mapping of the sidecar at ``path`` with ``values``, and add ``locks``.

    Only the mapping's entries change: the key line (and its comment), every other field, the
    comments and the line endings stay byte for byte. A sidecar without the field gets it appended.
    ``locks`` go at the end of ``locked_joints``, each with an entry ``locked_joints.NAME: "EST:
    reason"`` at the end of ``sources`` (fields appended when missing). The file changes only if the
    rewritten sidecar loads (:func:`placement.workshop.load.write_if_it_loads`).

    Args:
        path: The sidecar file (UTF-8 YAML).
        values: {joint: value (m or rad)}.
        locks: {joint: value (m or rad)} to add to ``locked_joints``.
        reason: Why they are locked, for ``sources``.

    Returns:
        The robot loaded from the rewritten file.

    Raises:
        AssemblyError: A field is not a plain mapping that can be rewritten in place, or the
            rewritten sidecar does not load (the file is then left as it was).
    """
    text = path.read_bytes().decode("utf-8")
    root = yaml.compose(text)
    if not isinstance(root, yaml.MappingNode):
        raise AssemblyError(f"{path}: expected a mapping of fields at the top level")
    fields = {"reference_configuration": [f"{_key(name)}: {_number(v)}" for name, v in values.items()]}
    if locks:
        fields["locked_joints"] = [f"{_key(name)}: {_number(v)}" for name, v in locks.items()]
        fields["sources"] = [f"{_key('locked_joints.' + name)}: {_key('EST: ' + reason)}" for name in locks]
    edits, missing = [], []
    for field, entries in fields.items():
        node = next((value for key, value in root.value if key.value == field), None)
        if node is None:
            missing.append(field)
        elif field == "reference_configuration":
            edits.append((node.start_mark.index, _end(text, node), _mapping_text(path, text, node, field, entries)))
        else:
            edits.append(_appended(path, text, node, field, entries))
    for start, end, part in sorted(edits, reverse=True):
        text = text[:start] + part + text[end:]
    ending = "\r\n" if "\r\n" in text else "\n"
    for field in missing:
        separator = "" if not text or text.endswith(("\n", "\r")) else ending
        text += separator + f"{field}:{ending}" + "".join(f"  {entry}{ending}" for entry in fields[field])
    return write_if_it_loads(path, text)


def _appended(path: Path, text: str, node: yaml.Node, field: str, entries: list[str]) -> tuple[int, int, str]:
    """The edit (start, end, new text) that adds ``entries`` at the end of the mapping ``node``, in its style."""
    if not isinstance(node, yaml.MappingNode) or any(key.value == "<<" for key, _ in node.value):
        raise AssemblyError(f"{path}: {field} is not a plain mapping; add {', '.join(entries)} to it by hand")
    if node.flow_style or not node.value:
        return node.start_mark.index, node.end_mark.index, "{" + ", ".join(
            [text[key.start_mark.index:value.end_mark.index] for key, value in node.value] + entries) + "}"
    ending = "\r\n" if "\r\n" in text else "\n"
    end = _end(text, node)
    return end, end, "".join(ending + " " * node.start_mark.column + entry for entry in entries)


def _mapping_text(path: Path, text: str, node: yaml.Node, field: str, entries: list[str]) -> str:
    """The mapping of ``entries`` ("key: value" lines), in the style (block or flow) and indentation of ``node``."""
    if not isinstance(node, yaml.MappingNode) or any(key.value == "<<" for key, _ in node.value):
        raise AssemblyError(f"{path}: {field} is not a plain mapping of joint values; "
                            "replace it by hand with the block printed without --write")
    if node.flow_style or not node.value:
        return "{" + ", ".join(entries) + "}"
    ending = "\r\n" if "\r\n" in text else "\n"
    return (ending + " " * node.start_mark.column).join(entries)


def _end(text: str, node: yaml.Node) -> int:
    """Where ``node``'s text ends: a flow mapping at its brace, a block one at the end of its last line."""
    if not isinstance(node, yaml.MappingNode) or node.flow_style or not node.value:
        return node.end_mark.index
    last = node.value[-1][1].end_mark.index
    ends = [i for i in (text.find("\n", last), text.find("\r", last)) if i >= 0]
    return min(ends) if ends else len(text)


def write_gepetto_sidecar(path: Path, robot: Robot, reference: dict[str, float], locks: dict[str, float] | None = None,
                          reason: str = "") -> Robot:
    """Write the sidecar of the Gepetto ``robot.yaml`` at ``path`` to ``placement.yaml`` beside it, only if it
    loads: a ``robot.yaml`` that describes no valid robot leaves no ``placement.yaml`` to hide its fix.

    Args:
        path: The ``robot.yaml``.
        robot: The robot loaded from it.
        reference: The closed configuration {joint: value (m or rad)}, without the ``locks``.
        locks: {joint: value (m or rad)} to hold, written under ``locked_joints``, each marked EST under
            ``sources`` with ``reason``.
        reason: Why they are locked.

    Returns:
        The robot loaded from the file written.

    Raises:
        AssemblyError: The sidecar would not load (nothing is written); the message says what to fix.
    """
    try:
        held = locked_robot(robot, reference, locks or {})
        return write_if_it_loads(sidecar_beside(path), sidecar_text(path, held, reference, locks or {}, reason))
    except AssemblyError as error:
        raise AssemblyError(f"{error}; fix {YAML_NAME} (name_mot lists the actuated joints; joint_name with joint_type "
                            f"FIXED locks a joint at 0) or {URDF_NAME}, and run assemble --write again") from None
