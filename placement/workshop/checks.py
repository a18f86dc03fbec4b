"""Physics checks of a robot model: forward-dynamics round trip and power balance.

These prove that the inverse dynamics of :mod:`placement.dynamics` is exact for a given robot
file: the efforts it returns, applied in Pinocchio's constrained forward dynamics, reproduce the
prescribed accelerations, and the power they deliver equals the rate of change of the
mechanical energy. ``python -m placement check ROBOT`` runs them on a demonstration trajectory,
and adds plausibility warnings about the robot files (:func:`plausibility_warnings`).
"""

from __future__ import annotations

import dataclasses
import statistics
from collections.abc import Callable
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin

from placement.dynamics.inverse import actuator_efforts
from placement.energy.trace import motor_trace
from placement.kinematics import joint_trajectory
from placement.kinematics.exceptions import UnreachableError
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.robot.closures import LWA, closure_residuals
from placement.robot.mjcf import is_mjcf, read_mjcf
from placement.robot.model import Robot
from placement.robot.plausibility import massless_note
from placement.robot.urdf import urdf_limits_missing

AMPLITUDE_FRACTION = 0.05  # default check amplitude, as a fraction of the robot's size
FALLBACK_AMPLITUDE_M = 0.01  # when the robot gives no size (end effector at the base, no workspace)
HEAVY_LINK_RATIO = 100.0  # a link heavier than this many median link masses is suspicious
PEAK_CURRENT_A = 500.0  # a motor whose peak torque takes more current than this (A) is suspicious
MAX_HALVINGS = 10  # the default amplitude is halved at most this often (to 1/1024) to stay reachable


