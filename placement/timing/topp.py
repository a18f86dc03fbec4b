"""TOPP-RA's two passes, compiled (numba) and batched over placements and runs.

Time-optimal path parameterisation by reachability analysis (Pham and Pham, IEEE T-RO 2018):
along a path sampled at s_0 < ... < s_N, the state at sample i is x_i = ṡ² and the control on the
interval after it is u_i = s̈, so that x_{i+1} = x_i + 2·Δ_i·u_i with Δ_i = s_{i+1} − s_i. At each
interval the limits are rows a·u + b·x + c ≤ 0 kept at both of its ends (the interpolation
scheme: at the far end x_{i+1} = x_i + 2·Δ_i·u_i, so the far rows are a + 2·Δ_i·b, b, c), and
0 ≤ x_i ≤ x̄_i, the speed bound.

- The backward pass finds the controllable sets K_i = [x_min, x_max]: the squared speeds at s_i
  from which some u keeps every row and reaches K_{i+1}, from K_N = {0} (the run ends at rest).
  Each end is a linear program in (u, x), solved by Seidel's incremental algorithm.
- The forward pass starts at rest and, at each sample, takes the largest u whose next state is in
  K_{i+1} (a linear program in u alone).

This is the ``toppra`` package's own route (``TOPPRA`` with its ``seidel`` solver wrapper) step for
step, with its tolerances, the warm start of its linear programs and the forward pass's guards
(each next state lowered by the lesser of 1e-8 and 0.01 % and clipped into K_{i+1}; a step that
finds no u retried from a state lowered by the lesser of 1e-8 and 0.1 %), so that its answers
are toppra's: the tests check the cycle times against toppra's on known answers and random
paths. What toppra does per step in Python runs here compiled, every run of every placement in
one call; numba caches the machine code on disk.
"""

from __future__ import annotations

import numpy as np
from numba import njit

LP_TINY = 1e-10  # a coefficient below this is zero, and a row violated by less holds (toppra's seidel wrapper)
LP_SMALL = 1e-8  # a parallel row violated by more than this makes a linear program infeasible
VAR_BOUND = 1e8  # |s̈| bound of the linear programs
LP1D_BOUND = 1e10  # the line's own bound in the one-dimensional subproblems (never active at a solution)
START_SLACK = 1e-5  # rest must lie within K_0 widened by this (m²/s²)
BACKOFF = 1e-8  # the forward pass's absolute lowering of a state (m²/s²)
MAX_TRIES = 10  # retries of a forward step from a lowered state
OBJECTIVE_TILT = 1e-9  # weight of s̈ in the backward pass's objectives (toppra's)


@njit(cache=True)
def _lp1d(direction: float, rows: np.ndarray, x: float, low: float, high: float) -> tuple[bool, float]:
    """max direction·t over the rows (3, width) a·t + b·x + c ≤ 0 at a given x, low ≤ t ≤ high.

    Returns:
        Whether it is feasible, and the optimal t.
    """
    lowest, highest = low, high
    for i in range(rows.shape[1]):
        a = rows[0, i]
        if a > LP_TINY:
            t = -(rows[1, i] * x + rows[2, i]) / a
            if t < highest:
                highest = t
        elif a < -LP_TINY:
            t = -(rows[1, i] * x + rows[2, i]) / a
            if t > lowest:
                lowest = t
    if lowest > highest:
        return False, np.nan
    if abs(direction) < LP_TINY or direction < 0:
        return True, lowest
    return True, highest


@njit(cache=True)
def _lp2d(v_u: float, v_x: float, a: np.ndarray, b: np.ndarray, c: np.ndarray, x_high: float, active: np.ndarray,
          order: np.ndarray) -> tuple[bool, float]:
    """max v_u·u + v_x·x over a·u + b·x + c ≤ 0, |u| ≤ VAR_BOUND and 0 ≤ x ≤ x_high, by Seidel's incremental
    algorithm.

    The rows that were active at the previous solution (``active``, updated) go first. ``order`` is scratch
    (rows,).

    Returns:
        Whether it is feasible, and the optimal x.
    """
    rows = len(a)
    low_u, high_u, low_x = -VAR_BOUND, VAR_BOUND, 0.0
    if low_x > x_high:
        return False, np.nan
    best_u, first = (high_u, -2) if v_u > LP_TINY else (low_u, -1)
    best_x, second = (x_high, -4) if v_x > LP_TINY else (low_x, -3)
    if 0 <= active[0] < rows and 0 <= active[1] < rows and active[0] != active[1]:
        order[0], order[1] = active[1], active[0]
        filled = 2
        for i in range(rows):
            if i != active[0] and i != active[1]:
                order[filled] = i
                filled += 1
    else:
        for i in range(rows):
            order[i] = i
    for k in range(rows):
        i = order[k]
        if a[i] * best_u + b[i] * best_x + c[i] < LP_TINY:
            continue
        first = i
        norm = a[i] ** 2 + b[i] ** 2
        origin_u, origin_x = -a[i] * c[i] / norm, -b[i] * c[i] / norm  # the origin projected on the row's line
        tangent_u, tangent_x = -b[i], a[i]
        feasible, t, row = _on_line(origin_u, origin_x, tangent_u, tangent_x, tangent_u * v_u + tangent_x * v_x, k,
                                    a, b, c, order, low_u, high_u, low_x, x_high)
        if not feasible or row < 0:  # infeasible, or unbounded along the line
            return False, np.nan
        best_u, best_x = origin_u + t * tangent_u, origin_x + t * tangent_x
        second = order[row] if row < k else -1 - (row - k)
    active[0], active[1] = first, second
    return True, best_x


