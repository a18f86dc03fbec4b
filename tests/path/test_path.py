"""Paths: shapes, timing laws, process forces and the file format."""

import numpy as np
import pytest

from placement.path.exceptions import PathFileError
from placement.path.load import load_path
from placement.path.realistic_law import DoubleS
from tests.support.paths import EXAMPLE


def write(tmp_path, text, name="path.yaml"):
    file = tmp_path / name
    file.write_text(text)
    return file


def test_paper_rectangle_runs_each_side_at_the_feed(tmp_path):
    path = load_path(EXAMPLE)
    samples = path.sample()
    assert len(path.segments) == 4 and path.length_m == pytest.approx(0.18)
    np.testing.assert_allclose(samples.position_m[0], [-0.015, -0.030, 0.0])
    np.testing.assert_allclose(np.linalg.norm(samples.velocity_m_s, axis=1), 0.66)
    assert np.abs(samples.acceleration_m_s2).max() == 0.0
    assert samples.t_s[-1] == pytest.approx(0.18 / 0.66)
    assert list(np.unique(samples.piece)) == [0, 1, 2, 3]
    # Anticlockwise about Z_p: A -> B runs along +X_p.
    np.testing.assert_allclose(samples.tangent[0], [1.0, 0.0, 0.0])


def test_process_force_sign_convention():
    samples = load_path(EXAMPLE).sample()
    # Feeding along +X_p: the feed force opposes the motion, the radial force points to the left
    # of the feed (+Y_p), the axial force along +Z_p.
    np.testing.assert_allclose(samples.force_on_tool_N[0], [-10.0, 215.0, 25.0])
    # On side B -> C (feeding along +Y_p) the radial force points along -X_p.
    on_bc = np.flatnonzero(samples.piece == 1)[0]
    np.testing.assert_allclose(samples.force_on_tool_N[on_bc], [-215.0, -10.0, 25.0], atol=1e-12)


def test_circle_has_centripetal_acceleration(tmp_path):
    path = load_path(write(tmp_path, "units: m\nshape: {type: circle, radius: 0.02}\nfeed_m_s: 0.5\n"))
    s = path.sample()
    np.testing.assert_allclose(np.linalg.norm(s.position_m, axis=1), 0.02)
    np.testing.assert_allclose(s.acceleration_m_s2, -s.position_m * 0.5**2 / 0.02**2, atol=1e-9)


def test_arc_and_polyline_shapes(tmp_path):
    arc = load_path(write(tmp_path, "units: mm\nshape: {type: arc, radius: 10, start_deg: 90, sweep_deg: -90}\n"
                                    "feed_m_s: 0.1\n"))
    np.testing.assert_allclose(arc.segments[0].end_m, [0.01, 0.0, 0.0], atol=1e-15)
    assert arc.length_m == pytest.approx(np.pi / 2 * 0.01)
    line = load_path(write(tmp_path, "units: mm\nshape: {type: polyline, points: [[0, 0], [30, 0], [30, 40]], "
                                     "closed: true}\nfeed_m_s: 0.2\n"))
    assert len(line.segments) == 3 and line.length_m == pytest.approx(0.12)


def on_rounded_outline(points, half_width, half_length, radius):
    """Distance of each point (N, 3) from the outline of a rectangle with rounded corners centred on the origin."""
    x, y = np.abs(points[:, 0]), np.abs(points[:, 1])
    cx, cy = half_width - radius, half_length - radius  # the corners' centres
    corner = np.hypot(np.maximum(x - cx, 0.0), np.maximum(y - cy, 0.0))
    in_corner = (x > cx) & (y > cy)
    side = np.minimum(np.abs(x - half_width) + np.where(y > cy, np.inf, 0.0),
                      np.abs(y - half_length) + np.where(x > cx, np.inf, 0.0))
    return np.where(in_corner, np.abs(corner - radius), side)


def joins_are_tangent(path):
    """Each segment's end tangent is the next one's start tangent (the last joins the first: a closed outline)."""
    segments = path.segments
    for before, after in zip(segments, segments[1:] + segments[:1]):
        end = before.point(np.array([before.length_m]), np.ones(1), np.zeros(1))
        start = after.point(np.zeros(1), np.ones(1), np.zeros(1))
        np.testing.assert_allclose(end[0], start[0], atol=1e-15)  # continuous position ...
        np.testing.assert_allclose(end[3], start[3], atol=1e-12)  # ... and tangent


