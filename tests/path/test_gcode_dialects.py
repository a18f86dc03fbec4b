"""Controller dialects: what CAM posts and senders write for controllers other than LinuxCNC, read as those controllers
read it (with one warning per kind, naming the lines) or refused by the construct's own name.

Each program below is written as the post or sender named beside it writes it (FreeCAD's Centroid post, a grbl
sender's job, Fusion 360's Haas and personal-use posts, Fanuc Macro B); the expected paths come from the same program
without the controller's words, or written out here, never from the reader itself.
"""

import sys
import warnings

import numpy as np
import pytest

from placement.__main__ import main
from placement.exceptions import PlacementWarning
from placement.path.exceptions import GcodeDialectWarning, GcodeError, PathFileError
from placement.path.load import load_path


def program(tmp_path, code, extra="", name="p", shape=""):
    """A path file naming a G-code program written beside it; the path and the dialect warnings it gave."""
    (tmp_path / f"{name}.nc").write_text(code)
    file = tmp_path / f"{name}.yaml"
    file.write_text(f"shape: {{type: gcode, file: {name}.nc{shape}}}\n" + extra)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = load_path(file)
    return path, [str(w.message) for w in caught if issubclass(w.category, GcodeDialectWarning)]


def ends_mm(path):
    return [np.round(np.array([s.start_m, s.end_m]) * 1e3, 9).tolist() for s in path.segments]


def refused(tmp_path, code, shape=""):
    (tmp_path / "bad.nc").write_text(code)
    (tmp_path / "bad.yaml").write_text(f"shape: {{type: gcode, file: bad.nc{shape}}}\n")
    with pytest.raises(GcodeError) as error:
        load_path(tmp_path / "bad.yaml")
    return error.value


CUT = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F300\nG1 X10\nG1 Y10\nG0 Z5\n"


def test_the_dialect_warning_is_a_placement_warning():
    assert issubclass(GcodeDialectWarning, PlacementWarning)


# grbl's $ lines

GRBL_JOB = """$X
$H
$$
$#
$G
$I
$N
$N0=G54
$110=5000.000
$
?
""" + CUT + "M2\n"


def test_grbl_system_commands_are_skipped_with_one_warning_naming_their_lines(tmp_path):
    path, told = program(tmp_path, GRBL_JOB)
    plain, quiet = program(tmp_path, CUT + "M2\n", name="plain")
    assert ends_mm(path) == ends_mm(plain) and not quiet
    assert len(told) == 1
    assert "grbl system commands and status queries (lines 1, 2, 3, 4, 5, 6, 7, 8 and 3 more)" in told[0]
    assert "skipped" in told[0]
    assert "$H (line 2) sends the machine home" in told[0]


