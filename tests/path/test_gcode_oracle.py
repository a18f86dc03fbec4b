"""The G-code reader against an independent oracle: LinuxCNC's own RS-274/NGC interpreter.

``rs274`` (Debian's ``linuxcnc-uspace``) runs a program standalone and prints the canonical
machine commands it would send: STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED (end, centre, plane,
turns), DWELL, SET_FEED_RATE, ... For each program below, written for this test, the moves of
:func:`placement.path.gcode.read_program` must be rs274's, in order: the kind of move, end points,
arc centres, planes and turns, the feed of each feed move and the dwells. rs274 prints four
decimals, so every length is compared to rs274's printed precision: within 0.00005 program units
(plus 1e-9 mm) of the printed value; feeds likewise (rs274 prints G93's inverse time as the
feed in units/min it means; in G95 the feed is F·S), and dwells to 0.00005 s. Moves of no
length (rs274 prints them, the reader drops them) are left out of both. rs274 prints the moves in
program coordinates, and the active work coordinate system's offset (SET_G5X_OFFSET) and the G92
offset (SET_G92_OFFSET) apart, each in its line's units: both are added, giving machine coordinates,
less the work offset in force at the program's first move (the reader's path frame is the system the
program first moves in, its origin where that system's origin is then: G10 L2 before any move
moves it); rotary axes are not compared (the reader ignores them while they hold one value).

rs274 starts at the machine's zero with the reference positions #5161-#5183 at zero and no work
offset; the reader is given the same machine (``Machine`` with zero offset and references) and the
same tool diameters (rs274 reads them from a tool table, ``-t``), which cutter radius compensation
(G41, G42, G41.1, G42.1) offsets the path by. Each program starts with a rapid to the origin, so the
reader's first point is known; but those in ``FIRST_RAPID_FROM_ANYWHERE`` set work offsets before
it, and their first rapid starts, for the reader, where the machine happens to be (rs274's machine
zero): the reader leaves it out, and so it is left out of rs274's moves. Programs rs274 refuses for
a corner the tool cannot reach, the reader refuses at the same line.

Without rs274 the test skips, except where ``CI`` is set: there it fails (.ci/run installs it).
"""

import os
import re
import shutil
import subprocess
import warnings

import numpy as np
import pytest

from placement.path.exceptions import GcodeDialectWarning, GcodeError
from placement.path.gcode import INCH_M, MM_M, Machine, read_program

RS274 = shutil.which("rs274")
PRINTED = 0.5e-4  # half the last printed decimal of rs274's numbers
CANON = re.compile(r"^\s*\d+ N\.\.\.\.\. (\w+)\((.*)\)\s*$")
TOOLS_INCH = {1: 0.2, 2: 0.1}  # the tool table's diameters: tool 1 5.08 mm, tool 2 2.54 mm
MACHINE = Machine(np.zeros(3), np.zeros(3), np.zeros(3), given=True,
                  tool_diameters_m={tool: inches * INCH_M for tool, inches in TOOLS_INCH.items()})
PLANE_AXES = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}  # first, second, normal axis of ARC_FEED