@njit(cache=True)
def _on_line(origin_u: float, origin_x: float, tangent_u: float, tangent_x: float, direction: float, k: int,
             a: np.ndarray, b: np.ndarray, c: np.ndarray, order: np.ndarray, low_u: float, high_u: float, low_x: float,
             x_high: float) -> tuple[bool, float, int]:
    """max direction·t along the line origin + t·tangent over the rows ``order[:k]`` and the bounds on u and x
    (rows k to k + 3), within ±LP1D_BOUND: each row bounds t from one side, or holds or fails everywhere along the
    line (parallel to it).

    Returns:
        Whether it is feasible, the optimal t, and the row active there (−1, −2: the line's own bounds).
    """
    lowest, low_row, highest, high_row = -LP1D_BOUND, -1, LP1D_BOUND, -2
    for j in range(k + 4):
        if j == k:
            aj, bj, cj = -1.0, 0.0, low_u
        elif j == k + 1:
            aj, bj, cj = 1.0, 0.0, -high_u
        elif j == k + 2:
            aj, bj, cj = 0.0, -1.0, low_x
        elif j == k + 3:
            aj, bj, cj = 0.0, 1.0, -x_high
        else:
            aj, bj, cj = a[order[j]], b[order[j]], c[order[j]]
        denominator = tangent_u * aj + tangent_x * bj
        at_origin = cj + origin_x * bj + origin_u * aj
        if denominator > LP_TINY:  # t ≤ −at_origin/denominator
            t = -(at_origin / denominator)
            if t < highest:
                highest, high_row = t, j
        elif denominator < -LP_TINY:  # t ≥ −at_origin/denominator
            t = -at_origin / denominator
            if t > lowest:
                lowest, low_row = t, j
        elif at_origin > LP_SMALL:  # parallel to the row's line, and beyond it
            return False, np.nan, 0
    if lowest > highest:
        return False, np.nan, 0
    if abs(direction) < LP_TINY or direction < 0:
        return True, lowest, low_row
    return True, highest, high_row


@njit(cache=True)
def _stage_rows(arc_m: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray, i: int, next_low: float,
                next_high: float, rows: np.ndarray) -> float:
    """The rows (3, 2 + 2·m) of interval i: the next state within [next_low, next_high], then the limits at both
    ends. Returns the interval's length."""
    m, delta = a.shape[1], arc_m[i + 1] - arc_m[i]
    rows[0, 0], rows[1, 0], rows[2, 0] = -2 * delta, -1.0, next_low
    rows[0, 1], rows[1, 1], rows[2, 1] = 2 * delta, 1.0, -next_high
    for j in range(m):
        rows[0, 2 + j], rows[1, 2 + j], rows[2, 2 + j] = a[i, j], b[i, j], c[i, j]
        rows[0, 2 + m + j] = a[i + 1, j] + 2 * delta * b[i + 1, j]
        rows[1, 2 + m + j], rows[2, 2 + m + j] = b[i + 1, j], c[i + 1, j]
    return delta


@njit(cache=True)
def _controllable_sets(arc_m: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray, x_max: np.ndarray,
                       start: int, stop: int, sets: np.ndarray, rows: np.ndarray, order: np.ndarray) -> bool:
    """The backward pass over the run of samples start to stop − 1: ``sets[i]``, the lowest and highest ṡ² at
    sample i from which the run can end at rest, and ``rows[i]`` (3, width), interval i's rows
    (:func:`_stage_rows`), which the forward pass reads. Returns whether every set exists and holds rest at the
    start."""
    upper_active, lower_active = np.zeros(2, dtype=np.int64), np.zeros(2, dtype=np.int64)
    sets[stop - 1, 0], sets[stop - 1, 1] = 0.0, 0.0
    for i in range(stop - 2, start - 1, -1):
        stage = rows[i]
        _stage_rows(arc_m, a, b, c, i, sets[i + 1, 0], sets[i + 1, 1], stage)
        x_high = min(VAR_BOUND, x_max[i])
        feasible_high, highest = _lp2d(-OBJECTIVE_TILT, 1.0, stage[0], stage[1], stage[2], x_high, upper_active, order)
        feasible_low, lowest = _lp2d(OBJECTIVE_TILT, -1.0, stage[0], stage[1], stage[2], x_high, lower_active, order)
        if not (feasible_high and feasible_low):
            return False
        sets[i, 0], sets[i, 1] = max(lowest, 0.0), highest
    return not (START_SLACK < sets[start, 0] or sets[start, 1] + START_SLACK < 0)


