"""Command line: the checks a user runs, and clear errors with exit code 2."""

import json
import math
import re
import subprocess
import sys

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.placing.transform import VARIABLES
from placement.workshop.catalog import builtin_robots_dir
from tests.support.paths import EXAMPLE


def test_robots_lists_the_orthoglide(capsys):
    assert main(["robots"]) == 0
    assert "orthoglide" in capsys.readouterr().out


def test_check_proves_the_orthoglide_model(capsys):
    assert main(["check", "orthoglide", "--samples", "40"]) == 0
    out = capsys.readouterr().out
    assert "closed-form plug-in" in out and "exact to round-off" in out


def test_check_a_sidecar_by_path(capsys):
    assert main(["check", str(builtin_robots_dir() / "fivebar" / "fivebar.yaml"), "--samples", "30"]) == 0
    assert "generic solver" in capsys.readouterr().out


def test_unknown_robot_exits_2_with_the_known_names(capsys):
    assert main(["check", "orthoglyde"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: unknown robot 'orthoglyde'") and "orthoglide" in err


def test_close_names_are_suggested(capsys):
    assert main(["check", "orthoglyde"]) == 2
    assert "did you mean orthoglide?" in capsys.readouterr().err
    assert main(["--robot", "ur10", "--path", "examples/circle.yaml"]) == 2
    assert "did you mean erd:ur10?" in capsys.readouterr().err


def test_help_lists_every_command_and_version_prints_it(capsys):
    from placement.cli import SUBCOMMANDS

    with pytest.raises(SystemExit):
        main(["--help"])
    text = capsys.readouterr().out
    for name in SUBCOMMANDS:
        assert re.search(rf"^  {name} +\S", text, re.MULTILINE), name  # one line each, with what it does
    assert "--version" in text and "--debug" in text
    assert main(["--version"]) == 0
    assert re.fullmatch(r"placement \S+\n", capsys.readouterr().out)


def test_bad_sidecar_exits_2_naming_the_field(tmp_path, capsys):
    sidecar = tmp_path / "robot.yaml"
    sidecar.write_text("name: x\nurdf: missing.urdf\ngravity_m_s2: [0, 0, -9.81]\n"
                       "end_effector: {frame: tool, task: position}\nactuators: [{joint: a}]\n")
    assert main(["check", str(sidecar)]) == 2
    err = capsys.readouterr().err
    assert "robot.yaml, field 'urdf'" in err and "not found" in err and "Traceback" not in err


def test_module_entry_point_runs():
    result = subprocess.run([sys.executable, "-m", "placement", "robots"], capture_output=True, text=True, check=False)
    assert result.returncode == 0 and "orthoglide" in result.stdout


QUICK = ["--robot", "orthoglide", "--path", str(EXAMPLE), "--time-step", "0.004", "--quiet"]


def test_main_job_reports_best_worst_and_gain_and_writes_json_and_trace(tmp_path, capsys):
    import csv
    import json

    out_json, out_csv = tmp_path / "result.json", tmp_path / "trace.csv"
    assert main(QUICK + ["--json", str(out_json), "--trace", str(out_csv)]) == 0
    text = capsys.readouterr().out
    assert "best placement (least energy)" in text and "worst placement (most energy)" in text and "gain:" in text
    document = json.loads(out_json.read_text())
    assert document["objective"] == "energy"
    for key in ("best", "worst"):
        entry = document[key]
        assert set(entry["placement"]) == {"x", "y", "z", "phi", "theta", "psi"}
        assert entry["objective"]["name"] == "energy" and entry["objective"]["value"] == entry["energy_J"]
        assert entry["recheck_energy_J"] == entry["objective"]["recheck_value"]
        assert entry["feasible"] is True and entry["energy_J"] > 0
        # Clipping the braking power away can only add to each drive's signed energy.
        signed = {name: sum(entry["energy_parts_J"][part][name] for part in ("joule", "inductive", "back_emf"))
                  for name in entry["energy_per_actuator_J"]}
        assert all(entry["energy_per_actuator_J"][name] >= signed[name] - 1e-12 for name in signed)
        assert all(m["margin"] >= 0 for m in entry["margins"])
        assert f"{entry['energy_J']:.4f} J" in text
    # The JSON placements, evaluated again through the Python API, give the JSON energies.
    evaluator = Evaluator(load_robot("orthoglide"), load_path(EXAMPLE), EvaluatorSettings(time_step_s=0.004))
    again = evaluator.evaluate([[document[key]["placement"][v] for v in VARIABLES] for key in ("best", "worst")])
    np.testing.assert_allclose(again.value, [document["best"]["energy_J"], document["worst"]["energy_J"]], rtol=1e-12)
    assert document["gain"] == pytest.approx((again.value[1] - again.value[0]) / again.value[1], rel=1e-12)
    rows = list(csv.reader(out_csv.open()))
    assert rows[0][:8] == ["t", "x", "y", "z", "speed", "tool_force_x", "tool_force_y", "tool_force_z"]
    assert rows[0][8:16] == ["q_slider_x", "qd_slider_x", "qdd_slider_x", "force_slider_x", "motor_speed_slider_x",
                             "motor_torque_slider_x", "current_slider_x", "power_slider_x"]  # a calibration log's names
    assert len(rows[0]) == 8 + 3 * 8 + 3 and len(rows) > 40  # and the deflection (the Orthoglide gives its stiffness)
    assert rows[0][-3:] == ["deflection_x", "deflection_y", "deflection_z"]
    # The trace is the best placement's: its tool points are the path placed there.
    from placement.placing.transform import transform_path_to_base

    best = document["best"]["placement"]
    placed, _ = transform_path_to_base(load_path(EXAMPLE).sample(0.004), np.array([list(best.values())]))
    np.testing.assert_allclose(np.array(rows[1:], dtype=float)[:, 1:4], placed.position_m, atol=1e-8)
    assert list(tmp_path.iterdir()) and not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
    # The duty cycle: the best's RMS motor torques are those of the trace's torque column (trapezoid rule), the
    # ratio is to the Orthoglide's rating, and nothing but the pass limits the rate (no rest asked for)
    table = np.array(rows[1:], dtype=float)
    torque = table[:, [rows[0].index(f"motor_torque_{name}") for name in ("slider_x", "slider_y", "slider_z")]]
    duty = document["best"]["duty"]
    rms = np.sqrt(np.trapezoid(torque**2, table[:, 0], axis=0) / (table[-1, 0] - table[0, 0]))
    np.testing.assert_allclose(list(duty["rms_torque_Nm"].values()), rms, rtol=1e-6)
    np.testing.assert_allclose(list(duty["ratio"].values()), rms / (400 / (3000 * 2 * np.pi / 60)), rtol=1e-6)
    assert duty["cycles_per_hour"] == pytest.approx(3600 / document["best"]["cycle_time_s"]) and "cycles per hour" in text
    # The tolerance box of the best placement: positive widths for every free variable, printed in the report
    assert all(document["best"]["tolerance"]["half_width"][name] > 0 for name in ("x", "y", "z", "phi"))
    assert text.count("tolerance (every limit holds") == 2
    for name in ("gcode", "abb", "kuka", "ur", "fanuc"):
        assert main(["export", str(out_json), "--to", name, "--out", str(tmp_path / f"frame.{name}")]) == 0


def test_at_evaluates_one_placement(tmp_path, capsys):
    import json

    out_json = tmp_path / "at.json"
    assert main(QUICK + ["--at", "x=0,y=0,z=0,phi=30", "--json", str(out_json)]) == 0
    text = capsys.readouterr().out
    assert "phi = 30.00 deg" in text and "energy" in text
    at = json.loads(out_json.read_text())["at"]
    assert at["placement"]["phi"] == pytest.approx(math.radians(30))
    assert "best" not in json.loads(out_json.read_text())


def test_results_are_deterministic_for_a_seed(tmp_path):
    import json

    files = [tmp_path / f"{k}.json" for k in range(2)]
    for file in files:
        assert main(QUICK + ["--minimize", "--seed", "7", "--json", str(file)]) == 0
    first, second = (json.loads(f.read_text()) for f in files)
    assert first["best"] == second["best"]


def bad_path(tmp_path, text):
    file = tmp_path / "path.yaml"
    file.write_text(text)
    return file


def run_bad(args, capsys):
    try:
        code = main(args)
    except SystemExit as exit_:  # argparse's own check of an option's type: usage, then the message
        code = exit_.code
    err = capsys.readouterr().err
    assert code == 2 and (err.startswith("error: ") or "placement: error: argument " in err) and "Traceback" not in err
    return err


def test_bad_inputs_exit_2_with_a_clear_message(tmp_path, capsys):
    base = ["--robot", "orthoglide", "--quiet", "--path"]
    assert "file not found" in run_bad(base + [str(tmp_path / "none.yaml")], capsys)
    assert "not valid YAML" in run_bad(base + [str(bad_path(tmp_path, "units: [mm\n"))], capsys)
    assert "unknown field" in run_bad(base + [str(bad_path(tmp_path, "units: mm\nshape: {type: circle, radius: 5}\n"
                                                                      "feed_m_s: 0.3\nspeed: 1\n"))], capsys)
    assert "shape.width" in run_bad(base + [str(bad_path(tmp_path, "units: mm\nshape: {type: rectangle, width: 0, "
                                                                     "length: 60}\nfeed_m_s: 0.66\n"))], capsys)
    assert "orthoglide" in run_bad(["--robot", "orthoglyde", "--path", str(EXAMPLE)], capsys)
    assert "--at" in run_bad(QUICK + ["--at", "x=zero"], capsys)
    circle = str(bad_path(tmp_path, "units: mm\nshape: {type: circle, radius: 20}\nfeed_m_s: 0.3\n"))
    assert "--max-acceleration" in run_bad(base + [circle, "--timing", "realistic"], capsys)


@pytest.mark.parametrize("extra, words", [
    (["--json", "/nonexistent/folder/out.json"], ["--json", "does not exist"]),
    (["--trace", "."], ["--trace", "is a folder"]),
    (["--at", "x=nan"], ["--at", "finite"]),
    (["--free", "x,foo"], ["unknown placement variable", "foo"]),
    (["--free", "x,y", "--fix", "x=10"], ["both free and fixed"]),
    (["--at", "x=0", "--fix", "z=5"], ["--at evaluates one placement"]),
    (["--timing", "realistic", "--max-acceleration", "0"], ["--max-acceleration", "expected a finite number > 0"]),
    (["--time-step", "0"], ["--time-step"]),
])
def test_bad_options_exit_2_naming_the_option(capsys, extra, words):
    err = run_bad(QUICK + extra, capsys)
    for word in words:
        assert word in err


def test_fixing_a_variable_takes_it_out_of_the_default_search(tmp_path):
    out = tmp_path / "fixed.json"
    assert main(QUICK + ["--minimize", "--fix", "z=-20", "--generations", "5", "--json", str(out)]) == 0
    assert json.loads(out.read_text())["best"]["placement"]["z"] == pytest.approx(-0.020)


def test_non_finite_numbers_in_a_path_file_are_rejected(tmp_path, capsys):
    path = bad_path(tmp_path, "units: mm\nshape: {type: circle, radius: .inf}\nfeed_m_s: 0.3\n")
    err = run_bad(["--robot", "orthoglide", "--quiet", "--path", str(path)], capsys)
    assert "shape.radius" in err and "finite" in err


def test_an_unreachable_at_placement_exits_2_and_writes_no_trace(tmp_path, capsys):
    trace = tmp_path / "trace.csv"
    err = run_bad(QUICK + ["--at", "x=1000", "--trace", str(trace)], capsys)
    assert "leaves the robot's reach" in err and not trace.exists()
    err = run_bad(QUICK + ["--at", "x=120"], capsys)  # reachable, but outside the workspace cube
    assert "breaks the workspace" in err


def test_feed_beyond_the_drives_is_answered_with_the_binding_limit(tmp_path, capsys):
    path = bad_path(tmp_path, "units: mm\nshape: {type: rectangle, width: 30, length: 60}\nfeed_m_s: 3.0\n"
                              "time_step_s: 0.004\n")
    assert main(["--robot", "orthoglide", "--path", str(path), "--quiet"]) == 2
    warning, error = capsys.readouterr().err.strip().splitlines()
    assert warning.startswith("warning: ") and "feed_m_s 3 m/s is above every joint's top speed (1 m/s)" in warning
    assert error.startswith("error: no feasible placement") and "speed" in error


def test_path_too_large_is_answered_with_the_binding_limit(tmp_path, capsys):
    path = bad_path(tmp_path, "units: mm\nshape: {type: rectangle, width: 150, length: 300}\nfeed_m_s: 0.66\n"
                              "time_step_s: 0.004\n")
    err = run_bad(["--robot", "orthoglide", "--path", str(path), "--quiet"], capsys)
    assert "no feasible placement" in err and "workspace" in err


def test_json_is_written_atomically(tmp_path, monkeypatch):
    from placement import files
    from placement.output import report

    target = tmp_path / "result.json"
    report.write_json(target, {"energy_J": 1.0})

    def fail(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(files.os, "replace", fail)
    with pytest.raises(OSError):
        report.write_json(target, {"energy_J": 2.0})
    assert target.read_text() == '{\n  "energy_J": 1.0\n}\n'  # the old file is whole
    assert [p.name for p in tmp_path.iterdir()] == ["result.json"]  # no temporary file left


def test_map_command_writes_the_map_figure_and_scene(tmp_path, capsys):
    out = tmp_path / "map.npz"
    assert main(["map", "--robot", "orthoglide", "--path", str(EXAMPLE), "--grid", "x=-110:50:5,y=-90:30:4",
                 "--fix", "z=0,phi=0", "--time-step", "0.004", "--workers", "1", "--quiet", "--out", str(out),
                 "--png", str(tmp_path / "map.png"), "--html", str(tmp_path / "map.html")]) == 0
    from placement.search.sweep import SweepResult

    result = SweepResult.load(out)
    assert result.value.shape == (5, 4) and result.axes[0][0] == pytest.approx(-0.110)
    assert (tmp_path / "map.png").is_file() and (tmp_path / "map.svg").is_file()
    assert "energy map" in (tmp_path / "map.html").read_text()
    assert "20 placements" in capsys.readouterr().out
    assert main(["map", "--robot", "orthoglide", "--path", str(EXAMPLE), "--grid", "x=1:2", "--out", str(out)]) == 2
    # A figure alone will do; nothing to write is refused before any work.
    png = tmp_path / "alone.png"
    assert main(["map", "--robot", "orthoglide", "--path", str(EXAMPLE), "--grid", "x=-110:50:3,y=-90:30:3",
                 "--time-step", "0.004", "--workers", "1", "--quiet", "--png", str(png)]) == 0
    assert png.is_file() and "written to" not in capsys.readouterr().out.split("figure")[0]
    assert main(["map", "--robot", "orthoglide", "--path", str(EXAMPLE), "--grid", "x=-110:50:3"]) == 2
    assert "give what to write" in capsys.readouterr().err


def test_the_map_command_keeps_the_margin_as_the_main_job_does(tmp_path):
    from placement.search.sweep import SweepResult

    maps = {}
    for margin in ("0", "10"):
        out = tmp_path / f"map_{margin}.npz"
        assert main(["map", "--robot", "orthoglide", "--path", str(EXAMPLE), "--grid", "x=-110:50:4,y=-90:30:4",
                     "--margin", margin, "--workers", "1", "--quiet", "--out", str(out)]) == 0
        maps[margin] = SweepResult.load(out)
    assert np.array_equal(maps["0"].value, maps["10"].value)  # the same energies, another verdict
    assert (maps["10"].feasible <= maps["0"].feasible).all() and maps["10"].feasible.sum() < maps["0"].feasible.sum()
    with pytest.raises(SystemExit) as refused:
        main(["map", "--robot", "orthoglide", "--path", str(EXAMPLE), "--grid", "x=-110:50:4", "--margin", "100",
              "--out", str(tmp_path / "m.npz")])
    assert refused.value.code == 2


def test_html_scene_of_two_paths(tmp_path, capsys):
    page = tmp_path / "scene.html"
    assert main(QUICK[:3] + [str(EXAMPLE), str(EXAMPLE)] + QUICK[4:] + ["--minimize", "--html", str(page)]) == 0
    text = page.read_text()
    assert "MeshCat.Viewer" in text and "least energy" in text and "2 paths" in text
    assert page.stat().st_mode & 0o044  # readable by others, like any file the user writes
