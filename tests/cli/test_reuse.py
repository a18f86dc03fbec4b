"""Answers that hold when reused: a margin from every limit, printed optima that re-enter as printed, optima that
pass their own denser re-check, strict JSON, and warnings about likely unit mistakes."""

import json
import re

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.output.report import strict
from placement.search.lattice import LATTICE_MOVES
from placement.search.reporting import as_printed, binding, reported_point
from placement.search.space import default_space
from tests.support.paths import EXAMPLE

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2

# An 80 x 40 mm rectangle with 10 mm corner radii, as a G-code program, at 0.3 m/s under the paper's timing law.
ROUNDED = """%
G21 G90 G17
G0 X40. Y0. Z0.
G1 Y-10. F18000.
G2 X30. Y-20. I-10. J0.
G1 X-30.
G2 X-40. Y-10. I0. J10.
G1 Y10.
G2 X-30. Y20. I10. J0.
G1 X30.
G2 X40. Y10. I0. J-10.
G1 Y0.
M30
%
"""
ALWAYS_ONE = ("reachability", "optimal timing")  # margins of 1 (holds) or -1 (broken), not shares of a range


def no_constant(name: str) -> None:
    raise ValueError(f"strict JSON has no {name}")


def read_strict(file) -> dict:
    """A JSON file parsed strictly: Infinity, -Infinity or NaN fail."""
    return json.loads(file.read_text(), parse_constant=no_constant)


def rounded_rectangle(tmp_path) -> str:
    (tmp_path / "rounded.nc").write_text(ROUNDED)
    (tmp_path / "rounded.yaml").write_text(
        "name: rounded rectangle 80 x 40 mm\nshape: {type: gcode, file: rounded.nc}\nrapids: {mode: skip}\n"
        "process_forces_N: {feed: 10, radial: 215, axial: 25}\ntiming: {mode: paper}\ntime_step_s: 0.001\n")
    return str(tmp_path / "rounded.yaml")


def printed_placements(out: str) -> dict[str, str]:
    """The best and worst placements as the report prints them, written as --at takes them (mm and deg)."""
    found = {}
    for which in ("best", "worst"):
        line = out.split(f"{which} placement (")[1].splitlines()[1]
        found[which] = ",".join(re.sub(r"\s|mm|deg", "", item) for item in line.split(","))
    return found


@pytest.mark.parametrize("which_path, margin", [("rect", 5), ("rounded", 5), ("rounded", 0)])
def test_margin_kept_and_printed_optima_re_enter(tmp_path, capsys, which_path, margin):
    path = str(EXAMPLE) if which_path == "rect" else rounded_rectangle(tmp_path)
    assert main(["--robot", "orthoglide", "--path", path, "--margin", str(margin), "--quiet",
                 "--json", str(tmp_path / "result.json")]) == 0
    out = capsys.readouterr().out
    document = read_strict(tmp_path / "result.json")
    assert document["margin"] == margin / 100
    for which in ("best", "worst"):
        optimum = document[which]
        shares = [m["margin"] for m in optimum["margins"] if m["kind"] not in ALWAYS_ONE]
        assert min(shares) >= margin / 100 and optimum["margin_kept"] == margin / 100
        assert optimum["recheck_holds"] and optimum["recheck_tightest"]["margin"] >= margin / 100
    assert document["gain"] > 0.5
    for which, given in printed_placements(out).items():
        for required in {0, margin}:  # the printed placement holds as printed, with the margin and without
            assert main(["--robot", "orthoglide", "--path", path, "--at", given, "--margin", str(required),
                         "--json", str(tmp_path / f"at_{which}.json")]) == 0, given
            at = read_strict(tmp_path / f"at_{which}.json")["at"]
            np.testing.assert_array_equal(list(at["placement"].values()), list(document[which]["placement"].values()))
        assert main(["--robot", "orthoglide", "--path", path, "--at-json", str(tmp_path / "result.json"),
                     "--which", which, "--margin", str(margin)]) == 0
    assert "every limit keeps a" in out if margin else "margin" not in out.split("\n\n")[0]


def test_a_placement_inside_the_margin_exits_2_naming_it(capsys):
    # The README's worst placement touches the workspace's x min side: as printed before, phi = -43.42 deg, a hair
    # outside; as printed now, inside, but not 5 % inside.
    args = ["--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=-95.28,y=-94.69,z=-126.79,phi=-43.41"]
    assert main(args[:-1] + [args[-1].replace("43.41", "43.42")]) == 2
    assert main(args) == 0
    capsys.readouterr()
    assert main([*args, "--margin", "5"]) == 2
    err = capsys.readouterr().err
    assert "within the 5 % margin of the workspace (x min" in err


def test_printed_placements_read_back_exactly():
    placement = np.array([0.0529812345, -0.0331249, -0.1247851, np.radians(90.4149), 0.0, np.radians(-0.004)])
    printed = as_printed(placement)
    assert np.abs(printed - placement).max() <= max(0.005e-3, np.radians(0.005))
    assert printed[0] == float("52.98") * 1e-3 and printed[3] == float("90.41") * (np.pi / 180)
    assert np.array_equal(as_printed(printed), printed)