PROGRAMS = {
    "spindle_number": """G21 G90 G17 G0 X0 Y0 Z0
M3 $0 S1000
G1 X10 F600
S2000 $0
G1 Y10
M5 $-1
M2
""",
    "parameters_expressions_functions": """G21 G90 G17 G0 X0 Y0 Z0
#1 = 10
#<depth> = -2
#<_speed> = [300 * 2]
#2 = [#1 / 4 + 2 ** 3 - 7 MOD 3]
G1 X#1 Y[#2] Z#<depth> F#<_speed>
G1 X[SIN[30] * 10] Y[COS[60] * 10 + ABS[-3]] Z[SQRT[16] - 5]
G1 X[ATAN[1]/[1] / 9] Y[FIX[2.7] + FUP[2.2] + ROUND[2.5]] Z[EXP[1] - LN[1] - 3]
G1 X[TAN[45] + ASIN[1] / 90 + ACOS[0] / 90] Y[[1 LT 2] + [2 GT 1] * 2 + [1 EQ 1] * 4 + [1 NE 1] * 8]
G1 X[[1 AND 0] + [1 OR 0] * 2 + [1 XOR 1] * 4 + [3 GE 3] + [2 LE 1]] Y-#1 Z-[#1 / 10]
#1 = 2 #2 = #1 #3 = 1 (all set after the line is read: #2 takes the old #1)
G1 X#2 Y#1 Z[-7 MOD 3 - 1.5 * 2 ** 2 ** 0.5]
G1 X[##3] Y[-#1 + [1 + 2] * 3 / 4] F[#<_speed> / 2]
M2
""",
    "while_loop_spiral": """G21 G90 G0 X0 Y0 Z0
G1 Z-1 F200
#<i> = 0
O100 while [#<i> LT 12]
  G1 X[[5 + #<i> / 2] * COS[#<i> * 30]] Y[[5 + #<i> / 2] * SIN[#<i> * 30]] Z[-1 - #<i> / 10]
  #<i> = [#<i> + 1]
O100 endwhile
G0 Z5
M2
""",
    "subroutines_arguments_return": """G21 G90 G0 X0 Y0 Z0
O<square> sub
  #<half> = [#1 / 2]
  G0 X[#2 - #<half>] Y[#3 - #<half>]
  G1 Z#4 F[#5]
  G1 X[#2 + #<half>]
  Y[#3 + #<half>]
  X[#2 - #<half>]
  Y[#3 - #<half>]
  G0 Z2
O<square> endsub
O200 sub
  O<square> call [#1] [0] [0] [-1] [150]
  O200 if [#1 GT 6]
    O200 return [#1]
  O200 endif
  O<square> call [#1 / 2] [#1] [#1] [-2] [300]
O200 endsub
O200 call [4]
O200 call [8]
G0 X[#<_value>] Y0
M2
""",
    "conditions_and_loops": """G21 G90 G0 X0 Y0 Z0
G1 F100
#1 = 0
O10 do
  O20 if [#1 EQ 1]
    G1 X1 Y1
  O20 elseif [#1 EQ 2]
    G1 X2 Y0
  O20 elseif [#1 EQ 3]
    G1 X3 Y3
  O20 else
    G1 X#1 Y-1
  O20 endif
  #1 = [#1 + 1]
O10 while [#1 LT 6]
O30 repeat [3]
  G91 G1 Z-0.5
  G90
O30 endrepeat
#2 = 0
O40 while [1]
  #2 = [#2 + 1]
  O41 if [#2 GT 3]
    O40 break
  O41 endif
  O42 if [#2 EQ 2]
    O40 continue
  O42 endif
  G1 X[#2 * 3] Y5
O40 endwhile
M2
""",
    "drilling_cycles_g81_g82_g83": """G21 G90 G17 G0 X0 Y0 Z0
G0 Z10
G98 G81 X5 Y5 Z-3 R2 F120
X10
G99 Y10
G82 X15 Y15 Z-4 R1 P0.5
G83 X20 Y0 Z-7.5 R1.5 Q2
G80 G0 Z1
G91 G99 G81 X3 Y2 Z-2 R1 L3 F90
G90 G80 G0 Z10
M2
""",
    "drilling_cycles_g73_g85_g89_and_planes": """G21 G90 G17 G0 X0 Y0 Z0
G0 Z5
G73 X2 Y3 Z-4 R1 Q1.5 F150
G85 X4 Y3 Z-2 R1
G98 G89 X6 Y3 Z-2.5 R0.5 P1.25
G80
G18 G0 X0 Y8 Z0
G99 G81 Z3 X2 Y-2 R6 F100
G19 G0 X8 Y0 Z0
G81 Y3 Z2 X-1 R6
G80 G17
M2
""",
    "circles_helices_planes": """G21 G90 G17 G0 X0 Y0 Z0
G1 X10 F500
G2 I-5 J0
G3 I-5 J0 Z-2
G3 X0 Y10 I-10 J0 Z-3 P2
G2 X10 Y0 R10
G3 X0 Y-10 R-10 F250
G18 G2 X5 Z2 I5 K0
G19 G3 Y0 Z2 J5 K0
G18 G3 I2 K0
G19 G2 J0 K1 X3
G17 G90.1 G2 X3 Y10 I3 J5
G91.1
M2
""",
    "inches_and_incremental": """G20 G90 G0 X0 Y0 Z0
G1 X1 Y0.5 F20
G91 G1 X0.25 Y-0.125 Z-0.1
G2 X0.5 Y0 I0.25 J0
G3 X-0.5 Y0 R0.25
G90 G21 G1 X10 Y5 F300
G91 G20 G1 X0.1 F10
G90
M2
""",
    "g92_you_are_here_at_the_start": """G21 G90 (a pen plotter's start: the pen stands where the drawing begins)
G92 X5 Y-3 Z2
G1 X10 F3500
G1 Y10 Z0
G0 X5 Y-3 Z2
M2
""",
    "incremental_from_the_start": """G21 G91 G17 (a thread mill's helix, run from where the tool stands)
G1 Z-3 F200
G1 X2 Y-1 F100
G3 X1 Y1 Z0.5 R1.2
G3 X-1 Y1 Z0.5 I-1 J0
G1 X-2
G90 G0 Z5
M2
""",
    "reference_returns_and_machine_moves": """G21 G90 G0 X0 Y0 Z0
G1 X10 Y10 Z-1 F400
G28 G91 Z0.
G90 G0 X5 Y5 Z3
G28 X8 Y8
G0 X2 Y3 Z4
G28.1
G0 X7 Y7 Z7
G28
G30 Z9
G0 X1 Y1 Z1
G53 G0 X4 Y5 Z6
G53 G1 X1 F100
M2
""",
    "dwells_modes_and_machine_words": """%
O0001 (a post's program number)
G90 G94 G17 G49 G40 G80 G21
G0 X0 Y0 Z0
T1 M6
S12000 M3
G54 G0 X10 Y5
G43 Z15. H1
M8
G61 G1 Z-1 F500
G4 P0.75
G61.1 G1 X12 Y5
M0
G64 P0.01 Q0.01 G1 X14
M1
G4 P2
M7
M60
G95 G1 X16 F0.01
G94 G1 X18 F250
G93 G1 X20 Y7 F30
G2 X22 Y5 R2 F20
G94 M9 M5
G0 Z10
M30
%
""",
    "axis_offsets_g92": """G21 G90 G17 G0 X0 Y0 Z0
G0 X10 Y5 Z2
G92 X0 Y0
G1 Z-1 F300
G1 X5 Y5
G2 X10 Y0 I5 J0
G91 G1 X-2 Y-2
G90 G92 Z10
G1 Z8
G92.2
G1 X3 Y4 Z-1
G92.3
G1 X1 Y1
G90.1 G3 X-1 Y1 I0 J1
G91.1
G0 X2 Y2 Z12
G81 X4 Y4 Z5 R11 F120
G80
G92.1
G0 X0 Y0 Z0
G20 G92 X1
G21 G1 X10 F200
G92.3
G1 Y3
G0 @5 ^90
M2
""",
    "extra_axes_held_at_one_value": """G21 G90 G17 G0 X0 Y0 Z0 A0 B15
G1 X10 Y2 A0 F300
G2 X20 Y2 I5 J0 B15
G91 G1 Y5 A0 B0
G90 G0 Z5 A0
M2
""",
    "work_offsets_g10_l2_l20_g54_to_g59_3": """G21 G90 G17 G0 X0 Y0 Z0
G1 X5 Y5 F300
G10 L2 P2 X10 Y20 Z5
G10 L2 P3 X-15 Y7.5 Z-2
G55 G1 X1 Y1
G2 X5 Y1 I2 J0
G56 G0 X0 Y0 Z1
G1 Z-1
G10 L20 P1 X3 Y3 (G54 from the current point, while in G56)
G54 G1 X4 Y4
G91 G10 L2 P2 X1 (G91 does not change G10 L2)
G90 G55 G1 X0 Y0 Z0
G10 L20 P0 X2 Y2 (P0: the active system)
G1 X3 Y3
G92 X1 Y1
G10 L20 P0 X0 Y0 (the G92 offset counted)
G1 X2 Z1
G92.1
G1 X4
G10 L2 P6 X1 Y2 Z3
G59 G1 X0 Y0 Z0
G10 L2 P0 Z10 (the active system moves after the program has moved)
G1 X1 Y1 Z0
G20 G10 L2 P4 X1 Y1 Z0 (inches)
G21 G57 G1 X0 Y0
G10 L2 P7 X5 Y-5 Z0
G59.1 G1 X1
G54 G81 X1 Y1 Z-2 R1
G80
G55 G1 X0 Y0
G90.1 G3 X4 Y0 I2 J0
G91.1
G28
G53 G0 X1 Y2 Z3
G54 G0 X0 Y0 Z0
M2
""",
    "work_offsets_set_before_the_first_move_two_fixtures_m99": """G10 L2 P1 X-100 Y-50 Z-20
G10 L2 P2 X-40 Y-50 Z-20
G17 G21 G90 G54 G0 X0 Y0 Z5
G1 Z-1 F200
G1 X10
G2 X20 Y0 I5 J0
G0 Z5
G55 G0 X0 Y0
G1 Z-1
G1 X10
G3 X20 Y0 I5 J0
G0 Z5
G28 Z0
G53 G0 X-60 Y-40
M99 (the main program's end, as M2)
G1 X100 Y100
""",
    "polar_words": """G21 G90 G0 X0 Y0 Z0
G0 X10 Y0 Z2
G81 R1 Z-2 F90
^120
^240
G80 G0 @15 ^33
G91 G81 @5 R1 Z-2 L3
G90 G80 G0 X20 Y0
G91 G81 ^45 R1 Z-1.5 L4
G90 G80 G1 @10 ^-30 F200
G91 G1 @-2 ^10
G1 ^15
G90
M2
""",
    "compensation_pocket_inside_g41": """G21 G90 G17 G0 X0 Y0 Z0
T1 M6
G41 G1 X10 Y0 F100
G1 X20 Y0
G1 Z-1
G0 Z-1
G1 X20 Y10
G3 X10 Y20 I-10 J0
G1 X0 Y10
G1 X5 Y5
G40 G1 X0 Y0
M2
""",
    "compensation_outside_g42_lines_arcs_plunge": """G21 G90 G17 G0 X0 Y0 Z0
G0 X-10 Y-10 Z5
T1 M6
G42 G0 X0 Y0
G1 Z-1 F200
G1 X0 Y20
G1 X30 Y20
G2 X40 Y10 I0 J-10
G1 X40 Y0
G3 X30 Y-5 R8
G1 X0 Y0
G0 Z5
G40 G0 X-10 Y-10
M2
""",
    "compensation_arcs_both_ways_g41": """G21 G90 G17 G0 X0 Y0 Z0
T2 M6
G41 G1 X10 Y0 F300
G3 X30 Y0 I10 J0
G2 X50 Y0 I10 J0
G3 X60 Y10 I0 J10
G1 X60 Y30
G3 X50 Y40 R10
G2 X30 Y40 R-10
G1 X10 Y40
G2 X10 Y20 I0 J-10
G3 X0 Y10 R10
G1 X0 Y5
G40 G1 X-5 Y-5
M2
""",
    "compensation_g41_1_g42_1_inches_incremental": """G20 G90 G17 G0 X0 Y0 Z0
G41.1 D0.25 G1 X1 Y0 F10
G1 X2 Y0.5
G1 X3 Y0
G1 X3 Y1
G2 X2 Y2 R1
G1 X0 Y2
G1 X0 Y0.5
G40 G1 X-1 Y-1
G42.1 D0.1 G1 X0 Y0
G91 G1 X1 Y1
G1 X1 Y-1
G90 G3 X2 Y0 I0 J0.5
G40 G0 X0 Y0
M2
""",
    "compensation_z_moves_rapids_reentry": """G21 G90 G17 G0 X0 Y0 Z0
G0 Z5
T1 M6
G41 G0 X10 Y10
G1 Z-1 F100
G1 X10 Y40
G1 Z-2
G1 X40 Y40
G1 X40 Y10
G1 X12 Y10
G0 Z5
G40 G0 X0 Y0
G42 G1 X10 Y10 Z-1
G1 X40 Y10
G1 X40 Y40
G0 X10 Y40
G0 X10 Y10
G40 G1 X0 Y0
M2
""",
    "compensation_entry_arcs_and_reentry": """G21 G90 G17 G0 X0 Y0 Z0
T1 M6
G41 G3 X20 Y0 I10 J0 F200
G1 X20 Y10
G40
G42 G1 X0 Y10
G1 X0 Y30
G2 X10 Y40 R10
G40 G0 X0 Y50
G41 G2 X20 Y50 R-10
G3 X30 Y40 I0 J-10
G40 G1 X40 Y40
M2
""",
    "compensation_reentry_offset_from_the_programmed_point": """G21 G90 G17 G0 X0 Y0 Z0
T1 M6
G41 G1 X20 Y0 F200
G1 X20 Y10
G40
G42 G1 X25 Y30
G1 X0 Y30
G40
G41 G1 X20 Y50
G1 X20 Y60
G40 G0 X0 Y0
M2
""",
    "compensation_g18_lathe_contour_y_never_given": """G20 G90 G18 G0 X0 Z0
G0 X0.3 Z0
T2 M6
G42 G1 X0.1 F30
G3 X0 Z0.1 R0.1
G1 Z1
G2 R0.25 X-0.25 Z1.25
G3 R0.25 X-0.5 Z1.5
G1 Z1.75
G40 G0 X0.3
T1 M6
G41 G0 Z1.85
G0 X-0.3
G1 X-0.4 F20
G2 X-0.5 Z1.75 R0.1
G1 Z1.5
G40 G1 X0.3 Z0
M2
""",
}
FIRST_RAPID_FROM_ANYWHERE = {"work_offsets_set_before_the_first_move_two_fixtures_m99"}


