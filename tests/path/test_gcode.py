"""G-code programs as tool paths: geometry, feeds, rapids, forces by kind, errors, and energy.

Expected values come from geometry written out here (circles, helices, chords) and from the
equivalent path shapes, never from the reader itself.
"""

import dataclasses
import re

import numpy as np
import pytest

from placement import load_robot
from placement.__main__ import main
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path import ngc_flow
from placement.path.exceptions import GcodeError, PathFileError
from placement.path.load import load_path
from tests.support.paths import EXAMPLES

PLACEMENTS = [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.05, -0.04, 0.03, 0.5, 0.0, 0.0], [-0.06, 0.05, -0.05, -1.0, 0.0, 0.0]]
TIMING = "timing: {mode: paper, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\n"


def program(tmp_path, code, extra="", name="p"):
    """A path file naming a G-code program written beside it."""
    (tmp_path / f"{name}.nc").write_text(code)
    file = tmp_path / f"{name}.yaml"
    file.write_text(f"shape: {{type: gcode, file: {name}.nc}}\n" + extra)
    return load_path(file)


def path_file(tmp_path, text, name="q"):
    file = tmp_path / f"{name}.yaml"
    file.write_text(text)
    return load_path(file)


def assert_same_samples(a, b, atol=1e-9):
    assert len(a) == len(b)
    for field in ("t_s", "position_m", "velocity_m_s", "acceleration_m_s2", "tangent", "force_on_tool_N", "piece"):
        np.testing.assert_allclose(getattr(a, field), getattr(b, field), atol=atol, rtol=0, err_msg=field)


def finite_differences(samples):
    """Central differences of position and velocity in time, within each piece: (index, velocity, acceleration)."""
    t, p, v = samples.t_s, samples.position_m, samples.velocity_m_s
    inside = np.flatnonzero((samples.piece[:-2] == samples.piece[2:]) & (t[2:] > t[:-2])) + 1
    dt = (t[inside + 1] - t[inside - 1])[:, None]
    return inside, (p[inside + 1] - p[inside - 1]) / dt, (v[inside + 1] - v[inside - 1]) / dt


RECTANGLE = """%
(the paper's 30 x 60 mm rectangle at 40 m/min, as examples/rect.yaml)
G21 G90 G17
G0 X-15 Y-30 Z0
G1 X15 F39600
Y30
X-15
Y-30
M30
%
"""
RECT_FORCES = "process_forces_N: {feed: 10, radial: 215, axial: 25}\n" + TIMING


def test_a_rectangle_of_g1_moves_is_the_rectangle_shape(tmp_path):
    gcode = program(tmp_path, RECTANGLE, RECT_FORCES)
    shape = load_path(EXAMPLES / "rect.yaml")
    assert gcode.feed_m_s == pytest.approx(0.66, rel=1e-15) and len(gcode.segments) == 4
    assert_same_samples(gcode.sample(), shape.sample())
    robot = load_robot("orthoglide")
    energies = [Evaluator(robot, path).evaluate(np.array(PLACEMENTS)).value for path in (gcode, shape)]
    np.testing.assert_allclose(energies[0], energies[1], rtol=1e-9)


def test_arcs_by_offsets_by_radius_and_the_arc_shape_agree(tmp_path):
    # A quarter circle of radius 10 mm about the origin, from (0, 10) clockwise to (10, 0).
    start = "G21 G90 G0 X0 Y10 Z0\n"
    by_offsets = program(tmp_path, start + "G2 X10 Y0 I0 J-10 F6000\n", name="ij")
    by_radius = program(tmp_path, start + "G2 X10 Y0 R10 F6000\n", name="r")
    shape = path_file(tmp_path, "units: mm\nshape: {type: arc, radius: 10, start_deg: 90, sweep_deg: -90}\nfeed_m_s: 0.1\n")
    for path in (by_offsets, by_radius):
        assert_same_samples(path.sample(), shape.sample(), atol=1e-12)
    # The long way round (R < 0) is the other three quarters, anticlockwise by G3 with R > 0 the short one.
    long_way = program(tmp_path, start + "G2 X10 Y0 R-10 F6000\n", name="long")
    assert long_way.length_m == pytest.approx(1.5 * np.pi * 0.01, rel=1e-12)
    short_ccw = program(tmp_path, start + "G3 X10 Y0 R10 F6000\n", name="ccw")
    middle = short_ccw.segments[0].point(np.array([short_ccw.length_m / 2]), np.ones(1), np.zeros(1))[0][0]
    # Anticlockwise from (0, 10) to (10, 0) the short way: about (10, 10), from 180° through 225° to 270°.
    np.testing.assert_allclose(middle, [0.01 + 0.01 * np.cos(np.radians(225)), 0.01 + 0.01 * np.sin(np.radians(225)), 0],
                               atol=1e-15)


def test_a_full_circle_by_offsets(tmp_path):
    path = program(tmp_path, "G0 X25 Y5 Z-1\nG2 X25 Y5 I-5 J0 F3000\n")  # radius 5 mm about (20, 5), clockwise
    samples = path.sample()
    center, speed = np.array([0.02, 0.005, -0.001]), 0.05
    radial = samples.position_m - center
    np.testing.assert_allclose(np.linalg.norm(radial, axis=1), 0.005, rtol=1e-12)
    assert path.length_m == pytest.approx(2 * np.pi * 0.005, rel=1e-12)
    np.testing.assert_allclose(samples.acceleration_m_s2, -radial * speed**2 / 0.005**2, atol=1e-12)
    np.testing.assert_allclose(np.cross(radial, samples.velocity_m_s)[:, 2], -0.005 * speed, rtol=1e-12)  # clockwise


