"""Kinetostatic and shaking objectives against published values and independent Pinocchio algorithms."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.objectives.kinetostatics import dimensionless_task_map
from placement.objectives.shaking import base_wrench


@pytest.fixture(scope="module")
def orthoglide():
    return load_robot("orthoglide")


@pytest.fixture(scope="module")
def tiny_path(tmp_path_factory):
    """A 10 µm line: the indices of a path this short are those of its start point."""
    file = tmp_path_factory.mktemp("paths") / "tiny.yaml"
    file.write_text("name: tiny\nunits: m\nshape: {type: polyline, points: [[0, 0], [0.00001, 0]]}\nfeed_m_s: 0.01\n")
    return load_path(file)


def _at_points(robot, path, objective, names):
    points = robot.workspace.points_m
    placements = np.array([[*points[name], 0.0, 0.0, 0.0] for name in names])
    return Evaluator(robot, path, EvaluatorSettings(objective=objective)).evaluate(placements).value


def test_orthoglide_transmission_factors_are_one_at_the_isotropic_point_and_two_at_the_cube_corners(orthoglide, tiny_path):
    # Chablat and Wenger sized the Orthoglide so that its velocity transmission factors stay in
    # [1/2, 2] over the cube, reaching the bounds at Q+ and Q-; J = I at O_b.
    factor = _at_points(orthoglide, tiny_path, "transmission", ["O_b", "Q_plus", "Q_minus"])
    np.testing.assert_allclose(factor, [1.0, 2.0, 2.0], atol=5e-4)
    condition = _at_points(orthoglide, tiny_path, "dexterity", ["O_b", "C"])
    assert condition[0] == pytest.approx(1.0, abs=5e-4)
    assert condition[1] > 1.01


def test_the_condition_number_does_not_depend_on_the_length_used_for_a_translational_slider_machine(orthoglide):
    rng = np.random.default_rng(3)
    task_map = rng.normal(size=(20, 3, 3))
    np.testing.assert_allclose(dimensionless_task_map(orthoglide, task_map), task_map, rtol=1e-14)


@pytest.mark.parametrize("name", ["orthoglide", "ur5", "delta"])
def test_the_base_wrench_is_the_momentum_rate_of_pinocchio_centre_of_mass_and_centroidal_dynamics(name):
    robot = load_robot(name)
    rng = np.random.default_rng(7)
    q = np.array([pin.randomConfiguration(robot.model) for _ in range(6)])
    v, a = rng.normal(size=(2, 6, robot.model.nv))
    wrench = base_wrench(robot, q, v, a)
    data = robot.model.createData()
    for k in range(6):
        pin.centerOfMass(robot.model, data, q[k], v[k], a[k])
        mass, com, com_acceleration = data.mass[0], data.com[0], data.acom[0]
        centroidal = pin.computeCentroidalMomentumTimeVariation(robot.model, data, q[k], v[k], a[k])
        np.testing.assert_allclose(wrench[k, :3], mass * com_acceleration, atol=1e-10)
        np.testing.assert_allclose(wrench[k, 3:], centroidal.angular + np.cross(com, mass * com_acceleration), atol=1e-10)


def test_a_robot_at_rest_does_not_shake_its_base_whatever_gravity_does():
    robot = load_robot("ur5")
    q = np.array([pin.randomConfiguration(robot.model) for _ in range(4)])
    rest = np.zeros((4, robot.model.nv))
    np.testing.assert_allclose(base_wrench(robot, q, rest, rest), 0.0, atol=1e-12)


def test_the_shaking_force_grows_with_the_square_of_the_feed_on_the_orthoglide(orthoglide):
    # Constant feed on each segment: every acceleration is centripetal-like (v² times geometry),
    # so doubling the feed multiplies the inertial forces by four.
    path = load_path("examples/rect.yaml")
    placement = np.array([[-0.03, -0.03, -0.03, 0.3, 0.0, 0.0]])
    slow = Evaluator(orthoglide, path, EvaluatorSettings(objective="shaking_force")).evaluate(placement).value[0]
    fast = Evaluator(orthoglide, dataclasses.replace(path, feed_m_s=2 * path.feed_m_s),
                     EvaluatorSettings(objective="shaking_force")).evaluate(placement).value[0]
    assert fast / slow == pytest.approx(4.0, rel=1e-6)
