"""Redundant joints profiled along the path: the seven-axis Panda, its knots as placement variables, --lock.

Physics, not snapshots: the resolved motion reaches every target and follows its profile, its rates are the
derivatives of its positions, its efforts and energy are those Pinocchio's RNEA gives on the same joint
trajectory, and a joint held still leaves the other joints as the six-axis arm moves them.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.energy.integration import electric_energy
from placement.energy.trace import motor_trace
from placement.evaluation.evaluator import Evaluator, denser
from placement.kinematics.base import task_error
from placement.path import load_path
from placement.placing.profiles import joint_profiles, knot_shares, path_share, redundant_variables
from placement.placing.transform import placed_task
from placement.robot.exceptions import RobotFileError
from placement.robot.sidecar import Redundancy
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.space import default_space
from placement.workshop.load import edit_redundancy, robot_from_sidecar
from tests.support.paths import EXAMPLES
from tests.support.rnea_reference import rnea_actuator_efforts

CIRCLE, RECT, CONTOUR = EXAMPLES / "circle.yaml", EXAMPLES / "rect.yaml", EXAMPLES / "contour.yaml"
BENT = np.array([0.40, 0.0, 0.30, 0.2, 0.1, -0.1, -0.3, 0.4, 0.1])  # a placement with joint 3 swinging along the path


@pytest.fixture(scope="module")
def panda():
    return load_robot("panda")


@pytest.fixture(scope="module")
def locked(panda):
    return edit_redundancy(panda, {"panda_joint3": 0.0})


def test_the_panda_has_seven_axes_and_three_knots_of_joint_3(panda, locked):
    assert len(panda.actuators) == 7 and panda.redundant_joints == ("panda_joint3",)
    assert redundant_variables(panda) == ("panda_joint3@0", "panda_joint3@1", "panda_joint3@2")
    assert len(locked.actuators) == 6 and locked.redundant_joints == () and "panda_joint3" in locked.locked_joints


def test_profiles_are_smooth_and_their_rates_are_their_derivatives():
    """The chain rule of q(σ(t)): rates and accelerations against finite differences of the positions, a closed path's
    profile back to its start, each knot at its share of the path."""
    samples = load_path(CIRCLE).sample(0.0005)
    knots = np.array([[[0.1, 0.5, -0.3]]])
    position, velocity, acceleration = (values[:, 0] for values in joint_profiles(knots, samples))
    t = samples.t_s
    inner = slice(2, -2)
    assert np.abs(np.gradient(position, t) - velocity)[inner].max() < 1e-3 * np.abs(velocity).max()
    assert np.abs(np.gradient(velocity, t) - acceleration)[inner].max() < 1e-2 * np.abs(acceleration).max()
    assert position[0] == pytest.approx(0.1) and position[-1] == pytest.approx(0.1)  # closed: periodic
    sigma = path_share(samples)[0]
    for value, share in zip(knots[0, 0], knot_shares(3, True), strict=True):
        assert np.interp(share, sigma, position) == pytest.approx(value, abs=1e-4)


def test_the_resolved_motion_reaches_its_targets_and_follows_the_profile(panda):
    evaluator = Evaluator(panda, load_path(CIRCLE))
    batch = evaluator.batch(BENT[None])
    assert batch.reachable.all()
    task, _ = placed_task(panda, evaluator.samples, BENT[None])
    joints, data = batch.joints, panda.model.createData()
    q3 = joints.q[:, panda.redundant_q_indices[0]]
    np.testing.assert_allclose(q3, task.joint_position[:, 0], atol=1e-10)
    assert np.ptp(q3) > 0.3  # joint 3 moves along the path
    for k in range(0, len(joints.q), 7):
        pin.framesForwardKinematics(panda.model, data, joints.q[k])
        assert np.linalg.norm(task_error(panda, data, task.position_m[k], task.rotation[k])) < 1e-9
        jacobian = pin.computeFrameJacobian(panda.model, data, joints.q[k], panda.end_effector_frame_id,
                                            pin.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(jacobian @ joints.v[k], task.twist()[k], atol=1e-9)
    t, inner = evaluator.samples.t_s, slice(2, -2)
    finite = np.gradient(joints.q, t, axis=0)
    assert np.abs(finite - joints.v)[inner].max() < 2e-3 * np.abs(joints.v).max()


@pytest.mark.parametrize("path", [CIRCLE, RECT])
def test_energy_of_the_resolved_motion_is_rnea_on_its_joint_trajectory(panda, path):
    """Efforts by Pinocchio's RNEA, sample by sample, with the tool's process load, on the same joint trajectory:
    the same efforts and the same electric energy to 1e-9."""
    placement = BENT if path == CIRCLE else np.array([0.45, 0.0, 0.35, 0.0, 0.0, 0.0, 0.2, -0.2, 0.3])
    evaluator = Evaluator(panda, load_path(path))
    batch = evaluator.batch(placement[None])
    assert batch.reachable.all()
    joints = batch.joints
    _, force = placed_task(panda, evaluator.samples, placement[None])
    efforts = rnea_actuator_efforts(panda, joints, force)
    np.testing.assert_allclose(batch.effort[0], efforts, rtol=1e-9, atol=1e-9 * np.abs(efforts).max())
    v, a = joints.v[:, panda.actuated_v_indices], joints.a[:, panda.actuated_v_indices]
    energy = electric_energy(panda, motor_trace(panda, efforts, v, a), evaluator.samples.t_s, evaluator.samples.piece)
    assert energy.total_J == pytest.approx(float(batch.energy.total_J[0]), rel=1e-9)


def test_joint_3_held_at_zero_moves_the_others_as_the_six_axis_arm(panda, locked):
    """A redundant joint held still (one knot at 0) is the locked arm plus that joint's holding current: every other
    actuator's motion, effort and energy as with --lock panda_joint3=0."""
    path = load_path(CIRCLE)
    place = np.array([0.40, 0.0, 0.30, 0.0, 0.0, 0.0])
    held = edit_redundancy(panda, {}, knots=1)
    free = Evaluator(held, path).batch(np.append(place, 0.0)[None])
    fixed = Evaluator(locked, path).batch(place[None])
    others = [k for k, a in enumerate(held.actuators) if a.joint != "panda_joint3"]
    np.testing.assert_allclose(free.effort[0][:, others], fixed.effort[0], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(free.energy.per_actuator_J[0][others], fixed.energy.per_actuator_J[0], rtol=1e-9)
    assert free.energy.per_actuator_J[0][2] > 0.0  # joint 3 holds against gravity: its Joule heat


def test_knots_are_searched_within_the_joint_range(panda):
    space = default_space(panda)
    assert space.free[-3:] == redundant_variables(panda)
    np.testing.assert_allclose(space.lower[-3:], -2.8973, atol=1e-4)
    assert space.full(np.zeros(len(space.free))).shape == (1, 9)


def test_a_redundant_joint_must_be_actuated(panda):
    sidecar = panda.edited_sidecar(redundancy=Redundancy(joints=["panda_finger_joint1"], knots=2))
    with pytest.raises(RobotFileError) as error:
        robot_from_sidecar(panda.sidecar_path, sidecar)
    assert error.value.field == "redundancy.joints.0" and "not an actuated joint" in str(error.value)


@pytest.mark.slow
@pytest.mark.parametrize("path", [CIRCLE, CONTOUR])  # a closed path (periodic profile) and an open one
def test_the_unlocked_optimum_is_at_least_as_good_as_the_locked_one(panda, locked, path):
    """The whole-path resolution finds an energy at most the six-axis arm's (1e-6 relative), and its reported motion
    keeps every limit on the 4x denser re-check."""
    tool_path = load_path(path)
    settings = SearchSettings(seed=0, worst=False)
    unlocked = optimize_placement(panda, tool_path, settings=settings).best
    six_axis = optimize_placement(locked, tool_path, settings=settings).best
    assert unlocked is not None and six_axis is not None
    assert unlocked.detail.value <= six_axis.detail.value * (1 + 1e-6)
    assert unlocked.holds
    evaluator = Evaluator(panda, tool_path)
    check = denser(evaluator, 4).recheck(unlocked.detail.placement[None], evaluator)
    assert check.feasible[0] and np.ptp(unlocked.detail.configuration[:, 2]) >= 0.0
