"""The loaded (complementary) correction: under a finite load the tangent compliance T·(K_ρ − K_C)⁻¹·Tᵀ at the loaded
posture equals the finite-difference tangent of the full nonlinear equilibrium (tests/support/static_equilibrium.py),
where the linear compliance alone does not."""

import numpy as np
import pinocchio as pin
import pytest

from placement import TaskTrajectory, load_robot
from placement.kinematics import joint_trajectory
from placement.kinematics.base import solver_for
from placement.stiffness import joint_springs, tool_compliance
from placement.stiffness.loaded import complementary_stiffness, loaded_compliance
from placement.workshop.checks import demo_trajectory
from tests.support.static_equilibrium import equilibrium, tool_pose

TANGENT_RELATIVE = 1e-6
PRELOAD_DEFLECTION_M = 1e-3  # the finite load moves the tool about this far: K_C is then of the order 1e-3 of K


@pytest.mark.parametrize("name", ["orthoglide", "ur5"])
def test_the_loaded_compliance_is_the_tangent_of_the_nonlinear_equilibrium(name):
    robot = load_robot(name)
    q0 = joint_trajectory(robot, demo_trajectory(robot)(np.array([0.13]))).q[0]
    springs = joint_springs(robot)
    by_v = {a.v_index: k for a, k in zip(robot.actuators, springs.actuator_stiffness)}
    dimension = robot.task_dimension
    direction = np.zeros(dimension)
    direction[:3] = [0.3, -0.8, 0.5]
    start = joint_trajectory(robot, demo_trajectory(robot)(np.array([0.13])))
    preload = direction * PRELOAD_DEFLECTION_M / np.linalg.norm(tool_compliance(springs, start)[0] @ direction)
    loaded_q = equilibrium(robot, q0, by_v, preload)
    pose = tool_pose(robot, robot.model.createData(), loaded_q)
    still = np.zeros((1, 3))
    task = TaskTrajectory(pose.translation[None], still, still, *((pose.rotation[None], still, still)
                                                                  if dimension == 6 else ()))
    joints = joint_trajectory(robot, task)
    assert np.abs(pin.difference(robot.model, joints.q[0], loaded_q)).max() < 1e-9  # the same posture
    stiffness_c = complementary_stiffness(solver_for(robot), task, joints, preload[None])
    predicted = loaded_compliance(springs, joints, stiffness_c)[0]
    step = 1e-3 * np.linalg.norm(preload)
    tangent = np.column_stack([_moved(robot, equilibrium(robot, q0, by_v, preload - step * e),
                                      equilibrium(robot, q0, by_v, preload + step * e), dimension) / (2 * step)
                               for e in np.eye(dimension)])
    scale = np.abs(predicted).max()
    assert np.abs(tangent - predicted).max() <= TANGENT_RELATIVE * scale
    linear = tool_compliance(springs, joints)[0]
    assert np.abs(tangent - linear).max() > 10 * TANGENT_RELATIVE * scale  # the correction matters at this load


def _moved(robot, before, after, dimension):
    """The tool's move from configuration ``before`` to ``after``: translation, then the rotation vector of
    R_after·R_beforeᵀ (world frame) for a pose task, the twist the compliance maps a load to."""
    data = robot.model.createData()
    start, end = tool_pose(robot, data, before), tool_pose(robot, data, after)
    moved = end.translation - start.translation
    return moved if dimension == 3 else np.concatenate([moved, pin.log3(end.rotation @ start.rotation.T)])