@pytest.mark.parametrize("code, center, normal, radius, rise", [
    # G18: the ZX plane, normal +Y; G2 is clockwise seen from +Y: from X20 Z0 about (10, 0, 0) up through Z+10.
    ("G18 G0 X20 Y3 Z0\nG2 X0 Z0 I-10 K0 F1200\n", [0.01, 0.003, 0.0], [0, 1, 0], 0.01, 0.0),
    # G19: the YZ plane, normal +X, anticlockwise from Y10 Z0 about (0, 0, 0) three quarters round.
    ("G19 G0 X2 Y10 Z0\nG3 Y0 Z-10 J-10 K0 F1200\n", [0.002, 0.0, 0.0], [1, 0, 0], 0.01, 0.0),
    # A helix in G17: one and a quarter turns down 5 mm about (0, 0) (a full turn, then a quarter).
    ("G17 G0 X8 Y0 Z0\nG3 X8 Y0 Z-4 I-8 J0 F1200\nG3 X0 Y8 Z-5 I-8 J0\n", [0.0, 0.0, 0.0], [0, 0, 1], 0.008, -0.005),
])
def test_arcs_in_every_plane_and_helices_are_exact(tmp_path, code, center, normal, radius, rise):
    path = program(tmp_path, "G21 G90\n" + code, "time_step_s: 0.0002\n")
    samples = path.sample()
    normal, center = np.array(normal, dtype=float), np.array(center)
    offset = samples.position_m - center
    along = offset @ normal
    in_plane = offset - along[:, None] * normal
    np.testing.assert_allclose(np.linalg.norm(in_plane, axis=1), radius, rtol=1e-12)
    # The motion along the normal is proportional to the angle turned (the arc length): a helix.
    travelled = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(samples.position_m, axis=0), axis=1))])
    np.testing.assert_allclose(along, rise * travelled / travelled[-1], atol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(samples.velocity_m_s, axis=1), 0.02, rtol=1e-12)
    inside, velocity, acceleration = finite_differences(samples)
    np.testing.assert_allclose(samples.velocity_m_s[inside], velocity, atol=2e-7)
    np.testing.assert_allclose(samples.acceleration_m_s2[inside], acceleration, atol=2e-5)
    np.testing.assert_allclose(samples.tangent, samples.velocity_m_s / 0.02, atol=1e-12)


def test_g18_clockwise_is_seen_from_plus_y(tmp_path):
    path = program(tmp_path, "G18 G0 X20 Y0 Z0\nG2 X0 Z0 I-10 K0 F1200\n")
    # Seen from +Y (looking towards -Y, Z up), +X points left: clockwise from X20 climbs through Z+10.
    z = path.sample(0.001).position_m[:, 2]
    assert z.max() == pytest.approx(0.01, abs=1e-6) and z.min() > -1e-12


def test_inches_and_incremental_moves_equal_their_millimetre_absolute_twins(tmp_path):
    metric = program(tmp_path, "G21 G90 G0 X0 Y0 Z0\nG1 X25.4 Y12.7 F254\nG2 X50.8 Y12.7 I12.7 J0\nG1 Z-2.54\n",
                     name="mm")
    inches = program(tmp_path, "G20 G90 G0 X0 Y0 Z0\nG91\nG1 X1 Y0.5 F10\nG2 X1 Y0 R0.5\nG1 Z-0.1\n", name="inch")
    assert_same_samples(metric.sample(), inches.sample(), atol=1e-12)


def test_feeds_of_each_move_in_both_timing_laws_and_the_feed_scale(tmp_path):
    code = "G0 X0 Y0 Z0\nG1 X30 F3000\nG1 Y40 F6000\nG1 X0 Y0\n"
    paper = program(tmp_path, code)
    samples = paper.sample()
    speed = np.linalg.norm(samples.velocity_m_s, axis=1)
    np.testing.assert_allclose(speed[samples.piece == 0], 0.05, rtol=1e-12)
    np.testing.assert_allclose(speed[samples.piece >= 1], 0.1, rtol=1e-12)
    assert samples.t_s[-1] == pytest.approx(0.03 / 0.05 + 0.09 / 0.1, rel=1e-12)
    doubled = dataclasses.replace(paper, feed_m_s=2 * paper.feed_m_s).sample()  # what `placement feed` does
    assert doubled.t_s[-1] == pytest.approx(samples.t_s[-1] / 2, rel=1e-12)
    # Realistic: each move of a corner-to-corner run reaches its own feed (look-ahead), never more.
    tangent = program(tmp_path, "G0 X0 Y0 Z0\nG1 X100 F3000\nG1 X200 F6000\n",
                      "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\n", name="r")
    timed = tangent.sample()
    speed = np.linalg.norm(timed.velocity_m_s, axis=1)
    first = timed.position_m[:, 0] < 0.1
    assert speed[first].max() == pytest.approx(0.05, rel=1e-12) and speed[~first].max() == pytest.approx(0.1, rel=1e-12)


ENTRY = """G21 G90 G0 X0 Y0 Z5
G0 Z1
G1 Z-2 F600
G1 X20 F1200
G0 Z5
G0 X40
G0 Z1
G1 Z-2 F600
G1 X60 F1200
"""
BY_KIND = ("process_forces_N: {cutting: {feed: 10, radial: 200, axial: 20}, plunging: {feed: 30, axial: 90},"
           " rapid: {axial: 1}}\n")


