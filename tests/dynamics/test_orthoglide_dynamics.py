"""Orthoglide inverse dynamics against what is known of the machine: the lumped model is only an approximation, and
a static hold at the isotropic point loads one slider.

The forward round trip, the power balance and the massless-leg limit (the lumped model of the closed-form plug-in)
are checked with every other robot's in tests/robot/test_contract.py.
"""

import numpy as np
import pinocchio as pin

from placement import load_robot
from placement.dynamics.inverse import inverse_dynamics
from tests.support.trajectories import orthoglide_path

closed_form = load_robot("orthoglide").plugin


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
