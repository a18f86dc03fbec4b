"""Physics checks of a robot model: forward-dynamics round trip and power balance.

These prove that the inverse dynamics of :mod:`placement.dynamics` is exact for a given robot
file: the efforts it returns, applied in Pinocchio's constrained forward dynamics, reproduce the
prescribed accelerations, and the power they deliver equals the rate of change of the
mechanical energy. ``python -m placement check ROBOT`` runs them on a demonstration trajectory.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
import pinocchio as pin

from placement.dynamics import actuator_efforts
from placement.kinematics import JointTrajectory, TaskTrajectory, joint_trajectory
from placement.robot.closures import LWA, closure_residuals
from placement.robot.model import Robot


def demo_trajectory(robot: Robot, amplitude_m: float = 0.01,
                    duration_s: float = 1.0) -> Callable[[np.ndarray], TaskTrajectory]:
    """A smooth Lissajous motion of the end effector around its reference position.

    The motion spans the directions in which the mechanism can move its end effector at the
    reference configuration (a plane for a planar robot); a pose task keeps the orientation.

    Args:
        robot: The robot.
        amplitude_m: Amplitude along each direction (m).
        duration_s: Period of the slowest component (s).

    Returns:
        A function of time (s) giving the task trajectory, with exact derivatives.
    """
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    frame = data.oMf[robot.end_effector_frame_id]
    center, rotation = frame.translation.copy(), frame.rotation.copy()
    zeros = np.zeros((1, 3))
    still = TaskTrajectory(center[None], zeros, zeros, *((rotation[None], zeros, zeros) if robot.task == "pose" else ()))
    u, singular, _ = np.linalg.svd(joint_trajectory(robot, still, "numeric").task_map[0, :3])
    directions = u[:, : int((singular > 1e-9 * singular.max()).sum())]
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
    """

    samples: int
    closure_gap: float
    solver_gap: float | None
    forward_error: float
    power_error_W: float
    peak_power_W: float
    peak_effort: np.ndarray

    @property
    def passed(self) -> bool:
        """Whether every check is within its tolerance."""
        return (self.closure_gap < 1e-9 and (self.solver_gap is None or self.solver_gap < 1e-8)
                and self.forward_error < 1e-6 and self.power_error_W <= 1e-6 * max(self.peak_power_W, 1e-3))


def check_robot(robot: Robot, samples: int = 100) -> CheckReport:
    """Run the physics checks on a demonstration trajectory around the reference configuration.

    Args:
        robot: The robot; it is not modified.
        samples: Samples of the one-second demonstration trajectory.

    Returns:
        The residuals of every check.
    """
    model = pin.Model(robot.model)
    # Massless bodies cut from a loop (weld stubs) make the forward KKT system singular; a tiny
    # armature on the passive joints, used by both directions, keeps it regular.
    passive = np.setdiff1d(np.arange(model.nv), robot.actuated_v_indices)
    model.armature[passive] += 1e-9
    robot = dataclasses.replace(robot, model=model)
    path = demo_trajectory(robot)
    t = np.linspace(0.0, 1.0, samples)
    joints = joint_trajectory(robot, path(t))
    effort = actuator_efforts(robot, joints)
    data = model.createData()
    closure_gap = max((np.abs(closure_residuals(robot, data, q)).max(initial=0.0) for q in joints.q), default=0.0)
    solver_gap = None
    if robot.closed_form is not None:
        numeric = joint_trajectory(robot, path(t), "numeric")
        solver_gap = float(np.abs(numeric.q - joints.q).max())
    forward = forward_accelerations(robot, joints, effort)
    power = (effort * joints.v[:, robot.actuated_v_indices]).sum(axis=1)
    return CheckReport(samples=samples, closure_gap=float(closure_gap), solver_gap=solver_gap,
                       forward_error=float(np.abs(forward - joints.a).max()),
                       power_error_W=float(np.abs(power - energy_rate(robot, path, t)).max()),
                       peak_power_W=float(np.abs(effort * joints.v[:, robot.actuated_v_indices]).max()),
                       peak_effort=np.abs(effort).max(axis=0))