def canonical(text):
    """rs274's moves and dwells in mm: (kind, end, centre (first, second), plane axes, turns, feed in mm/min,
    tolerance in mm), dwells as ("dwell", seconds); moves of no length left out; any other printed line fails."""
    events, position, plane, unit = [], np.zeros(3), "XY", 1.0  # mm per program unit
    feed, per_revolution, spindle = 0.0, False, 0.0
    offset = np.zeros(3)  # G92's (mm): rs274 prints the moves in program coordinates, the offset in its line's units
    work = np.zeros(3)  # the active work coordinate system's offset (mm), likewise
    origin = None  # the work offset at the first move: the path frame's origin
    for line in text.splitlines():
        if line.strip() in ("", "executing"):
            continue
        match = CANON.match(line)
        assert match, f"rs274 printed: {line}"
        name, arguments = match.groups()
        numbers = [float(n) for n in re.findall(r"-?\d+\.\d+|-?\d+", arguments)] if name != "COMMENT" else []
        tolerance = PRINTED * unit + 1e-9
        if name == "USE_LENGTH_UNITS":
            unit = 25.4 if "INCHES" in arguments else 1.0
        elif name == "SELECT_PLANE":
            plane = arguments.rsplit("_", 1)[1]
        elif name == "SET_G92_OFFSET":
            offset = np.array(numbers[:3]) * unit
        elif name == "SET_G5X_OFFSET":
            work = np.array(numbers[1:4]) * unit
        elif name == "SET_FEED_RATE":  # units/min (rs274 turns G93's inverse time into it), or units/rev
            feed = numbers[0]
        elif name == "SET_FEED_MODE":
            per_revolution = int(numbers[1]) == 1
        elif name == "SET_SPINDLE_SPEED":
            spindle = numbers[1]
        elif name == "DWELL":
            events.append(("dwell", numbers[0], None, None, None, None, PRINTED))
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "ARC_FEED"):
            origin = work if origin is None else origin
            shift = offset + work - origin  # program coordinates to the path frame's
            rate = None if name == "STRAIGHT_TRAVERSE" else (
                feed * spindle * unit, PRINTED * spindle * unit + 1e-9) if per_revolution else (
                feed * unit, tolerance)
            if name == "ARC_FEED":
                first, second, normal = PLANE_AXES[plane]
                end = position.copy()
                shift = shift[[first, second, normal]]
                end[first], end[second], end[normal] = np.array(numbers[:2] + numbers[5:6]) * unit + shift
                events.append(("arc", end, np.array(numbers[2:4]) * unit + shift[:2], (first, second, normal),
                               int(numbers[4]), rate, tolerance))
            else:
                end = np.array(numbers[:3]) * unit + shift
                if np.abs(end - position).max() > 1e-12:
                    events.append(("rapid" if name == "STRAIGHT_TRAVERSE" else "line", end, None, None, None, rate,
                                   tolerance))
            position = end
    return events


