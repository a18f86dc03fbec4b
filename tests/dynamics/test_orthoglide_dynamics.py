"""Orthoglide inverse dynamics proved by physics: forward round trip, power balance, lumped limit."""

import numpy as np
import pinocchio as pin
import pytest

from placement.dynamics.inverse import inverse_dynamics
from placement.robot import load_robot
from placement.robot.checks import energy_rate, forward_accelerations
from tests.support.trajectories import orthoglide_path

closed_form = load_robot("orthoglide").plugin

# Groove-milling load of the paper on the tool (N), turned to an oblique direction.
CUTTING_FORCE_N = np.array([10.0, -215.0, 25.0])


def load_on(task):
    return np.tile(CUTTING_FORCE_N, (len(task), 1))


@pytest.mark.parametrize("method", ["closed_form", "numeric"])
def test_forward_dynamics_reproduces_the_prescribed_accelerations(orthoglide, method):
    # The welded wrist stubs of legs y and z carry no inertia; a tiny armature keeps the forward
    # solver's KKT system regular. The same model serves the inverse and the forward computation.
    orthoglide.model.armature[np.setdiff1d(np.arange(18), orthoglide.actuated_v_indices)] += 1e-9
    task = orthoglide_path(np.linspace(0.0, 1.0, 25))
    result = inverse_dynamics(orthoglide, task, load_on(task), method)
    accelerations = forward_accelerations(orthoglide, result.joints, result.effort, load_on(task))
    assert np.abs(accelerations - result.joints.a).max() <= 1e-8


def test_power_balance_with_gravity_rotor_inertia_and_load(orthoglide):
    t = np.linspace(0.0, 1.0, 60)
    task = orthoglide_path(t)
    result = inverse_dynamics(orthoglide, task, load_on(task))
    power_in = (result.effort * result.velocity).sum(axis=1) + (load_on(task) * task.velocity_m_s).sum(axis=1)
    rate = energy_rate(orthoglide, orthoglide_path, t)
    peak = np.abs(result.effort * result.velocity).max()
    assert peak > 50.0  # the test path is dynamic enough to mean something
    assert np.abs(power_in - rate).max() <= 1e-6 * peak


def test_massless_legs_equal_the_lumped_analytic_model(orthoglide):
    model = orthoglide.model
    for axis in "xyz":
        for body in ("yoke", "bar1", "bar2", "far"):
            model.inertias[model.getJointId(f"{body}_{axis}")] = pin.Inertia.Zero()
    task = orthoglide_path(np.linspace(0.0, 1.0, 200))
    result = inverse_dynamics(orthoglide, task, load_on(task))
    lumped = closed_form.lumped_actuator_forces(
        task.position_m, task.velocity_m_s, task.acceleration_m_s2, closed_form.leg_length_m(model),
        platform_mass_kg=model.inertias[model.getJointId("wrist_x")].mass,
        slider_mass_kg=model.inertias[model.getJointId("slider_x")].mass,
        slider_inertia_kg=orthoglide.actuators[0].reflected_inertia,
        gravity_m_s2=model.gravity.linear, external_force_N=load_on(task))
    assert np.abs(result.effort).max() > 100.0
    assert np.abs(result.effort - lumped).max() <= 1e-9 * np.abs(result.effort).max()


def test_real_legs_differ_from_the_lumped_model(orthoglide):
    """The legs' own inertia matters: the lumped model is an approximation of the exact one."""
    task = orthoglide_path(np.linspace(0.0, 1.0, 200))
    result = inverse_dynamics(orthoglide, task)
    model = orthoglide.model
    lumped = closed_form.lumped_actuator_forces(
        task.position_m, task.velocity_m_s, task.acceleration_m_s2, closed_form.leg_length_m(model),
        model.inertias[model.getJointId("wrist_x")].mass, model.inertias[model.getJointId("slider_x")].mass,
        orthoglide.actuators[0].reflected_inertia, model.gravity.linear)
    assert np.abs(result.effort - lumped).max() > 1.0


def test_static_hold_against_gravity_loads_only_the_vertical_slider_at_the_isotropic_point(orthoglide):
    """At O_b with legs along the axes, gravity on the platform goes straight into slider z."""
    model = orthoglide.model
    for axis in "xyz":
        for body in ("yoke", "bar1", "bar2", "far"):
            model.inertias[model.getJointId(f"{body}_{axis}")] = pin.Inertia.Zero()
    from placement.kinematics import TaskTrajectory

    zeros = np.zeros((1, 3))
    result = inverse_dynamics(orthoglide, TaskTrajectory(zeros, zeros, zeros))
    platform = model.inertias[model.getJointId("wrist_x")].mass
    slider = model.inertias[model.getJointId("slider_x")].mass
    np.testing.assert_allclose(result.effort[0], [0.0, 0.0, (platform + slider) * 9.81], atol=1e-9)