def test_grbl_homing_leaves_the_position_unknown(tmp_path):
    # After $H the machine is at its home, which the program does not know: the feed move from there is left out.
    path, told = program(tmp_path, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F300\n$H\nG1 X10\nG0 Z5\nG0 X0 Y0\nG1 Z-1\nG1 Y10\n")
    assert ends_mm(path) == [[[0, 0, 5], [0, 0, -1]], [[0, 0, 5], [0, 0, -1]], [[0, 0, -1], [0, 10, -1]]]
    assert any("line 5" in note and "unknown position" in note for note in path.notes) and "$H (line 4)" in told[0]


@pytest.mark.parametrize("line, words", [
    ("$J=G91 X10 F500", ["grbl jog ('$J=')", "G0 or G1"]),
    ("$C", ["check mode ('$C')"]),
    ("$SLP", ["sleep ('$SLP')"]),
    ("$RST=#", ["'$RST='", "work offsets"]),
    ("$TLR", ["an unknown grbl system command"]),
])
def test_grbl_commands_that_move_or_stop_the_machine_are_refused_by_name(tmp_path, line, words):
    error = refused(tmp_path, CUT + line + "\nG1 X20\n")
    assert error.line == 7 and error.word == line.replace(" ", "")
    for expected in words:
        assert expected in str(error)


# Centroid: M25, M99

FREECAD_CENTROID = """;Exported by FreeCAD
;Post Processor: centroid_post
;Output Time:2024-01-01 12:00:00
G90 G80 G40 G49
;begin preamble
G53 G00 G17
G21
;begin operation
M6 T1
M3 S1000
G0 X0.0000 Y0.0000 Z5.0000
G1 Z-1.0000 F100.0
X10.0000 Y0.0000
G2 X20.0000 Y0.0000 I5.0000 J0.0000
;end operation: Profile
;begin postamble
M5
M25
G49 H0
G90 G80 G40 G49
M99
"""


def test_freecads_centroid_post_is_read_m25_as_z_home_and_m99_as_the_end(tmp_path):
    path, told = program(tmp_path, FREECAD_CENTROID)
    twin, _ = program(tmp_path, "G21 G90 G0 X0 Y0 Z5\nG1 Z-1 F100\nX10 Y0\nG2 X20 Y0 I5 J0\nM2\n", name="twin")
    assert ends_mm(path) == ends_mm(twin)
    assert any("M25 (line 18) is Centroid's Z home" in text and "does not give (shape.machine.g28_mm)" in text
               for text in told)
    assert any("M99 (line 21) ends the main program, as M2" in text for text in told)


def test_m25_moves_z_alone_to_the_machines_home_when_the_path_file_gives_it(tmp_path):
    machine = ", machine: {work_offset_mm: [100, 50, -200], g28_mm: [0, 0, 0]}"
    path, told = program(tmp_path, FREECAD_CENTROID, "rapids: {mode: timed, feed_m_s: 0.5}\n", shape=machine)
    last = path.segments[-1]
    assert last.rapid and np.allclose(last.start_m * 1e3, [20, 0, -1]) and np.allclose(last.end_m * 1e3, [20, 0, 200])
    assert any("to the Z of shape.machine.g28_mm" in text for text in told)


def test_m25_leaves_z_unknown_without_the_machines_home(tmp_path):
    # A retract that ends the cut: the feed move after it, from an unknown Z, is left out (with a note).
    path, _ = program(tmp_path, "G21 G90 G0 X0 Y0 Z5\nG1 Z-1 F100\nX10\nM25\nG1 X20\nG0 Z5\nG1 Z-2\n")
    assert ends_mm(path) == [[[0, 0, 5], [0, 0, -1]], [[0, 0, -1], [10, 0, -1]], [[20, 0, 5], [20, 0, -2]]]
    assert any("line 5" in note and "unknown position" in note for note in path.notes)


def test_m99_ends_the_main_program_and_is_refused_in_a_subroutine(tmp_path):
    path, _ = program(tmp_path, CUT + "M99\nG1 X100 Y100\n")
    assert ends_mm(path)[-1] == [[10, 0, -1], [10, 10, -1]]
    error = refused(tmp_path, "O100 sub\nG1 X1\nM99\nO100 endsub\n" + CUT + "O100 call\n")
    assert error.line == 3 and error.word == "M99" and "inside an O-word subroutine" in str(error)
    error = refused(tmp_path, "O100 sub\nM73\nG91\nO100 endsub\n" + CUT + "O100 call\n")  # LinuxCNC's M73
    assert error.line == 2 and error.word == "M73" and "restores the modal state" in str(error)


# M codes that do not move the tool

def test_m_codes_that_do_not_move_the_tool_are_ignored_with_one_warning(tmp_path):
    # Fusion 360's Haas post: through-spindle coolant, spindle orientation, brakes, chip conveyor.
    haas = ("%\nO01001 (PART)\nG90 G94 G17 G40 G49 G80\nG21\nT1 M6\nS5000 M3\nG54\nM88\nM31\nG0 X0 Y0 Z5\nM10\n"
            "G1 Z-1 F300\nG1 X10\nG1 Y10\nM11\nG0 Z5\nM89\nM9\nM19 R90\nM33\nM73\nM74\nM30\n%\n")
    path, told = program(tmp_path, haas)
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain) and len(told) == 1
    for expected in ["M88, through-spindle coolant on (Haas) (line 8)", "M89, through-spindle coolant off (Haas) "
                     "(line 17)", "M10, clamp or rotary brake on (line 11)", "M19, spindle orientation (line 19)",
                     "M31, chip conveyor forward (Haas) (line 9)", "M73, tool air blast on (Haas", "do not move the tool"]:
        assert expected in told[0]


def test_a_rotrics_dexarm_drawing_is_read_its_module_and_straight_rapids_ignored_with_one_warning(tmp_path):
    # Rotrics Studio's header for the DexArm (a Marlin-based arm): straight G0 moves, the pen module; then the drawing.
    dexarm = (";--------- HEADER FROM ROTRIX STUDIO FOR DEXARM\n\nM2000;custom:line mode\nM888 P0;custom:header is "
              "write&draw\n\n;--------- END OF DEXARM HEADER\n\n" + CUT)
    path, told = program(tmp_path, dexarm)
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain) and len(told) == 1
    for expected in ["M888, front-end module (Rotrics DexArm", "(line 4)", "M2000, G0 moves in straight lines",
                     "(line 3)"]:
        assert expected in told[0]


def test_rotrics_dexarms_jump_rapids_are_refused_by_name(tmp_path):
    error = refused(tmp_path, "M2001\n" + CUT)
    assert error.line == 1 and error.word == "M2001" and "turn the joints at once" in str(error)


def test_rs274ngcs_own_m_codes_give_no_warning(tmp_path):
    _, told = program(tmp_path, "M6 T1\nM3 S1000\nM7\nM8\n" + CUT + "M9\nM5\nM48\nM49\nM30\n")
    assert told == []


@pytest.mark.parametrize("word, words", [
    ("M600", ["may move the tool"]), ("M72", ["may move the tool"]), ("M21", ["may move the tool"]),
    ("M98 P100", ["Fanuc subprogram calls (M98 P)"]), ("M97 P100", ["Haas local subprograms (M97 P)"]),
])
def test_unknown_m_codes_are_refused_naming_the_word_and_the_line(tmp_path, word, words):
    error = refused(tmp_path, CUT + word + "\n")
    assert error.line == 7 and error.word == word.split()[0]
    for expected in words:
        assert expected in str(error)


# Fanuc Macro B, refused by name

