"""Pareto fronts: dominance, the front's ends against single-objective searches, and the command line."""

from __future__ import annotations

import json

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from placement import load_path, load_robot
from placement.__main__ import main
from placement.contract import OBJECTIVES
from placement.search.optimize import SearchSettings
from placement.search.pareto import knee_index, non_dominated, pareto_front

SMALL = SearchSettings(population=24, max_generations=20)


def _dominates(a: np.ndarray, b: np.ndarray) -> bool:
    return bool((a <= b).all() and (a < b).any())


@settings(max_examples=60, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 30), st.integers(2, 3)), elements=st.integers(0, 5).map(float)))
def test_the_kept_rows_are_exactly_those_no_row_dominates(values):
    keep = non_dominated(values)
    for i, row in enumerate(values):
        dominated = any(_dominates(other, row) for other in values)
        copy_before = any((values[j] == row).all() for j in range(i))
        assert keep[i] == (not dominated and not copy_before)


def test_the_knee_of_a_convex_front_is_its_corner():
    values = np.array([[0.0, 1.0], [0.1, 0.1], [0.5, 0.05], [1.0, 0.0]])
    assert knee_index(values) == 1


def test_the_orthoglide_front_is_mutually_non_dominated_and_ends_at_each_objective_optimum():
    robot, path = load_robot("orthoglide"), load_path("examples/rect.yaml")
    front = pareto_front(robot, path, ("energy", "dexterity"), settings=SMALL)
    values = np.array([m.values for m in front.members])
    dense = np.array([m.recheck_values for m in front.members])
    assert len(front.members) >= 10
    assert non_dominated(values).all() and non_dominated(dense).all()
    assert all(m.margin >= 0 for m in front.members)
    for column, name in enumerate(front.objectives):
        end = values[front.end(name), column]
        assert OBJECTIVES.get(name).sign * (end - front.optima[name]) <= 0.005 * abs(front.optima[name])
    # The ends are the extremes: energy rises along the front while the condition number falls.
    assert np.all(np.diff(values[:, 0]) >= 0) and np.all(np.diff(values[:, 1]) <= 0)


def test_the_command_line_writes_the_front_and_refuses_a_single_objective(tmp_path, capsys):
    out = tmp_path / "front.json"
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--objectives", "energy,transmission",
                 "--population", "24", "--generations", "10", "--json", str(out), "--png", str(tmp_path / "f.png"),
                 "--quiet"]) == 0
    document = json.loads(out.read_text())
    assert document["objectives"] == ["energy", "transmission"]
    assert set(document["drawn"]) == {"knee", "best energy", "best transmission"}
    assert (tmp_path / "f.png").stat().st_size > 0 and (tmp_path / "f.svg").stat().st_size > 0
    members = document["members"]
    assert members[document["ends"]["energy"]]["values"]["energy"] == min(m["values"]["energy"] for m in members)
    capsys.readouterr()
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--objectives", "energy"]) == 2
    assert "two or three different objective names" in capsys.readouterr().err
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--objectives", "energy,dexterity",
                 "--at", "x=0"]) == 2
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--members", "knee"]) == 2
    capsys.readouterr()
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--objectives", "energy,dexterity",
                 "--members", "kne"]) == 2  # refused before the search
    captured = capsys.readouterr()
    assert "--members: expected knee" in captured.err and "search:" not in captured.out


class _Evaluated:
    """Two objectives of a placement vector, its first two entries, moved at round-off by the row (as a batch split
    over threads moves them); every placement feasible."""

    def __init__(self, placements: np.ndarray) -> None:
        rows = np.arange(len(placements))
        self.values = placements[:, :2] + 1e-15 * np.column_stack([rows, -rows])
        self.feasible = np.ones(len(placements), dtype=bool)
        self.margins = np.ones((len(placements), 1))


class _Model:
    def evaluate(self, placements: np.ndarray) -> _Evaluated:
        return _Evaluated(placements)

    def recheck(self, placements: np.ndarray, fine: object) -> _Evaluated:
        return _Evaluated(placements)


def test_a_placement_given_twice_is_one_member():
    """An objective's own optimum seeds NSGA-II, and its archive returns it: the front lists it once, though its two
    evaluations differ at round-off (the UR5's front listed its deflection end twice)."""
    from placement.search.pareto import _members

    placements = np.array([[1.0, 3.0, 0, 0, 0, 0], [2.0, 2.0, 0, 0, 0, 0], [3.0, 1.0, 0, 0, 0, 0],
                           [3.0, 1.0, 0, 0, 0, 0]])
    members = _members(_Model(), _Model(), np.array([1.0, 1.0]), placements)
    assert len(members) == 3
    assert np.array_equal(np.array([m.placement for m in members])[:, :2], [[1.0, 3.0], [2.0, 2.0], [3.0, 1.0]])