def test_a_candidate_that_fails_is_passed_over_with_a_note():
    robot, path = load_robot("orthoglide"), load_path(EXAMPLE)
    space = default_space(robot, free=("x", "y"))
    fine = Evaluator(robot, path, EvaluatorSettings(time_step_s=0.002))
    dense = Evaluator(robot, path, EvaluatorSettings(time_step_s=0.0005, exact=True))
    outside, inside = np.array([0.07, 0.07]), np.array([0.0, 0.0])  # the first puts the groove past x max
    assert not fine.evaluate(space.full(outside)).feasible[0]
    x, note, _ = reported_point([outside, inside], fine, dense, space, 1.0)
    # The best printed point the lattice search reaches from it (placement.search.lattice), no worse than it: (0, 0) is
    # no optimum, and the search stops after LATTICE_MOVES moves of 0.01 mm.
    assert np.abs(x - inside).max() <= (LATTICE_MOVES + 1) * 1e-5 + 1e-12
    assert fine.evaluate(space.full(x)).value[0] <= fine.evaluate(space.full(inside)).value[0]
    assert note is not None and "candidate 2" in note and "workspace" in note
    x, note, _ = reported_point([inside], fine, dense, space, 1.0)
    assert note is None


def test_an_unreachable_placement_binds_on_reachability():
    robot, path = load_robot("orthoglide"), load_path(EXAMPLE)
    check = Evaluator(robot, path, EvaluatorSettings(time_step_s=0.002)).evaluate(
        np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.5, 0.5, 0.5, 0.0, 0.0, 0.0]]))
    assert check.reachable[0] and not check.reachable[1]
    assert check.limits[binding(check, 1)] == "reachability: path"
    assert check.limits[binding(check, 0)] != "reachability: path"


def test_json_is_strict():
    document = strict({"a": float("inf"), "b": [np.float64("nan"), 1.5], "c": {"d": -np.inf, "e": "x"}})
    assert document == {"a": None, "b": [None, 1.5], "c": {"d": None, "e": "x"}}
    json.loads(json.dumps(document, allow_nan=False), parse_constant=no_constant)


def test_an_unreachable_at_placement_writes_strict_json(tmp_path):
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=500,y=500",
                 "--json", str(tmp_path / "at.json")]) == 2
    at = read_strict(tmp_path / "at.json")["at"]
    assert at["objective"]["value"] is None and at["reachable"] is False


def test_metres_typed_without_a_unit_warn_and_strict_refuses(capsys):
    args = ["--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=0.05,y=0.03,z=-0.1"]
    main(args)
    err = capsys.readouterr().err
    assert "warning: --at x=0.05 is read as 0.05 mm" in err and "write x=0.05m (50 mm)" in err
    assert "z=-0.1m" in err and len(err.strip().splitlines()) >= 3
    assert main([*args, "--strict"]) == 2
    assert "error: --strict" in capsys.readouterr().err
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=0.05m,y=30,z=-0.1m"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_a_feed_in_mm_per_min_warns_or_is_refused(tmp_path, capsys):
    text = EXAMPLE.read_text()
    (tmp_path / "f40.yaml").write_text(text.replace("feed_m_s: 0.66", "feed_m_s: 40"))
    (tmp_path / "f3000.yaml").write_text(text.replace("feed_m_s: 0.66", "feed_m_s: 3000"))
    main(["--robot", "orthoglide", "--path", str(tmp_path / "f40.yaml"), "--at", "x=0"])
    err = capsys.readouterr().err
    assert "feed_m_s 40 m/s is above every joint's top speed (1 m/s): a value in mm/min? 40 mm/min = 0.0006667 m/s" in err
    assert main(["--robot", "orthoglide", "--path", str(tmp_path / "f40.yaml"), "--at", "x=0", "--strict"]) == 2
    capsys.readouterr()
    assert main(["--robot", "orthoglide", "--path", str(tmp_path / "f3000.yaml"), "--at", "x=0"]) == 2
    err = capsys.readouterr().err
    assert "feed_m_s" in err and "at most 100 m/s" in err and "3000 mm/min = 0.05 m/s" in err


@pytest.mark.parametrize("text, words", [("{}", "no 'best.placement'"), ("[1", "cannot read"),
                                         ('{"best": {"placement": {"x": "a"}}}', "no 'best.placement'")])
def test_at_json_errors_name_the_file(tmp_path, capsys, text, words):
    (tmp_path / "r.json").write_text(text)
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--at-json", str(tmp_path / "r.json")]) == 2
    err = capsys.readouterr().err
    assert words in err and "r.json" in err


def test_no_gain_is_given_beside_an_optimum_that_fails_its_recheck():
    import dataclasses

    from placement.output.report import format_result
    from placement.search.optimize import SearchSettings, optimize_placement

    robot, path = load_robot("orthoglide"), load_path(EXAMPLE)
    result = optimize_placement(robot, path, evaluation=EvaluatorSettings(time_step_s=0.01),
                                settings=SearchSettings(max_generations=3, population=8))
    assert result.best.holds and result.worst.holds and result.gain > 0.5
    broken = dataclasses.replace(result, worst=dataclasses.replace(result.worst, recheck_margin=-0.01,
                                                                   recheck_limit="workspace: x max"))
    assert broken.gain is None
    text = format_result(robot, broken)
    assert "gain: not given, the worst placement fails its 4x denser re-check" in text and "saves" not in text
    assert "a limit is exceeded between the path's samples (workspace: x max, margin -1.0000 %)" in text