def test_rapids_skipped_or_timed_and_forces_by_kind(tmp_path):
    skipped = program(tmp_path, ENTRY, BY_KIND, name="skip")
    samples = skipped.sample()
    assert len(skipped.segments) == 4 and skipped.length_m == pytest.approx(0.046)
    plunge, cut = samples.tangent[:, 2] < -0.99, samples.tangent[:, 0] > 0.99
    np.testing.assert_allclose(samples.force_on_tool_N[plunge], [[0, 0, 90 + 30]] * plunge.sum())
    np.testing.assert_allclose(samples.force_on_tool_N[cut], [[-10, 200, 20]] * cut.sum())
    timed = program(tmp_path, ENTRY, BY_KIND + "rapids: {mode: timed, feed_m_s: 0.5}\n", name="timed")
    s = timed.sample()
    rapid = np.array([timed.segments[k].rapid for k in s.piece])
    assert timed.segments[0].rapid and rapid.sum() > 0 and len(timed.segments) == 8  # the first G0 starts unknown
    np.testing.assert_allclose(np.linalg.norm(s.velocity_m_s[rapid], axis=1), 0.5, rtol=1e-12)
    np.testing.assert_allclose(s.force_on_tool_N[rapid], [[0, 0, 1]] * rapid.sum())
    assert s.t_s[-1] == pytest.approx(samples.t_s[-1] + (0.004 + 0.007 + 0.02 + 0.004) / 0.5, rel=1e-12)


def test_flat_forces_keep_todays_meaning(tmp_path):
    flat = program(tmp_path, ENTRY, "process_forces_N: {feed: 10, radial: 200, axial: 20}\n", name="flat")
    samples = flat.sample()
    plunge = samples.tangent[:, 2] < -0.99
    np.testing.assert_allclose(samples.force_on_tool_N[plunge], [[0, 0, 20 + 10]] * plunge.sum())


def test_a_skipped_rapid_starts_a_new_piece_in_the_realistic_law(tmp_path):
    path = program(tmp_path, ENTRY, "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\n")
    samples = path.sample()
    jump = np.flatnonzero(np.linalg.norm(np.diff(samples.position_m, axis=0), axis=1) > 0.01)
    assert len(jump) == 1 and samples.piece[jump[0]] == 0 and samples.piece[jump[0] + 1] == 1
    np.testing.assert_allclose(samples.position_m[jump[0]], [0.02, 0, -0.002], atol=1e-12)
    np.testing.assert_allclose(samples.position_m[jump[0] + 1], [0.04, 0, 0.001], atol=1e-12)
    assert np.linalg.norm(samples.velocity_m_s[[jump[0], jump[0] + 1]], axis=1).max() < 1e-9  # at rest at both ends


def pocket_as_chords(text, chords_per_quarter):
    """The G-code of ``text`` (absolute, G17, mm) with every G2/G3 replaced by G1 chords of its circle, the circle
    worked out here from I/J or R."""
    position, motion, out = {"X": 0.0, "Y": 0.0, "Z": 0.0}, None, []
    for line in text.splitlines():
        code = re.sub(r"\(.*?\)", "", line).upper()
        words = dict(re.findall(r"([A-Z])([-+]?[\d.]+)", code))
        for g in re.findall(r"G(\d+)", code):
            if int(g) in (0, 1, 2, 3):
                motion = int(g)
        end = {axis: float(words[axis]) if axis in words else position[axis] for axis in "XYZ"}
        if motion in (2, 3) and any(axis in words for axis in "XY"):
            start = np.array([position["X"], position["Y"]])
            stop = np.array([end["X"], end["Y"]])
            if "R" in words:
                half = np.linalg.norm(stop - start) / 2
                left = np.array([-(stop - start)[1], (stop - start)[0]]) / (2 * half)
                side = 1.0 if motion == 3 else -1.0
                center = (start + stop) / 2 + side * np.sqrt(float(words["R"]) ** 2 - half**2) * left
            else:
                center = start + np.array([float(words.get("I", 0)), float(words.get("J", 0))])
            a0 = np.arctan2(*(start - center)[::-1])
            a1 = np.arctan2(*(stop - center)[::-1])
            turn = (a1 - a0) % (2 * np.pi) if motion == 3 else -((a0 - a1) % (2 * np.pi))
            turn = turn if abs(turn) > 1e-9 else (2 * np.pi if motion == 3 else -2 * np.pi)
            count = int(np.ceil(chords_per_quarter * abs(turn) / (np.pi / 2)))
            radius = np.linalg.norm(start - center)
            feed = f" F{words['F']}" if "F" in words else ""
            for k in range(1, count + 1):
                angle = a0 + turn * k / count
                z = position["Z"] + (end["Z"] - position["Z"]) * k / count
                out.append(f"G1 X{center[0] + radius * np.cos(angle):.12f} Y{center[1] + radius * np.sin(angle):.12f} "
                           f"Z{z:.12f}{feed if k == 1 else ''}")
        else:
            out.append(line)
        position = end
    return "\n".join(out) + "\n"


def test_the_pocket_costs_the_same_energy_as_its_polyline(tmp_path):
    """The issue's bar: the pocket from G-code within 1 % of the same moves with the arcs cut into chords."""
    exact = load_path(EXAMPLES / "pocket.yaml")
    (tmp_path / "chords.nc").write_text(pocket_as_chords((EXAMPLES / "pocket.nc").read_text(), 16))
    (tmp_path / "chords.yaml").write_text((EXAMPLES / "pocket.yaml").read_text().replace("pocket.nc", "chords.nc"))
    chords = load_path(tmp_path / "chords.yaml")
    assert chords.length_m == pytest.approx(exact.length_m, rel=1e-4)
    robot = load_robot("orthoglide")
    energies = [Evaluator(robot, path).evaluate(np.array(PLACEMENTS)).value for path in (exact, chords)]
    assert np.all(np.abs(energies[1] / energies[0] - 1) < 0.01)