def ours(program):
    """The reader's moves and dwells in the same form, in mm: (kind, end, centre, axes, turns, feed, segment)."""
    events, dwells = [], list(program.dwells)
    for k, segment in enumerate(program.segments):
        events += [("dwell", d.duration_s) for d in dwells if d.after == k]
        end = segment.end_m / MM_M
        feed = None if segment.rapid else segment.feed_ratio * program.feed_m_s * 60 / MM_M
        if segment.center_m is None:
            events.append(("rapid" if segment.rapid else "line", end, None, None, None, feed, segment))
        else:
            axes = tuple(int(np.argmax(np.abs(segment.axes[:, j]))) for j in range(3))
            centre = np.array([segment.center_m[axes[0]], segment.center_m[axes[1]]]) / MM_M
            turns = int(np.ceil(abs(segment.sweep_rad) / (2 * np.pi) - 1e-9)) * int(np.sign(segment.sweep_rad))
            events.append(("arc", end, centre, axes, turns, feed, segment))
    events += [("dwell", d.duration_s) for d in dwells if d.after == len(program.segments)]
    return events


def run_rs274(tmp_path, name, text):
    # Tools of no length (the tip is the programmed point); rs274 alone reads the table's diameters in inches.
    (tmp_path / "tool.tbl").write_text("".join(f"T{tool} P{tool} Z0 D{inches}\n" for tool, inches in TOOLS_INCH.items()))
    program = tmp_path / f"{name}.ngc"
    program.write_text(text)
    result = subprocess.run([RS274, "-g", "-t", str(tmp_path / "tool.tbl"), str(program)], capture_output=True,
                            text=True, timeout=60, cwd=tmp_path)
    return program, result.stdout + result.stderr


