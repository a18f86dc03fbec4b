"""The smallest distance of each pair of shapes along runs of configurations, with few exact distances (compiled).

A run is a placement's samples along its path: from one configuration to the next, every body
moves a little, and so does every distance. An exact distance ``d``, found in one configuration of
a run along coal's normal ``n``, bounds the pair's distance in every other one from below twice:

- by ``d`` less how far the two bodies move in between (less ``LIPSCHITZ_SLACK_M``, well above
  coal's rounding): a signed distance, penetrations too, changes by at most the bodies' moves, and
  a body whose bounding sphere (centre ``c``, radius ``r``) goes from one placement to another moves
  each of its points by at most ``|Δc| + ‖ΔR‖₂·r``, where ``‖ΔR‖₂ = ‖ΔR‖_F/√2`` for the difference
  of two rotations;
- by the gap between the two shapes' projections on ``n`` there
  (:func:`placement.cell.bounds.projection_gap`): ``d`` itself where it was found, for boxes and
  cylinders, and close to the distance wherever the bodies have turned little, as along a path.

The exact distances go by rounds: in each, every chunk of ``CHUNK`` configurations of a run, and
every shape pair whose lowest value there may still be the smallest distance of its group (its
body pair, say) in the run (below the smallest found in the run, to the rounding; at most the
threshold) gets its exact distance there (:func:`lowest_open`, then coal), which raises the bounds
of the rest of its chunk (:func:`record`). Each chunk and shape pair keeps the list of its
configurations that may still need an exact distance: a value only rises and the smallest found
only falls, so a configuration leaves it for good, and each round costs what is left; chunks keep
those lists short on long runs (a dense re-check's whole path) and let them take an exact distance
each per round. A run's smallest distance of a group, where at most the threshold, is then the
same number as with every distance exact, and every other value stays a lower bound at least
that smallest.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from placement.cell.bounds import projection_gap

CHUNK = 128  # configurations of a run whose pending ones are kept in one list
LIPSCHITZ_SLACK_M = 1e-5  # what a bound from a neighbouring exact distance gives up to coal's rounding (m)


@njit(cache=True)
def shape_centres(rotation, origin, centre):
    """(M, G, 3) the centre of every shape's bounding sphere in every configuration (base frame, m), from the shapes'
    frames (rotation (M, G, 3, 3), origin (M, G, 3)) and the centres in those frames (G, 3)."""
    m_count, g_count = origin.shape[0], origin.shape[1]
    out = np.empty((m_count, g_count, 3))
    for m in range(m_count):
        for g in range(g_count):
            for i in range(3):
                out[m, g, i] = (rotation[m, g, i, 0] * centre[g, 0] + rotation[m, g, i, 1] * centre[g, 1]
                                + rotation[m, g, i, 2] * centre[g, 2] + origin[m, g, i])
    return out


@njit(cache=True)
def smallest_exact(values, exact, column_group, groups, starts, chunk_run, runs):
    """(runs, groups) each run's smallest exact value of each group of shape pairs (inf where none is exact).

    Args:
        values: (M, K) the distances of K shape pairs in M configurations: bounds, or exact where ``exact``.
        exact: (M, K) which values are exact.
        column_group: (K,) the group of each shape pair (its body pair, say).
        groups: How many groups.
        starts: (C + 1,) the first configuration of each of C chunks of the runs, then M.
        chunk_run: (C,) the run of each chunk.
        runs: How many runs.
    """
    out = np.full((runs, groups), np.inf)
    for c in range(len(chunk_run)):
        for m in range(starts[c], starts[c + 1]):
            for k in range(values.shape[1]):
                if exact[m, k]:
                    out[chunk_run[c], column_group[k]] = min(out[chunk_run[c], column_group[k]], values[m, k])
    return out


@njit(cache=True, inline="always")
def _pending(value, is_exact, threshold, ceiling):
    """Whether a value may still need its exact distance: not exact, at most the threshold, below the ceiling (the
    run's smallest of its group, to the rounding)."""
    return not is_exact and value <= threshold and value < ceiling


@njit(cache=True)
def pending_rows(values, exact, smallest, column_group, starts, chunk_run, threshold, rounding):
    """Each chunk's configurations that may still need an exact distance, shape pair by shape pair.

    Args:
        values, exact, column_group, starts, chunk_run: As :func:`smallest_exact`.
        smallest: (runs, groups) each run's smallest exact distance of each group so far (inf: none).
        threshold: A value above this needs no exact distance (m).
        rounding: How far below a bound coal's distance may lie (m).

    Returns:
        (M, K) rows: chunk c's list for shape pair k is ``rows[starts[c] : starts[c] + count[c, k], k]``;
        (C, K) count.
    """
    m_count, k_count = values.shape
    rows, count = np.empty((m_count, k_count), np.int64), np.zeros((len(chunk_run), k_count), np.int64)
    for c in range(len(chunk_run)):
        for k in range(k_count):
            ceiling = smallest[chunk_run[c], column_group[k]] + rounding
            for m in range(starts[c], starts[c + 1]):
                if _pending(values[m, k], exact[m, k], threshold, ceiling):
                    rows[starts[c] + count[c, k], k] = m
                    count[c, k] += 1
    return rows, count


@njit(cache=True)
def lowest_open(values, exact, rows, count, smallest, column_group, starts, chunk_run, threshold, rounding):
    """The next exact distances to compute: each chunk's shape pair's lowest value among its pending rows (dropping
    those no longer pending; :func:`pending_rows` for the arguments).

    Returns:
        The configurations (rows), shape pairs (columns) and chunks to compute, configuration by configuration.
    """
    chunks, k_count = count.shape
    chosen, columns, chunk = (np.empty(chunks * k_count, np.int64), np.empty(chunks * k_count, np.int64),
                              np.empty(chunks * k_count, np.int64))
    total = 0
    for c in range(chunks):
        for k in range(k_count):
            ceiling = smallest[chunk_run[c], column_group[k]] + rounding
            kept, lowest, at = 0, np.inf, -1
            for i in range(starts[c], starts[c] + count[c, k]):
                m = rows[i, k]
                if _pending(values[m, k], exact[m, k], threshold, ceiling):
                    rows[starts[c] + kept, k] = m
                    kept += 1
                    if values[m, k] < lowest:
                        lowest, at = values[m, k], m
            count[c, k] = kept
            if at >= 0:
                chosen[total], columns[total], chunk[total] = at, k, c
                total += 1
    order = np.argsort(chosen[:total], kind="mergesort")
    return chosen[:total][order], columns[:total][order], chunk[:total][order]


@njit(cache=True)
def _move(centre_m, rotation, shape, radius, one, other):
    """The most any point of a shape moves from configuration ``one`` to ``other`` (m)."""
    squared = 0.0
    for i in range(3):
        for j in range(3):
            squared += (rotation[one, shape, i, j] - rotation[other, shape, i, j]) ** 2
    shift = 0.0
    for i in range(3):
        shift += (centre_m[one, shape, i] - centre_m[other, shape, i]) ** 2
    return np.sqrt(shift) + np.sqrt(squared / 2.0) * radius[shape]


@njit(cache=True)
def record(values, exact, rows, count, smallest, column_group, starts, chunk_run, threshold, rounding, chosen, columns,
           chunk, found, normal, centre_m, rotation, kind, extent, radius, first, second, slack):
    """Write the exact distances ``found`` at (``chosen``, ``columns``), update each run's smallest, and raise the
    pending values of their chunks' shape pairs to the bounds they give (module docstring), dropping those no
    longer pending.

    Args:
        values, exact, rows, count, smallest, column_group, starts, chunk_run, threshold, rounding: As
            :func:`pending_rows` (``values``, ``exact``, ``rows``, ``count`` and ``smallest`` updated).
        chosen, columns, chunk: The configurations, shape pairs and chunks of the exact distances.
        found: The exact distances (m).
        normal: (len(chosen), 3) the unit normals along which coal found them (base frame).
        centre_m, rotation: (M, G, 3) and (M, G, 3, 3) every shape's bounding-sphere centre and rotation.
        kind, extent, radius: (G,), (G, 3), (G,) the shapes' enclosures (:func:`placement.cell.bounds.shape_supports`).
        first, second: (K,) the shapes of each pair.
        slack: Given up to coal's rounding (m).
    """
    gap = np.empty(3)
    for i_chosen in range(len(chosen)):
        one, k, c, distance = chosen[i_chosen], columns[i_chosen], chunk[i_chosen], found[i_chosen]
        values[one, k], exact[one, k] = distance, True
        group = column_group[k]
        smallest[chunk_run[c], group] = min(smallest[chunk_run[c], group], distance)
        ceiling = smallest[chunk_run[c], group] + rounding
        a, b, n = first[k], second[k], normal[i_chosen]
        kept = 0
        for j in range(starts[c], starts[c] + count[c, k]):
            other = rows[j, k]
            if not exact[other, k] and values[other, k] < distance - slack:
                bound = (distance - slack - _move(centre_m, rotation, a, radius, one, other)
                         - _move(centre_m, rotation, b, radius, one, other))
                for i in range(3):
                    gap[i] = centre_m[other, b, i] - centre_m[other, a, i]
                plane = projection_gap(gap, n[0], n[1], n[2], kind[a], extent[a], radius[a], rotation[other, a],
                                       kind[b], extent[b], radius[b], rotation[other, b])
                values[other, k] = max(values[other, k], bound, plane)
            if _pending(values[other, k], exact[other, k], threshold, ceiling):
                rows[starts[c] + kept, k] = other
                kept += 1
        count[c, k] = kept