def _reference_motion(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """End-effector position (m) and rotation at the reference configuration, and the unit
    directions (3, k) in which the mechanism can move it there (a plane for a planar robot)."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    frame = data.oMf[robot.end_effector_frame_id]
    center, rotation = frame.translation.copy(), frame.rotation.copy()
    zeros = np.zeros((1, 3))
    still = TaskTrajectory(center[None], zeros, zeros, *((rotation[None], zeros, zeros) if robot.task == "pose" else ()))
    u, singular, _ = np.linalg.svd(joint_trajectory(robot, still, "numeric").task_map[0, :3])
    return center, rotation, u[:, : int((singular > 1e-9 * singular.max()).sum())]


def default_amplitude(robot: Robot) -> tuple[float, str]:
    """The check motion's amplitude scaled to the robot's size: 5 % of a length.

    The length is the workspace box's smallest side along the motion when the sidecar declares a
    workspace: the smallest side among the axes the end effector moves along at the reference
    configuration (an axis counts when its squared projection on the span of the motion is at
    least half the largest axis's, so a planar robot's flat side is skipped). Without a
    workspace, it is the distance from the base (the URDF root) to the end effector at the
    reference configuration; the amplitude is 1 cm when that distance is zero.

    Args:
        robot: The robot.

    Returns:
        The amplitude (m) and a few words saying what it was scaled to.
    """
    center, _, directions = _reference_motion(robot)
    workspace = robot.workspace
    if workspace is not None:
        weight = (directions**2).sum(axis=1)  # how far each axis lies in the motion's span, 0..1
        sides = (np.array(workspace.max_m) - np.array(workspace.min_m))[weight >= 0.5 * weight.max()]
        side = float(sides.min())
        return AMPLITUDE_FRACTION * side, f"5 % of the workspace box's smallest side along the motion, {side:.4g} m"
    reach = float(np.linalg.norm(center))
    if reach <= 0:
        return FALLBACK_AMPLITUDE_M, "the end effector is at the base and no workspace is declared"
    return AMPLITUDE_FRACTION * reach, f"5 % of the base to end-effector distance, {reach:.4g} m"


def demo_trajectory(robot: Robot, amplitude_m: float | None = None,
                    duration_s: float = 1.0) -> Callable[[np.ndarray], TaskTrajectory]:
    """A smooth Lissajous motion of the end effector around its reference position.

    The motion spans the directions in which the mechanism can move its end effector at the
    reference configuration (a plane for a planar robot); a pose task keeps the orientation.

    Args:
        robot: The robot.
        amplitude_m: Amplitude along each direction (m); None: :func:`default_amplitude`.
        duration_s: Period of the slowest component (s).

    Returns:
        A function of time (s) giving the task trajectory, with exact derivatives.
    """
    if amplitude_m is None:
        amplitude_m = default_amplitude(robot)[0]
    center, rotation, directions = _reference_motion(robot)
    w = (2 * np.pi / duration_s * np.array([1.0, 1.5, 2.0]))[: directions.shape[1]]
    phase = np.array([0.0, 0.7, 1.9])[: directions.shape[1]]

    def path(t_s: np.ndarray) -> TaskTrajectory:
        angle = w * np.asarray(t_s, dtype=float)[:, None] + phase
        p = center + amplitude_m * np.sin(angle) @ directions.T
        v = amplitude_m * (w * np.cos(angle)) @ directions.T
        a = -amplitude_m * (w**2 * np.sin(angle)) @ directions.T
        if robot.task == "position":
            return TaskTrajectory(p, v, a)
        still_rate = np.zeros_like(p)
        return TaskTrajectory(p, v, a, np.tile(rotation, (len(p), 1, 1)), still_rate, still_rate)

    return path


def forward_accelerations(robot: Robot, joints: JointTrajectory, effort: np.ndarray,
                          external_load: np.ndarray | None = None) -> np.ndarray:
    """Joint accelerations from Pinocchio's constrained forward dynamics under the given efforts.

    Applies tau = S·F + J_eeᵀ·w_ext at every sample and solves ``constraintDynamics`` with one
    rigid constraint per loop closure.
    """
    model, data = robot.model, robot.model.createData()
    constraints = []
    for closure in robot.closures:
        f1, f2 = (model.frames[i] for i in closure.frame_ids)
        kind = pin.ContactType.CONTACT_3D if closure.kind == "point" else pin.ContactType.CONTACT_6D
        constraints.append(pin.RigidConstraintModel(kind, model, f1.parentJoint, f1.placement,
                                                    f2.parentJoint, f2.placement, pin.LOCAL))
    constraint_data = [c.createData() for c in constraints]
    pin.initConstraintDynamics(model, data, constraints, constraint_data)
    accelerations = np.zeros_like(joints.a)
    for k in range(len(joints.q)):
        tau = np.zeros(model.nv)
        tau[robot.actuated_v_indices] = effort[k]
        if external_load is not None:
            pin.computeJointJacobians(model, data, joints.q[k])
            jacobian = pin.getFrameJacobian(model, data, robot.end_effector_frame_id, LWA)
            tau += jacobian[: external_load.shape[1]].T @ external_load[k]
        settings = pin.ProximalSettings(1e-12, 1e-10, 20)
        accelerations[k] = pin.constraintDynamics(model, data, joints.q[k], joints.v[k], tau,
                                                  constraints, constraint_data, settings)
    return accelerations


def mechanical_energy(robot: Robot, joints: JointTrajectory) -> np.ndarray:
    """Kinetic (with rotor inertia) plus potential energy of the tree, J, per sample."""
    model, data = robot.model, robot.model.createData()
    energy = np.zeros(len(joints.q))
    for k, (q, v) in enumerate(zip(joints.q, joints.v)):
        mass_matrix = pin.crba(model, data, q)
        mass_matrix = np.triu(mass_matrix) + np.triu(mass_matrix, 1).T
        energy[k] = 0.5 * v @ mass_matrix @ v + pin.computePotentialEnergy(model, data, q)
    return energy


def energy_rate(robot: Robot, path: Callable[[np.ndarray], TaskTrajectory], t_s: np.ndarray,
                step_s: float = 1e-3, method: str = "auto") -> np.ndarray:
    """d(T + V)/dt at times ``t_s`` by a five-point central difference along the exact path (W)."""
    weights = {-2: 1 / 12, -1: -8 / 12, 1: 8 / 12, 2: -1 / 12}
    return np.sum([w * mechanical_energy(robot, joint_trajectory(robot, path(t_s + s * step_s), method))
                   for s, w in weights.items()], axis=0) / step_s


@dataclasses.dataclass(frozen=True)
class CheckReport:
    """Outcome of :func:`check_robot` (SI units).

    Attributes:
        samples: Samples of the demonstration trajectory.
        closure_gap: Largest closure residual along it (m and rad).
        solver_gap: Largest joint difference closed form vs generic solver (m and rad), or None
            when the robot has no closed-form plug-in.
        forward_error: Largest joint acceleration error of the forward round trip.
        power_error_W: Largest power-balance residual (W).
        peak_power_W: Largest actuator power (W), the scale of ``power_error_W``.
        peak_effort: Largest |effort| per actuator (N or N·m).
        amplitude_m: Amplitude of the demonstration motion along each direction (m).
        amplitude_basis: What the amplitude was scaled to, or "given".
        warnings: Plausibility warnings about the robot files, one line each (they do not fail
            the check; see :func:`plausibility_warnings`).
    """

    samples: int
    closure_gap: float
    solver_gap: float | None
    forward_error: float
    power_error_W: float
    peak_power_W: float
    peak_effort: np.ndarray
    amplitude_m: float
    amplitude_basis: str
    warnings: tuple[str, ...]

    @property
    def passed(self) -> bool:
        """Whether every check is within its tolerance."""
        return (self.closure_gap < 1e-9 and (self.solver_gap is None or self.solver_gap < 1e-8)
                and self.forward_error < 1e-6 and self.power_error_W <= 1e-6 * max(self.peak_power_W, 1e-3))


def check_robot(robot: Robot, samples: int = 100, amplitude_m: float | None = None) -> CheckReport:
    """Run the physics checks on a demonstration trajectory around the reference configuration.

    With the default amplitude, a robot whose reference configuration lies near the edge of its
    reach (a CAD export with its arms stretched, say) is checked at the largest of the default
    amplitude halved 1 to ``MAX_HALVINGS`` times whose motion stays reachable, and the report's
    ``amplitude_basis`` says so.

    Args:
        robot: The robot; it is not modified.
        samples: Samples of the one-second demonstration trajectory.
        amplitude_m: Amplitude of the motion along each direction (m); None scales it to the
            robot's size (:func:`default_amplitude`).

    Returns:
        The residuals of every check, and the plausibility warnings.

    Raises:
        ValueError: ``amplitude_m`` is not a finite number > 0.
        UnreachableError: The motion leaves the reachable region (too large an amplitude; with the
            default one, even halved ``MAX_HALVINGS`` times: the error of the default amplitude).
    """
    if amplitude_m is not None and not 0 < amplitude_m < np.inf:
        raise ValueError(f"amplitude_m must be a finite number > 0 m, got {amplitude_m}")
    if amplitude_m is not None:
        return _check_at(robot, samples, amplitude_m, "given")
    amplitude_m, basis = default_amplitude(robot)
    try:
        return _check_at(robot, samples, amplitude_m, basis)
    except UnreachableError as error:
        first = error
    for halvings in range(1, MAX_HALVINGS + 1):
        try:
            return _check_at(robot, samples, amplitude_m / 2**halvings, f"{basis}, halved {halvings} time(s): the "
                             f"larger motions leave the reachable region ({first.reason})")
        except UnreachableError:
            continue
    raise first


def _check_at(robot: Robot, samples: int, amplitude_m: float, basis: str) -> CheckReport:
    """:func:`check_robot` at one amplitude (m), ``basis`` saying what it was scaled to."""
    model = pin.Model(robot.model)
    # Massless bodies cut from a loop (weld stubs) make the forward KKT system singular; a tiny
    # armature on the passive joints, used by both directions, keeps it regular.
    passive = np.setdiff1d(np.arange(model.nv), robot.actuated_v_indices)
    model.armature[passive] += 1e-9
    checked = dataclasses.replace(robot, model=model)
    path = demo_trajectory(checked, amplitude_m)
    t = np.linspace(0.0, 1.0, samples)
    joints = joint_trajectory(checked, path(t))
    effort = actuator_efforts(checked, joints)
    data = model.createData()
    closure_gap = max((np.abs(closure_residuals(checked, data, q)).max(initial=0.0) for q in joints.q), default=0.0)
    solver_gap = None
    if checked.closed_form is not None:
        numeric = joint_trajectory(checked, path(t), "numeric")
        solver_gap = float(np.abs(numeric.q - joints.q).max())
    forward = forward_accelerations(checked, joints, effort)
    power = (effort * joints.v[:, checked.actuated_v_indices]).sum(axis=1)
    return CheckReport(samples=samples, closure_gap=float(closure_gap), solver_gap=solver_gap,
                       forward_error=float(np.abs(forward - joints.a).max()),
                       power_error_W=float(np.abs(power - energy_rate(checked, path, t)).max()),
                       peak_power_W=float(np.abs(effort * joints.v[:, checked.actuated_v_indices]).max()),
                       peak_effort=np.abs(effort).max(axis=0), amplitude_m=float(amplitude_m), amplitude_basis=basis,
                       warnings=plausibility_warnings(robot, joints, effort))


def plausibility_warnings(robot: Robot, joints: JointTrajectory, effort: np.ndarray) -> tuple[str, ...]:
    """Signs of a mistyped robot file, one line each: what the physics checks cannot see.

    Args:
        robot: The robot.
        joints: A motion of the robot (the check motion).
        effort: (N, n_act) actuator efforts along it (N or N·m), rotor inertia included.

    Returns:
        Warnings about moving links without inertia (loaded with ``allow_massless``), heavy links, efforts beyond
        the drives, motors whose peak torque takes an implausible current, and joints without URDF limits.
    """
    note = massless_note(robot)
    return (*([note] if note else []), *heavy_link_warnings(link_masses(robot)), *effort_warnings(robot, joints, effort),
            *current_warnings(robot), *limit_warnings(robot))


def current_warnings(robot: Robot) -> list[str]:
    """Motors whose peak torque takes more than PEAK_CURRENT_A (max_torque_Nm / torque_constant_Nm_per_A): a peak
    torque raised without the torque constant, say, which would make every Joule loss absurd."""
    warnings = []
    for actuator in robot.actuators:
        if actuator.drive is None:
            continue
        motor = actuator.drive.motor
        current = motor.max_torque_Nm / motor.torque_constant_Nm_per_A
        if current > PEAK_CURRENT_A:
            warnings.append(f"motor of actuator '{actuator.joint}': its peak torque takes {current:.4g} A "
                            f"(max_torque_Nm {motor.max_torque_Nm:.4g} / torque_constant_Nm_per_A "
                            f"{motor.torque_constant_Nm_per_A:.4g}), more than {PEAK_CURRENT_A:g} A: check that both "
                            "come from the same motor")
    return warnings


def link_masses(robot: Robot) -> dict[str, float]:
    """Mass of every URDF link that declares an inertial, or that the sidecar's ``links`` gives one, kg, by link name;
    of an MJCF, of every body that carries a joint (with the bodies welded to it)."""
    if is_mjcf(robot.urdf_path):
        return read_mjcf(robot.urdf_path).masses
    masses = {}
    for link in ElementTree.parse(robot.urdf_path).getroot().iter("link"):
        mass = link.find("inertial/mass")
        if mass is not None:
            masses[link.get("name", "?")] = float(mass.get("value", "0"))
    return masses | {name: float(inertial.mass_kg) for name, inertial in robot.link_inertials.items()}


def heavy_link_warnings(masses: dict[str, float]) -> list[str]:
    """Links heavier than 100 times the median mass of the links that have mass (kg)."""
    positive = [mass for mass in masses.values() if mass > 0]
    if not positive:
        return []
    median = statistics.median(positive)
    return [f"link '{name}' weighs {mass:.4g} kg, more than {HEAVY_LINK_RATIO:g}x the median link mass "
            f"{median:.4g} kg (check its <mass> in the URDF)"
            for name, mass in masses.items() if mass > HEAVY_LINK_RATIO * median]


def effort_warnings(robot: Robot, joints: JointTrajectory, effort: np.ndarray) -> list[str]:
    """Actuators whose drive cannot deliver the motor torque the check motion needs.

    The motor torque comes from :func:`placement.energy.trace.motor_trace` (transmission ratio,
    efficiency, friction and rotor inertia); actuators without a drive are skipped.
    """
    driven = [i for i, actuator in enumerate(robot.actuators) if actuator.drive is not None]
    if not driven:
        return []
    subset = dataclasses.replace(robot, actuators=tuple(robot.actuators[i] for i in driven))
    columns = robot.actuated_v_indices[driven]
    torque = np.abs(motor_trace(subset, effort[:, driven], joints.v[:, columns], joints.a[:, columns]).torque_Nm)
    warnings = []
    for k, (actuator, drive) in enumerate(zip(subset.actuators, subset.drives)):
        peak, limit = float(torque[:, k].max()), drive.motor.max_torque_Nm
        if peak > limit:
            unit = "N" if actuator.prismatic else "N m"
            warnings.append(f"actuator '{actuator.joint}' needs a peak motor torque of {peak:.4g} N m on the check "
                            f"motion (joint effort {np.abs(effort[:, driven[k]]).max():.4g} {unit}), beyond its "
                            f"drive's limit of {limit:.4g} N m")
    return warnings


def limit_warnings(robot: Robot) -> list[str]:
    """One-coordinate joints whose URDF gives no position limits (Pinocchio reads [0, 0] or huge)."""
    sidecar_limits = {a.joint: a for a in robot.actuators}
    warnings = []
    for joint_id, joint in enumerate(robot.model.joints):
        name = robot.model.names[joint_id]
        if joint_id == 0 or joint.nq != 1 or not urdf_limits_missing(robot.model, joint_id):
            continue
        actuator = sidecar_limits.get(name)
        kind = "MJCF (no range)" if is_mjcf(robot.urdf_path) else "URDF"
        warnings.append(f"joint '{name}' has no limits in the {kind}" + (
            f"; the sidecar's [{actuator.position_min:g}, {actuator.position_max:g}] are used" if actuator
            else " (a passive joint: nothing checks its range)"))
    return warnings