@pytest.mark.parametrize("line, text, words", [
    ("IF [#1 EQ 0] THEN #2 = 5", "", ["Fanuc Macro B 'IF ... THEN' is not read", "o100 if"]),
    ("N20 IF [#1 GT 3] GOTO 100", "", ["Fanuc Macro B 'IF ... GOTO' is not read"]),
    ("WHILE [#1 LT 3] DO 1", "", ["Fanuc Macro B 'WHILE ... DO' is not read", "o100 while"]),
    ("END 1", "", ["Fanuc Macro B 'END' (closing a WHILE ... DO)"]),
    ("GOTO 100", "", ["Fanuc Macro B 'GOTO' is not read"]),
    ("DPRNT[X#100[44]]", "", ["Fanuc Macro B 'DPRNT'/'BPRNT'", "does not move the tool"]),
    ("POPEN", "", ["Fanuc Macro B 'POPEN'/'PCLOS'"]),
    ("#2 = #1 + 1", "#2=#1+1", ["Fanuc Macro B expression without brackets", "#1=[#2+1]"]),
    ("G1 X#1+2", "X#1+2", ["without brackets", "X[#1+2]"]),
    ("#2 = #0", "#0", ["Fanuc Macro B's vacant (null) value"]),
    ("G1 X#5001", "#5001", ["Fanuc Macro B system variable (the current position)"]),
    ("G65 P9010 A1", "G65", ["Fanuc Macro B macro call (G65, G66, G67)"]),
])
def test_fanuc_macro_b_is_refused_by_the_constructs_name(tmp_path, line, text, words):
    error = refused(tmp_path, CUT + "#1 = 0\n" + line + "\n")
    assert error.line == 8 and error.word == text
    message = str(error)
    assert message.startswith(f"{tmp_path / 'bad.nc'}, line 8") and "unknown function" not in message
    for expected in words:
        assert expected in message


# The controller's modal feed for feed moves before the first F

PERSONAL_USE = "G90 G94 G17\nG21\nG54\nS10000 M3\nG0 X0 Y0 Z5\nG1 X10 Y0\nG1 Z-1\nG1 X20 F600\nG1 Y10\nM30\n"


def test_feed_moves_before_any_f_are_refused_saying_how_to_give_the_modal_feed(tmp_path):
    error = refused(tmp_path, PERSONAL_USE)
    assert error.line == 6 and error.word == "X10"
    assert "before any feed rate" in str(error) and "shape.initial_feed_m_s" in str(error)


def test_feed_moves_before_any_f_run_at_the_path_files_initial_feed(tmp_path):
    path, told = program(tmp_path, PERSONAL_USE, shape=", initial_feed_m_s: 0.005")
    assert path.feed_m_s == pytest.approx(0.01)  # the highest: F600 mm/min
    assert [s.feed_ratio for s in path.segments] == pytest.approx([0.5, 0.5, 1.0, 1.0])
    assert len(told) == 1 and "lines 6, 7 come before the program's first F" in told[0] and "300 mm/min" in told[0]


def test_the_initial_feed_does_not_stand_for_a_feed_per_revolution(tmp_path):
    error = refused(tmp_path, "G21 G90 G95 S1000\nG0 X0 Y0 Z0\nG1 X10\n", shape=", initial_feed_m_s: 0.005")
    assert error.line == 3 and "before any feed rate" in str(error)


def test_an_initial_feed_in_mm_per_minute_is_refused_saying_so(tmp_path):
    (tmp_path / "p.nc").write_text(PERSONAL_USE)
    (tmp_path / "p.yaml").write_text("shape: {type: gcode, file: p.nc, initial_feed_m_s: 600}\n")
    with pytest.raises(PathFileError, match="initial_feed_m_s.*a value in mm/min"):
        load_path(tmp_path / "p.yaml")


# G10 L2 / L20 beyond the oracle's programs (tests/path/test_gcode_oracle.py)

def test_g10_l20_at_the_start_makes_the_machines_point_the_programs_origin(tmp_path):
    # grbl senders' "zero here": the current point, wherever the machine is, becomes X0 Y0 Z0.
    path, _ = program(tmp_path, "$H\nG10 L20 P1 X0 Y0 Z0\nG21 G90\nG1 Z-1 F300\nG1 X10\n")
    assert ends_mm(path) == [[[0, 0, 0], [0, 0, -1]], [[0, 0, -1], [10, 0, -1]]]


def test_work_offsets_set_before_the_first_move_machine_two_fixtures(tmp_path):
    # Haas: the fixtures' offsets set at the start, the same contour cut in G54 and G55, 60 mm apart along X.
    code = "G10 L2 P1 X-100 Y-50 Z-20\nG10 L2 P2 X-40 Y-50 Z-20\nG21 G90 G54 G0 X0 Y0 Z5\nG1 Z-1 F200\nG1 X10\n" \
           "G0 Z5\nG55 G0 X0 Y0\nG1 Z-1\nG1 X10\n"
    path, _ = program(tmp_path, code)
    assert ends_mm(path) == [[[0, 0, 5], [0, 0, -1]], [[0, 0, -1], [10, 0, -1]], [[60, 0, 5], [60, 0, -1]],
                             [[60, 0, -1], [70, 0, -1]]]