@pytest.mark.slow
def test_the_pocket_example_runs_end_to_end(capsys):
    code = main(["--robot", "orthoglide", "--path", str(EXAMPLES / "pocket.yaml"), "--generations", "2",
                 "--population", "8", "--quiet", "--time-step", "0.004"])
    out = capsys.readouterr().out
    assert code == 0 and "pocket 40 x 30 mm" in out and "feeds 0.02 to 0.12 m/s" in out


@pytest.mark.parametrize("code, line, word, words", [
    ("G0 X0 Y0 Z0\nG41 G1 X10 F100\n", 2, "G41", ["cutter radius compensation needs the tool"]),
    ("G0 X0 Y0 Z0\nT3 M6\nG42 G1 X10 F100\n", 3, "G42", ["tool 3's diameter is not given", "tool_diameters_mm"]),
    ("G0 X0 Y0 Z0\nG19 G41.1 D2 G1 X10 F100\n", 2, "G41.1", ["not G19"]),
    ("G0 X0 Y0 Z0\nG41.1 G1 X10 F100\n", 2, "G41.1", ["needs the tool diameter D"]),
    ("G0 X0 Y0 Z0\nG1 X10 D1 F100\n", 2, "D1", ["D belongs to cutter radius compensation"]),
    ("G0 X0 Y0 Z0\nG41.1 D2 G1 X10 F100\nG19\n", 3, "G19", ["plane changes"]),
    ("G0 X0 Y0 Z0\nG41.1 D2 G1 X10 F100\nG81 X1 Y1 Z-3 R1\n", 3, "X1", ["cannot run under cutter radius"]),
    ("G54\nG0 X0 Y0 Z0\nG55 X1\n", 3, "G55", ["changes work coordinate system"]),
    ("G0 X0 Y0 Z0\nG10 L2 P1 X0\n", 2, "G10", ["G10 L2 moves G54", "shape.machine.work_offset_mm"]),
    ("G0 X0 Y0 Z0\nG92\n", 2, "G92", ["the coordinates the current point gets"]),
    ("G0 X0 Y0 Z0\nG28 X0\nG92 X1\n", 3, "G92", ["unknown position"]),
    ("G0 X0 Y0 Z0\nG84 X1 Y1 Z-3 R1 F100\n", 2, "G84", ["tapping", "G73, G81-G83, G85, G89 are read"]),
    ("G0 X0 Y0 Z0 A0\nG1 X10 A5 F100\n", 2, "A5", ["the extra axis A moves", "rotary"]),
    ("G0 X0 Y0 Z0 B1\nG91 G1 X10 B0 F100\nB0.5\n", 3, "B0.5", ["the extra axis B moves"]),
    ("G0 X0 Y0 Z0\nG1 X10 E5 F100\n", 2, "E5", ["the extruder (E) moves here", "3D print"]),
    ("G0 X0 Y0 Z0\nG1 X10\n", 2, "X10", ["before any feed rate"]),
    ("G0 X0 Y0 Z0\nG1 X1.2.3 F100\n", 2, "X1.2.3", ["expected a number"]),
    ("G0 X0 Y0 Z0\nG1 X#<nope> F100\n", 2, "#<NOPE>", ["read before it is set"]),
    ("G0 X0 Y0 Z0\nG1 X[1/0] F100\n", 2, "/", ["division by zero"]),
    ("G0 X0 Y0 Z0\nG1 X[1+2 F100\n", 2, "F", ["expected an operator"]),
    ("G0 X0 Y0 Z0\nG1 X[1+2\n", 2, "[1+2", ["not closed"]),
    ("G0 X0 Y0 Z0\nG1 X[sqrt[-1]] F100\n", 2, "SQRT[-1]", ["undefined"]),
    ("G0 X0 Y0 Z0\nG1 Xfoo[1] F100\n", 2, "FOO", ["unknown function"]),
    ("G0 X0 Y0 Z0\nO100 call\n", 2, "O100CALL", ["no subroutine O100"]),
    ("G0 X0 Y0 Z0\nO100 while [1]\nG1 X1 F100\n", 2, "O100WHILE[1]", ["no matching endwhile"]),
    ("G0 X0 Y0 Z0\nG1 F100\nO100 while [1]\nG1 X1\nO100 endwhile\n", 5, "", ["more than 1,000 lines run"]),
    ("G0 X0 Y0 Z0\nO100 endsub\n", 2, "O100ENDSUB", ["outside a subroutine"]),
    ("G0 X0 Y0 Z0\nG95 G1 X10 F0.1\n", 2, "X10", ["spindle speed S"]),
    ("G0 X0 Y0 Z0\nG93 G1 X10 F5\nX20\n", 3, "X20", ["every feed move gives its F"]),
    ("G0 X0 Y0 Z0\nG81 X1 Y1 Z-3 F100\n", 2, "G81", ["retract level R"]),
    ("G0 X0 Y0 Z0\nG83 X1 Y1 Z-3 R1 F100\n", 2, "G83", ["needs Q"]),
    ("G0 X0 Y0 Z0\nG81 X1 Y1 Z3 R1 F100\n", 2, "R1", ["below the bottom"]),
    ("G0 X0 Y0 Z0\nG1 X1 P2 F100\n", 2, "P2", ["P belongs to G4"]),
    ("G0 X0 Y0 Z0\nG28.1 X1\nG1 X1 F100 Q2\n", 3, "Q2", ["Q belongs to"]),
    ("G0 X0 Y0 Z0\nG2 X10 Y0 I5.1 J0 F100\n", 2, "I5.1", ["radius does not fit"]),
    ("G0 X0 Y0 Z0\nG2 X10 Y0 R4.9 F100\n", 2, "R4.9", ["smaller than half the chord"]),
    ("G0 X0 Y0 Z0\nG2 X0 Y0 R5 F100\n", 2, "R5", ["full circle"]),
    ("G0 X0 Y0 Z0\nG1 G2 X1 F100\n", 2, "G2", ["second motion word"]),
    ("G0 X0 Y0 Z0\nG17 G2 X10 K3 F100\n", 2, "K3", ["G17 arcs take centre offsets I and J"]),
    ("G0 X0 Y0 Z0\nG1 X10 F0\n", 2, "F0", ["must be > 0"]),
    ("G0 X0 Y0 Z0\nM98 P100\n", 2, "M98", ["Fanuc subprogram calls (M98 P)", "O-word subroutines"]),
    ("G0 X0 Y0 Z0\nG1 X10 F100 (open comment\n", 2, "", ["not closed"]),
    ("G0 X0 Y0 Z0\nG1 X10 I5 F100\n", 2, "I5", ["belong to arcs"]),
    ("G0 X0 Y0 Z0\nG4\n", 2, "G4", ["duration P"]),
    ("G0 X0 Y0 Z0\nG2 X10 Y0 F100\n", 2, "X10", ["needs its centre"]),
    ("G0 X0 Y0\nG91 Z-1\n", 2, "Z-1", ["incremental"]),
])
def test_program_errors_name_the_line_and_the_word(tmp_path, monkeypatch, code, line, word, words):
    monkeypatch.setattr(ngc_flow, "MAX_EXECUTED_BLOCKS", 1000)  # the endless loop's bound, reached quickly
    with pytest.raises(GcodeError) as error:
        program(tmp_path, code)
    assert error.value.line == line and error.value.word == word
    message = str(error.value)
    assert message.startswith(f"{tmp_path / 'p.nc'}, line {line}") and (not word or f"'{word}'" in message)
    for expected in words:
        assert expected in message


