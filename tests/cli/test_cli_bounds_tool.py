"""Bounds given with --free, the message when bounds are missing, and a tool tip offset in the sidecar."""

import json
import math

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.__main__ import main
from placement.exceptions import SettingsError
from placement.placing.values import parse_free
from placement.robot.exceptions import RobotFileError
from tests.support.paths import EXAMPLE
from tests.support.robot_copies import TOOL_OFFSET_M, TOOL_RPY_RAD, edited_copy, with_tool

QUICK = ["--robot", "orthoglide", "--path", str(EXAMPLE), "--time-step", "0.004", "--quiet",
         "--generations", "3", "--population", "8"]


def run_bad(args, capsys):
    try:
        code = main(args)
    except SystemExit as exit_:
        code = exit_.code
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and "Traceback" not in err
    return err


def test_free_parses_names_and_bounds_in_mm_and_degrees():
    names, bounds = parse_free("y=-40:40, x,phi=-90:90,z=-0.02m:0.01m,psi=-0.1rad:0.2rad", "--free")
    assert names == ("y", "x", "phi", "z", "psi")
    assert bounds["y"] == pytest.approx((-0.040, 0.040))
    assert bounds["phi"] == pytest.approx((-math.pi / 2, math.pi / 2))
    assert bounds["z"] == pytest.approx((-0.02, 0.01)) and bounds["psi"] == pytest.approx((-0.1, 0.2))
    assert "x" not in bounds


@pytest.mark.parametrize("text, words", [
    ("y=40:-40", ["MIN below MAX", "y=40:-40"]),
    ("y=a:b", ["name=MIN:MAX", "mm", "y=a:b"]),
    ("y=1", ["name=MIN:MAX", "y=1"]),
    ("y=1:2:3", ["name=MIN:MAX"]),
    ("phi=0:inf", ["finite", "deg"]),
    ("=1:2", ["name=MIN:MAX"]),
    ("y=1:2,y", ["twice"]),
    ("w=1:2", ["unknown placement variable"]),
])
def test_bad_bounds_exit_2_naming_the_option(capsys, text, words):
    err = run_bad(QUICK + ["--free", text], capsys)
    assert err.startswith("error: --free: ") and len(err.strip().splitlines()) == 1
    for word in words:
        assert word in err
    with pytest.raises(SettingsError):
        parse_free(text, "--free")


def test_the_optimum_lies_inside_the_bounds_given(tmp_path):
    out = tmp_path / "bounded.json"
    assert main(QUICK + ["--free", "x=10:30,y=-40:-20,phi=-20:20", "--fix", "z=-10", "--json", str(out)]) == 0
    document = json.loads(out.read_text())
    for key in ("best", "worst"):
        x = document[key]["placement"]
        assert 0.010 - 1e-12 <= x["x"] <= 0.030 + 1e-12
        assert -0.040 - 1e-12 <= x["y"] <= -0.020 + 1e-12
        assert abs(x["phi"]) <= math.radians(20) + 1e-12
        assert x["z"] == pytest.approx(-0.010) and x["theta"] == 0.0 and x["psi"] == 0.0


def without_workspace(document):
    del document["workspace"]
    document["sources"] = {k: v for k, v in document["sources"].items() if not k.startswith("workspace")}


def test_missing_bounds_name_the_option_and_the_sidecar_fields(tmp_path, capsys):
    sidecar = edited_copy("orthoglide", tmp_path, without_workspace)
    quick = QUICK[:1] + [str(sidecar)] + QUICK[2:]
    err = run_bad(quick + ["--free", "x,y,phi"], capsys)
    assert "--free x=MIN:MAX,y=MIN:MAX" in err and "(mm)" in err
    assert "workspace.min_m/max_m" in err and "placement.bounds" in err
    out = tmp_path / "given.json"
    assert main(quick + ["--free", "x=-10:10,y=-10:10,phi", "--minimize", "--json", str(out)]) == 0
    best = json.loads(out.read_text())["best"]["placement"]
    assert abs(best["x"]) <= 0.010 + 1e-12 and abs(best["y"]) <= 0.010 + 1e-12


def frame_placements(robot, q):
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    return data.oMf[robot.end_effector_frame_id]


@pytest.fixture(scope="module")
def ur5_pair(tmp_path_factory):
    plain = load_robot("ur5")
    tipped = load_robot(edited_copy("ur5", tmp_path_factory.mktemp("tool"), with_tool(TOOL_OFFSET_M, TOOL_RPY_RAD)))
    return plain, tipped


def test_a_tool_offset_moves_the_end_effector_by_r_d(ur5_pair):
    plain, tipped = ur5_pair
    assert tipped.model.frames[tipped.end_effector_frame_id].name == "tool0_tool_tip"
    rng = np.random.default_rng(3)
    for q in (plain.reference_q, *(pin.randomConfiguration(plain.model) for _ in range(5)), rng.normal(size=6)):
        flange, tip = frame_placements(plain, q), frame_placements(tipped, q)
        np.testing.assert_allclose(tip.translation, flange.translation + flange.rotation @ TOOL_OFFSET_M, rtol=0, atol=1e-12)
        np.testing.assert_allclose(tip.rotation, flange.rotation @ pin.rpy.rpyToMatrix(*TOOL_RPY_RAD), rtol=0, atol=1e-12)


def test_a_tool_offset_needs_its_source(tmp_path):
    with pytest.raises(RobotFileError) as error:
        load_robot(edited_copy("ur5", tmp_path, with_tool(TOOL_OFFSET_M, source=False)))
    assert error.value.field == "end_effector.offset_m" and "sources" in str(error.value)


def test_a_tool_source_names_a_field_of_the_sidecar(tmp_path):
    def edit(document):
        with_tool(TOOL_OFFSET_M, source=False)(document)
        document["sources"]["end_effector.offset_m"] = "EST: a 125 mm spindle"
    robot = load_robot(edited_copy("ur5", tmp_path, edit))
    assert robot.sidecar.end_effector.offset_m == tuple(TOOL_OFFSET_M)
