"""What real CAM posts and sample programs write beyond LinuxCNC's strict reading: a first feed move from where the
machine happens to be, G92 offsets, extra axes held at one value, K0 on G17 arcs, axis words after G80, a
program given in place of a path file, and a program without tool motion."""

import numpy as np
import pytest

from placement.__main__ import main
from placement.limits.workspace import workspace_misfit
from placement.path.exceptions import PathFileError
from placement.path.load import load_path


def program(tmp_path, code, name="p"):
    """A path file naming a G-code program written beside it."""
    (tmp_path / f"{name}.nc").write_text(code)
    file = tmp_path / f"{name}.yaml"
    file.write_text(f"shape: {{type: gcode, file: {name}.nc}}\n")
    return load_path(file)


def ends_mm(path):
    return [np.round(np.array([s.start_m, s.end_m]) * 1e3, 9).tolist() for s in path.segments]


def test_a_first_feed_move_from_an_unknown_position_is_left_out_with_a_note(tmp_path):
    # Many posts start with "G1 Z1 F..." before any X, Y: the machine is wherever it is.
    path = program(tmp_path, "G21 G90\nG1 Z1 F300\nG0 X0 Y0\nG1 Z-1\nG1 X10\n")
    assert ends_mm(path) == [[[0, 0, 1], [0, 0, -1]], [[0, 0, -1], [10, 0, -1]]]
    assert any("line 2" in note and "left out" in note for note in path.notes)


def test_a_g92_offset_moves_the_program_as_its_absolute_twin(tmp_path):
    shifted = program(tmp_path, "G21 G90 G0 X10 Y5 Z2\nG92 X0 Y0 Z0\nG1 Z-3 F200\nG2 X4 Y0 I2 J0\nG81 X1 Y1 Z-2 R1\n"
                                "G80 G92.1 G1 X0 Y0\n", name="shifted")
    twin = program(tmp_path, "G21 G90 G0 X10 Y5 Z2\nG1 Z-1 F200\nG2 X14 Y5 I2 J0\nG81 X11 Y6 Z0 R3\nG80 G1 X0 Y0\n",
                   name="twin")
    assert ends_mm(shifted) == ends_mm(twin)
    arcs = [s for s in shifted.segments if s.center_m is not None]
    np.testing.assert_allclose(arcs[0].center_m * 1e3, [12, 5, -1], atol=1e-9)


def test_an_extra_axis_held_at_one_value_is_ignored_with_a_note(tmp_path):
    with_a = program(tmp_path, "G21 G90 G0 X0 Y0 Z0 A0\nG1 X10 A0 F100\nG91 G1 Y5 A0\n", name="a")
    without = program(tmp_path, "G21 G90 G0 X0 Y0 Z0\nG1 X10 F100\nG91 G1 Y5\n", name="b")
    assert ends_mm(with_a) == ends_mm(without)
    assert any("axis A holds 0" in note for note in with_a.notes)


def test_a_zero_normal_offset_on_an_arc_is_accepted(tmp_path):
    freecad = program(tmp_path, "G21 G90 G0 X0 Y0 Z0\nG2 X10 Y0 Z0 I5 J0 K0.000 F100\n", name="k0")
    plain = program(tmp_path, "G21 G90 G0 X0 Y0 Z0\nG2 X10 Y0 Z0 I5 J0 F100\n", name="plain")
    assert ends_mm(freecad) == ends_mm(plain) and freecad.segments[0].center_m is not None


def test_axis_words_after_g80_move_in_the_motion_mode_before_the_cycle(tmp_path):
    path = program(tmp_path, "G21 G90 G0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 F100\nG80\nX5 Y5\n")
    assert len(path.segments) == 1  # the cycle's feed; its rapids and the last move are left out by default
    timed = tmp_path / "timed.yaml"
    timed.write_text("shape: {type: gcode, file: p.nc}\nrapids: {mode: timed, feed_m_s: 0.5}\n")
    moves = load_path(timed).segments
    assert moves[-1].rapid and np.allclose(moves[-1].end_m * 1e3, [5, 5, 1])


def test_a_program_given_as_the_path_runs_with_the_defaults_and_says_so(tmp_path):
    code = "G21 G90 G0 X0 Y0 Z0\nG1 X10 F600\nG1 Y10\n"
    (tmp_path / "job.ngc").write_text(code)
    bare = load_path(tmp_path / "job.ngc")
    assert bare.name == "job" and "in place of a path file" in bare.notes[0]
    assert ends_mm(bare) == ends_mm(program(tmp_path, code))


