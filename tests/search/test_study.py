"""Studies: each row is the search of its pair, infeasible pairs are rows that say why."""

from __future__ import annotations

import csv
import dataclasses
import math

import pytest

from placement import EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.path.schema import Timing
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.study import run_study

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