@pytest.mark.parametrize("units, scale", [("mm", 1e-3), ("in", 0.0254)])
def test_a_rectangle_with_rounded_corners(tmp_path, units, scale):
    path = load_path(write(tmp_path, f"units: {units}\nshape: {{type: rectangle, width: 80, length: 40, "
                                     "corner_radius: 8}\nfeed_m_s: 0.04\n"
                                     "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\n"))
    assert len(path.segments) == 8 and len(path.runs()) == 1  # tangent all round: the tool never stops
    assert path.length_m == pytest.approx((2 * (80 - 16) + 2 * (40 - 16) + 2 * np.pi * 8) * scale, rel=1e-12)
    joins_are_tangent(path)
    samples = path.sample()
    assert on_rounded_outline(samples.position_m, 40 * scale, 20 * scale, 8 * scale).max() < 1e-12
    np.testing.assert_allclose(samples.position_m[0], [-32 * scale, -20 * scale, 0.0], atol=1e-15)
    with pytest.raises(PathFileError, match="half the shorter side"):
        load_path(write(tmp_path, "units: mm\nshape: {type: rectangle, width: 80, length: 40, corner_radius: 21}\n"
                                  "feed_m_s: 0.04\n"))


def test_a_slot_is_a_stadium(tmp_path):
    path = load_path(write(tmp_path, "units: mm\nshape: {type: slot, length: 50, width: 10}\nfeed_m_s: 0.05\n"
                                     "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\n"))
    # Two straights of length - width and two half circles of the width's diameter.
    assert [s.center_m is None for s in path.segments] == [True, False, False, True, False, False]
    assert path.length_m == pytest.approx(2 * (50 - 10) * 1e-3 + np.pi * 10e-3, rel=1e-12)
    assert len(path.runs()) == 1
    joins_are_tangent(path)
    samples = path.sample()
    assert on_rounded_outline(samples.position_m, 0.025, 0.005, 0.005).max() < 1e-12
    circle = load_path(write(tmp_path, "units: mm\nshape: {type: slot, length: 10, width: 10}\nfeed_m_s: 0.05\n"))
    assert circle.length_m == pytest.approx(np.pi * 10e-3, rel=1e-12) and all(s.center_m is not None
                                                                             for s in circle.segments)
    with pytest.raises(PathFileError, match="at least the width"):
        load_path(write(tmp_path, "units: mm\nshape: {type: slot, length: 5, width: 10}\nfeed_m_s: 0.05\n"))


def test_inches(tmp_path):
    path = load_path(write(tmp_path, "units: in\nshape: {type: polyline, points: [[0, 0], [1, 0], [1, 2]]}\n"
                                     "feed_m_s: 0.1\n"))
    assert path.length_m == pytest.approx(3 * 0.0254, rel=1e-15)
    np.testing.assert_allclose(path.segments[-1].end_m, [0.0254, 0.0508, 0.0], rtol=1e-15)


def realistic(tmp_path):
    return load_path(write(tmp_path, "units: mm\nshape: {type: rectangle, width: 30, length: 60}\nfeed_m_s: 0.66\n"
                                     "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\n"
                                     "time_step_s: 0.0005\n"))


CIRCLE = ("units: mm\nshape: {type: circle, radius: 20}\nfeed_m_s: 0.5\n"
          "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\ntime_step_s: 0.0001\n")
ARC = ("units: mm\nshape: {type: arc, radius: 5, start_deg: 0, sweep_deg: 270}\nfeed_m_s: 0.5\n"
       "timing: {mode: realistic, max_acceleration_m_s2: 10, max_jerk_m_s3: 500}\ntime_step_s: 0.0001\n")


@pytest.mark.parametrize("text", [None, CIRCLE, ARC], ids=["rectangle", "circle", "arc"])
def test_realistic_timing_respects_speed_acceleration_and_jerk(tmp_path, text):
    path = realistic(tmp_path) if text is None else load_path(write(tmp_path, text))
    s = path.sample()
    speed = np.linalg.norm(s.velocity_m_s, axis=1)
    assert speed.max() <= 0.66 + 1e-12 and speed[0] == 0 and speed[-1] == pytest.approx(0, abs=1e-9)
    assert np.linalg.norm(s.acceleration_m_s2, axis=1).max() <= 10 + 1e-9
    jerk = np.linalg.norm(np.diff(s.acceleration_m_s2, axis=0) / np.diff(s.t_s)[:, None], axis=1)
    assert jerk.max() <= 500 * (1 + 1e-6)
    assert s.t_s[-1] > path.length_m / path.feed_m_s  # stopping costs time
    # Positions are the integral of velocities (trapezoidal rule error O(dt²)).
    integrated = s.position_m[0] + np.concatenate([[np.zeros(3)], np.cumsum(
        (s.velocity_m_s[1:] + s.velocity_m_s[:-1]) / 2 * np.diff(s.t_s)[:, None], axis=0)])
    assert np.abs(integrated - s.position_m).max() < 1e-6
    end = path.segments[-1].end_m
    np.testing.assert_allclose(s.position_m[-1], end, atol=1e-12)


@pytest.mark.parametrize("distance", [0.001, 0.03, 0.5])
def test_double_s_travels_the_distance(distance):
    profile = DoubleS(distance, 0.66, 10.0, 500.0)
    s, v, a = profile(np.array([0.0, profile.duration_s]))
    assert s[-1] == pytest.approx(distance, rel=1e-9) and v[-1] == pytest.approx(0, abs=1e-9)


