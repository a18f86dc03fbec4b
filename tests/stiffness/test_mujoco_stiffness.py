"""MuJoCo, an independent engine, settles each robot's springs under a constant load on the tool to the deflection
placement's compliance predicts.

The MuJoCo model is built from the robot's tree and closures (tests/support/mujoco_model.py); each actuated joint
gets MuJoCo's joint spring (``stiffness`` about ``springref`` = the unloaded posture) and a damping near critical,
gravity is off, the load is applied by ``xfrc_applied`` and the motion integrated until it rests. Tolerance 5e-4
relative: MuJoCo's closures are soft (equality constraints with a 0.1 ms time constant, hence the Orthoglide's test
springs of 1e5 N/m, soft enough beside them) and the load's own nonlinearity is of the order δ/L, about 3e-5 for a
10 µm deflection; seen: 3e-5 (Orthoglide) and 4e-5 (UR5).
"""

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.kinematics import joint_trajectory
from placement.stiffness import JointSprings, tool_compliance
from placement.workshop.checks import demo_trajectory

mujoco = pytest.importorskip("mujoco", reason="the optional test extra 'mujoco' is not installed")
mujoco_model = pytest.importorskip("tests.support.mujoco_model")

AGREEMENT = 5e-4

CASES = {  # robot: springs (N/m or N·m/rad), load on the tool (N), settling time (s), time step (s)
    "ur5": ([6e4] * 3 + [1.6e4] * 3, [3.0, -5.0, 8.0], 1.0, 1e-4),
    "orthoglide": ([1e5] * 3, [1.0, -0.5, 0.8], 0.3, 1e-5),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_mujoco_settles_to_the_predicted_deflection(name):
    stiffness, load, seconds, step = CASES[name]
    robot = load_robot(name)
    joints = joint_trajectory(robot, demo_trajectory(robot)(np.array([0.13])))
    q0 = joints.q[0]
    simulation = mujoco_model.Simulation(robot)
    model = simulation.model
    model.opt.gravity[:] = 0.0
    model.opt.timestep = step
    inertia = pin.crba(robot.model, robot.model.createData(), q0) + np.diag(robot.model.armature)
    for actuator, k in zip(robot.actuators, stiffness):
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, actuator.joint)
        model.jnt_stiffness[joint] = k
        model.qpos_spring[model.jnt_qposadr[joint]] = q0[actuator.q_index]
        model.dof_damping[model.jnt_dofadr[joint]] = 2 * np.sqrt(k * inertia[actuator.v_index, actuator.v_index])
    simulation.set_state(q0, np.zeros(robot.model.nv))
    tool = simulation.run(np.zeros((int(seconds / step), len(robot.actuators))), np.array(load))
    springs = JointSprings(np.array(stiffness), np.zeros(0, dtype=int), np.zeros(0))
    predicted = tool_compliance(springs, joints)[0][:3, :3] @ np.array(load)
    assert np.linalg.norm(tool[-1] - tool[0] - predicted) <= AGREEMENT * np.linalg.norm(predicted)
    assert np.linalg.norm(tool[-1] - tool[int(0.9 * len(tool))]) <= 0.1 * AGREEMENT * np.linalg.norm(predicted)  # at rest
