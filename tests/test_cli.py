"""Command line: the checks a user runs, and clear errors with exit code 2."""

import subprocess
import sys

from placement.__main__ import main
from conftest import ROBOTS_DIR


def test_robots_lists_the_orthoglide(capsys):
    assert main(["robots"]) == 0
    assert "orthoglide" in capsys.readouterr().out


def test_check_proves_the_orthoglide_model(capsys):
    assert main(["check", "orthoglide", "--samples", "40"]) == 0
    out = capsys.readouterr().out
    assert "closed-form plug-in" in out and "exact to round-off" in out


def test_check_a_sidecar_by_path(capsys):
    assert main(["check", str(ROBOTS_DIR / "fivebar" / "fivebar.yaml"), "--samples", "30"]) == 0
    assert "generic solver" in capsys.readouterr().out


def test_unknown_robot_exits_2_with_the_known_names(capsys):
    assert main(["check", "orthoglyde"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: unknown robot 'orthoglyde'") and "orthoglide" in err


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