@pytest.mark.parametrize("code", ["G21 G90\nG0 X0 Y0 Z5\nM2\n", "#1 = 5\n(only parameters)\n"])
def test_a_program_without_tool_motion_exits_2_saying_so(tmp_path, capsys, code):
    (tmp_path / "none.ngc").write_text(code)
    with pytest.raises(PathFileError, match="no tool motion"):
        load_path(tmp_path / "none.ngc")
    assert main(["--robot", "orthoglide", "--path", str(tmp_path / "none.ngc"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "no tool motion" in err and "Traceback" not in err


def test_a_program_larger_than_the_workspace_is_told_it_does_not_fit(tmp_path, capsys):
    # A 300 x 300 mm square on the Orthoglide (a 200 mm workspace cube): no placement, said before any search.
    (tmp_path / "big.ngc").write_text("G21 G90 G0 X0 Y0 Z0\nG1 X300 F3000\nY300\nX0\nY0\n")
    assert main(["--robot", "orthoglide", "--path", str(tmp_path / "big.ngc"), "--quiet"]) == 2
    captured = capsys.readouterr()
    assert "does not fit in the workspace" in captured.err and "300.0 x 300.0 x 0.0 mm" in captured.err
    assert "search:" not in captured.out


@pytest.mark.parametrize("width_mm, length_mm, height_mm, fits", [
    (190, 190, 0, True), (210, 20, 5, True),  # the second only across the box's diagonal
    (300, 300, 0, False), (260, 50, 0, False), (20, 20, 205, False)])
def test_the_workspace_fit_check_turns_the_path_about_its_tool_axis(width_mm, length_mm, height_mm, fits):
    corners = np.array([[0, 0, 0], [width_mm, 0, 0], [width_mm, length_mm, 0], [0, length_mm, height_mm]]) * 1e-3
    box = ([-0.1, -0.1, -0.1], [0.1, 0.1, 0.1])
    assert (workspace_misfit(*box, corners, (-np.pi, np.pi)) is None) == fits
    if fits and width_mm > 200:
        assert workspace_misfit(*box, corners, (0.0, 0.0)) is not None  # without the turn it does not


def test_a_program_that_never_gives_its_units_is_read_in_mm_and_says_so(tmp_path):
    """LinuxCNC's sample programs often leave the units to the machine's configuration: the reader takes mm, as G21
    would, and says so; a program that gives G21 or G20 gets no such note."""
    silent = program(tmp_path, "G90 G0 X0 Y0 Z0\nG1 X10 F600\n", name="silent")
    metric = program(tmp_path, "G21 G90 G0 X0 Y0 Z0\nG1 X10 F600\n", name="metric")
    assert ends_mm(silent) == ends_mm(metric) == [[[0, 0, 0], [10, 0, 0]]]
    assert any("never gives its units" in note for note in silent.notes)
    assert not any("units" in note for note in metric.notes)


@pytest.mark.parametrize("offset_mm, bound_mm, fits", [(0, 100, True), (300, 100, False), (300, 400, True),
                                                       (-300, 100, False), (120, 100, True)])
def test_the_fit_check_keeps_the_origin_within_the_placements_bounds(offset_mm, bound_mm, fits):
    """A 50 mm square drawn ``offset_mm`` from its program's origin (as a DexArm drawing lies 200-340 mm ahead of the
    arm's base), in a 200 mm box: it fits only if an origin within ±``bound_mm`` brings it in, at some turn."""
    square = (np.array([[0, 0, 0], [50, 0, 0], [50, 50, 0], [0, 50, 0]]) + [offset_mm, 0, 0]) * 1e-3
    box = ([-0.1, -0.1, -0.1], [0.1, 0.1, 0.1])
    bounds = ([-bound_mm * 1e-3] * 3, [bound_mm * 1e-3] * 3)
    problem = workspace_misfit(*box, square, (-np.pi, np.pi), bounds)
    assert (problem is None) == fits
    if not fits:
        assert "at any placement the search may take" in problem and "--free" in problem
    assert workspace_misfit(*box, square, (-np.pi, np.pi)) is None  # its extent alone fits


def test_a_drawing_far_from_its_origin_is_answered_before_the_search(tmp_path, capsys):
    (tmp_path / "far.gcode").write_text("G21 G90\nG0 X0 Y250 Z0\nG1 X50 F3000\nY300\nX0\nY250\n")
    assert main(["--robot", "orthoglide", "--path", str(tmp_path / "far.gcode"), "--quiet"]) == 2
    captured = capsys.readouterr()
    assert "(0.0, 250.0, 0.0) to (50.0, 300.0, 0.0) mm" in captured.err and "search:" not in captured.out
