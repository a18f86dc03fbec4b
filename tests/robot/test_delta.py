"""The Delta (ABB IRB 340 dimensions), solved by the generic closed-loop machinery, proved by physics.

The reference for the kinematics is Williams' closed form (tests/delta_analytic.py). Nothing here
uses the placement kinematics to compute the reference. The forward round trip, the power balance and
the massless-leg limit (the lumped model of tests/delta_analytic.py) are checked with every other
robot's in tests/robot/test_contract.py.
"""

import json
import math

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.dynamics.inverse import inverse_dynamics
from placement.kinematics import joint_trajectory
from placement.workshop.catalog import builtin_robots_dir
from tests.support.delta_analytic import lumped_torques_Nm, williams_inverse_kinematics
from tests.support.generators import urdf_generator
from tests.support.paths import CIRCLE
from tests.support.trajectories import lissajous

DELTA_DIR = builtin_robots_dir() / "delta"


@pytest.fixture
def delta():
    """A freshly loaded Delta (tests may modify its model)."""
    return load_robot("delta")


def platform_path(t_s):
    """A 3-D platform path inside the workspace box, peak speed about 1.7 m/s."""
    return lissajous(t_s, center_m=(0.05, -0.08, -1.0), amplitude_m=(0.25, 0.2, 0.08),
                     frequency_hz=(1.1, 1.7, 0.9), phase_rad=(0.3, 1.1, 2.0))


def test_generic_solver_equals_williams_closed_form(delta):
    task = platform_path(np.linspace(0.0, 2.0, 120))
    joints = joint_trajectory(delta, task, "numeric")
    theta, theta_dot, theta_ddot, _ = williams_inverse_kinematics(task.position_m, task.velocity_m_s,
                                                                  task.acceleration_m_s2)
    act = delta.actuated_v_indices
    assert np.ptp(theta, axis=0).min() > 0.3  # the path moves every arm
    np.testing.assert_allclose(joints.q[:, delta.actuated_q_indices], theta, rtol=0, atol=1e-9)
    np.testing.assert_allclose(joints.v[:, act], theta_dot, rtol=0, atol=1e-9)
    np.testing.assert_allclose(joints.a[:, act], theta_ddot, rtol=0, atol=1e-8)


def test_real_legs_differ_from_the_lumped_model(delta):
    """The arms and rods weigh: with them the efforts leave the lumped model by newton-metres."""
    model = delta.model
    task = platform_path(np.linspace(0.0, 2.0, 150))
    result = inverse_dynamics(delta, task)
    lumped = lumped_torques_Nm(task, model.inertias[model.getJointId("wrist_1")].mass,
                               np.array([a.reflected_inertia for a in delta.actuators]), model.gravity.linear,
                               np.zeros(3))
    assert np.abs(result.effort - lumped).max() > 1.0


def rotated_120_deg(placement):
    """The placement turned by +120 degrees about the base's vertical axis (leg 1 -> 2 -> 3)."""
    turn = 2 * math.pi / 3
    x, y = placement[0], placement[1]
    return np.array([math.cos(turn) * x - math.sin(turn) * y, math.sin(turn) * x + math.cos(turn) * y,
                     placement[2], placement[3] + turn, placement[4], placement[5]])


def test_a_path_turned_by_120_degrees_costs_the_same_energy_with_the_actuators_permuted(delta):
    evaluator = Evaluator(delta, load_path(CIRCLE), EvaluatorSettings(time_step_s=0.004, workers=1))
    placement = np.array([0.15, -0.10, -1.00, 0.3, 0.0, 0.0])
    energy = evaluator.detail(placement).energy.per_actuator_J
    turned = evaluator.detail(rotated_120_deg(placement)).energy.per_actuator_J
    assert energy.max() > 1.05 * energy.min()  # the placement loads the arms unequally: the permutation shows
    np.testing.assert_allclose(turned, np.roll(energy, 1), rtol=1e-6)


def test_committed_urdf_is_what_the_generator_writes():
    module = urdf_generator(DELTA_DIR)
    assert (DELTA_DIR / "delta.urdf").read_text() == module.urdf_text()


def test_the_command_line_places_the_circle_on_the_delta(tmp_path):
    # A small budget (two generations of six, a coarse sampling) runs every stage of the search.
    out = tmp_path / "result.json"
    assert main(["--robot", "delta", "--path", str(CIRCLE), "--minimize", "--time-step", "0.05", "--generations", "2",
                 "--population", "6", "--quiet", "--json", str(out)]) == 0
    best = json.loads(out.read_text())["best"]
    assert best["feasible"] and 0.0 < best["energy_J"] < math.inf
