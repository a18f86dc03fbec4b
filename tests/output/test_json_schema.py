"""The ``--json`` output is what docs/schemas/result.schema.json says, field by field (the site's reference page is
drawn from that schema): real output of each kind of run validates, with no field the schema does not name."""

import json

import jsonschema
import pytest

from placement.__main__ import main
from tests.support.paths import CIRCLE, EXAMPLE, EXAMPLES, ROOT

SCHEMA = json.loads((ROOT / "docs" / "schemas" / "result.schema.json").read_text(encoding="utf-8"))
VALIDATOR = jsonschema.Draft202012Validator(SCHEMA)
QUICK = ["--generations", "8", "--population", "16", "--quiet"]

RUNS = {  # each kind of document: a search with its duty cycle and boxes, --at (a planar robot, a cell), a front
    "search": ["--robot", "orthoglide", "--path", str(EXAMPLE), "--rest", "0.5", *QUICK],
    "at on a planar robot": ["--robot", "fivebar", "--path", str(CIRCLE), "--at", "x=0,y=0"],
    "at in a cell": ["--robot", "orthoglide", "--path", str(EXAMPLES / "pocket.yaml"), "--cell",
                     str(EXAMPLES / "cell_orthoglide.yaml"), "--at", "x=0,y=0,z=-40"],
    "front": ["--robot", "orthoglide", "--path", str(EXAMPLE), "--objectives", "energy,transmission", *QUICK],
    "two paths": ["--robot", "orthoglide", "--path", str(EXAMPLE), str(CIRCLE), "--minimize", *QUICK],
    "seven axes, error bars": ["--robot", "panda", "--path", str(CIRCLE), "--error-bars", *QUICK],
    "at, loaded stiffness": ["--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=0,y=0,z=0", "--loaded-stiffness"],
    "a track's knots in m": ["--robot", "ur5_track", "--path", str(EXAMPLES / "long_seam.yaml"), "--at",
                             "x=450,z=200,phi=90,track@0=-700,track@1=100,track@2=750"],
    "a workpiece on a positioner": ["--robot", "ur5_positioner", "--path", str(EXAMPLES / "positioner_weld.yaml"),
                                    "--at", "phi=-120,tilt@0=-10,tilt@1=-25,tilt@2=-20,rotate@0=290,rotate@1=140,"
                                    "rotate@2=-20"],
    "optimality gap": ["--robot", "orthoglide", "--path", str(EXAMPLE), "--minimize", "--free", "x,phi", "--gap", "300",
                       *QUICK],
}


def test_the_schema_is_valid_json_schema():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("run", RUNS)
def test_real_json_output_validates_against_the_schema(run, tmp_path, capsys):
    out = tmp_path / "result.json"
    assert main([*RUNS[run], "--json", str(out)]) in (0, 2)  # 2: an --at placement that breaks a limit, written too
    printed = capsys.readouterr().out
    document = json.loads(out.read_text(encoding="utf-8"))
    errors = [f"{'/'.join(map(str, error.absolute_path))}: {error.message[:300]}" for error in VALIDATOR.iter_errors(document)]
    assert errors == []
    answers = document.get("paths", [document])
    keys = {key for answer in answers for key in answer}
    expected = {"search": {"best", "worst", "gain"}, "at on a planar robot": {"at"}, "at in a cell": {"at"},
                "front": {"members", "knee", "drawn"}, "two paths": {"best"},
                "seven axes, error bars": {"best", "worst", "uncertainty"}, "at, loaded stiffness": {"at"},
                "a track's knots in m": {"at"}, "a workpiece on a positioner": {"at", "workpiece_frame"},
                "optimality gap": {"best", "optimality_gap"}}[run]
    assert expected <= keys  # the run gave the document kind it stands for
    if run == "search":
        assert {"duty", "tolerance", "recheck_tightest"} <= set(document["best"])
    if run == "seven axes, error bars":
        assert "profiles" in document["best"] and "basins" in document["best"]
    if run == "at, loaded stiffness":
        assert 0 < document["at"]["deflection"]["loaded_correction"] < 1e-4
    if run == "a track's knots in m":
        assert "knots_m" in document["at"]["profiles"]["track"]
    if run == "optimality gap":  # stated as an estimate, in the report too, never as a proof
        gap = document["optimality_gap"]
        assert gap["kind"] == "estimated" and gap["lower_bound"] <= gap["best"] <= document["best"]["objective"]["value"]
        assert "optimality gap (estimated, not a proof" in printed
    if run == "at in a cell":
        assert any("nearest_points_m" in margin for margin in document["at"]["margins"])


def test_a_field_the_schema_does_not_name_or_a_missing_one_is_refused():
    document = {"robot": "r", "path": "p", "objective": "energy", "regeneration": "clip", "timing": "paper",
                "samples": 3, "margin": 0.0}
    assert VALIDATOR.is_valid(document)
    assert not VALIDATOR.is_valid({**document, "energy": 1.0})
    assert not VALIDATOR.is_valid({key: value for key, value in document.items() if key != "timing"})
