"""A second closed-loop mechanism, solved only by the generic machinery, checked independently."""

import numpy as np
import pinocchio as pin

from placement.dynamics.inverse import inverse_dynamics
from placement.kinematics import joint_trajectory
from placement.robot.checks import energy_rate, forward_accelerations
from tests.support import fivebar_analytic as analytic
from tests.support.trajectories import lissajous

TIP_FORCE_N = np.array([4.0, -6.0, 0.0])


def tip_path(t):
    return lissajous(t, center_m=(0.01, 0.30, 0.0), amplitude_m=(0.05, 0.04, 0.0), frequency_hz=(1.3, 0.8, 1.0),
                     phase_rad=(0.2, 0.9, 0.0))


def test_generic_kinematics_equal_the_analytic_inverse_kinematics(fivebar):
    task = tip_path(np.linspace(0.0, 2.0, 80))
    joints = joint_trajectory(fivebar, task)
    p, v, a = task.position_m, task.velocity_m_s, task.acceleration_m_s2
    expected = analytic.joint_angles(analytic.Taylor2(p[:, 0], v[:, 0], a[:, 0]),
                                     analytic.Taylor2(p[:, 1], v[:, 1], a[:, 1]))
    for name, value in expected.items():
        index = fivebar.model.joints[fivebar.model.getJointId(name)].idx_q
        np.testing.assert_allclose(joints.q[:, index], value.v, atol=1e-10, err_msg=name)
        np.testing.assert_allclose(joints.v[:, index], value.d1, atol=1e-10, err_msg=name)
        np.testing.assert_allclose(joints.a[:, index], value.d2, atol=1e-9, err_msg=name)


def test_forward_dynamics_reproduces_the_prescribed_accelerations(fivebar):
    task = tip_path(np.linspace(0.0, 2.0, 30))
    load = np.tile(TIP_FORCE_N, (len(task), 1))
    result = inverse_dynamics(fivebar, task, load)
    accelerations = forward_accelerations(fivebar, result.joints, result.effort, load)
    assert np.abs(accelerations - result.joints.a).max() <= 1e-8


def test_power_balance(fivebar):
    t = np.linspace(0.0, 2.0, 50)
    task = tip_path(t)
    load = np.tile(TIP_FORCE_N, (len(t), 1))
    result = inverse_dynamics(fivebar, task, load)
    power_in = (result.effort * result.velocity).sum(axis=1) + (load * task.velocity_m_s).sum(axis=1)
    peak = np.abs(result.effort * result.velocity).max()
    assert np.abs(power_in - energy_rate(fivebar, tip_path, t)).max() <= 1e-6 * peak


def test_every_test_robot_passes_the_physics_check(fivebar):
    from placement.robot import load_robot, robot_names
    from placement.robot.checks import check_robot

    for name in robot_names():
        report = check_robot(load_robot(name), samples=40)
        assert report.passed and report.power_error_W <= 1e-6 * report.peak_power_W, name


def test_massless_distal_links_equal_the_lumped_model(fivebar):
    model = fivebar.model
    tip = model.frames[fivebar.end_effector_frame_id].placement.translation
    model.inertias[model.getJointId("b1")] = pin.Inertia(analytic.PAYLOAD_MASS, tip, np.zeros((3, 3)))
    model.inertias[model.getJointId("b2")] = pin.Inertia.Zero()
    task = tip_path(np.linspace(0.0, 2.0, 60))
    load = np.tile(TIP_FORCE_N, (len(task), 1))
    result = inverse_dynamics(fivebar, task, load)
    rotor = fivebar.actuators[0].reflected_inertia  # the geared motor's inertia at the joint
    lumped = analytic.lumped_torques(task.position_m, task.velocity_m_s, task.acceleration_m_s2, load,
                                     prox_inertia_A_kg_m2=analytic.PROX_INERTIA_A + rotor)
    assert np.abs(result.effort).max() > 1.0
    assert np.abs(result.effort - lumped).max() <= 1e-9 * np.abs(result.effort).max()
