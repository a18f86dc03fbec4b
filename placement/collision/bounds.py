"""Lower bounds of the distances between collision shapes, for many configurations at once (compiled).

Cheap bounds, everywhere, from what encloses the shapes. A shape is described by what encloses
it: a sphere (centre in the shape's frame, radius), and, tighter, its support function along a
direction: a box's (a coal box, or a mesh's convex hull by its bounding box in its own frame), a
cylinder's, or the sphere's for any other shape. Two convex shapes are at least as far apart as
the gap between their projections on any line (the gap along a unit axis ``n`` is
``|n·(c_b - c_a)| - s_a(n) - s_b(n)``, the supports measured from the centres:
:func:`projection_gap`); when they overlap, the largest such gap is minus their penetration depth,
so every gap is a lower bound of the signed distance too. The bound of a pair
(:func:`pair_bounds`) is the largest of: the bounding spheres' gap (against a cell body, from the
first shape's sphere to the cell body's bounding box, less the depth of the sphere's centre inside
that box), and, when that does not already exceed the threshold, the gaps along the line of the
centres and the line from the first shape's centre to the nearest point of the second's bounding
box. (The gaps along the shapes' own axes would tighten it further, at twice the cost; the bounds
near an exact distance below do better where it matters.)

Tight bounds, along runs of configurations, near an exact distance. A run is a placement's
samples along its path: from one configuration to the next, every body moves a little, and so
does every distance. An exact distance ``d``, found in one configuration of a run along coal's
normal ``n``, bounds the pair's distance in every other one from below twice:

- by ``d`` less how far the two bodies move in between (less ``LIPSCHITZ_SLACK_M``, well above
  coal's rounding): a signed distance, penetrations too, changes by at most the bodies' moves, and
  a body whose bounding sphere (centre ``c``, radius ``r``) goes from one placement to another moves
  each of its points by at most ``|Δc| + ‖ΔR‖₂·r``, where ``‖ΔR‖₂ = ‖ΔR‖_F/√2`` for the difference
  of two rotations;
- by the gap between the two shapes' projections on ``n`` there: ``d`` itself where it was found,
  for boxes and cylinders, and close to the distance wherever the bodies have turned little, as
  along a path.

So the smallest distance of each pair along a run takes few exact distances, by rounds: in each,
every chunk of ``CHUNK`` configurations of a run, and every shape pair whose lowest value there may
still be the smallest distance of its group (its body pair, say) in the run (below the smallest
found in the run, to the rounding; at most the threshold) gets its exact distance there
(:func:`lowest_open`, then coal), which raises the bounds of the rest of its chunk
(:func:`record`). After ``ONE_BY_ONE`` such rounds, a chunk's shape pair takes all its pending
configurations in one round instead: where the bounds stay far below the distances (between a
serial arm's links, say), each exact distance spares few others, and rounds would cost more than
they spare. Each chunk and shape pair keeps the list of its
configurations that may still need an exact distance: a value only rises and the smallest found only falls, so a configuration
leaves it for good, and each round costs what is left; chunks keep those lists short on long runs
(a dense re-check's whole path) and let them take an exact distance each per round. A run's
smallest distance of a group, where at most the threshold, is then the same number as with every
distance exact, and every other value stays a lower bound at least that smallest. (One file: numba's
cache does not follow calls into other files.)

Coarse bounds, along runs, from the joints' motion (:func:`lever_bounds`), where the others need
not be computed. A point of a shape moves, when joint ``j`` turns by ``Δq``, by at most ``Δq``
times its distance from the joint's origin, and by ``Δq`` when the joint slides; that distance is
at most the lengths of the links in between (and the travel of the sliding joints among them) plus
the shape's sphere's offset and radius, whatever the configuration: a lever ``L[g, j]`` of shape
``g``. So from one configuration of a run to another, shape ``g`` moves by at most
``Σ_j L[g, j]·|Δq_j|`` (along the straight line between them in joint space), and a pair's
distance changes by at most its two shapes' moves. The shapes are placed at every
``ANCHOR_STRIDE``-th configuration of a run and its last (the anchors) first; a configuration in
between whose pairs all keep a bound above the threshold from one of its two anchors takes those
bounds, and the others are placed in turn (all of them at once, where they are most). Along a
path, the shapes far from the cell are placed at the anchors only.
"""

from __future__ import annotations

import coal
import numpy as np
from numba import njit

SPHERE, BOX, CYLINDER = 0, 1, 2  # how a shape's support function is computed
ANCHOR_STRIDE = 8  # the shapes are placed at every this many configurations of a run first
CHUNK = 128  # configurations of a run whose pending ones are kept in one list
ONE_BY_ONE = 4  # exact distances a chunk's shape pair takes one at a time, lowest bound first, before all the rest
LIPSCHITZ_SLACK_M = 1e-5  # what a bound from a neighbouring exact distance gives up to coal's rounding (m)


