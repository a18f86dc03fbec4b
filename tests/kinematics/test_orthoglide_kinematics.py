"""Orthoglide kinematics: closed form = generic solver, closures hold, Jacobians, known points."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from placement import load_robot
from placement.kinematics import joint_trajectory
from placement.kinematics.exceptions import UnreachableError
from placement.kinematics.trajectories import TaskTrajectory
from placement.robot.closures import closure_jacobian, closure_residuals
from tests.support.trajectories import orthoglide_path

closed_form = load_robot("orthoglide").plugin

LEG = 0.2 / (1 / np.sqrt(6) + 1 / np.sqrt(18))
Q_PLUS, Q_MINUS = LEG / np.sqrt(18), -LEG / np.sqrt(6)
SLIDERS = [0, 6, 12]  # q indices of slider_x, slider_y, slider_z


def test_sliders_are_the_actuators_in_axis_order(orthoglide):
    assert [a.q_index for a in orthoglide.actuators] == SLIDERS


def static(points):
    points = np.atleast_2d(np.asarray(points, dtype=float))
    return TaskTrajectory(points, np.zeros_like(points), np.zeros_like(points))


def test_closed_form_equals_generic_solver_along_a_path(orthoglide):
    task = orthoglide_path(np.linspace(0.0, 1.0, 150))
    closed = joint_trajectory(orthoglide, task, "closed_form")
    numeric = joint_trajectory(orthoglide, task, "numeric")
    for field in ("q", "v", "a", "basis", "task_map"):
        np.testing.assert_allclose(getattr(closed, field), getattr(numeric, field), atol=1e-9, err_msg=field)


@settings(max_examples=15, deadline=None)
@given(st.lists(st.floats(Q_MINUS, Q_PLUS), min_size=3, max_size=3),
       st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3),
       st.lists(st.floats(-20.0, 20.0), min_size=3, max_size=3))
def test_closed_form_equals_generic_solver_anywhere_in_the_cube(p, v, a):
    robot = load_robot("orthoglide")
    task = TaskTrajectory(np.array([p]), np.array([v]), np.array([a]))
    closed = joint_trajectory(robot, task, "closed_form")
    numeric = joint_trajectory(robot, task, "numeric")
    for field in ("q", "v", "a", "task_map"):
        np.testing.assert_allclose(getattr(closed, field), getattr(numeric, field), atol=1e-8, err_msg=field)


def test_closures_hold_along_a_path(orthoglide):
    joints = joint_trajectory(orthoglide, orthoglide_path(np.linspace(0.0, 1.0, 100)), "closed_form")
    data = orthoglide.model.createData()
    worst = max(np.abs(closure_residuals(orthoglide, data, q)).max() for q in joints.q)
    assert worst < 1e-13
    # Joint velocities lie in the closure null space: J_c·v = 0.
    worst_rate = max(np.abs(closure_jacobian(orthoglide, data, q) @ v).max() for q, v in zip(joints.q, joints.v))
    assert worst_rate < 1e-12


def test_actuator_jacobian_equals_finite_differences_and_the_formula(orthoglide):
    points = orthoglide_path(np.linspace(0.0, 1.0, 40)).position_m
    joints = joint_trajectory(orthoglide, static(points), "closed_form")
    inverse = np.linalg.inv(joints.task_map)  # d rho / d p
    step = 1e-6
    for axis in range(3):
        offset = np.zeros(3)
        offset[axis] = step
        plus = joint_trajectory(orthoglide, static(points + offset), "closed_form").q[:, SLIDERS]
        minus = joint_trajectory(orthoglide, static(points - offset), "closed_form").q[:, SLIDERS]
        np.testing.assert_allclose(inverse[:, :, axis], (plus - minus) / (2 * step), atol=1e-8)
    np.testing.assert_allclose(inverse, closed_form.jacobian(points, LEG), atol=1e-12)


def test_rates_and_accelerations_equal_time_finite_differences(orthoglide):
    t, h = np.linspace(0.0, 1.0, 50), 1e-5
    joints = joint_trajectory(orthoglide, orthoglide_path(t), "numeric")
    plus = joint_trajectory(orthoglide, orthoglide_path(t + h), "closed_form")
    minus = joint_trajectory(orthoglide, orthoglide_path(t - h), "closed_form")
    np.testing.assert_allclose(joints.v, (plus.q - minus.q) / (2 * h), atol=1e-7)
    np.testing.assert_allclose(joints.a, (plus.v - minus.v) / (2 * h), atol=1e-5)


def test_jacobian_is_identity_at_the_isotropic_point(orthoglide):
    for method in ("closed_form", "numeric"):
        joints = joint_trajectory(orthoglide, static([0.0, 0.0, 0.0]), method)
        np.testing.assert_allclose(joints.task_map[0], np.eye(3), atol=1e-12)
        np.testing.assert_allclose(joints.q[0, SLIDERS], LEG, atol=1e-12)


def test_velocity_transmission_factors_are_one_half_and_two_at_q_plus_and_q_minus(orthoglide):
    diagonal = np.ones(3) / np.sqrt(3)
    joints = joint_trajectory(orthoglide, static([[Q_PLUS] * 3, [Q_MINUS] * 3]), "closed_form")
    jacobian = np.linalg.inv(joints.task_map)  # rhodot = J·pdot
    factors = np.linalg.norm(jacobian @ diagonal, axis=1)
    np.testing.assert_allclose(factors, [0.5, 2.0], atol=1e-12)
    # Over all directions, the factors stay within [1/2, 2] at both points.
    singular = np.linalg.svd(jacobian, compute_uv=False)
    assert singular.min() == pytest.approx(0.5, abs=1e-12) and singular.max() == pytest.approx(2.0, abs=1e-12)


def test_slider_travel_over_the_cube_spans_exactly_the_derived_limits(orthoglide):
    """rho_min = L/sqrt(6) = 0.126795 m at Q-; rho_max = L(1 + 1/sqrt(18)) = 0.383788 m at (Q+_x, 0, 0).

    The paper prints 0.126 and 0.383 m (truncated); the workspace sides pass through 0.
    """
    axis = np.union1d(np.linspace(Q_MINUS, Q_PLUS, 41), [0.0])
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    rho = joint_trajectory(orthoglide, static(grid), "closed_form").q[:, SLIDERS]
    assert rho.min() == pytest.approx(LEG / np.sqrt(6), abs=1e-12)
    assert rho.max() == pytest.approx(LEG * (1 + 1 / np.sqrt(18)), abs=1e-12)
    assert (round(rho.min(), 6), round(rho.max(), 6)) == (0.126795, 0.383788)
    limits = orthoglide.actuators[0]
    assert (limits.position_min, limits.position_max) == pytest.approx((rho.min(), rho.max()), abs=1e-12)


@pytest.mark.parametrize("method", ["closed_form", "numeric"])
def test_unreachable_positions_are_reported_not_nan(orthoglide, method):
    points = np.array([[0.0, 0.0, 0.0], [0.0, 0.35, 0.0], [0.01, 0.0, 0.0]])
    with pytest.raises(UnreachableError) as error:
        joint_trajectory(orthoglide, static(points), method)
    assert error.value.sample_indices == [1]
    assert error.value.n_unreachable == 1


def test_compiled_plugin_gives_the_taylor_arithmetic_numbers_bit_for_bit(orthoglide):
    """The plug-in's compiled solver (which the closed_form solver runs) against its Taylor arithmetic, at every
    sample: inside the cube, beyond the legs' reach, and where a square root or an arc tangent's radius is zero."""
    from placement.kinematics.closed_form import ClosedFormSolver, _by_taylor_arithmetic

    rng = np.random.default_rng(7)
    n = 3000
    points = rng.uniform(-0.3, 0.3, (n, 3))
    points[:4] = [[0.0, LEG, 0.0], [0.0, 0.0, 0.0], [LEG, 0.0, 0.0], [Q_MINUS] * 3]  # sqrt(0), O_b, a leg stretched
    task = TaskTrajectory(points, rng.normal(0.0, 1.0, (n, 3)), rng.normal(0.0, 10.0, (n, 3)))
    compiled = closed_form.make_compiled_closed_form(orthoglide.model)
    by_kernel = compiled(task.position_m, task.velocity_m_s, task.acceleration_m_s2)
    by_taylor = _by_taylor_arithmetic(orthoglide, task.position_m, task.velocity_m_s, task.acceleration_m_s2)
    assert set(by_kernel[0]) == set(orthoglide.model.names[1:]) and by_kernel[0] == by_taylor[0]
    for kernel, taylor, what in zip(by_kernel[1:], by_taylor[1:], ("value", "rate", "acceleration", "gradient")):
        np.testing.assert_array_equal(kernel, taylor, err_msg=what)
    solver = ClosedFormSolver(orthoglide, 1)
    assert solver._compiled is not None  # the solver runs the compiled plug-in
    reachable = solver.solve(task)[1]
    assert 0 < reachable.sum() < n and not reachable[0] and reachable[1]