@pytest.mark.parametrize("code, line, word, words", [
    ("G10 L2 P1 R30\n", 7, "R30", ["rotated coordinate system"]),
    ("G10 L20 P12 X0\n", 7, "P12", ["G154 P", "not read"]),
    ("G10 L2 X0\n", 7, "G10", ["needs P"]),
    ("G10 P1 X0\n", 7, "G10", ["G10 needs L"]),
    ("G10 L1 P1 R3\n", 7, "R3", ["radius in LinuxCNC but a length or a wear", "tool_diameters_mm"]),
    ("G10 L12 P1 R3\n", 7, "L12", ["cutter radius or diameter offset", "tool_diameters_mm"]),
    ("G10 L3 P1\n", 7, "L3", ["not read"]),
    ("G56 G0 X0\n", 7, "G56", ["changes work coordinate system to G56", "G10 L2 P3"]),
    ("G10 L2 P2 X10 Y10 Z0\nG55 G0 X0\n", 8, "G55", ["whose offset G10 sets in machine coordinates",
                                                     "shape.machine.work_offset_mm"]),
    ("G28\nG10 L20 P1 X0 Y0 Z0\n", 8, "G10", ["not known here (X, Y, Z)"]),
    ("G41.1 D2 G1 X20\nG10 L2 P0 X1\n", 8, "G10", ["cutter radius compensation"]),
])
def test_work_offsets_the_reader_cannot_follow_are_refused_naming_the_word(tmp_path, code, line, word, words):
    error = refused(tmp_path, CUT + code)
    assert error.line == line and error.word == word
    for expected in words:
        assert expected in str(error)


def test_tool_lengths_set_by_g10_do_not_move_the_tool_tip(tmp_path):
    path, _ = program(tmp_path, "G10 L1 P1 Z25.4\n" + CUT + "G10 L10 P1 Z0\n")
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain)


# On the command line

def test_the_command_line_prints_each_kind_of_dialect_word_once_as_a_warning(tmp_path, capsys, monkeypatch):
    # A 300 mm square does not fit the Orthoglide: it exits 2 right after reading the program.
    code = "$H\nG21 G90 G0 X0 Y0 Z0\nM88\nG1 X300 F3000\nM88\nY300\nX0\nY0\nM89\nM99\n"
    (tmp_path / "big.ngc").write_text(code)

    def shown(message, category, filename, lineno, file=None, line=None):  # Python's own showwarning, unrecorded
        sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))

    monkeypatch.setattr(warnings, "showwarning", shown)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        assert main(["--robot", "orthoglide", "--path", str(tmp_path / "big.ngc"), "--quiet"]) == 2
    lines = capsys.readouterr().err.splitlines()
    told = [line for line in lines if line.startswith("warning: ")]
    assert len(told) == 3 and "Traceback" not in "".join(lines)
    assert "$H (line 1)" in told[0] and "M88, through-spindle coolant on (Haas) (lines 3, 5)" in told[1]
    assert "M99 (line 10)" in told[2]


# What posts write around the moves

def test_an_end_point_before_any_motion_word_is_a_rapid_as_grbl_and_fanuc_start_in_g0(tmp_path):
    # A Fusion 360 post's tool change: "T12 M6" then "Z10" before any G0 (grbl, Fanuc and Haas start in G0).
    code = "G90 G94\nG17\nG21\nG28 G91 Z0\nG90\nT12 M6\nZ10\nG54\nG0 X0 Y0\nZ5\nG1 Z-1 F200\nX10\n"
    path, told = program(tmp_path, code, "rapids: {mode: timed, feed_m_s: 0.5}\n")
    assert path.segments[0].rapid and np.allclose(path.segments[0].start_m * 1e3, [0, 0, 10])  # (from where Z10 went)
    assert len(told) == 1 and "line 7 gives an end point before any motion word: read as G0" in told[0]


def test_text_after_the_programs_end_is_not_read(tmp_path):
    # A post's summary after M30 (as the posts of rotary jobs in Universal G-code Sender's test files write it).
    path, _ = program(tmp_path, CUT + "M30\n\n( Output Ends Here )\nPost Process Timed at; 32 Min, 50.0 sec\n")
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain)
    error = refused(tmp_path, CUT + "Post Process Timed at; 32 Min, 50.0 sec\nM30\n")
    assert error.line == 7


@pytest.mark.parametrize("name", ["OCIRCLE(Circle)", "O7997A(NestedShtCutoff)", ":1001", "O0001 (PART)"])
def test_a_program_named_in_letters_or_by_isos_colon_is_read(tmp_path, name):
    path, told = program(tmp_path, f"%\n{name}\n" + CUT + "M30\n%\n")
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain) and told == []


def test_a_fanuc_macro_after_a_program_named_in_letters_is_refused_by_its_name(tmp_path):
    # A plasma control's macro program: the first line that cannot be read is the macro's IF, named as such.
    code = "%\nOCIRCLE(Circle)\n#139=0(0=pierce inner)\n#140=.6250(Diameter)\nIF[#139EQ1]GOTO20\nN10(pierce inner)\n"
    error = refused(tmp_path, code)
    assert error.line == 5 and "Fanuc Macro B 'IF ... GOTO' is not read" in str(error)


