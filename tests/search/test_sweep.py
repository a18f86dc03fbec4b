"""Energy maps: parallel = serial = the evaluator, any executor, files that reload, figures."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.output.plots import label_decimals
from placement.path import load_path
from placement.search.sweep import SweepResult, sweep
from tests.support.paths import EXAMPLE

AXES = {"x": np.linspace(-0.12, 0.06, 7), "y": np.linspace(-0.12, 0.06, 6)}
FIXED = {"z": -0.01, "phi": 0.3}


@pytest.fixture(scope="module")
def serial():
    from placement import load_robot

    robot = load_robot("orthoglide")
    path = load_path(EXAMPLE)
    return robot, path, sweep(robot, path, AXES, FIXED, evaluation=EvaluatorSettings(time_step_s=0.004, workers=1))


def test_map_equals_the_evaluator_point_by_point(serial):
    robot, path, result = serial
    evaluator = Evaluator(robot, path, EvaluatorSettings(time_step_s=0.004))
    i, j = 2, 4
    direct = evaluator.evaluate(np.array([[AXES["x"][i], AXES["y"][j], -0.01, 0.3, 0.0, 0.0]]))
    assert result.value[i, j] == direct.value[0] and result.feasible[i, j] == direct.feasible[0]
    assert result.value.shape == (7, 6) and result.feasible.any() and not result.feasible.all()


def test_parallel_workers_and_any_executor_give_the_same_map(serial):
    robot, path, result = serial
    parallel = sweep(robot, path, AXES, FIXED, evaluation=EvaluatorSettings(time_step_s=0.004, workers=2))
    with ThreadPoolExecutor(max_workers=2) as executor:
        threaded = sweep(robot, path, AXES, FIXED, executor=executor, evaluation=EvaluatorSettings(time_step_s=0.004))
    for other in (parallel, threaded):
        np.testing.assert_array_equal(other.value, result.value)
        np.testing.assert_array_equal(other.tightest, result.tightest)


def test_map_file_reloads(serial, tmp_path):
    *_, result = serial
    result.save(tmp_path / "map.npz")
    again = SweepResult.load(tmp_path / "map.npz")
    np.testing.assert_array_equal(again.value, result.value)
    assert again.variables == ("x", "y") and again.limits == result.limits
    assert again.masked_value().mask.sum() == (~result.feasible).sum()


def test_infeasible_points_name_a_broken_limit(serial):
    *_, result = serial
    broken = {result.limits[k] for k in result.tightest[~result.feasible]}
    assert broken and all(label.startswith(("workspace", "joint")) for label in broken)


def test_map_figure_is_written(serial, tmp_path):
    from placement.output.plots import map_figure, save

    *_, result = serial
    files = save(map_figure(result, "test"), tmp_path / "map")
    assert all((tmp_path / name).stat().st_size > 5000 for name in ("map.png", "map.svg")) and len(files) == 2


def test_workers_evaluate_the_robot_as_changed_in_memory():
    """A robot without a plug-in travels to the workers as it is, not reloaded from its file."""
    import dataclasses

    from placement import load_robot

    robot = load_robot("fivebar")
    path = load_path(EXAMPLE.with_name("circle.yaml"))
    heavier = dataclasses.replace(robot, model=robot.model.copy())
    heavier.model.inertias[heavier.model.getJointId("b1")].mass *= 2.0
    placements = np.array([[0.0, 0.30, 0.0, 0.0, 0.0, 0.0], [0.02, 0.28, 0.0, 0.5, 0.0, 0.0],
                           [-0.02, 0.31, 0.0, -0.5, 0.0, 0.0], [0.01, 0.32, 0.0, 1.0, 0.0, 0.0]])
    with Evaluator(heavier, path, EvaluatorSettings(time_step_s=0.01, workers=2)) as parallel:
        in_workers = parallel.evaluate(placements).value
    here = Evaluator(heavier, path, EvaluatorSettings(time_step_s=0.01, workers=1)).evaluate(placements).value
    original = Evaluator(robot, path, EvaluatorSettings(time_step_s=0.01, workers=1)).evaluate(placements).value
    np.testing.assert_array_equal(in_workers, here)
    assert not np.allclose(here, original)


def test_a_plug_in_robot_changed_in_memory_travels_to_the_workers(serial):
    """The Orthoglide's plug-in module is re-loaded in the workers; the model goes as it is."""
    import pickle

    import pinocchio as pin

    robot, path, result = serial
    calm = pickle.loads(pickle.dumps(robot))
    assert calm.closed_form is not None
    calm.model.gravity = pin.Motion.Zero()
    here = sweep(calm, path, AXES, FIXED, evaluation=EvaluatorSettings(time_step_s=0.004, workers=1))
    there = sweep(calm, path, AXES, FIXED, evaluation=EvaluatorSettings(time_step_s=0.004, workers=2))
    np.testing.assert_array_equal(here.value, there.value)
    assert not np.allclose(here.value[result.feasible], result.value[result.feasible])


@pytest.mark.parametrize("levels", [np.linspace(4.0, 40.0, 6), np.linspace(0.3656, 0.3690, 6), np.linspace(1e-4, 9e-4, 5)])
def test_contour_labels_tell_the_levels_apart(levels):
    labels = [f"%.{label_decimals(levels)}f" % level for level in levels]
    assert len(set(labels)) == len(labels)
