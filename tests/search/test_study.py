"""Studies: each row is the search of its pair, infeasible pairs are rows that say why."""

from __future__ import annotations

import csv
import dataclasses
import math

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.cell.cell_file import load_cell
from placement.path.path_file import Timing
from placement.robot.equip import equip
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.study import run_study

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2

SMALL = SearchSettings(population=16, max_generations=5)


def test_a_study_row_is_the_search_of_its_pair():
    robot, path = load_robot("orthoglide"), load_path("examples/rect.yaml")
    (row,) = run_study([robot], [path], settings=SMALL, workers=1)
    result = optimize_placement(robot, path, settings=SMALL)
    assert row.feasible and row.reason == ""
    assert row.best_energy_J == result.best.detail.value and row.worst_energy_J == result.worst.detail.value
    assert row.gain == pytest.approx(result.gain, rel=1e-12)
    assert [row.x_m, row.y_m, row.z_m, row.phi_rad] == list(result.best.detail.placement[:4])
    assert row.cycle_time_s == pytest.approx(path.sample().t_s[-1]) and math.isnan(row.fastest_cycle_time_s)


def test_under_the_optimal_timing_a_row_gives_the_best_placement_s_own_time_and_the_fastest_one():
    robot = load_robot("orthoglide")
    path = dataclasses.replace(load_path("examples/rect.yaml"), timing=Timing(mode="optimal"))
    (row,) = run_study([robot], [path], settings=SMALL, workers=1)
    result = optimize_placement(robot, path, settings=dataclasses.replace(SMALL, worst=False))
    fastest = optimize_placement(robot, path, evaluation=EvaluatorSettings(objective="cycle_time"),
                                 settings=dataclasses.replace(SMALL, worst=False))
    assert row.cycle_time_s == result.best.detail.samples.t_s[-1]
    assert row.fastest_cycle_time_s == fastest.best.detail.value <= row.cycle_time_s


def test_the_study_command_writes_one_row_per_pair_and_exits_2_when_one_is_infeasible(tmp_path, capsys):
    out = tmp_path / "study.csv"
    code = main(["study", "--robots", "orthoglide,fivebar", "--paths", "examples/rect.yaml", "--out", str(out),
                 "--generations", "5", "--workers", "1", "--quiet"])
    rows = list(csv.DictReader(out.open()))
    assert [(r["robot"], r["feasible"]) for r in rows] == [("orthoglide", "True"), ("fivebar", "False")]
    assert code == 2 and "motor torque" in rows[1]["reason"]
    assert "fivebar" in capsys.readouterr().out
    assert main(["study", "--robots", "orthoglide", "--paths", "examples/rect.yaml", "--out", "x.txt"]) == 2


def _study_rows(tmp_path, *options):
    out = tmp_path / "study.csv"
    assert main(["study", "--robots", "orthoglide", "--paths", "examples/rect.yaml", "--out", str(out),
                 "--generations", "5", "--workers", "1", "--quiet", *options]) == 0
    return list(csv.DictReader(out.open()))


def _placement(row):
    return np.array([float(row[name]) for name in ("x_m", "y_m", "z_m", "phi_rad", "theta_rad", "psi_rad")])


def test_the_study_command_samples_the_paths_at_its_time_step(tmp_path):
    """--time-step: the row's energy is that of the best placement on the coarser sampling, not the file's."""
    (row,) = _study_rows(tmp_path, "--time-step", "0.004")
    robot, path = load_robot("orthoglide"), load_path("examples/rect.yaml")
    coarse, fine = (Evaluator(robot, path, EvaluatorSettings(time_step_s=step, workers=1)).detail(_placement(row))
                    for step in (0.004, None))
    assert len(coarse.samples) < len(fine.samples) / 3
    assert float(row["best_energy_J"]) == pytest.approx(coarse.energy.total_J, rel=1e-12)
    assert float(row["best_energy_J"]) != pytest.approx(fine.energy.total_J, rel=1e-6)


def test_the_study_command_ranks_by_its_objective_in_its_cell(tmp_path):
    """--objective and --cell, as the main command has them: the row's placements are ranked by the peak torque of
    the robot carrying the cell's 2 kg spindle, and its energies are that robot's."""
    cell = tmp_path / "spindle.yaml"
    cell.write_text("description: a 2 kg spindle on the tool frame\ntool: {name: spindle, frame: tool, mass_kg: 2.0, "
                    "com_m: [0, 0, 0.05], inertia_kg_m2: [0.001, 0.001, 0.0006, 0, 0, 0]}\n")
    (row,) = _study_rows(tmp_path, "--objective", "peak_torque", "--cell", str(cell))
    assert row["objective"] == "peak_torque" and float(row["best_value"]) < float(row["worst_value"])
    path = load_path("examples/rect.yaml")
    bare = load_robot("orthoglide")
    equipped = equip(bare, load_cell(cell))
    detail = Evaluator(equipped, path, EvaluatorSettings(objective="peak_torque", workers=1)).detail(_placement(row))
    assert float(row["best_value"]) == pytest.approx(detail.value, rel=1e-12)
    assert float(row["best_energy_J"]) == pytest.approx(detail.energy.total_J, rel=1e-12)
    alone = Evaluator(bare, path, EvaluatorSettings(objective="peak_torque", workers=1)).detail(_placement(row))
    assert alone.value != pytest.approx(detail.value, rel=1e-6)  # so the row's value (equal to detail's) carries the spindle
