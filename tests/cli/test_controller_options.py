"""--initial-feed and --tool-diameter: what RS-274 leaves to the controller, given to a bare G-code program on the
command line as a path file's shape.initial_feed_m_s and shape.tool_diameters_mm give it."""

import json
import math

import numpy as np
import pytest

from placement.path.load import ControllerSettings, load_path
from tests.support.cli import run_command as run

# G2 before any F (GCodeKit4's circle_cut writes this): a 2 mm plunge and a half circle of radius 10 mm at the
# controller's modal feed, then 10 + 20 mm at F600.
ARC_FIRST = "G21 G90 G94 G17\nG0 X0 Y0 Z2\nG1 Z0\nG2 X20 Y0 I10 J0\nG1 X20 Y10 F600\nG1 X0 Y10\nM30\n"
# G42 D8 with tool 8's diameter not given (cncjs's thread milling writes this).
COMPENSATED = "G21 G90 G94 G17\nG0 X0 Y0 Z0\nG42 D8 G1 X10 F300\nG1 Y10\nG1 X0\nG40 G0 Y20\nM30\n"
AT = ["--robot", "orthoglide", "--quiet", "--at", "x=0,y=0,z=-100,phi=0"]


def test_a_bare_program_with_an_arc_before_f_reads_with_initial_feed_timed_as_by_the_path_file(tmp_path, capsys):
    (tmp_path / "job.nc").write_text(ARC_FIRST)
    (tmp_path / "job.yaml").write_text("shape: {type: gcode, file: job.nc, initial_feed_m_s: 0.005}\n")
    results = {}
    for name, argv in {"option": ["--path", str(tmp_path / "job.nc"), "--initial-feed", "300"],
                       "file": ["--path", str(tmp_path / "job.yaml")]}.items():
        out = tmp_path / f"{name}.json"
        code, _, err = run([*AT, *argv, "--json", str(out)], capsys)
        assert code == 0, err
        results[name] = json.loads(out.read_text())["at"]
    # 300 mm/min = 5 mm/s over the plunge (2 mm) and the half circle (10π mm), 600 mm/min over 30 mm
    expected_s = (2 + 10 * math.pi) / 5 + 30 / 10
    assert results["option"]["cycle_time_s"] == pytest.approx(expected_s, rel=1e-9)
    assert results["file"]["cycle_time_s"] == pytest.approx(expected_s, rel=1e-9)
    assert results["option"]["energy_J"] == pytest.approx(results["file"]["energy_J"], rel=1e-12)


def test_without_the_option_the_refusal_names_the_option_and_the_field(tmp_path, capsys):
    (tmp_path / "job.nc").write_text(ARC_FIRST)
    code, _, err = run([*AT, "--path", str(tmp_path / "job.nc")], capsys)
    assert code == 2 and "line 3" in err
    assert "--initial-feed MM_PER_MIN" in err and "shape.initial_feed_m_s" in err


def test_tool_diameter_gives_cutter_compensation_its_tool_as_the_path_file_does(tmp_path, capsys):
    (tmp_path / "job.nc").write_text(COMPENSATED)
    code, _, err = run([*AT, "--path", str(tmp_path / "job.nc")], capsys)
    assert code == 2 and "line 3" in err and "--tool-diameter 8=MM" in err and "shape.tool_diameters_mm" in err
    (tmp_path / "job.yaml").write_text("shape: {type: gcode, file: job.nc, tool_diameters_mm: {8: 4}}\n")
    by_option = load_path(tmp_path / "job.nc", controller=ControllerSettings(tool_diameters_mm={8: 4.0}))
    by_file = load_path(tmp_path / "job.yaml")
    ends = [np.array([s.end_m for s in path.segments]) for path in (by_option, by_file)]
    assert np.array_equal(ends[0], ends[1])
    # G42 with a 4 mm tool: the tool centre runs 2 mm to the right of the motion, so the top side (from X10 to X0)
    # runs at Y 12 mm, and the right side (up) at X 12 mm
    assert np.allclose(ends[0][-1], [0.0, 0.012, 0.0], atol=1e-12)
    assert np.isclose(ends[0][:, 0], 0.012, atol=1e-12).any()
    code, _, err = run([*AT, "--path", str(tmp_path / "job.nc"), "--tool-diameter", "T8=4"], capsys)
    assert code == 0, err


def test_the_options_override_the_path_files_fields(tmp_path):
    (tmp_path / "job.nc").write_text(ARC_FIRST)
    (tmp_path / "job.yaml").write_text("shape: {type: gcode, file: job.nc, initial_feed_m_s: 0.005}\n")
    path = load_path(tmp_path / "job.yaml", controller=ControllerSettings(initial_feed_m_s=0.01))
    assert [s.feed_ratio for s in path.segments] == pytest.approx([1.0, 1.0, 1.0, 1.0])  # all at 600 mm/min


def test_a_path_that_is_no_program_says_the_options_are_not_used(tmp_path):
    (tmp_path / "c.yaml").write_text("units: mm\nshape: {type: circle, radius: 10}\nfeed_m_s: 0.1\n")
    path = load_path(tmp_path / "c.yaml", controller=ControllerSettings(initial_feed_m_s=0.01))
    assert any("do not apply to c.yaml, a circle: not used" in note for note in path.notes)


@pytest.mark.parametrize(("extra", "words"), [
    (["--initial-feed", "0.02"], ["--initial-feed", "a value in m/s? 0.02 m/s = 1200 mm/min"]),
    (["--initial-feed", "-5"], ["--initial-feed", "> 0"]),
    (["--initial-feed", "1e9"], ["--initial-feed", "at most 6e+06"]),
    (["--tool-diameter", "8"], ["--tool-diameter", "expected T=MM"]),
    (["--tool-diameter", "x=3"], ["--tool-diameter", "expected T=MM"]),
    (["--tool-diameter", "8=wide"], ["--tool-diameter", "tool 8's diameter in mm"]),
    (["--tool-diameter", "8=nan"], ["--tool-diameter", "finite"]),
    (["--tool-diameter", "8=3", "--tool-diameter", "T8=4"], ["--tool-diameter", "tool 8 is given twice"]),
])
def test_bad_values_exit_2_naming_the_option(tmp_path, capsys, extra, words):
    (tmp_path / "job.nc").write_text(ARC_FIRST)
    for command in ([], ["map", "--grid", "x=-10:10:2,y=-10:10:2", "--out", str(tmp_path / "m.npz")]):
        code, _, err = run([*command, "--robot", "orthoglide", "--path", str(tmp_path / "job.nc"), *extra], capsys)
        assert code == 2
        for word in words:
            assert word in err, err
