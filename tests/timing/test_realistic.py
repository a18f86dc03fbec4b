"""The realistic timing law's look-ahead: the feed drops only where the geometry requires it, within the bounds."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from placement.path.load import load_path
from placement.path.realistic_law import segment_speeds

ACCELERATION, JERK = 10.0, 500.0
TIMING = f"timing: {{mode: realistic, max_acceleration_m_s2: {ACCELERATION:g}, max_jerk_m_s3: {JERK:g}}}\n"

# An 80 x 40 mm rectangle with 8 mm corner radii at F2400 (0.04 m/s), anticlockwise from the bottom straight.
ROUNDED = """G21 G90 G17
G0 X-32 Y-20 Z0
G1 X32 Y-20 F{feed}
G3 X40 Y-12 I0 J8
G1 X40 Y12
G3 X32 Y20 I-8 J0
G1 X-32 Y20
G3 X-40 Y12 I0 J-8
G1 X-40 Y-12
G3 X-32 Y-20 I8 J0
"""
# A sharp corner between two lines, then two feeds on one straight line (a fast move, a slow one).
CORNER_AND_FEEDS = """G21 G90 G17
G0 X0 Y0 Z0
G1 X40 F6000
G1 Y40
G1 Y80 F1200
"""


def program(tmp_path, text, step_s=0.0005):
    (tmp_path / "job.nc").write_text(text)
    (tmp_path / "job.yaml").write_text(f"shape: {{type: gcode, file: job.nc}}\n{TIMING}time_step_s: {step_s}\n")
    return load_path(tmp_path / "job.yaml")


def check_bounds(path):
    """The sampled motion against the law's bounds: speed within each segment's feed, tangential + centripetal
    acceleration within a_max, its rate within j_max except across a curvature jump, where the acceleration jumps
    by at most j_max over one sampling step (the controller's interpolation period)."""
    s = path.sample()
    step = path.time_step_s
    speed = np.linalg.norm(s.velocity_m_s, axis=1)
    feeds = np.array([path.speed_m_s(segment) for segment in path.segments])
    assert np.linalg.norm(s.acceleration_m_s2, axis=1).max() <= ACCELERATION * (1 + 1e-9)
    change = np.linalg.norm(np.diff(s.acceleration_m_s2, axis=0), axis=1)
    dt = np.diff(s.t_s)
    over = change > JERK * dt * (1 + 1e-6)
    joins = sum(1 for a, b in zip(path.segments, path.segments[1:]) if (a.center_m is None) != (b.center_m is None))
    assert over.sum() <= joins
    assert (change[over] <= JERK * (step + dt[over]) * (1 + 1e-9)).all()
    # Each sample's segment: the speed never exceeds its feed.
    arc = np.concatenate([[0.0], np.cumsum((speed[1:] + speed[:-1]) / 2 * dt)])
    bounds = np.cumsum([0.0] + [segment.length_m for segment in path.segments])
    index = np.clip(np.searchsorted(bounds, arc, side="right") - 1, 0, len(feeds) - 1)
    assert (speed <= feeds[index] + 1e-12).all()
    np.testing.assert_allclose(arc[-1], path.length_m, rtol=1e-6)  # the speeds integrate to the path's length
    return s, speed


def test_the_straights_of_a_rounded_rectangle_reach_the_feed(tmp_path):
    path = program(tmp_path, ROUNDED.format(feed=2400))
    assert len(path.runs()) == 1  # tangent-continuous: no stop
    s, speed = check_bounds(path)
    assert speed.max() == pytest.approx(0.04, rel=1e-9)
    assert speed[0] == 0 and speed[-1] == pytest.approx(0.0, abs=1e-12)
    # Each straight runs at the feed along most of its length (64 mm and 24 mm; 0.04 m/s needs ~0.16 mm to reach).
    reports = segment_speeds(path)
    assert [r.reached_m_s for r in reports] == pytest.approx([0.04] * 8, rel=1e-9)
    assert {r.bound for r in reports} == {"feed"}
    # The time: the length at the feed plus what starting and stopping cost (well under a second).
    assert path.length_m / 0.04 < s.t_s[-1] < path.length_m / 0.04 + 0.05


def test_the_rounded_rectangle_shape_runs_as_its_program(tmp_path):
    (tmp_path / "shape.yaml").write_text("units: mm\nshape: {type: rectangle, width: 80, length: 40, corner_radius: 8}\n"
                                         f"feed_m_s: 0.04\n{TIMING}time_step_s: 0.0005\n")
    shape, gcode = load_path(tmp_path / "shape.yaml"), program(tmp_path, ROUNDED.format(feed=2400))
    ours, theirs = shape.sample(), gcode.sample()
    np.testing.assert_allclose(ours.t_s, theirs.t_s, rtol=1e-12)
    np.testing.assert_allclose(ours.position_m, theirs.position_m, atol=1e-12)


def test_a_finer_sampling_samples_the_same_motion(tmp_path):
    """The interpolation period at curvature jumps is the file's time_step_s: sampling finer (--time-step) leaves the
    motion, hence the duration, as it is."""
    path = program(tmp_path, ROUNDED.format(feed=30000))
    coarse, fine = path.sample(), path.sample(path.time_step_s / 4)
    assert fine.t_s[-1] == pytest.approx(coarse.t_s[-1], rel=1e-12)
    speeds = [np.linalg.norm(samples.velocity_m_s, axis=1) for samples in (coarse, fine)]
    np.testing.assert_allclose(np.interp(coarse.t_s, fine.t_s, speeds[1]), speeds[0], atol=1e-4 * speeds[0].max())


def test_faster_feeds_slow_down_only_on_the_arcs(tmp_path):
    path = program(tmp_path, ROUNDED.format(feed=30000))  # 0.5 m/s
    _, speed = check_bounds(path)
    reports = segment_speeds(path)
    straights, arcs = reports[0::2], reports[1::2]
    # The 64 mm straights reach the feed; the 24 mm ones, between two arcs, are too short to.
    assert [r.reached_m_s for r in straights[0::2]] == pytest.approx([0.5] * 2, rel=1e-9)
    assert all(r.reached_m_s < 0.5 and r.bound == "length (short of the feed cap)" for r in straights[1::2])
    # On an 8 mm arc: v²/r within a_max/√2.
    cap = np.sqrt(ACCELERATION / np.sqrt(2) * 0.008)
    for report in arcs:
        assert report.reached_m_s <= cap * (1 + 1e-9)
        assert "centripetal acceleration" in report.bound or "sampled" in report.bound
    assert speed.max() == pytest.approx(0.5, rel=1e-9)


def test_the_speed_rests_at_a_corner_and_drops_before_a_slower_feed(tmp_path):
    path = program(tmp_path, CORNER_AND_FEEDS)
    s, speed = check_bounds(path)
    corner = np.argmin(np.linalg.norm(s.position_m - [0.04, 0.0, 0.0], axis=1))
    assert np.linalg.norm(s.position_m[corner] - [0.04, 0.0, 0.0]) < 1e-15 and speed[corner] < 1e-12
    reports = segment_speeds(path)
    assert [r.reached_m_s for r in reports] == pytest.approx([0.1, 0.1, 0.02], rel=1e-9)
    # At the feed change (y = 40 mm) the tool has already slowed to the slower feed.
    change = np.argmin(np.abs(s.position_m[:, 1] - 0.04) + (s.position_m[:, 0] < 0.04))
    assert speed[change] <= 0.02 + 2 * ACCELERATION * path.time_step_s


def test_a_circle_reaches_its_feed_when_the_curvature_allows(tmp_path):
    (tmp_path / "circle.yaml").write_text(f"units: mm\nshape: {{type: circle, radius: 8}}\nfeed_m_s: 0.1\n{TIMING}"
                                          "time_step_s: 0.0002\n")
    path = load_path(tmp_path / "circle.yaml")
    _, speed = check_bounds(path)
    assert speed.max() == pytest.approx(0.1, rel=1e-9)
    slow = dataclasses.replace(path, feed_m_s=1.0)  # above what 8 mm allows: the curvature bounds it
    _, speed = check_bounds(slow)
    assert speed.max() <= np.sqrt(ACCELERATION / np.sqrt(2) * 0.008) * (1 + 1e-9)
    assert segment_speeds(slow)[0].bound in ("centripetal acceleration", "sampled acceleration and jerk")