@pytest.mark.parametrize("text, field, words", [
    ("units: mm\nshape: {type: rectangle, width: -30, length: 60}\nfeed_m_s: 0.66\n", "shape.width", ["greater than 0"]),
    ("units: mm\nshape: {type: rectangle, width: 30, length: 60}\nfeed_m_s: 0\n", "feed_m_s", ["greater than 0"]),
    ("units: inch\nshape: {type: circle, radius: 1}\nfeed_m_s: 0.1\n", "units", ["'m'", "'mm'"]),
    ("units: mm\nshape: {type: circle, radius: 1}\nfeed: 0.1\n", "feed", ["unknown field", "feed_m_s"]),
    ("units: mm\nshape: {type: circle, radius: 1, width: 3}\nfeed_m_s: 0.1\n", "shape.width", ["unknown field", "radius"]),
    ("units: mm\nshape: {type: square, side: 1}\nfeed_m_s: 0.1\n", "shape", ["rectangle"]),
    ("units: mm\nshape: {type: circle, radius: 1}\nfeed_m_s: 0.1\ntiming: {mode: realistic}\n", "timing",
     ["max_acceleration_m_s2"]),
    ("units: mm\nshape: {type: polyline, points: [[1, 1], [1, 1]]}\nfeed_m_s: 0.1\n", "shape.points", ["coincide"]),
    ("units: mm\nshape: {type: circle, radius: 1\n", "", ["not valid YAML"]),
])
def test_bad_path_files_name_the_field(tmp_path, text, field, words):
    file = write(tmp_path, text)
    with pytest.raises(PathFileError) as error:
        load_path(file)
    assert error.value.field == field and str(file) in str(error.value)
    for word in words:
        assert word in str(error.value)


def test_missing_path_file(tmp_path):
    with pytest.raises(PathFileError, match="file not found"):
        load_path(tmp_path / "nowhere.yaml")


def test_short_reprs():
    """print(path), print(robot) and the results say what they are in a line, not pages of arrays or Pinocchio."""
    import numpy as np

    from placement import Evaluator, EvaluatorSettings, load_robot

    path, robot = load_path(EXAMPLE), load_robot("orthoglide")
    assert repr(path) == "ToolPath('rectangle 30 x 60 mm, groove milling', 4 segments, 180 mm, feed 0.66 m/s, paper timing)"
    assert repr(robot).startswith("Robot('orthoglide', 3 actuators (slider_x, slider_y, slider_z), position task")
    evaluator = Evaluator(robot, path, EvaluatorSettings(workers=1))
    at = np.array([0.0, 0.0, -0.03, 0.0, 0.0, 0.0])
    assert repr(evaluator.evaluate(at[None])).startswith("Evaluation(1 placements, 1 feasible, energy ")
    text = repr(evaluator.detail(at))
    assert text.startswith("PlacementDetail(at (0.00, 0.00, -30.00) mm, (0.00, 0.00, 0.00) deg: energy ")
    assert len(text) < 200 and "\n" not in repr(robot)


def test_a_path_given_as_a_dict(tmp_path):
    fields = {"units": "mm", "shape": {"type": "circle", "radius": 20}, "feed_m_s": 0.2}
    path = load_path(fields)
    assert path.name == "path" and path.length_m == pytest.approx(2 * np.pi * 0.02, rel=1e-12)
    assert repr(load_path(write(tmp_path, "units: mm\nshape: {type: circle, radius: 20}\nfeed_m_s: 0.2\n", "path.yaml"))) \
        == repr(path)
    with pytest.raises(PathFileError) as error:
        load_path({**fields, "feed_m_s": -1})
    assert error.value.field == "feed_m_s" and "<dict>" in str(error.value)
    (tmp_path / "job.nc").write_text("G21 G0 X0 Y0 Z0\nG1 X10 F600\n")
    job = load_path({"shape": {"type": "gcode", "file": "job.nc"}}, folder=tmp_path)  # files beside ``folder``
    assert job.length_m == pytest.approx(0.01)


def test_a_time_step_that_cannot_sample_the_path_is_refused_naming_the_option(capsys):
    """--time-step 1e6 on the 0.27 s groove would leave 8 samples and 4.39 J instead of 4.80 J: refused."""
    from placement.__main__ import main

    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--time-step", "1e6", "--at", "x=0"]) == 2
    error = capsys.readouterr().err
    assert "--time-step" in error and "time_step_s" in error and "0.2727 s" in error


def test_a_short_path_without_a_time_step_gets_enough_samples(tmp_path):
    """A 5 mm stroke at 1 m/s lasts 5 ms: the default step shrinks so that it has 20 samples, not 6."""
    short = tmp_path / "short.yaml"
    short.write_text("units: mm\nshape: {type: polyline, points: [[0, 0], [5, 0]]}\nfeed_m_s: 1.0\n")
    path = load_path(short)
    assert path.time_step_s == pytest.approx(0.005 / 20)
    assert len(path.sample()) == 21