@pytest.fixture(scope="module")
def rs274_present():
    if RS274 is None:
        if os.environ.get("CI"):
            pytest.fail("rs274 (Debian's linuxcnc-uspace) is missing: the oracle test must run in CI (.ci/run "
                        "installs it)")
        pytest.skip("rs274 (Debian's linuxcnc-uspace) is not installed")


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_the_reader_moves_as_linuxcnc_does(tmp_path, rs274_present, name):
    text = PROGRAMS[name]
    program_file, printed = run_rs274(tmp_path, name, text)
    expected = canonical(printed)
    if name in FIRST_RAPID_FROM_ANYWHERE:
        assert expected[0][0] == "rapid", printed
        expected = expected[1:]
    with warnings.catch_warnings(record=True) as told:  # M99 at the main program's end, read as M2 (as rs274 does)
        warnings.simplefilter("always", GcodeDialectWarning)
        program = read_program(program_file, MACHINE)
    assert [str(w.message) for w in told if "M99" in text and "M99 (line" in str(w.message)] or "M99" not in text
    got = ours(program)
    assert [e[0] for e in got] == [e[0] for e in expected], printed
    for before, after in zip(program.segments, program.segments[1:]):  # each move starts where the last ended
        np.testing.assert_allclose(after.start_m, before.end_m, rtol=0, atol=1e-12)
    for k, (mine, theirs) in enumerate(zip(got, expected)):
        where, tolerance = f"event {k}: {theirs}", theirs[6]
        if theirs[0] == "dwell":
            assert abs(mine[1] - theirs[1]) <= tolerance, where
            continue
        np.testing.assert_allclose(mine[1], theirs[1], rtol=0, atol=tolerance, err_msg=where)
        if theirs[0] == "arc":
            assert mine[3] == theirs[3] and mine[4] == theirs[4], where
            np.testing.assert_allclose(mine[2], theirs[2], rtol=0, atol=tolerance, err_msg=where)
        if theirs[5] is not None:
            feed, slack = theirs[5]
            assert abs(mine[5] - feed) <= slack, where