def shape_supports(shapes: list[coal.CollisionGeometry]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                                    np.ndarray]:
    """What encloses each shape, in its own frame.

    Returns:
        kind (G,): SPHERE, BOX or CYLINDER; centre (G, 3) of its bounding sphere and box (m);
        radius (G,) of that sphere (m); box_half (G, 3): half extents of its bounding box (m);
        extent (G, 3): its support's parameters: a box's half extents, or a cylinder's radius, 0 and
        half length along its z axis (m).
    """
    count = len(shapes)
    kind, centre, radius = np.full(count, SPHERE, dtype=np.int64), np.zeros((count, 3)), np.zeros(count)
    box_half, extent = np.zeros((count, 3)), np.zeros((count, 3))
    for g, shape in enumerate(shapes):
        shape.computeLocalAABB()
        box = shape.aabb_local
        box_half[g] = (np.asarray(box.max_) - np.asarray(box.min_)) / 2
        if isinstance(shape, coal.Sphere):
            radius[g] = shape.radius
        elif isinstance(shape, coal.Cylinder):
            kind[g], radius[g] = CYLINDER, np.hypot(shape.radius, shape.halfLength)
            extent[g] = (shape.radius, 0.0, shape.halfLength)
        elif isinstance(shape, coal.ConvexBase):
            points = np.array(shape.points())
            centre[g] = (points.min(axis=0) + points.max(axis=0)) / 2
            radius[g] = np.linalg.norm(points - centre[g], axis=1).max()
            kind[g], extent[g] = BOX, (points.max(axis=0) - points.min(axis=0)) / 2
        else:
            centre[g] = np.asarray(box.center())
            radius[g] = np.linalg.norm(box_half[g])
            if isinstance(shape, coal.Box):
                kind[g], extent[g] = BOX, np.asarray(shape.halfSide)
    return kind, centre, radius, box_half, extent


@njit(cache=True, inline="always")
def _support(kind, extent, radius, rotation, n0, n1, n2):
    """Half width of a shape's projection on the unit direction (n0, n1, n2) (base frame), from its centre."""
    if kind == SPHERE:
        return radius
    l0 = rotation[0, 0] * n0 + rotation[1, 0] * n1 + rotation[2, 0] * n2  # the direction in the shape's frame
    l1 = rotation[0, 1] * n0 + rotation[1, 1] * n1 + rotation[2, 1] * n2
    l2 = rotation[0, 2] * n0 + rotation[1, 2] * n1 + rotation[2, 2] * n2
    if kind == BOX:
        return extent[0] * abs(l0) + extent[1] * abs(l1) + extent[2] * abs(l2)
    return extent[2] * abs(l2) + extent[0] * np.sqrt(max(0.0, 1.0 - l2 * l2))


@njit(cache=True, inline="always")
def projection_gap(d, n0, n1, n2, kind_a, extent_a, radius_a, rotation_a, kind_b, extent_b, radius_b, rotation_b):
    """Gap between the projections of two shapes on a direction (any length; 0 gives -inf), centres ``d`` apart."""
    norm = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if norm == 0.0:
        return -np.inf
    n0, n1, n2 = n0 / norm, n1 / norm, n2 / norm
    return (abs(d[0] * n0 + d[1] * n1 + d[2] * n2) - _support(kind_a, extent_a, radius_a, rotation_a, n0, n1, n2)
            - _support(kind_b, extent_b, radius_b, rotation_b, n0, n1, n2))


@njit(cache=True)
def pair_bounds(rotation, centre_m, first, second, against_cell, kind, radius, box_half, extent, threshold):
    """(M, K) lower bounds of the distances of K shape pairs in M configurations (see the module).

    Args:
        rotation, centre_m: (M, G, 3, 3) and (M, G, 3): every shape's rotation and bounding-sphere centre in every
            configuration (:func:`shape_centres`).
        first, second: (K,) the shapes of each pair.
        against_cell: (K,) the second shape is a cell body (its bounding box then bounds the sphere's gap).
        kind, radius, box_half, extent: the shapes' enclosures (:func:`shape_supports`).
        threshold: A bound above this is not refined further (m).
    """
    m_count, k_count = rotation.shape[0], len(first)
    out = np.empty((m_count, k_count))
    d, local = np.empty(3), np.empty(3)
    for m in range(m_count):
        for k in range(k_count):  # scalars, not views: the loop runs for every pair of every configuration
            a, b = first[k], second[k]
            d0 = centre_m[m, b, 0] - centre_m[m, a, 0]
            d1 = centre_m[m, b, 1] - centre_m[m, a, 1]
            d2 = centre_m[m, b, 2] - centre_m[m, a, 2]
            if against_cell[k]:  # from the first sphere to the second's bounding box, in the box's frame
                outside, depth = 0.0, np.inf  # how far the centre is outside the box, or inside it
                for i in range(3):
                    local[i] = -(rotation[m, b, 0, i] * d0 + rotation[m, b, 1, i] * d1 + rotation[m, b, 2, i] * d2)
                    outside += max(abs(local[i]) - box_half[b, i], 0.0) ** 2
                    depth = min(depth, box_half[b, i] - abs(local[i]))
                bound = (np.sqrt(outside) if depth < 0.0 else -depth) - radius[a]
            else:
                bound = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) - radius[a] - radius[b]
            if bound <= threshold:
                d[0], d[1], d[2] = d0, d1, d2
                bound = max(bound, _refined(d, local, against_cell[k], kind[a], extent[a], radius[a], rotation[m, a],
                                            kind[b], extent[b], radius[b], rotation[m, b], box_half[b]))
            out[m, k] = bound
    return out


