"""The compiled TOPP-RA passes against the ``toppra`` package (the reference), on known answers, random rows, the
bounds of real robots along real paths, and degenerate runs."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.contract.limit import path_bounds
from placement.dynamics.path_dynamics import path_dynamics
from placement.path.path_file import Timing
from placement.placing.transform import placed_task
from placement.timing.optimal import bound_rows, speed_bound, time_optimal
from placement.timing.topp import time_placements
from tests.support.toppra_reference import toppra_run


def run_time(arc_m: np.ndarray, speed: np.ndarray) -> float:
    """The time (s) to run the samples at ``speed``, s̈ constant between them (inf if the tool stops midway)."""
    with np.errstate(divide="ignore"):
        return float(np.sum(2 * np.diff(arc_m) / (speed[1:] + speed[:-1])))


def ours(arc_m, a, b, c, x_max):
    """One run timed by the compiled passes, as :func:`toppra_run` answers: (ṡ, s̈) or None."""
    speed, acceleration, timed = time_placements(arc_m, [0, len(arc_m)], [False], a[None], b[None], c[None],
                                                 x_max[None], [True])
    return (speed[0], acceleration[0]) if timed[0] else None


def assert_same_timing(arc_m, a, b, c, x_max):
    """Both routes find a timing or neither does, with the same cycle time (1e-6 relative) and speeds."""
    reference, found = toppra_run(arc_m, a, b, c, x_max), ours(arc_m, a, b, c, x_max)
    assert (reference is None) == (found is None)
    if reference is not None and found is not None:
        assert run_time(arc_m, found[0]) == pytest.approx(run_time(arc_m, reference[0]), rel=1e-6)
        np.testing.assert_allclose(found[0], reference[0], rtol=1e-6, atol=1e-9)
    return found


def acceleration_rows(samples: int, top: float) -> tuple[np.ndarray, ...]:
    """Rows |s̈| ≤ top at each sample."""
    a = np.tile([1.0, -1.0], (samples, 1))
    return a, np.zeros_like(a), np.full_like(a, -top)


@pytest.mark.parametrize("length_m, feed_m_s", [(0.1, 0.3), (0.02, 0.3)])
def test_a_speed_and_an_acceleration_bound_give_the_trapezoid_or_the_triangle(length_m, feed_m_s):
    """Known answers: accelerate at the bound, cruise at the feed (where the run is long enough), brake."""
    top = 2.0
    arc = length_m * np.linspace(0.0, 1.0, 401)
    found = assert_same_timing(arc, *acceleration_rows(len(arc), 0.99 * top), np.full(len(arc), feed_m_s**2))
    assert found is not None
    if length_m >= feed_m_s**2 / top:
        expected = length_m / feed_m_s + feed_m_s / top
    else:
        expected = 2 * np.sqrt(length_m / top)
    assert run_time(arc, found[0]) == pytest.approx(expected, rel=0.01)
    assert found[0].max() <= feed_m_s * (1 + 1e-12) and np.abs(found[1]).max() <= 0.99 * top * (1 + 1e-9)


def random_run(rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    """A run of random samples with random rows: speed bounds (b > 0), accelerations bounded by the speed (a and b
    both), rows that always hold; the rest allowed at rest (c < 0) or, now and then, not; speed caps of 0 now and
    then."""
    n, m = rng.integers(2, 60), rng.integers(0, 7)
    arc = np.concatenate([[0.0], np.cumsum(rng.uniform(0.2, 1.0, n - 1))]) * rng.uniform(0.001, 0.05)
    a = rng.normal(size=(n, m)) * rng.choice([0.0, 1.0], size=m, p=[0.2, 0.8])
    b = rng.normal(size=(n, m)) * rng.choice([0.0, 1.0, 10.0], size=m)
    c = -rng.uniform(0.05, 1.0, (n, m))
    if m and rng.uniform() < 0.1:  # not allowed at rest at one sample
        i, j = rng.integers(n), rng.integers(m)
        a[i, j], c[i, j] = rng.normal(), -c[i, j]
    x_max = rng.uniform(0.1, 2.0, n) ** 2
    if rng.uniform() < 0.1:
        x_max[rng.integers(n)] = 0.0
    return arc, a, b, c, x_max


def test_random_runs_are_timed_as_toppra_times_them():
    rng = np.random.default_rng(7)
    outcomes = {"timed": 0, "none": 0}
    for _ in range(300):
        arc, a, b, c, x_max = random_run(rng)
        found = assert_same_timing(arc, a, b, c, x_max)
        outcomes["timed" if found is not None else "none"] += 1
        if found is not None:  # every row holds at both ends of every interval, 0 ≤ ṡ² ≤ x̄
            x, u = found[0] ** 2, found[1][:-1]
            assert (x <= x_max * (1 + 1e-9) + 1e-12).all()
            slack = 1e-6 * (1 + np.abs(a[:-1]) + np.abs(b[:-1]))
            assert (a[:-1] * u[:, None] + b[:-1] * x[:-1, None] + c[:-1] <= slack).all()
    assert outcomes["timed"] > 200 and outcomes["none"] > 5  # both answers seen


@pytest.mark.parametrize("robot_name, low, high", [
    ("orthoglide", [-0.1, -0.1, -0.1, -1.5, 0, 0], [0.05, 0.05, 0.05, 1.5, 0, 0]),
    ("ur5", None, None),
])
def test_the_bounds_of_a_robot_along_a_path_are_timed_as_toppra_times_them(robot_name, low, high):
    """Random placements of the rectangle: each placement's cycle time under the optimal law is toppra's, run by
    run, to 1e-6."""
    robot = load_robot(robot_name)
    path = dataclasses.replace(load_path("examples/rect.yaml"), timing=Timing(mode="optimal"))
    evaluator = Evaluator(robot, path, EvaluatorSettings(workers=1))
    geometry = evaluator.geometry
    assert geometry is not None
    if low is None:
        low, high = np.r_[robot.workspace.min_m, -3.1, 0, 0], np.r_[robot.workspace.max_m, 3.1, 0, 0]
    placements = np.random.default_rng(3).uniform(low, high, (6, 6))
    task, force = placed_task(robot, geometry.samples, placements)
    joints, reachable, _ = evaluator.solver.solve(task, len(placements))
    reachable = reachable.reshape(len(placements), -1).all(axis=1)
    dynamics = path_dynamics(robot, joints, force, len(placements))
    law = time_optimal(robot, geometry, dynamics, reachable)
    bounds = path_bounds(robot, dynamics)
    speed_max = speed_bound(bounds, geometry.feed_m_s, len(placements))
    a, b, c = bound_rows(bounds, speed_max)
    assert law.timed.sum() >= 4 and a.shape[-1] >= 6
    for k in np.flatnonzero(reachable):
        total = 0.0
        for start, stop in zip(geometry.run_starts[:-1], geometry.run_starts[1:]):
            run = slice(start, stop)
            reference = toppra_run(geometry.arc_m[run], a[k, run], b[k, run], c[k, run], speed_max[k, run] ** 2)
            if reference is None:
                total = np.inf
                break
            total += run_time(geometry.arc_m[run], reference[0])
        assert law.duration_s[k] == pytest.approx(total, rel=1e-6)


def test_a_run_that_cannot_start_or_stop_has_no_timing_in_either_route():
    arc = np.linspace(0.0, 0.01, 20)
    a, b, c = acceleration_rows(len(arc), 1.0)
    c[0, 0] = 0.5  # s̈ ≤ -0.5 at the start: the tool cannot leave rest
    assert assert_same_timing(arc, a, b, c, np.ones(len(arc))) is None
    c[0, 0], c[-1, 1] = -1.0, 0.5  # s̈ ≥ 0.5 at the end: it cannot come to rest
    assert assert_same_timing(arc, a, b, c, np.ones(len(arc))) is None


def test_a_speed_cap_of_zero_stops_the_tool_there_as_in_toppra():
    arc = np.linspace(0.0, 0.01, 41)
    x_max = np.ones(len(arc))
    x_max[20] = 0.0
    found = assert_same_timing(arc, *acceleration_rows(len(arc), 1.0), x_max)
    assert found is not None and found[0][20] == 0.0 and found[0][10] > 0.0
    found = assert_same_timing(arc, *acceleration_rows(len(arc), 1.0), np.zeros(len(arc)))  # never moves
    assert found is not None and (found[0] == 0).all() and run_time(arc, found[0]) == np.inf


@pytest.mark.parametrize("arc", [np.zeros(2), np.array([0.0, 0.01, 0.01, 0.02])])
def test_a_run_without_length_is_refused_by_both_routes(arc):
    rows = acceleration_rows(len(arc), 1.0)
    with pytest.raises(ValueError):
        toppra_run(arc, *rows, np.ones(len(arc)))
    with pytest.raises(ValueError, match="increasing arc lengths"):
        ours(arc, *rows, np.ones(len(arc)))


def test_runs_and_placements_are_timed_apart_and_holds_are_left_at_rest():
    """Two placements of three runs, the middle one a hold: each run as timed alone; a placement with a run
    that has no timing is not timed, and the other still is."""
    rng = np.random.default_rng(1)
    arc = np.concatenate([np.linspace(0.0, 0.02, 30), [0.0, 0.0], np.linspace(0.0, 0.01, 25)])
    starts, held = np.array([0, 30, 32, len(arc)]), np.array([False, True, False])
    a, b, c = (np.stack([term, term]) for term in acceleration_rows(len(arc), 1.5))
    b = b + rng.uniform(0.0, 2.0, b.shape)
    c[1, 40] = 0.3  # the second placement's last run cannot pass sample 40
    x_max = np.full((2, len(arc)), 0.2**2)
    speed, acceleration, timed = time_placements(arc, starts, held, a, b, c, x_max, [True, True])
    assert timed.tolist() == [True, False]
    assert (speed[1] == 0).all() and (speed[0, 30:32] == 0).all() and (acceleration[0, 30:32] == 0).all()
    for start, stop in ((0, 30), (32, len(arc))):
        run = slice(start, stop)
        reference = toppra_run(arc[run], a[0, run], b[0, run], c[0, run], x_max[0, run])
        assert reference is not None
        np.testing.assert_array_equal(speed[0, run], reference[0])
        np.testing.assert_array_equal(acceleration[0, run], reference[1])