@pytest.mark.parametrize("text, field, words", [
    ("shape: {type: gcode, file: p.nc}\nunits: mm\n", "units", ["G20", "remove units"]),
    ("shape: {type: gcode, file: p.nc}\nfeed_m_s: 0.1\n", "feed_m_s", ["F words"]),
    ("shape: {type: gcode, file: p.nc}\nrapids: {mode: timed}\n", "rapids", ["feed_m_s"]),
    ("shape: {type: gcode, file: p.nc}\nprocess_forces_N: {feed: 1, cutting: {feed: 2}}\n", "process_forces_N",
     ["not both"]),
    ("units: mm\nshape: {type: circle, radius: 5}\nfeed_m_s: 0.1\nrapids: {mode: skip}\n", "rapids", ["G-code"]),
    ("shape: {type: circle, radius: 5}\nfeed_m_s: 0.1\n", "units", ["missing"]),
    ("shape: {type: gcode, file: missing.nc}\n", "", ["not found", "missing.nc"]),
])
def test_path_file_fields_for_programs(tmp_path, text, field, words):
    (tmp_path / "p.nc").write_text("G0 X0 Y0 Z0\nG1 X10 F100\n")
    file = tmp_path / "path.yaml"
    file.write_text(text)
    with pytest.raises(PathFileError) as error:
        load_path(file)
    assert error.value.field == field
    for expected in words:
        assert expected in str(error.value)