@njit(cache=True)
def _greedy_pass(arc_m: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray, sets: np.ndarray, start: int,
                 stop: int, x: np.ndarray, u: np.ndarray, rows: np.ndarray) -> bool:
    """The forward pass over the run of samples start to stop − 1, from rest, on the backward pass's ``rows``:
    ``x[i]``, ṡ² at sample i, and ``u[i]``, the largest s̈ after it whose next state is controllable. Returns whether
    every step found one."""
    x[start] = 0.0
    i, tries = start, 0
    while i < stop - 1:
        delta = arc_m[i + 1] - arc_m[i]
        feasible, step = _lp1d(2 * delta, rows[i], x[i], -VAR_BOUND, VAR_BOUND)
        if not feasible:
            if tries == MAX_TRIES:
                return False
            x[i] = max(x[i] - BACKOFF, 0.999 * x[i])
            tries += 1
            continue
        tries = 0
        u[i] = step
        reached = x[i] + 2 * delta * step
        reached = max(reached - BACKOFF, 0.9999 * reached)
        x[i + 1] = min(sets[i + 1, 1], max(sets[i + 1, 0], reached))
        i += 1
    u[stop - 1] = u[stop - 2]
    return True


def time_placements(arc_m: np.ndarray, run_starts: np.ndarray, held: np.ndarray, a: np.ndarray, b: np.ndarray,
                    c: np.ndarray, x_max: np.ndarray, timed: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The time-optimal timing of K placements, run by run, rest to rest.

    Args:
        arc_m: (N,) each sample's arc length from its run's start (m), increasing along each run.
        run_starts: (R + 1,) the first sample of each run, then N.
        held: (R,) which runs are holds (at rest, not timed here).
        a, b, c: (K, N, m) rows a·s̈ + b·ṡ² + c ≤ 0 at each sample of each placement.
        x_max: (K, N) the speed bound, squared (m²/s²).
        timed: (K,) which placements to time.

    Returns:
        (K, N) ṡ (m/s), (K, N) s̈ on the interval after each sample (the one before, at a run's end), and (K,)
        which placements are timed: those asked for whose every run has a timing. ṡ and s̈ are zero where a
        placement is not timed, and on holds.

    Raises:
        ValueError: A run that is not a hold has fewer than two samples, or arc lengths that do not increase.
    """
    arc_m, run_starts = np.asarray(arc_m, dtype=float), np.asarray(run_starts, dtype=np.int64)
    held = np.asarray(held, dtype=bool)
    for start, stop in zip(run_starts[:-1][~held], run_starts[1:][~held]):
        if stop - start < 2 or (np.diff(arc_m[start:stop]) <= 0).any():
            raise ValueError(f"the run of samples {start} to {stop - 1} needs two samples or more at increasing arc "
                             f"lengths, got {arc_m[start:stop]}")
    timed = np.array(timed, dtype=bool)
    a, b, c, x_max = (np.ascontiguousarray(term, dtype=float) for term in (a, b, c, x_max))
    speed, acceleration = np.zeros(x_max.shape), np.zeros(x_max.shape)
    _time_placements(arc_m, run_starts, held, a, b, c, x_max, timed, speed, acceleration)
    return speed, acceleration, timed


@njit(cache=True)
def _time_placements(arc_m: np.ndarray, run_starts: np.ndarray, held: np.ndarray, a: np.ndarray, b: np.ndarray,
                     c: np.ndarray, x_max: np.ndarray, timed: np.ndarray, speed: np.ndarray,
                     acceleration: np.ndarray) -> None:
    """:func:`time_placements` on checked arrays, into ``speed`` and ``acceleration`` (zeros); ``timed`` is updated."""
    n, width = len(arc_m), 2 + 2 * a.shape[2]
    sets, x, u = np.zeros((n, 2)), np.zeros(n), np.zeros(n)
    rows = np.zeros((n, 3, width))
    order = np.zeros(width, dtype=np.int64)
    for p in range(len(timed)):
        if not timed[p]:
            continue
        for r in range(len(run_starts) - 1):
            start, stop = run_starts[r], run_starts[r + 1]
            if held[r]:
                continue
            if not (_controllable_sets(arc_m, a[p], b[p], c[p], x_max[p], start, stop, sets, rows, order)
                    and _greedy_pass(arc_m, a[p], b[p], c[p], sets, start, stop, x, u, rows)):
                timed[p] = False
                break
            for i in range(start, stop):
                speed[p, i], acceleration[p, i] = np.sqrt(x[i]), u[i]
        if not timed[p]:
            for i in range(n):
                speed[p, i], acceleration[p, i] = 0.0, 0.0
