"""Under the optimal timing law, every joint's motion at the evaluated samples (gathered when first read) is the
motion the actuators' own arrays describe: the same actuated positions and rates, and passive joints moving as the
closure lets them (v = G·ρ̇); it pickles as a plain joint trajectory; ranking placements by energy reads none of it;
and the actuators' arrays are laid out column by column."""

import dataclasses
import pickle

import numpy as np

from placement import load_robot
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings, batch_margins, batch_values
from placement.kinematics.trajectories import JointTrajectory
from placement.path.load import load_path
from placement.path.path_file import Timing

PLACEMENTS = np.array([[0.0, 0.0, -0.03, 0.0, 0.0, 0.0], [0.04, -0.02, -0.1, 0.5, 0.0, 0.0]])


def optimal_batch():
    robot = load_robot("orthoglide")
    path = dataclasses.replace(load_path("examples/rect.yaml"), timing=Timing(mode="optimal"))
    evaluator = Evaluator(robot, path, EvaluatorSettings(workers=1, threads=1))
    return robot, evaluator, evaluator.batch(PLACEMENTS)


def test_every_joint_moves_as_the_actuators_and_the_closure_say():
    robot, evaluator, batch = optimal_batch()
    joints, shape = batch.joints, batch.position.shape
    assert len(joints) == shape[0] * shape[1] == len(PLACEMENTS) * len(evaluator.samples)
    np.testing.assert_array_equal(joints.q[:, robot.actuated_q_indices].reshape(shape), batch.position)
    np.testing.assert_array_equal(joints.v[:, robot.actuated_v_indices].reshape(shape), batch.velocity)
    np.testing.assert_array_equal(joints.a[:, robot.actuated_v_indices].reshape(shape), batch.acceleration)
    assert np.abs(batch.velocity).max() > 0.1  # the placements move
    closure = np.einsum("nij,nj->ni", joints.basis, batch.velocity.reshape(-1, shape[2]))
    np.testing.assert_allclose(joints.v, closure, rtol=0, atol=1e-9 * np.abs(joints.v).max())


def test_it_pickles_as_a_plain_joint_trajectory():
    _, _, batch = optimal_batch()
    copy = pickle.loads(pickle.dumps(batch.joints))
    assert type(copy) is JointTrajectory
    for field in dataclasses.fields(JointTrajectory):
        np.testing.assert_array_equal(getattr(copy, field.name), getattr(batch.joints, field.name))


def test_ranking_by_energy_reads_no_joint_motion():
    _, evaluator, batch = optimal_batch()
    margins, _, reachable = batch_margins(batch)
    values = batch_values(batch, evaluator.objectives, reachable)
    assert np.isfinite(values).all() and np.isfinite(margins).all()
    assert not {field.name for field in dataclasses.fields(JointTrajectory)} & set(vars(batch.joints))


def test_the_actuators_arrays_run_along_the_samples():
    _, _, batch = optimal_batch()  # numpy's elementwise loops then span the samples, not rows of 3 actuators
    for name in ("tool_position_m", "position", "velocity", "acceleration", "effort"):
        values = getattr(batch, name)
        assert all(values[..., column].flags.c_contiguous for column in range(values.shape[2])), name
