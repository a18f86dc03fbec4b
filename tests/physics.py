"""Physics checks shared by the tests: forward dynamics round trip and power balance."""

from __future__ import annotations

from typing import Callable

import numpy as np
import pinocchio as pin

from placement.kinematics import LWA, JointTrajectory, TaskTrajectory, joint_trajectory
from placement.robot import Robot


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
    return sum(w * mechanical_energy(robot, joint_trajectory(robot, path(t_s + s * step_s), method))
               for s, w in weights.items()) / step_s
