"""Planar mechanisms declare their plane (placement.plane): placements are read in it, paths stay in it."""

import json

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, SearchSettings, load_path, load_robot, optimize_placement
from placement.__main__ import main
from placement.exceptions import PlacementError
from placement.placing.transform import plane_frame, transform_path_to_base
from placement.robot.exceptions import RobotFileError
from placement.robot.sidecar import Plane
from placement.search.space import default_space
from tests.support.paths import CIRCLE
from tests.support.robot_copies import TURN, edited_copy, vertical_fivebar


@pytest.fixture(scope="module")
def vertical(tmp_path_factory):
    return load_robot(vertical_fivebar(tmp_path_factory.mktemp("vertical")))


def test_plane_frame_of_the_vertical_plane_is_the_turn():
    rotation, origin = plane_frame(Plane(normal=(0.0, 2.0, 0.0)))
    np.testing.assert_allclose(rotation, TURN, atol=1e-15)
    np.testing.assert_array_equal(origin, np.zeros(3))
    np.testing.assert_array_equal(plane_frame(Plane(normal=(0.0, 0.0, 1.0)))[0], np.eye(3))


def test_vertical_copy_costs_what_the_horizontal_one_does(fivebar, vertical):
    space = default_space(vertical)
    assert space.free == ("x", "y", "phi")
    np.testing.assert_array_equal(space.lower, default_space(fivebar).lower)
    np.testing.assert_array_equal(space.upper, default_space(fivebar).upper)
    path = load_path(CIRCLE)
    placements = space.full(np.random.default_rng(3).uniform(space.lower, space.upper, (6, 3)))
    flat, upright = (Evaluator(robot, path, EvaluatorSettings(time_step_s=0.01, workers=1)) for robot in (fivebar, vertical))
    a, b = flat.evaluate(placements), upright.evaluate(placements)
    assert a.reachable.any()
    np.testing.assert_array_equal(a.reachable, b.reachable)
    np.testing.assert_allclose(b.value[b.reachable], a.value[a.reachable], rtol=1e-9)
    detail_a, detail_b = flat.detail(placements[a.reachable][0]), upright.detail(placements[a.reachable][0])
    np.testing.assert_allclose(detail_b.tool_position_m, detail_a.tool_position_m @ TURN.T, atol=1e-12)


def test_each_copy_s_optimum_costs_the_same_on_the_other(fivebar, vertical):
    """A search in the vertical plane reports placements that mean there what they mean in the horizontal one:
    each copy's optimum, feasible, costs the same on the other copy to 1e-9. (Which basin a small global search
    ends in depends on round-off, which differs between the copies, so the two optima need not be one.)"""
    path, settings = load_path(CIRCLE), SearchSettings(population=6, max_generations=3, seed=1, worst=False)
    evaluation = EvaluatorSettings(time_step_s=0.01)
    evaluators = [Evaluator(robot, path, evaluation) for robot in (fivebar, vertical)]
    for robot in (fivebar, vertical):
        best = optimize_placement(robot, path, evaluation=evaluation, settings=settings).best
        assert best is not None and best.holds
        values = [evaluator.evaluate(best.detail.placement[None]) for evaluator in evaluators]
        assert values[0].feasible[0] and values[1].feasible[0]
        assert values[1].value[0] == pytest.approx(values[0].value[0], rel=1e-9)
        assert values[0].value[0] == pytest.approx(best.detail.value, rel=1e-9)

def test_a_path_in_the_plane_stays_in_it():
    plane = Plane(normal=(0.3, -0.5, 0.8), point_m=(0.1, 0.2, -0.3))
    samples = load_path(CIRCLE).sample(0.005)
    rng = np.random.default_rng(0)
    placements = np.column_stack([rng.uniform(-0.2, 0.2, (20, 2)), np.zeros(20), rng.uniform(-np.pi, np.pi, 20),
                                  np.zeros((20, 2))])
    task, force = transform_path_to_base(samples, placements, plane)
    normal = np.array(plane.normal) / np.linalg.norm(plane.normal)
    assert np.abs((task.position_m - plane.point_m) @ normal).max() < 1e-12
    assert np.abs(task.velocity_m_s @ normal).max() < 1e-12
    moved = np.linalg.norm(task.position_m - plane.point_m, axis=1)
    assert moved.max() > 0.05  # the placements do move the path about the plane


def test_paths_cannot_leave_the_plane(vertical):
    with pytest.raises(PlacementError, match="moves in the plane.*z"):
        default_space(vertical, free=("x", "y", "z"))
    with pytest.raises(PlacementError, match="theta"):
        default_space(vertical, fixed={"theta": 0.1})


def test_a_plane_allows_only_in_plane_variables(tmp_path):
    def bad(document: dict) -> None:
        document["placement"] = {"plane": {"normal": [0, 0, 1]}, "free": ["x", "z"]}

    with pytest.raises(RobotFileError, match="placement.*only x, y, phi") as caught:
        load_robot(edited_copy("fivebar", tmp_path, bad))
    assert caught.value.problem.endswith("may be free or bounded (got z)")  # one "got": the validator's


def test_json_and_report_state_the_plane(vertical, tmp_path, capsys):
    out = tmp_path / "at.json"
    assert main(["--robot", str(vertical.sidecar_path), "--path", str(CIRCLE), "--at", "x=0,y=300",
                 "--time-step", "0.01", "--json", str(out)]) == 0
    assert "plane (sidecar placement.plane): normal [0, 1, 0]" in capsys.readouterr().out
    document = json.loads(out.read_text())
    np.testing.assert_allclose(document["plane"]["y_axis"], [0, 0, -1], atol=1e-15)
    assert document["at"]["feasible"]