def test_haas_and_fanuc_smoothing_modes_leave_the_path_as_programmed_with_one_warning(tmp_path):
    # Fusion 360's Haas and Fanuc posts: G187 P2 E0.05 (smoothness, corner tolerance), G103 P1, G05.1 Q1, G08 P1.
    code = "G21 G90\nG187 P2 E0.05\nG103 P1\nG05.1 Q1\nG08 P1\n" + CUT + "G187 P1\nG05.1 Q0\nG08 P0\nG103\nM30\n"
    path, told = program(tmp_path, code)
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain) and len(told) == 1
    for expected in ["G187, smoothness and corner tolerance (Haas) (lines 2, 12)", "G103, look-ahead limit (Haas) "
                     "(lines 3, 15)", "G5.1, AI contour control (Fanuc, with Q) (lines 4, 13)", "not modelled"]:
        assert expected in told[0]


@pytest.mark.parametrize("line, word, words", [
    ("G5.1 X10 Y10 I2 J2", "G5.1", ["quadratic spline (G5.1) is not read"]),
    ("G5 X10 Y10 I2 J2 P1 Q1", "G5", ["cubic spline (G5) is not read"]),
    ("G8", "G8", ["radius mode, G8"]),
    ("G1 X10 E5", "E5", ["the extruder (E) moves here"]),
])
def test_linuxcnc_splines_and_other_words_of_those_numbers_are_refused(tmp_path, line, word, words):
    error = refused(tmp_path, CUT + line + "\n")
    assert error.line == 7 and error.word == word
    for expected in words:
        assert expected in str(error)


def test_a_long_dwell_of_a_whole_number_is_read_in_seconds_with_a_warning(tmp_path):
    # A UCCNC or Fanuc-style post's spindle wait, G04 P4000: LinuxCNC and grbl read 4000 s, Fanuc 4 s.
    path, told = program(tmp_path, CUT + "G04 P4000\nG4 P2.5\nG4 P150.\nG4 P2\n")
    assert [hold.duration_s for hold in path.holds] == [4000.0, 2.5, 150.0, 2.0]
    assert len(told) == 1 and "the dwells of line 7 (G4 P with a whole number of at least 10)" in told[0]


VECTRIC_MACH3 = """( VCarve Pro, Mach2/3 post )
( File created: Monday, 1 January 2024 - 10:00 AM)
( Material Size)
( X= 100.000, Y= 100.000, Z= 10.000)
G00G21G17G90G40G49G80
G71G91.1
T1M06
G00G43Z20.000H1
S18000M03
G94
G00X0.000Y0.000Z5.000
G1Z-1.000F300.0
G1X10.000
G1Y10.000
G00Z20.000
G00X0.000Y0.000
M09
M30
"""


def test_vectrics_mach3_post_is_read_g71_as_millimetres_with_a_warning(tmp_path):
    path, told = program(tmp_path, VECTRIC_MACH3)
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain) and len(told) == 1
    assert "G71 (line 6) is read as Mach3's (and older controls') units" in told[0]
    inches, _ = program(tmp_path, "G70 G90\nG0 X0 Y0 Z0\nG1 X1 F10\n", name="inches")
    assert ends_mm(inches) == [[[0, 0, 0], [25.4, 0, 0]]]


@pytest.mark.parametrize("line, word, words", [
    ("G71 P10 Q20 D1", "G71", ["turning cycles G70, G71"]),
    ("G1 X20 E1.5", "E1.5", ["the extruder (E) moves here", "3D print"]),
    ("M104 S200 G1 X20", "M104", ["hotend temperature", "put it on a line of its own"]),
    ("M220 S150", "M220", ["feed override"]),
])
def test_lathe_cycles_and_3d_printers_words_are_refused_by_name(tmp_path, line, word, words):
    error = refused(tmp_path, CUT + line + "\n")
    assert error.line == 7 and error.word == word
    for expected in words:
        assert expected in str(error)


@pytest.mark.parametrize("line, word, words", [
    ("G15 H1", "G15", ["Okuma's G15 H selects a work coordinate system", "G54-G59"]),
    ("G16 X10 Y45", "G16", ["Fanuc's polar coordinates (G16)"]),
    ("G68 X0 Y0 R30", "G68", ["Fanuc's coordinate rotation (G68)"]),
    ("G68.2 X0 Y0 Z0 I0 J45 K0", "G68.2", ["tilted working plane"]),
    ("G43.4 H1", "G43.4", ["5-axis tool centre point control", "G43.4 and G43.5"]),
    ("G43.5 H1", "G43.5", ["5-axis tool centre point control"]),
])
def test_other_controllers_coordinate_and_5_axis_modes_are_refused_by_name(tmp_path, line, word, words):
    """Okuma's work systems, Fanuc's polar coordinates, rotation and tilted planes, and tool centre point control,
    each named at its line and word (LinuxCNC's rs274 reads none of them either)."""
    error = refused(tmp_path, CUT + line + "\n")
    assert error.line == 7 and error.word == word
    for expected in words:
        assert expected in str(error)


# Marlin (RepRapFirmware, Klipper): pen plotters and lasers driven by a 3D printer's firmware

MARLIN_PEN = """; a pen plotter's drawing as Inkscape's gcodetools writes it after a Marlin printer's start code
M104 S0 ; hotend off
M140 S0
M109 R0
M190 S0 ; wait for the bed
M106 P0 S255 ; fan on
M107
M82
G92 E0
M204 P500.00 R1000.00 T500.00
M205 X8.00 Y8.00 Z0.40 E5.00 ; jerk: settings, not a move
M117 Deploy the pen (then wait)
M118 E1 Drawing...
G21 G90 E0
G0 X0 Y0 Z5
G4 S1
G1 Z-1 F300
G4 P500
G1 X10
G1 Y10
G0 Z5
M400
M84
M18
M2
"""


