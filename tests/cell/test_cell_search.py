"""A robot in a cell: the tool's mass in the dynamics, collisions as a limit the search keeps, and the report."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pinocchio as pin
import pytest
import yaml

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.cell.cell_file import load_cell
from placement.contract.limit import margin_fields, tightest
from placement.limits.collision import (
    CHECK_SPACING_M,
    CLEARANCE_SCALE_M,
    EXACT_BAND_M,
    Collision,
    checked_samples,
    collision_scene,
)
from placement.robot.equip import equip
from placement.robot.tool import mount_tool
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.space import default_space

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2

SMALL = SearchSettings(population=24, max_generations=25)
RECT = "examples/rect.yaml"


def _cell(tmp_path, **fields) -> str:
    file = tmp_path / "cell.yaml"
    file.write_text(yaml.safe_dump(fields))
    return str(file)


def test_a_cells_tool_replaces_the_sidecars_in_the_dynamics(tmp_path):
    spindle = {"name": "spindle", "mass_kg": 2.0, "com_m": [0, 0, 0.075], "inertia_kg_m2": [4e-3, 4e-3, 1e-3, 0, 0, 0],
               "collision": {"type": "cylinder", "radius_m": 0.03, "length_m": 0.15, "xyz_m": [0, 0, 0.075]}}
    gripper = dict(spindle, name="gripper", mass_kg=1.2, com_m=[0.01, 0, 0.05])
    document = yaml.safe_load(open("robots/ur5/ur5.yaml").read())
    (tmp_path / "ur5.yaml").write_text(yaml.safe_dump(dict(document, tool=gripper)))
    bare, with_gripper = load_robot("ur5"), load_robot(tmp_path / "ur5.yaml")
    equipped = equip(with_gripper, load_cell(_cell(tmp_path, tool=spindle)))
    expected = mount_tool(bare, equipped.cell.tool)
    rng = np.random.default_rng(2)
    for _ in range(4):
        q, v, a = pin.randomConfiguration(bare.model), rng.normal(size=6), rng.normal(size=6)
        loaded_tau = pin.rnea(with_gripper.model, with_gripper.model.createData(), q, v, a)
        assert np.abs(loaded_tau - pin.rnea(bare.model, bare.model.createData(), q, v, a)).max() > 1e-2  # it carries the gripper
        np.testing.assert_allclose(pin.rnea(equipped.model, equipped.model.createData(), q, v, a),
                                   pin.rnea(expected.model, expected.model.createData(), q, v, a), atol=1e-12)


def test_the_workpiece_region_bounds_the_search_and_is_a_limit(tmp_path):
    robot = equip(load_robot("orthoglide"), load_cell(_cell(tmp_path, workpiece_region={
        "min_m": [-0.05, -0.06, -0.1], "max_m": [0.02, 0.03, 0.0]})))
    space = default_space(robot)
    np.testing.assert_allclose(space.lower[:3], [-0.05, -0.06, -0.1])
    np.testing.assert_allclose(space.upper[:3], [0.02, 0.03, 0.0])
    evaluation = Evaluator(robot, load_path(RECT)).evaluate(np.array([[0.0, 0.0, -0.05, 0, 0, 0],
                                                                      [0.0, 0.0, -0.05, np.pi / 2, 0, 0]]))
    column = [i for i, label in enumerate(evaluation.limits) if label.startswith("workpiece region")]
    # 30 mm wide along x, 60 mm along y: the unturned rectangle leaves the region at y = -0.06 + 0.03 ... and x,
    # turned by 90° it spans 60 mm along x from -0.03 to 0.03, beyond the region's x max of 0.02.
    assert evaluation.margins[0, column].min() >= 0
    assert evaluation.margins[1, column].min() == pytest.approx((0.02 - 0.03) / 0.07)


def test_an_obstacle_over_the_free_optimum_moves_the_answer_and_binds(tmp_path):
    robot, path = load_robot("orthoglide"), load_path(RECT)
    free = optimize_placement(robot, path, settings=dataclasses.replace(SMALL, worst=False)).best.detail
    tool_points = free.tool_position_m
    centre = (tool_points.max(axis=0) + tool_points.min(axis=0)) / 2
    size = tool_points.max(axis=0) - tool_points.min(axis=0) + 0.02
    cell = load_cell(_cell(tmp_path, margin_m=0.005, obstacles={
        "block": {"type": "box", "size_m": [float(size[0]), float(size[1]), 0.02],
                  "xyz_m": [float(centre[0]), float(centre[1]), float(centre[2] - 0.06)]}}))
    boxed = equip(robot, cell)
    before = Evaluator(boxed, path).detail(free.placement)
    assert not before.feasible and any(m.kind == "collision" and m.margin < 0 for m in before.margins)
    moved = optimize_placement(boxed, path, settings=dataclasses.replace(SMALL, worst=False)).best.detail
    assert moved.feasible and moved.value > free.value
    assert np.linalg.norm(moved.placement[:3] - free.placement[:3]) > 0.005
    binding = min(moved.margins, key=lambda m: m.margin)
    assert binding.kind == "collision" and "block" in binding.where and binding.margin < 0.02  # 1 mm search buffer
    dense = Evaluator(boxed, path, EvaluatorSettings(time_step_s=path.time_step_s / 4)).detail(moved.placement)
    assert all(m.value >= 0.005 - 1e-9 for m in dense.margins if m.kind == "collision" and "block" in m.where)


def test_the_report_names_the_nearest_pair_with_its_points(tmp_path, capsys):
    cell = _cell(tmp_path, margin_m=0.005, obstacles={"plate": {"type": "box", "size_m": [0.3, 0.3, 0.01],
                                                                 "xyz_m": [-0.03, -0.03, -0.16]}})
    out = tmp_path / "at.json"
    assert main(["--robot", "orthoglide", "--path", RECT, "--cell", cell, "--at", "z=-40", "--json", str(out)]) == 0
    margins = [m for m in json.loads(out.read_text())["at"]["margins"] if m["kind"] == "collision"]
    assert margins and all(len(m["nearest_points_m"]) == 2 for m in margins)
    robot = equip(load_robot("orthoglide"), load_cell(cell))
    scene = collision_scene(robot)
    pair = min(margins, key=lambda m: m["margin"])
    first, second = (np.array(p) for p in pair["nearest_points_m"])
    assert np.linalg.norm(first - second) == pytest.approx(pair["value"], abs=1e-9)
    assert pair["where"].endswith("/ plate") and scene.required_m.max() == 0.005
    assert "nearest at (" in capsys.readouterr().out


def test_a_tools_tip_follows_the_path_as_the_platform_would_the_shifted_path(tmp_path):
    # The Orthoglide's platform only translates: with a tip 10 mm along x and 60 mm below its tool frame,
    # placing a path at p is placing it at p - tip without one (the generic solver, then the closed form).
    tip = np.array([0.01, 0.0, -0.06])
    spindle = {"name": "spindle", "frame": "tool", "mass_kg": 0.5, "com_m": [0, 0, 0.05],
               "inertia_kg_m2": [3.4e-4, 3.4e-4, 1.6e-4, 0, 0, 0]}
    with_tip = equip(load_robot("orthoglide"), load_cell(_cell(tmp_path, tool=dict(spindle, tip={"xyz_m": tip.tolist()}))))
    without = equip(load_robot("orthoglide"), load_cell(_cell(tmp_path / "..", tool=spindle)))
    assert with_tip.model.frames[with_tip.end_effector_frame_id].name == "spindle_tip"
    path = load_path(RECT)
    placements = np.array([[-0.02, 0.01, -0.03, 0.3, 0.0, 0.0], [0.01, -0.04, 0.0, -1.0, 0.0, 0.0]])
    shifted = placements - np.hstack([tip, np.zeros(3)])
    tipped = Evaluator(with_tip, path).evaluate(placements)
    plain = Evaluator(without, path).evaluate(shifted)
    assert type(Evaluator(with_tip, path).solver).__name__ != type(Evaluator(without, path).solver).__name__
    np.testing.assert_allclose(tipped.value, plain.value, rtol=1e-7)


def test_the_ur5_deburring_job_in_its_cell_keeps_its_clearances_between_samples():
    robot = equip(load_robot("ur5"), load_cell("examples/cell_ur5_table_wall.yaml"))
    path = load_path("examples/contour.yaml")
    best = optimize_placement(robot, path, evaluation=EvaluatorSettings(time_step_s=0.04),
                              settings=SearchSettings(population=16, max_generations=6, worst=False)).best
    assert best is not None and best.detail.feasible
    assert best.recheck_margin >= -1e-4  # a limit the optimum touches may be grazed between samples, not more
    dense = Evaluator(robot, path, EvaluatorSettings(time_step_s=0.005)).detail(best.detail.placement)  # 8 times denser
    scene = collision_scene(robot)
    distances = scene.distances(dense.configuration)  # exact, every pair, every sample
    assert (distances >= scene.required_m).all()
    assert {"table", "wall", "fixture", "operator"} <= {second for _, second in scene.pairs}


def test_a_search_batchs_tightest_clearance_is_coals_distance_at_the_path_sample_it_names():
    """A search's batch checks some samples only: its tightest collision names the path's sample, where coal
    gives the same distance."""
    robot = equip(load_robot("orthoglide"), load_cell("examples/cell_orthoglide.yaml"))
    evaluator = Evaluator(robot, load_path("examples/pocket.yaml"), EvaluatorSettings())  # 6,842 samples
    placement = np.array([-0.108, -0.107, -0.0997, -2.19, 0.0, 0.0])  # the legs close to the vice
    batch = evaluator.batch(placement[None], exact=False)
    fields = margin_fields(batch)
    field = next(field for field in fields if field.kind == "collision")
    assert field.samples is not None and len(field.samples) < len(evaluator.samples) / 2  # the checked samples
    margin = next(margin for margin in tightest(fields) if margin.kind == "collision")
    scene = collision_scene(robot)
    exact = scene.distances(batch.joints.q[margin.sample])[0, scene.pairs.index(tuple(margin.where.split(" / ")))]
    assert margin.value == pytest.approx(exact, abs=1e-12) and margin.value < 0.05


@pytest.mark.parametrize("margin", [0.0, 0.6])
def test_a_search_batchs_distances_are_coals_up_to_the_clearance_and_margin_kept(margin, monkeypatch):
    """Each pair's smallest distance along a placement's checked samples is coal's wherever it is at most the
    clearance asked (the cell's, the search's 1 mm, the margin kept: 60 mm at 0.6) plus, unless the batch is
    read for feasibility only (a global search's), a 50 mm band; elsewhere a lower bound above that. So both
    decide every clearance as coal's distances do, the batch read for feasibility with fewer of coal's."""
    robot = equip(load_robot("orthoglide"), load_cell("examples/cell_orthoglide.yaml"))
    evaluator = Evaluator(robot, load_path("examples/pocket.yaml"), EvaluatorSettings(margin=margin))
    placements = np.array([[-0.108, -0.107, -0.11, -2.19, 0, 0], [-0.108, -0.107, -0.0997, -2.19, 0, 0],  # the legs
                           [-0.1, -0.09, -0.08, -2.0, 0, 0], [0.055, -0.097, 0.064, -1.08, 0, 0]])  # in the vice, near, far
    batch = evaluator.batch(placements)
    scene = collision_scene(robot)
    checked = checked_samples(batch.samples.position_m)
    q = batch.joints.q.reshape(len(placements), -1, robot.model.nq)[:, checked].reshape(-1, robot.model.nq)
    exact = scene.distances(q).reshape(len(placements), len(checked), -1).min(axis=1)  # coal's, every pair
    required = scene.required_m + CHECK_SPACING_M + CLEARANCE_SCALE_M * margin
    calls, counts = [], {}
    compute = pin.computeDistance
    monkeypatch.setattr(pin, "computeDistance", lambda *args: calls.append(1) or compute(*args))
    for feasibility_only, band in ((False, EXACT_BAND_M), (True, 0.0)):
        calls.clear()
        field = Collision().fields(dataclasses.replace(batch, feasibility_only=feasibility_only))[0]
        least = field.value.min(axis=1)
        within = exact <= required.max() + band
        assert within.any() and not within.all()
        np.testing.assert_array_equal(least[within], exact[within])
        assert (least[~within] > required.max() + band).all() and (least <= exact + 1e-9).all()
        np.testing.assert_array_equal(least >= required, exact >= required)
        counts[feasibility_only] = len(calls)
    assert counts[True] < counts[False] / 2
