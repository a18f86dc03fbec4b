"""Placement frames: the paper's matrix, and energy invariances of the placed path."""

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.exceptions import PlacementError
from placement.path import load_path
from placement.placing.transform import rotation_zyx, transform_path_to_base
from placement.search.space import PlacementSpace
from tests.support.paths import EXAMPLE

angles = st.floats(-np.pi, np.pi)


@settings(max_examples=50, deadline=None)
@given(angles, angles, angles)
def test_rotation_is_the_papers_matrix(phi, theta, psi):
    c, s = np.cos, np.sin
    paper = np.array([
        [c(phi) * c(theta), c(phi) * s(theta) * s(psi) - s(phi) * c(psi), c(phi) * s(theta) * c(psi) + s(phi) * s(psi)],
        [s(phi) * c(theta), s(phi) * s(theta) * s(psi) + c(phi) * c(psi), s(phi) * s(theta) * c(psi) - c(phi) * s(psi)],
        [-s(theta), c(theta) * s(psi), c(theta) * c(psi)]])
    np.testing.assert_allclose(rotation_zyx(phi, theta, psi), paper, atol=1e-15)
    np.testing.assert_allclose(paper, Rotation.from_euler("ZYX", [phi, theta, psi]).as_matrix(), atol=1e-14)


def test_transform_moves_and_turns_the_path():
    samples = load_path(EXAMPLE).sample()
    task, force = transform_path_to_base(samples, np.array([[0.01, 0.02, 0.03, np.pi / 2, 0.0, 0.0]]))
    # A at (-15, -30) mm turns to (30, -15) mm and moves by the origin.
    np.testing.assert_allclose(task.position_m[0], [0.04, 0.005, 0.03], atol=1e-15)
    np.testing.assert_allclose(task.velocity_m_s[0], [0.0, 0.66, 0.0], atol=1e-15)
    np.testing.assert_allclose(force[0], [-215.0, -10.0, 25.0], atol=1e-12)


def test_placement_space_rejects_unknown_variables():
    with pytest.raises(PlacementError, match="unknown placement variable"):
        PlacementSpace(free=("x", "w"), lower=np.zeros(2), upper=np.ones(2), fixed=np.zeros(6))


def test_rectangle_turned_half_a_turn_costs_the_same(orthoglide):
    """The paper's segments are independent: turning the rectangle by 180° gives the same set."""
    evaluator = Evaluator(orthoglide, load_path(EXAMPLE), EvaluatorSettings(regeneration="clip"))
    placements = np.array([[-0.05, 0.01, -0.02, 0.3, 0.0, 0.0], [-0.05, 0.01, -0.02, 0.3 + np.pi, 0.0, 0.0]])
    energy = evaluator.evaluate(placements).value
    assert energy[0] == pytest.approx(energy[1], rel=1e-12)


@pytest.mark.parametrize("mode", ["clip", "signed"])
def test_cyclic_symmetry_of_the_orthoglide(orthoglide, mode):
    """Without gravity the machine is invariant under x -> y -> z: a path turned that way costs
    the same, actuator energies permuted."""
    orthoglide.model.gravity = pin.Motion.Zero()
    cycle = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # e_x -> e_y -> e_z -> e_x
    origin, rotation = np.array([-0.04, 0.02, -0.03]), rotation_zyx(0.4, 0.2, -0.3)
    turned = Rotation.from_matrix(cycle @ rotation).as_euler("ZYX")
    evaluator = Evaluator(orthoglide, load_path(EXAMPLE), EvaluatorSettings(regeneration=mode))
    first = evaluator.detail(np.concatenate([origin, [0.4, 0.2, -0.3]]))
    second = evaluator.detail(np.concatenate([cycle @ origin, turned]))
    assert second.energy.total_J == pytest.approx(first.energy.total_J, rel=1e-10)
    np.testing.assert_allclose(second.energy.per_actuator_J, np.roll(first.energy.per_actuator_J, 1), rtol=1e-10)