def test_a_marlin_pen_drawing_is_read_its_firmwares_words_ignored_with_a_warning_per_kind(tmp_path):
    path, told = program(tmp_path, MARLIN_PEN)
    plain, _ = program(tmp_path, CUT + "M2\n", name="plain")
    assert ends_mm(path) == ends_mm(plain)  # M205 X8 Y8 Z0.4 is no move, M117's text no words
    # Marlin's G4 S is in seconds and its G4 P in milliseconds (Marlin's gcode docs, G4).
    assert [hold.duration_s for hold in path.holds] == [1.0, 0.5]
    firmware = next(text for text in told if text.startswith(str(tmp_path / "p.nc") + ": Marlin's"))
    for expected in ["M104, hotend temperature (line 2)", "M109, wait for the hotend temperature (line 4)",
                     "M117, message on the display (line 12)", "M205, the firmware's jerk limits (line 11)",
                     "M400, wait for the moves to finish (line 22)", "the waits for a temperature are not timed"]:
        assert expected in firmware
    assert any("the extruder's E (lines 9, 14) stays where it is" in text for text in told)
    assert any("G4 S (line 16) dwells S seconds" in text for text in told)
    assert any("G4 P (line 18) dwells P milliseconds" in text for text in told)
    assert any("M84, air jet off (Haas); motors off (Marlin) (line 23)" in text for text in told)


def test_a_dwell_of_p_stays_in_seconds_without_marlins_words(tmp_path):
    path, _ = program(tmp_path, CUT + "G4 P500\nM2\n")
    assert [hold.duration_s for hold in path.holds] == [500.0]


def test_marlins_homing_by_axis_letters_leaves_those_axes_unknown_as_grbls_does(tmp_path):
    marlin, told = program(tmp_path, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F300\nG28 X Y\nG1 X10\nG0 Z5\nG0 X0 Y0\n"
                                     "G1 Z-1\nG1 Y10\n")
    grbl, _ = program(tmp_path, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F300\n$HXY\nG1 X10\nG0 Z5\nG0 X0 Y0\n"
                                "G1 Z-1\nG1 Y10\n", name="grbl")
    assert ends_mm(marlin) == ends_mm(grbl) == [[[0, 0, 5], [0, 0, -1]], [[0, 0, 5], [0, 0, -1]],
                                                  [[0, 0, -1], [0, 10, -1]]]
    assert any("G28 with axis letters and no numbers (line 4) is Marlin's homing" in text for text in told)


@pytest.mark.parametrize("code, line, word", [
    ("G92 E0\nG1 X10 E0.5\n", 8, "E0.5"),  # absolute extrusion (Marlin's default)
    ("M83\nG1 X10 E0\nG1 X20 E0.2\n", 9, "E0.2"),  # relative: any E but 0 extrudes
    ("G91\nG1 X10 E0\nG1 X10 E-1\n", 9, "E-1"),  # G91 makes E relative too (a retraction)
    ("G92 E5\nM82\nG1 X10 E5\nG1 X20 E6\n", 10, "E6"),
])
def test_a_print_is_refused_where_its_extruder_first_moves(tmp_path, code, line, word):
    error = refused(tmp_path, CUT + code)
    assert (error.line, error.word) == (line, word)
    assert "the extruder (E) moves here" in str(error) and "3D print" in str(error)


def test_user_m_codes_are_read_as_not_moving_the_tool_with_a_warning(tmp_path):
    # Mr Beam's compressor (M100 P100 ... M100 P0); LinuxCNC runs the file M100 given P and Q.
    path, told = program(tmp_path, "M100 P100 Q2\n" + CUT + "M100 P0\nM2\n")
    plain, _ = program(tmp_path, CUT + "M2\n", name="plain")
    assert ends_mm(path) == ends_mm(plain)
    assert len(told) == 1 and "user-defined M codes M100-M199 (lines 1, 8)" in told[0]


def test_a_comment_longer_than_a_line_may_be_is_read(tmp_path):
    # Mr Beam's programs carry the engraved picture as base64 in a comment of ~100,000 characters.
    path, _ = program(tmp_path, "; Image: data:image/png;base64," + "A" * 5000 + "\n" + CUT)
    plain, _ = program(tmp_path, CUT, name="plain")
    assert ends_mm(path) == ends_mm(plain)
    error = refused(tmp_path, "G0 X" + "1" * 1200 + "\n")
    assert "longer than 1000 characters" in str(error)


def test_a_program_that_starts_incrementally_starts_at_its_origin_with_a_warning(tmp_path):
    # A thread mill's helix in G91 (cncjs's example), run from where the tool stands: its twin in absolute words.
    path, told = program(tmp_path, "G21 G91\nG1 Z-1 F100\nG1 X10\nG3 X-10 Y10 I-10 J0\nG90 G0 Z5\n")
    twin, _ = program(tmp_path, "G21 G90\nG0 X0 Y0 Z0\nG1 Z-1 F100\nG1 X10\nG3 X0 Y10 I-10 J0\nG0 Z5\n", name="twin")
    assert ends_mm(path) == ends_mm(twin)
    assert len(told) == 1 and "the program's first move (line 2) is incremental (G91)" in told[0]