def test_a_bad_program_exits_2_with_one_line(tmp_path, capsys):
    (tmp_path / "bad.nc").write_text("G21 G90\nG0 X0 Y0 Z0\nG41 G1 X5 F200\n")
    (tmp_path / "bad.yaml").write_text("shape: {type: gcode, file: bad.nc}\n")
    assert main(["--robot", "orthoglide", "--path", str(tmp_path / "bad.yaml"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bad.nc, line 3, word 'G41'" in err and "Traceback" not in err


@pytest.mark.parametrize("robot_name, at", [("orthoglide", [0.0, 0.0, 0.0, 0.3, 0.0, 0.0]),
                                            ("ur5", [0.45, 0.1, 0.2, 0.3, 0.0, 0.0])])
def test_the_kinematics_follow_a_program_across_skipped_rapids(robot_name, at):
    import pinocchio as pin

    from placement.kinematics import joint_trajectory
    from placement.placing.transform import placed_task

    robot = load_robot(robot_name)
    path = load_path(EXAMPLES / "pocket.yaml")
    samples = path.sample(0.004)
    task, _ = placed_task(robot, samples, np.array([at]))
    joints = joint_trajectory(robot, task)  # raises if a sample is unreachable or leaves the branch
    data = robot.model.createData()
    for k in range(0, len(samples), 5):
        pin.framesForwardKinematics(robot.model, data, joints.q[k])
        np.testing.assert_allclose(data.oMf[robot.end_effector_frame_id].translation, task.position_m[k], atol=1e-9)
    detail = Evaluator(robot, path, EvaluatorSettings(time_step_s=0.004)).detail(np.array(at))
    assert detail.reachable and np.isfinite(detail.energy.total_J)


def test_the_feed_command_scales_every_programmed_feed(capsys):
    assert main(["feed", "--robot", "orthoglide", "--path", str(EXAMPLES / "pocket.yaml"), "--at", "x=0,y=0",
                 "--feeds", "0.06:0.12:2", "--time-step", "0.004"]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines() if line.strip().startswith("0.")]
    (_, reached_1, time_1), (_, reached_2, time_2) = [[float(v) for v in row[:3]] for row in rows]
    # The program's highest F (7200 mm/min, 0.12 m/s) is the feed; at half of it every move takes twice as long.
    assert (reached_1, reached_2) == (0.06, 0.12) and time_1 == pytest.approx(2 * time_2, rel=1e-3)
    assert time_2 == pytest.approx(load_path(EXAMPLES / "pocket.yaml").sample(0.004).t_s[-1], abs=1e-4)  # as printed


def test_only_a_gap_is_a_jump_for_the_batched_march():
    from placement.kinematics.batched import JUMP_M, jump_steps

    steps = np.full(50, 0.6e-3)  # a path sampled every 0.6 mm ...
    steps[20] = 30e-3  # ... with a 30 mm gap
    assert jump_steps(steps).tolist() == [20]
    assert jump_steps(np.full(50, 3 * JUMP_M)).tolist() == []  # a coarsely sampled path has no jump


def test_a_repair_a_hair_outside_the_workspace_is_pulled_back_in():
    """The pocket's worst placement lies in a corner of the Orthoglide's workspace box, where the search's repair
    (the path's own sampling breaks a limit its coarse sampling missed: an arc's extreme) ends a hair outside."""
    from placement.search.local import Problem, inward_until_feasible
    from placement.search.space import default_space

    robot, path = load_robot("orthoglide"), load_path(EXAMPLES / "pocket.yaml")
    space = default_space(robot, half_turn=path.half_turn_symmetric())
    outside = np.array([-0.10800862, -0.10677171, -0.12279492, -2.18036395])
    with Evaluator(robot, path) as evaluator:
        problem = Problem(evaluator, space, -1.0)
        assert -1e-7 < problem.margins(outside).min() < 0
        inside = inward_until_feasible(problem, outside, space)
        assert problem.margins(inside).min() >= 0 and np.abs(inside - outside).max() < 1e-5


def test_a_posts_safety_line_and_one_work_coordinate_system_are_read(tmp_path):
    # Fanuc-style posts cancel canned cycles on the same line as a rapid, and name the work system.
    plain = program(tmp_path, "G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\n", name="plain")
    posted = program(tmp_path, "G0 G90 G40 G21 G17 G94 G80\nG55 X0 Y0 Z5 S500 M3\nG1 Z-1 F100\nG80 G1 X10\n",
                     name="posted")
    assert len(plain.segments) == len(posted.segments)
    for a, b in zip(plain.segments, posted.segments):
        np.testing.assert_allclose([a.start_m, a.end_m], [b.start_m, b.end_m], atol=1e-15)


def test_a_slow_program_without_a_time_step_is_sampled_every_half_millimetre(tmp_path):
    slow = program(tmp_path, "G0 X0 Y0 Z0\nG1 X100 F100\n", name="slow")  # 100 mm/min
    fast = program(tmp_path, "G0 X0 Y0 Z0\nG1 X100 F60000\n", name="fast")  # 1 m/s: 1 ms is finer than 0.5 mm
    assert slow.time_step_s == pytest.approx(0.0005 / (0.1 / 60)) and fast.time_step_s == 0.001
    spacing = np.diff(slow.sample().position_m[:, 0])
    assert spacing.max() <= 0.0005 + 1e-12


@pytest.mark.parametrize("timing", ["paper", "realistic", "optimal"])
def test_a_dwell_costs_the_static_holding_joule_power_for_its_duration(tmp_path, timing):
    # The UR5 holds the tool at rest for 2 s against gravity and an axial process force. The static joint efforts
    # are computed here with Pinocchio (gravity torque less the Jacobian's transpose times the force on the tool),
    # the motor currents from the gear ratio and torque constant, and the Joule power n·R·I² from them.
    import pinocchio as pin

    robot = load_robot("ur5")
    at = np.array([0.45, 0.1, 0.2, 0.3, 0.0, 0.0])
    forces = "process_forces_N: {feed: 0, radial: 0, axial: 40}\n"
    law = f"timing: {{mode: {timing}, max_acceleration_m_s2: 2, max_jerk_m_s3: 50}}\n"
    moves = "G21 G90 G0 X0 Y0 Z0\nG1 X10 F600\n{}G1 X20\nG1 Y10\n"
    held = program(tmp_path, moves.format("G4 P2\n"), forces + law, name="held")
    plain = program(tmp_path, moves.format("M0\n"), forces + law, name="plain")  # a stop there, no hold
    assert held.holds and held.holds[0].duration_s == 2.0
    details = [Evaluator(robot, path, EvaluatorSettings(time_step_s=0.004)).detail(at) for path in (held, plain)]
    assert all(d.reachable for d in details)
    hold = np.flatnonzero(np.all(details[0].samples.velocity_m_s == 0, axis=1)
                          & np.all(np.abs(details[0].samples.position_m - [0.01, 0, 0]) < 1e-12, axis=1))
    assert len(hold) >= 2 and np.ptp(details[0].samples.t_s[hold]) == pytest.approx(2.0, abs=1e-12)
    q = details[0].configuration[hold[0]]
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    phi = at[3]
    turn = np.array([[np.cos(phi), -np.sin(phi), 0.0], [np.sin(phi), np.cos(phi), 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(data.oMf[robot.end_effector_frame_id].translation, at[:3] + turn @ [0.01, 0, 0],
                               atol=1e-9)
    force = turn @ np.array([0.0, 0.0, 40.0])  # axial: along Z_p, on the tool from the workpiece
    jacobian = pin.computeFrameJacobian(robot.model, data, q, robot.end_effector_frame_id,
                                        pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3]
    effort = pin.computeGeneralizedGravity(robot.model, data, q) - jacobian.T @ force
    power = sum(d.motor.phases * d.motor.resistance_ohm
                * (tau / (d.transmission.ratio * d.transmission.efficiency * d.motor.torque_constant_Nm_per_A)) ** 2
                for d, tau in zip(robot.drives, effort))
    # The hold is the only difference: without it the same moves run, with a stop (M0) where the dwell was.
    extra = details[0].energy.total_J - details[1].energy.total_J
    assert extra == pytest.approx(power * 2.0, rel=1e-9)
    assert details[0].duration_s - details[1].duration_s == pytest.approx(2.0, abs=1e-3)


def test_a_fanuc_style_program_runs_end_to_end(capsys):
    # Safety line, G28 G91 Z0., T1 M6, S12000 M3, G54, G43 Z15. H1, M8, arcs by I/J, M9, M5, a G83 cycle, M30.
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLES / "racetrack_fanuc.yaml"), "--at", "x=0,y=0",
                 "--quiet"]) == 0
    out = capsys.readouterr().out
    assert out.count("note: G28") == 1 and "shape.machine.g28_mm" in out
    path = load_path(EXAMPLES / "racetrack_fanuc.yaml")
    slot = 2 * (36 - 16) + 2 * np.pi * 8  # two straights and two half circles of radius 8 mm, per depth
    cutting = sum(s.length_m for s in path.segments if s.center_m is not None or abs(s.end_m[2] - s.start_m[2]) < 1e-12)
    assert cutting == pytest.approx(2 * slot * 1e-3, rel=1e-12)
    drilled = [s for s in path.segments if s.start_m[0] in (-0.025, 0.025) and s.end_m[2] < s.start_m[2]]
    # R2 down to Z-8 in pecks of Q2: four pecks end at 0, -2, -4, -6, each followed by a feed from 0.254 mm above
    assert sum(s.length_m for s in drilled) == pytest.approx(2 * (10 + 4 * 0.254) * 1e-3, rel=1e-12)


def test_never_given_axes_stay_at_the_origin(tmp_path):
    # A plasma or laser program in X and Y only runs in the X_p Y_p plane.
    flat = program(tmp_path, "G21 G90 G0 X5 Y5\nG1 X10 F600\nG2 I-5 J0\nG1 Y-5\n", name="flat")
    assert len(flat.segments) == 3 and all(np.all(np.array([s.start_m[2], s.end_m[2]]) == 0) for s in flat.segments)
    circle = flat.segments[1]
    assert circle.length_m == pytest.approx(2 * np.pi * 5e-3, rel=1e-12)  # a full circle without end words


@pytest.mark.parametrize("mode, runs", [("G64", 1), ("G61", 2), ("G61.1", 3)])
def test_path_control_modes_set_where_the_tool_stops(tmp_path, mode, runs):
    # Three moves turning 0.5° and then 0° (collinear): blended in G64, the turn stops in G61 (exact path), every
    # end stops in G61.1 (exact stop).
    turn = np.radians(0.5)
    end = 10 + 10 * np.cos(turn), 10 * np.sin(turn)
    code = (f"G21 G90 G0 X0 Y0 Z0\n{mode}\nG1 X10 F600\nX{end[0]:.12f} Y{end[1]:.12f}\n"
            f"X{10 + 20 * np.cos(turn):.12f} Y{20 * np.sin(turn):.12f}\n")
    path = program(tmp_path, code, "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\n")
    assert len(path.runs()) == runs


def test_reference_returns_with_and_without_the_machine_positions(tmp_path):
    code = "G21 G90 G0 X0 Y0 Z0\nG1 X10 F600\nG28 Z5\nG0 X20 Y0 Z0\nG1 Y10\n"
    machine = "shape: {type: gcode, file: m.nc, machine: {g28_mm: [100, 0, 50], work_offset_mm: [90, 0, 0]}}\n"
    (tmp_path / "m.nc").write_text(code)
    (tmp_path / "m.yaml").write_text(machine + "rapids: {mode: timed, feed_m_s: 0.5}\n")
    known = load_path(tmp_path / "m.yaml")
    ends = [tuple(np.round(s.end_m * 1e3, 9)) for s in known.segments]
    # the intermediate point Z5, then X, Y, Z to the reference: machine (100, 0, 50) less the offset (90, 0, 0)
    assert ends[1:4] == [(10.0, 0.0, 5.0), (10.0, 0.0, 50.0), (20.0, 0.0, 0.0)] and not known.notes
    unknown = program(tmp_path, code, "rapids: {mode: timed, feed_m_s: 0.5}\n", name="u")
    assert [tuple(np.round(s.end_m * 1e3, 9)) for s in unknown.segments][1:] == [(10.0, 0.0, 5.0), (20.0, 10.0, 0.0)]
    assert "G28 (line 3)" in unknown.notes[0]


@pytest.mark.parametrize("code, feed_mm_min", [
    ("G93 G1 X30 F4\n", 30 * 4),  # inverse time: the move takes 1/4 min
    ("G95 S2000 G1 X30 F0.05\n", 0.05 * 2000),  # per revolution at S
    ("G94 G1 X30 F150\n", 150),
])
def test_feed_modes(tmp_path, code, feed_mm_min):
    path = program(tmp_path, "G21 G90 G0 X0 Y0 Z0\n" + code)
    assert path.speed_m_s(path.segments[0]) == pytest.approx(feed_mm_min / 60e3, rel=1e-12)


@pytest.mark.parametrize("code, radius_mm", [("G41", 3.0), ("G42", 3.0), ("G41", 1.0), ("G42", 1.0)])
def test_compensation_offsets_a_rectangle_by_the_tool_radius(tmp_path, code, radius_mm):
    """A 40 x 30 mm rectangle run clockwise from its corner (0, 0) once round and up its first side again, the tool's
    diameter from the path file, entered along that side. Outside it (G41: the tool on the left) the tool centre runs
    each side at r off, joined by quarter circles of radius r about the corners; inside (G42) the sides are
    shortened by r at each corner, except where the program starts and ends (at the offset points of (0, 0) and of
    (0, 30), the entry's end and G40's start)."""
    (tmp_path / "box.nc").write_text(f"""G21 G90 G0 X0 Y-10 Z0
T2 M6
{code} G0 X0 Y0
G1 X0 Y30 F600
X40
Y0
X0
Y30
G40 G0 X0 Y40
""")
    path = path_file(tmp_path, f"shape: {{type: gcode, file: box.nc, tool_diameters_mm: {{1: 50, 2: {2 * radius_mm}}}}}\n")
    feeds = [segment for segment in path.segments if not segment.rapid]
    r = radius_mm * 1e-3
    if code == "G41":
        expected, arcs = 2 * (0.040 + 0.030) + 0.030 + 2 * np.pi * r, 4
    else:
        expected, arcs = 2 * (0.030 - r) + 2 * (0.040 - 2 * r) + (0.030 - 2 * r), 0
    assert sum(segment.length_m for segment in feeds) == pytest.approx(expected, abs=1e-12)
    assert sum(segment.center_m is not None for segment in feeds) == arcs
    assert all(segment.radius_m == pytest.approx(r, abs=1e-15) for segment in feeds if segment.center_m is not None)


# A drilling cycle from where the machine happens to be, as FreeCAD's posts write a job's first one (G0 Z5, then G83)

FIRST_CYCLE = "G21 G90 G17\nG0 Z5\nG98\nG83 X-2.8 Y-2.5 Z-4 F60 Q1.5 R3\nG83 X-9.8 Y-2.5 Z-4 F60 Q1.5 R3\nG80\nG0 Z5\nM2\n"


@pytest.mark.parametrize("level, before", [("Z5", "G0 X-2.8 Y-2.5\n"), ("Z1", "G0 Z3\nG0 X-2.8 Y-2.5\n")])
def test_a_first_cycle_from_an_unknown_point_is_the_cycle_after_a_rapid_over_its_hole(tmp_path, level, before):
    """The moves known from the first hole on are those of the same program brought over the hole by rapids first
    (up to R first when the tool starts below it, as LinuxCNC's preliminary motion does): only rapids from the unknown
    point differ, and those are left out in both."""
    unknown = program(tmp_path, FIRST_CYCLE.replace("Z5\nG98", f"{level}\nG98"), name="unknown")
    known = program(tmp_path, FIRST_CYCLE.replace("Z5\nG98", f"{level}\n{before}G98"), name="known")
    assert [(s.start_m.tolist(), s.end_m.tolist(), s.rapid) for s in unknown.segments] == [
        (s.start_m.tolist(), s.end_m.tolist(), s.rapid) for s in known.segments]
    assert sum(not s.rapid for s in unknown.segments) == 2 * 5  # two holes, R3 to Z-4 in pecks of 1.5 mm: 5 feeds each


@pytest.mark.parametrize("code, words", [
    ("G0 Z5\nG81 X1 Z-3 R1 F100\n", ["unknown position (X, Y not given yet)"]),  # the hole's Y is not known
    ("G0 X1 Y1\nG81 X1 Y1 Z-3 R1 F100\n", ["unknown position (Z not given yet)"]),  # nor the level it starts at
    ("G0 Z5\nG91 G81 X1 Y1 Z-3 R1 F100\n", ["unknown position (X, Y not given yet)"]),  # steps from an unknown point
])
def test_a_first_cycle_whose_hole_or_level_is_not_known_is_refused(tmp_path, code, words):
    with pytest.raises(GcodeError) as error:
        program(tmp_path, code)
    assert error.value.line == 2 and all(word in str(error.value) for word in words)


def test_a_byte_order_mark_is_not_read_as_a_character_of_the_program(tmp_path):
    """Windows editors (Notepad) begin a UTF-8 file with U+FEFF; the program is the same without it."""
    code = "G21 G90\nG0 X0 Y0 Z0\nG1 X10 F100\n"
    (tmp_path / "bom.nc").write_text("\ufeff" + code, encoding="utf-8")
    (tmp_path / "bom.yaml").write_text("shape: {type: gcode, file: bom.nc}\n")
    with_mark, without = load_path(tmp_path / "bom.yaml"), program(tmp_path, code)
    assert [s.end_m.tolist() for s in with_mark.segments] == [s.end_m.tolist() for s in without.segments]


@pytest.mark.parametrize("line", [
    "G01 X-0.1100 Y-0.0300 F10    ", "N40 G1 X.5 Y-.25 Z+1. F300", "g0x1y2", "N10", "", "X1", "N7G2X1Y0I.5J0",
    "G00 X0.0000  Y0.0000  \r", "M06 T01", "n20 g91 g1 x-1.5e", "G1 X1 N5", "\tG0\tZ5", "O100", "G1 X[1+2]",
])
def test_a_line_of_letters_and_numbers_is_read_at_once_as_the_full_reader_reads_it(line):
    """The reader's shortcut for lines of plain words (most of a CAM post's) gives the words the full reader gives,
    or leaves the line to it."""
    from placement.path import ngc_expressions as ngc

    quick = ngc.read_line(line)
    try:
        full = ngc._Reader(ngc._strip(line)).block()
    except ngc._ExpressionError as error:  # the full reader refuses it: so does the line read at once
        assert quick.error is not None and str(quick.error) == str(error)
        return
    parameters = ngc.Parameters()
    assert [(w.letter, w.text, w.value(parameters)) for w in quick.words] == [
        (w.letter, w.text, w.value(parameters)) for w in full.words]
    assert (quick.assignments, quick.oword is None) == (full.assignments, full.oword is None)