@njit(cache=True, inline="always")
def _refined(d, local, against_cell, kind_a, extent_a, radius_a, ra, kind_b, extent_b, radius_b, rb, box_half_b):
    """The larger gap along the centres' line and towards the second's nearest box point."""
    best = projection_gap(d, d[0], d[1], d[2], kind_a, extent_a, radius_a, ra, kind_b, extent_b, radius_b, rb)
    if against_cell:  # towards the point of the second's box nearest the first's centre (``local``: that centre)
        n0 = n1 = n2 = 0.0
        for i in range(3):
            step = local[i] - min(max(local[i], -box_half_b[i]), box_half_b[i])  # from the box point to the centre
            n0, n1, n2 = n0 + rb[0, i] * step, n1 + rb[1, i] * step, n2 + rb[2, i] * step
        best = max(best, projection_gap(d, n0, n1, n2, kind_a, extent_a, radius_a, ra, kind_b, extent_b, radius_b, rb))
    return best


# ---------------------------------------------------------------- along runs


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
def lowest_open(values, exact, rows, count, taken, smallest, column_group, starts, chunk_run, threshold, rounding):
    """The next exact distances to compute: each chunk's shape pair's lowest value among its pending rows (dropping
    those no longer pending; :func:`pending_rows` for the arguments), or, once it has taken ``ONE_BY_ONE`` of
    them so (``taken`` (C, K), updated), all its pending rows at once (module docstring).

    Returns:
        The configurations (rows), shape pairs (columns) and chunks to compute, configuration by configuration,
        and whether each was taken one by one (its exact distance then raises the bounds of its chunk).
    """
    chunks, k_count = count.shape
    total = 0
    for c in range(chunks):
        for k in range(k_count):
            ceiling = smallest[chunk_run[c], column_group[k]] + rounding
            kept = 0
            for i in range(starts[c], starts[c] + count[c, k]):
                m = rows[i, k]
                if _pending(values[m, k], exact[m, k], threshold, ceiling):
                    rows[starts[c] + kept, k] = m
                    kept += 1
            count[c, k] = kept
            total += min(kept, 1) if taken[c, k] < ONE_BY_ONE else kept
    chosen, columns, chunk, alone = (np.empty(total, np.int64), np.empty(total, np.int64), np.empty(total, np.int64),
                                     np.empty(total, np.bool_))
    total = 0
    for c in range(chunks):
        for k in range(k_count):
            pending = rows[starts[c]:starts[c] + count[c, k], k]
            if not len(pending):
                continue
            one_by_one = taken[c, k] < ONE_BY_ONE
            picked = pending[np.argmin(values[pending, k]):][:1] if one_by_one else pending
            chosen[total:total + len(picked)], columns[total:total + len(picked)] = picked, k
            chunk[total:total + len(picked)], alone[total:total + len(picked)] = c, one_by_one
            total += len(picked)
            taken[c, k] += len(picked)
    order = np.argsort(chosen, kind="mergesort")
    return chosen[order], columns[order], chunk[order], alone[order]


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
def record(values, exact, rows, count, smallest, column_group, starts, chunk_run, chosen, columns, chunk, alone, found,
           normal, centre_m, rotation, slot, kind, extent, radius, first, second, slack):
    """Write the exact distances ``found`` at (``chosen``, ``columns``), update each run's smallest, and, for those
    taken ``alone``, raise the values of their chunks' pending shape pairs to the bounds they give (module
    docstring).

    Args:
        values, exact, rows, count, smallest, column_group, starts, chunk_run: As :func:`pending_rows`
            (``values``, ``exact`` and ``smallest`` updated).
        chosen, columns, chunk, alone: The configurations, shape pairs and chunks of the exact distances, and
            whether each was taken one by one (:func:`lowest_open`).
        found: The exact distances (m).
        normal: (len(chosen), 3) the unit normals along which coal found them (base frame).
        centre_m, rotation: (S, G, 3) and (S, G, 3, 3) every shape's bounding-sphere centre and rotation in the
            configurations placed.
        slot: (M,) where each configuration's shapes are in ``centre_m`` and ``rotation`` (those of the
            configurations pending, at least).
        kind, extent, radius: (G,), (G, 3), (G,) the shapes' enclosures (:func:`shape_supports`).
        first, second: (K,) the shapes of each pair.
        slack: Given up to coal's rounding (m).
    """
    gap = np.empty(3)
    for i_chosen in range(len(chosen)):
        one, k, c, distance = chosen[i_chosen], columns[i_chosen], chunk[i_chosen], found[i_chosen]
        values[one, k], exact[one, k] = distance, True
        group = column_group[k]
        smallest[chunk_run[c], group] = min(smallest[chunk_run[c], group], distance)
        if not alone[i_chosen]:
            continue
        a, b, n, placed = first[k], second[k], normal[i_chosen], slot[one]
        for j in range(starts[c], starts[c] + count[c, k]):
            other = rows[j, k]
            if not exact[other, k] and values[other, k] < distance - slack:
                there = slot[other]
                bound = (distance - slack - _move(centre_m, rotation, a, radius, placed, there)
                         - _move(centre_m, rotation, b, radius, placed, there))
                for i in range(3):
                    gap[i] = centre_m[there, b, i] - centre_m[there, a, i]
                plane = projection_gap(gap, n[0], n[1], n[2], kind[a], extent[a], radius[a], rotation[there, a],
                                       kind[b], extent[b], radius[b], rotation[there, b])
                values[other, k] = max(values[other, k], bound, plane)