REFUSED = {  # cutter radius compensation rs274 refuses, and the line it refuses
    "arc_radius_not_above_tool_radius": ("""G21 G90 G17 G0 X0 Y0 Z0
T1 M6
G41 G1 X10 Y0 F100
G1 X20 Y0
G3 X21 Y1 R1
G40 G1 X0 Y0
M2
""", 5),
    "concave_corner_gouges": ("""G21 G90 G17 G0 X0 Y0 Z0
T2 M6
G41 G1 X10 Y0 F300
G3 X20 Y10 I0 J10
G3 X30 Y20 I10 J0
G2 X40 Y30 I0 J10
G1 X40 Y40
G2 X30 Y50 I-10 J0
M2
""", 8),
    "inside_step_smaller_than_the_tool": ("""G21 G90 G17 G0 X0 Y0 Z0
T1 M6
G41 G1 X10 Y0 F100
G1 X20 Y0
G1 X20 Y1
G1 X10 Y1
M2
""", 6),
    "entry_move_shorter_than_the_radius": ("""G21 G90 G17 G0 X0 Y0 Z0
T1 M6
G42 G1 X1 Y0 F100
G1 X20 Y0
M2
""", 3),
}


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_the_reader_refuses_compensation_where_linuxcnc_does(tmp_path, rs274_present, name):
    text, line = REFUSED[name]
    program_file, printed = run_rs274(tmp_path, name, text)
    assert text.splitlines()[line - 1] in printed.splitlines()[-1], printed  # rs274's error names the line
    with pytest.raises(GcodeError, match=f"line {line},"):
        read_program(program_file, MACHINE)