def test_g92_at_the_start_makes_the_current_point_known_as_a_pen_plotters_you_are_here(tmp_path):
    # Inkscape's Unicorn plugin: "G92 X0.00 Y0.00 Z0.00 (you are here)", M300 pen servo, then G1 moves, Z at the end.
    path, _ = program(tmp_path, "G21\nG90\nG92 X0 Y0 Z0 (you are here)\nM300 S30 (pen down)\nG4 P150\n"
                                "G1 X-10 Y4 F3500\nG1 X-10 Y2\nG1 Z0 F150\n")
    assert ends_mm(path) == [[[0, 0, 0], [-10, 4, 0]], [[-10, 4, 0], [-10, 2, 0]]]
    assert [hold.duration_s for hold in path.holds] == [0.15]


# Other controllers' languages, refused by name at their line (placement.path.ngc_languages)

@pytest.mark.parametrize(("code", "line", "words"), [
    # Heidenhain conversational, as a TNC writes it (line numbers, Q parameters, FMAX)
    ("0 BEGIN PGM PART MM\n1 BLK FORM 0.1 Z X-50 Y-50 Z-20\n2 TOOL CALL 1 Z S3000\n3 L Z+50 R0 FMAX M3\n"
     "4 END PGM PART MM\n", 1, ["Heidenhain conversational (Klartext)", "'BEGIN PGM'"]),
    ("; a fragment without its header\nTOOL CALL 1 Z S3500\nL X+10 Y+0 R0 FMAX\n", 2,
     ["Heidenhain conversational", "'TOOL CALL'"]),
    ("G21 G90\nG0 X0 Y0 Z5\nL X+10 Y+5 RL F200\n", 3, ["Heidenhain conversational", "path block"]),
    ("%PART G71 *\nN10 G00 X+0 Y+0 *\n", 1, ["Heidenhain DIN/ISO program", "'%NAME G71 *'"]),
    # Siemens Sinumerik, as its CAM posts write it
    ("N10 G17 G90 G54\nN20 T=\"MILL10\" M6\n", 2, ["Siemens Sinumerik", "tool called by name"]),
    ("N10 G17 G90 G54\nN20 G0 X0 Y0 Z5\nN30 CYCLE81(10, 0, 2, -25, 0)\n", 3, ["Siemens Sinumerik", "cycle call"]),
    ("G21 G90\nTRANS X10 Y20\n", 2, ["Siemens Sinumerik", "a frame"]),
    ("G21 G90\nR1=5\nG0 X=R1\n", 2, ["Siemens Sinumerik", "an R parameter"]),
    ("G21 G90\nDEF REAL DEPTH=-5\n", 2, ["Siemens Sinumerik", "'DEF'"]),
    ("MSG(\"ROUGHING\")\nG0 X0\n", 1, ["Siemens Sinumerik", "MSG"]),
    # 5-axis tool centre point programming: the tip's coordinates with the rotary axes following
    ("N10 G17 G90 G54\nN20 TRAORI\nN30 G1 X10 A30 F500\n", 2, ["Siemens Sinumerik", "'TRAORI'", "tool centre point"]),
    ("0 FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS\n1 L X+10 R0 FMAX\n", 1,
     ["Heidenhain conversational", "'FUNCTION TCPM'", "tool centre point"]),
])
def test_another_controllers_language_is_refused_by_its_name(tmp_path, code, line, words):
    error = refused(tmp_path, code)
    assert error.line == line, str(error)
    assert "is not RS-274 G-code" in str(error) and "G-code (ISO, RS-274) post" in str(error)
    for word in words:
        assert word in str(error)


def test_rs274_that_looks_foreign_is_still_read(tmp_path):
    # a rotary axis alone, an R arc, a drilling cycle's R and L, a parameter read in a word: all RS-274
    path, _ = program(tmp_path, "G21 G90\nG0 X0 Y0 Z5 C0\nC0\nG1 Z0 F100\nG2 X10 Y0 R5\n#1=2\nG1 X[#1*10]\n"
                                "G81 X0 Y0 Z-1 R1 L1\nG80\nM2\n")
    assert len(path.segments) == 4  # the plunge, the arc, the line to X20 and the hole's feed (rapids left out)


def test_a_heidenhain_program_given_bare_is_refused_by_name_not_read_as_yaml(tmp_path):
    (tmp_path / "PART.H").write_text("0 BEGIN PGM PART MM\n1 TOOL CALL 1 Z S3000\n2 L X+0 Y+0 R0 FMAX\n"
                                     "3 END PGM PART MM\n")
    with pytest.raises(GcodeError, match="line 1: a Heidenhain conversational"):
        load_path(tmp_path / "PART.H")


def test_a_hash_comment_is_refused_saying_how_comments_are_written(tmp_path):
    error = refused(tmp_path, "# 4 mm square, laser at 10 %\nG21 G90\n")
    assert error.line == 1 and "'#' starts a parameter" in str(error) and "parentheses or after ';'" in str(error)