# ---------------------------------------------------------------- from the joints' motion


@njit(cache=True)
def anchor_rows(m_count, run, stride):
    """The anchors of runs of ``run`` configurations (M = ``m_count``): every ``stride``-th of each, and its last."""
    out = np.empty(m_count, np.int64)
    count = 0
    for m in range(m_count):
        offset = m % run
        if offset % stride == 0 or offset == run - 1:
            out[count] = m
            count += 1
    return out[:count]


@njit(cache=True)
def _moves(q, one, other, lever_start, lever_q, lever_value, out):
    """How far each shape may move from configuration ``one`` to ``other`` (m), into ``out`` (G,)."""
    for g in range(len(lever_start) - 1):
        total = 0.0
        for e in range(lever_start[g], lever_start[g + 1]):
            total += lever_value[e] * abs(q[other, lever_q[e]] - q[one, lever_q[e]])
        out[g] = total


@njit(cache=True)
def lever_bounds(q, values, run, stride, lever_start, lever_q, lever_value, first, second, threshold, slack):
    """Bounds above ``threshold`` of the configurations between the anchors (module docstring), where every pair has
    one; returns the configurations that do not (their values untouched).

    Args:
        q: (M, nq) the configurations, in runs of ``run``.
        values: (M, K) bounds of the K shape pairs, filled at the anchors (:func:`anchor_rows` of ``stride``).
        lever_start, lever_q, lever_value: The levers, shape by shape (G + 1,), then their joints' configuration
            indices and lengths (m, 1 for a sliding joint), for the shapes of ``lever_start[g]`` to
            ``lever_start[g + 1]``.
        first, second: (K,) the shapes of each pair.
        threshold: The bound every pair of a configuration must exceed (m).
        slack: Given up to the rounding (m).
    """
    m_count, k_count = values.shape
    moves = np.empty((2, len(lever_start) - 1))
    bound = np.empty(k_count)
    rest, count = np.empty(m_count, np.int64), 0
    for before in anchor_rows(m_count, run, stride):
        after = min(before + stride, before - before % run + run - 1)
        hopeless = False  # a pair at most the threshold at both anchors is so in between
        for k in range(k_count):
            hopeless = hopeless or (values[before, k] <= threshold and values[after, k] <= threshold)
        for m in range(before + 1, after):
            kept = not hopeless
            if kept:
                _moves(q, before, m, lever_start, lever_q, lever_value, moves[0])
                _moves(q, after, m, lever_start, lever_q, lever_value, moves[1])
            for k in range(k_count if kept else 0):
                a, b = first[k], second[k]
                bound[k] = max(values[before, k] - moves[0, a] - moves[0, b],
                               values[after, k] - moves[1, a] - moves[1, b]) - slack
                if not bound[k] > threshold:
                    kept = False
                    break
            if kept:
                values[m] = bound
            else:
                rest[count] = m
                count += 1
    return rest[:count]
