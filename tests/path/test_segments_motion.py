"""Every segment sampled at once equals each segment sampled on its own, and long paths keep their symmetry test."""

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from placement.path.load import load_path
from placement.path.segments import Hold, Run, Segment, segments_motion

NAMES = ("position", "velocity", "acceleration", "tangent")
TURNING = ("rotation", "angular_velocity", "angular_acceleration")


def random_segments(count, seed, oriented=True):
    """Lines, plane arcs and helices in random planes, some rapid, with random orientations and turns."""
    rng = np.random.default_rng(seed)
    segments, point = [], np.zeros(3)
    for k in range(count):
        orientation = dict(rotation=Rotation.random(random_state=seed + k).as_matrix(),
                           turn_rad=rng.normal(size=3) * 0.2) if oriented else {}
        if k % 3 == 0:
            segments.append(Segment(point, point, center_m=rng.normal(size=3) * 0.01, radius_m=rng.uniform(0.005, 0.05),
                                    start_angle_rad=rng.uniform(-3, 3), sweep_rad=rng.uniform(-3, 3),
                                    plane=Rotation.random(random_state=1000 + seed + k).as_matrix(),
                                    rise_m=rng.uniform(-0.01, 0.01), **orientation))
        else:
            end = point + rng.normal(size=3) * 0.01
            segments.append(Segment(point, end, rapid=bool(rng.integers(2)), **orientation))
            point = end
    return segments


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_all_segments_at_once_equal_each_segment_on_its_own(seed):
    segments = random_segments(40, seed)
    rng = np.random.default_rng(seed)
    index = np.sort(rng.integers(0, len(segments), 3000))
    s = rng.uniform(0, 1, len(index)) * np.array([segments[k].length_m for k in index])
    s_dot, s_ddot = rng.uniform(0, 2, len(index)), rng.normal(size=len(index))
    together = segments_motion(segments, index, s, s_dot, s_ddot, oriented=True)
    for k in np.unique(index):
        rows = index == k
        alone = segments[k].point(s[rows], s_dot[rows], s_ddot[rows]) + segments[k].orientation(
            s[rows], s_dot[rows], s_ddot[rows])
        for name, value in zip(NAMES + TURNING, alone):
            np.testing.assert_allclose(together[name][rows], value, rtol=0, atol=1e-12)
        assert (together["rapid"][rows] == segments[k].rapid).all()


def test_a_run_is_sampled_along_its_segments():
    run = Run(tuple(random_segments(30, 7, oriented=False)))
    s = np.linspace(0.0, run.length_m, 2000)
    motion = run.along(s, np.ones_like(s), np.zeros_like(s))
    bounds = run.bounds_m
    for k, segment in enumerate(run.segments):  # each sample on its segment, at its distance from the start
        rows = (s >= bounds[k]) & (s < bounds[k + 1]) if k < len(run.segments) - 1 else s >= bounds[k]
        np.testing.assert_allclose(motion["position"][rows], segment.point(s[rows] - bounds[k], s[rows], s[rows])[0],
                                   rtol=0, atol=1e-12)


def per_segment_paper_samples(path, step):
    """The paper law's samples computed segment by segment: each at its feed from its start, t by numpy.linspace,
    a hold a piece of two samples at rest after its segment."""
    t_all, position, velocity, piece, start, number = [], [], [], [], 0.0, 0

    def holds_after(after):
        nonlocal start, number
        for hold in [h for h in path.holds if h.after == after]:
            segment = path.segments[after - 1] if after else path.segments[0]
            at = segment.point(np.array([segment.length_m if after else 0.0]), np.zeros(1), np.zeros(1))[0]
            t_all.append(start + np.array([0.0, hold.duration_s]))
            position.append(np.repeat(at, 2, axis=0))
            velocity.append(np.zeros((2, 3)))
            piece.append(np.full(2, number))
            start, number = start + hold.duration_s, number + 1

    holds_after(0)
    for k, segment in enumerate(path.segments):
        speed = path.speed_m_s(segment)
        duration = segment.length_m / speed
        t = np.linspace(0.0, duration, max(2, int(np.ceil(duration / step)) + 1))
        p, v, _, _ = segment.point(speed * t, np.full_like(t, speed), np.zeros_like(t))
        t_all.append(start + t)
        position.append(p)
        velocity.append(v)
        piece.append(np.full(len(t), number))
        start, number = start + duration, number + 1
        holds_after(k + 1)
    return tuple(np.concatenate(x) for x in (t_all, position, velocity, piece))


@pytest.mark.parametrize("seed", [3, 4])
def test_the_paper_law_samples_every_segment_as_on_its_own(tmp_path, seed):
    rng = np.random.default_rng(seed)
    points = np.cumsum(rng.normal(size=(300, 3)) * 2.0, axis=0)  # mm
    file = tmp_path / "polyline.yaml"
    file.write_text("units: mm\nfeed_m_s: 0.5\ntime_step_s: 0.001\nshape:\n  type: polyline\n  points:\n"
                    + "".join(f"    - [{x:.6f}, {y:.6f}, {z:.6f}]\n" for x, y, z in points))
    path = load_path(file)
    path = dataclasses.replace(path, holds=(Hold(0, 0.1), Hold(5, 0.2), Hold(5, 0.05), Hold(len(path.segments), 0.3)))
    samples = path.sample()
    t, position, velocity, piece = per_segment_paper_samples(path, 0.001)
    np.testing.assert_allclose(samples.t_s, t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(samples.position_m, position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(samples.velocity_m_s, velocity, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(samples.piece, piece)


def circle_polyline(tmp_path, count, feed=0.5):
    angle = np.linspace(0.0, 2 * np.pi, count, endpoint=False)
    file = tmp_path / f"circle{count}.yaml"
    file.write_text(f"units: mm\nfeed_m_s: {feed}\nshape:\n  type: polyline\n  closed: true\n  points:\n"
                    + "".join(f"    - [{40 * np.cos(a):.9f}, {40 * np.sin(a):.9f}]\n" for a in angle))
    return load_path(file)


def test_the_half_turn_symmetry_of_a_long_polyline(tmp_path):
    assert circle_polyline(tmp_path, 20_000).half_turn_symmetric()  # each segment maps onto the opposite one
    assert not circle_polyline(tmp_path, 19_999).half_turn_symmetric()  # an odd count has no opposite segment
    path = circle_polyline(tmp_path, 20_000)
    slower = dataclasses.replace(path.segments[7], feed_ratio=0.5)  # one segment slower: its opposite one is not
    assert not dataclasses.replace(path, segments=(*path.segments[:7], slower, *path.segments[8:])).half_turn_symmetric()