def test_linuxcncs_outputs_and_input_wait_do_not_move_the_tool(tmp_path):
    # a LinuxCNC laser post: power by M67 E0 Q (analog), on and off with the motion by M62/M63 P0, a wait on input 0
    path, told = program(tmp_path, "G21 G90\nG0 X0 Y0 Z0\nM67 E0 Q40\nM62 P0\nG1 X10 F600\nM63 P0\n"
                                   "M66 P0 L3 Q2\nM68 E1 Q0\nM64 P1\nM65 P1\nG1 Y10\nM2\n")
    assert ends_mm(path) == [[[0, 0, 0], [10, 0, 0]], [[10, 0, 0], [10, 10, 0]]]
    assert len(told) == 1 and "M62-M68 (lines 3, 4, 6, 7, 8, 9, 10" in told[0]


@pytest.mark.parametrize("encoding", ["cp1252", "utf-16"])
def test_a_program_in_a_windows_encoding_is_read_its_comments_holding_what_they_hold(tmp_path, encoding):
    code = "(Fräser Ø6 mm, 90°)\nG21 G90\nG0 X0 Y0 Z0\nG1 X10 F600 (Tiefe 2 mm)\nM2\n"
    (tmp_path / "p.nc").write_bytes(code.encode(encoding))  # (Python writes UTF-16 with its byte order mark)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = load_path(tmp_path / "p.nc")
    assert ends_mm(path) == [[[0, 0, 0], [10, 0, 0]]]
    said = [str(w.message) for w in caught if issubclass(w.category, GcodeDialectWarning)]
    assert any("read as Windows-1252" in text for text in said) == (encoding == "cp1252")


def test_a_binary_file_is_refused_as_no_text(tmp_path):
    (tmp_path / "p.nc").write_bytes(b"G21\x00\x01\x02" * 10)
    with pytest.raises(PathFileError, match="not a text file"):
        load_path(tmp_path / "p.nc")


def test_a_spindle_number_that_is_no_whole_number_is_refused(tmp_path):
    error = refused(tmp_path, "G21 G90\nG0 X0 Y0 Z0\nM3 $0.5 S1000\n")
    assert error.line == 3 and error.word == "$0.5" and "spindle number" in str(error)


def test_a_double_slash_comment_is_refused_saying_how_comments_are_written(tmp_path):
    error = refused(tmp_path, "%\n// Stock is 3 x 3 x 1 in\nG70\nG0 X0 Y0\n")
    assert error.line == 2 and error.word == "//" and "MillMaster Pro" in str(error) and "after ';'" in str(error)


def test_fanucs_dwell_g4_x_lasts_x_seconds_and_moves_nothing(tmp_path):
    path, told = program(tmp_path, "G21 G90\nG0 X0 Y0 Z0\nG1 X5 F600\nG04 X1.5\nG1 X10\nM2\n")
    assert ends_mm(path) == [[[0, 0, 0], [5, 0, 0]], [[5, 0, 0], [10, 0, 0]]]
    assert [(hold.after, hold.duration_s) for hold in path.holds] == [(1, 1.5)]
    assert any("G4 X (line 4) dwells X seconds" in text for text in told)


def test_fanucs_words_ending_modes_that_are_not_read_change_nothing(tmp_path):
    """G15 (polar coordinates off) and G69 (coordinate rotation off) in a post's safety line: G16 and G68, which would
    turn those modes on, are refused, so ending them changes nothing: the same path, with a note naming the lines."""
    plain, _ = program(tmp_path, "G21 G90 G17 G40 G49 G80\nG0 X0 Y0 Z5\nG1 Z0 F300\nG1 X10\nM30\n", name="plain")
    path, told = program(tmp_path, "G21 G90 G17 G40 G49 G80 G15 G69\nG0 X0 Y0 Z5\nG1 Z0 F300\nG69\nG1 X10\nM30\n")
    assert ends_mm(path) == ends_mm(plain)
    assert any("change nothing: G15, polar coordinates off (G16, which turns them on, is not read) (line 1); G69, "
               "coordinate rotation off (G68, which turns it on, is not read) (lines 1, 4)" in text for text in told)


@pytest.mark.parametrize("select", ["G54.1 P3", "G154 P12"])
def test_an_additional_work_offset_selected_before_the_first_move_is_the_path_frame(tmp_path, select):
    # Fanuc's G54.1 P and Haas's G154 P, as Fusion 360's posts write them for a work offset past G59
    path, told = program(tmp_path, f"G21 G90 G17\n{select}\nG0 X0 Y0 Z5\nG1 Z0 F300\nG1 X10\nM30\n")
    assert ends_mm(path) == [[[0, 0, 5], [0, 0, 0]], [[0, 0, 0], [10, 0, 0]]]
    assert any("G54.1 P and G154 P (line 2) select an additional work offset" in text for text in told)


@pytest.mark.parametrize(("code", "word", "words"), [
    ("G21 G90\nG0 X0 Y0 Z0\nG54.1 P2\nG1 X10 F300\n", "G54.1", ["G54.1 P2", "write the program in one system"]),
    ("G21 G90\nG54.1 P49\n", "G54.1", ["P, a whole number from 1 to 48"]),
    ("G21 G90\nG154\n", "G154", ["P, a whole number from 1 to 99"]),
])
def test_an_additional_work_offset_whose_place_is_not_known_is_refused(tmp_path, code, word, words):
    error = refused(tmp_path, code)
    assert error.word == word
    for expected in words:
        assert expected in str(error)