# I/J/K arcs whose end lies off the start's circle, as CAM posts round them (Fusion 360's Haas post, at four inch
# decimals: 0.0000936 in at a 0.025 in radius): (units, radius, how much farther the end is, in program units).
# LinuxCNC takes 2·0.001·√2 in or 2·0.01·√2 mm, or 0.1 % of the larger radius, at most 100 times the first.
ARC_ENDS = [("G20", 0.025, 9.36e-5), ("G20", 0.025, 0.0028), ("G20", 0.025, 0.0029), ("G21", 1.0, 0.028),
            ("G21", 1.0, 0.029), ("G21", 100.0, 0.099), ("G21", 100.0, -0.099), ("G21", 100.0, 0.101),
            ("G21", 10000.0, 2.8), ("G21", 10000.0, 2.9), ("G20", 1000.0, 0.28), ("G20", 1000.0, 0.29)]


@pytest.mark.parametrize(("units", "radius", "error"), ARC_ENDS)
def test_an_arcs_end_off_its_circle_is_read_where_linuxcnc_reads_it(tmp_path, rs274_present, units, radius, error):
    text = f"{units} G90 G17\nG0 X{radius} Y0 Z0\nG3 X0 Y{radius + error:.7f} I{-radius} J0 F10\nM2\n"
    program_file, printed = run_rs274(tmp_path, "arc_end", text)
    linuxcnc_reads = "ARC_FEED" in printed
    try:
        read_program(program_file, MACHINE)
        reads = True
    except GcodeError as refusal:
        assert refusal.line == 3 and "radius does not fit" in str(refusal)
        reads = False
    assert reads == linuxcnc_reads, printed
