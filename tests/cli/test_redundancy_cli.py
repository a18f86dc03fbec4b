"""The command line of redundancy: --lock, --knots, the knots and the spin in --at, --at-json and --json."""

from __future__ import annotations

import json

import numpy as np
import pytest

from placement import Evaluator, load_path, load_robot
from placement.__main__ import main
from placement.cell.cell_file import load_cell
from placement.robot.equip import equip
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.space import default_space
from placement.workshop.load import edit_redundancy
from tests.support.paths import CIRCLE, EXAMPLES

KNOTS_AT = "x=400,y=0,z=300,panda_joint3@0=10,panda_joint3@1=0,panda_joint3@2=4"


def test_lock_gives_the_six_axis_arm(tmp_path, capsys):
    out = tmp_path / "locked.json"
    assert main(["--robot", "panda", "--path", str(CIRCLE), "--at", "x=400,y=0,z=300", "--lock", "panda_joint3=0",
                 "--json", str(out)]) == 0
    document = json.loads(out.read_text())["at"]
    assert list(document["placement"]) == ["x", "y", "z", "phi", "theta", "psi"] and "profiles" not in document
    assert "panda_joint3" not in document["energy_per_actuator_J"]
    six_axis = edit_redundancy(load_robot("panda"), {"panda_joint3": 0.0})
    again = Evaluator(six_axis, load_path(CIRCLE)).detail(np.array([0.4, 0.0, 0.3, 0.0, 0.0, 0.0]))
    assert document["energy_J"] == pytest.approx(float(again.energy.total_J), rel=1e-12)


@pytest.mark.parametrize(("lock", "message"), [("panda_joint9=0", "no movable joint 'panda_joint9'"),
                                               ("panda_joint3", "expected JOINT=VALUE"),
                                               ("panda_joint3=abc", "is not a number"),
                                               ("panda_joint3=400", "outside the joint's limits")])
def test_a_wrong_lock_exits_2_and_says_why(lock, message, capsys):
    code = main(["--robot", "panda", "--path", str(CIRCLE), "--at", "x=400", "--lock", lock])
    assert code == 2 and message in capsys.readouterr().err


def test_the_knots_go_through_at_json_and_back_exactly(tmp_path):
    """--json writes the knots with the placement and joint 3's profile along the path; --at-json reads them back to
    the very same energy."""
    first, second = tmp_path / "first.json", tmp_path / "second.json"
    assert main(["--robot", "panda", "--path", str(CIRCLE), "--at", KNOTS_AT, "--json", str(first)]) == 0
    document = json.loads(first.read_text())["at"]
    assert document["placement"]["panda_joint3@2"] == pytest.approx(np.radians(4.0), abs=1e-15)
    profile = document["profiles"]["panda_joint3"]
    assert profile["knot_shares"] == [0.0, 1 / 3, 2 / 3] and len(profile["position_rad"]) == len(profile["t_s"])
    assert profile["position_rad"][0] == pytest.approx(np.radians(10.0), abs=1e-9)  # a closed path: periodic
    assert np.ptp(profile["position_rad"]) > np.radians(8.0)  # joint 3 moves along the path
    assert main(["--robot", "panda", "--path", str(CIRCLE), "--at-json", str(first), "--which", "at",
                 "--json", str(second)]) == 0
    assert json.loads(second.read_text())["at"]["energy_J"] == document["energy_J"]


def test_knots_option_sets_the_profile_and_refuses_a_robot_without(tmp_path, capsys):
    out = tmp_path / "one.json"
    assert main(["--robot", "panda", "--path", str(CIRCLE), "--knots", "1", "--at", "x=400,z=300,panda_joint3@0=10",
                 "--json", str(out)]) == 0
    assert list(json.loads(out.read_text())["at"]["placement"])[-1] == "panda_joint3@0"
    assert main(["--robot", "ur5", "--path", str(CIRCLE), "--knots", "2", "--at", "x=400"]) == 2
    assert "no redundant joint" in capsys.readouterr().err


def test_a_spin_about_the_ur5s_last_axis_costs_nothing():
    """The UR5's tool is along wrist 3's axis: a constant spin only offsets wrist 3, every energy stays (1e-9)."""
    robot = edit_redundancy(load_robot("ur5"), {}, spin=True)
    evaluator = Evaluator(robot, load_path(CIRCLE))
    spins = np.radians([-150.0, -30.0, 0.0, 45.0, 120.0])
    placements = np.column_stack([np.tile([0.4, 0.0, 0.2, 0.3, 0.1, 0.0], (len(spins), 1)), spins])
    energy = evaluator.evaluate(placements).value
    assert np.isfinite(energy).all()
    np.testing.assert_allclose(energy, energy[2], rtol=1e-9)


def test_a_spindle_across_the_flange_makes_the_spin_count():
    robot = equip(edit_redundancy(load_robot("ur5"), {}, spin=True), load_cell(EXAMPLES / "cell_ur5_side_spindle.yaml"))
    placements = np.column_stack([np.tile([0.4, 0.0, 0.2, 0.0, 0.0, 0.0], (3, 1)), np.radians([0.0, 90.0, 180.0])])
    energy = Evaluator(robot, load_path(CIRCLE)).batch(placements).energy.total_J
    assert np.ptp(energy) > 0.1 * energy.min()


@pytest.mark.slow
def test_the_free_spin_is_at_least_as_good_as_the_fixed_one():
    """On the spindle across the UR5's flange, the search with the spin free finds at most the fixed spin's energy."""
    cell = load_cell(EXAMPLES / "cell_ur5_side_spindle.yaml")
    fixed = equip(load_robot("ur5"), cell)
    free = equip(edit_redundancy(load_robot("ur5"), {}, spin=True), cell)
    path, settings = load_path(CIRCLE), SearchSettings(seed=0, worst=False)
    best_fixed = optimize_placement(fixed, path, settings=settings).best
    best_free = optimize_placement(free, path, space=default_space(free), settings=settings).best
    assert best_fixed is not None and best_free is not None and best_free.holds
    assert best_free.detail.value <= best_fixed.detail.value * (1 + 1e-6)
