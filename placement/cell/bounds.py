"""Cheap lower bounds of the distances between collision shapes, for many configurations at once (compiled).

A shape is described by what encloses it: a sphere (centre in the shape's frame, radius), and,
tighter, its support function along a direction: a box's (a coal box, or a mesh's convex hull by
its bounding box in its own frame), a cylinder's, or the sphere's for any other shape. Two convex
shapes are at least as far apart as the gap between their projections on any line (the gap along
a unit axis ``n`` is ``|n·(c_b - c_a)| - s_a(n) - s_b(n)``, the supports measured from the centres);
when they overlap, the largest such gap is minus their penetration depth, so every gap is a lower
bound of the signed distance too. The bound of a pair is the largest of: the bounding spheres' gap
(against a cell body, from the first shape's sphere to the cell body's bounding box, less the depth
of the sphere's centre inside that box), and,
when that does not already exceed the threshold, the gaps along the line of the centres and the line
from the first shape's centre to the nearest point of the second's bounding box. (The gaps along the
shapes' own axes would tighten it further, at twice the cost: :mod:`placement.cell.runs` tightens the
bounds that matter, near an exact distance, more cheaply.)
"""

from __future__ import annotations

import coal
import numpy as np
from numba import njit

SPHERE, BOX, CYLINDER = 0, 1, 2  # how a shape's support function is computed


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
def pair_bounds(rotation, origin, first, second, against_cell, kind, centre, radius, box_half, extent, threshold):
    """(M, K) lower bounds of the distances of K shape pairs in M configurations (see the module).

    Args:
        rotation, origin: (M, G, 3, 3) and (M, G, 3): every shape's frame in every configuration.
        first, second: (K,) the shapes of each pair.
        against_cell: (K,) the second shape is a cell body (its bounding box then bounds the sphere's gap).
        kind, centre, radius, box_half, extent: the shapes' enclosures (:func:`shape_supports`).
        threshold: A bound above this is not refined further (m).
    """
    m_count, k_count = rotation.shape[0], len(first)
    out = np.empty((m_count, k_count))
    ca, cb, d, local = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for m in range(m_count):
        for k in range(k_count):
            a, b = first[k], second[k]
            ra, rb = rotation[m, a], rotation[m, b]
            for i in range(3):
                ca[i] = ra[i, 0] * centre[a, 0] + ra[i, 1] * centre[a, 1] + ra[i, 2] * centre[a, 2] + origin[m, a, i]
                cb[i] = rb[i, 0] * centre[b, 0] + rb[i, 1] * centre[b, 1] + rb[i, 2] * centre[b, 2] + origin[m, b, i]
                d[i] = cb[i] - ca[i]
            if against_cell[k]:  # from the first sphere to the second's bounding box, in the box's frame
                outside, depth = 0.0, np.inf  # how far the centre is outside the box, or inside it
                for i in range(3):
                    local[i] = -(rb[0, i] * d[0] + rb[1, i] * d[1] + rb[2, i] * d[2])
                    outside += max(abs(local[i]) - box_half[b, i], 0.0) ** 2
                    depth = min(depth, box_half[b, i] - abs(local[i]))
                bound = (np.sqrt(outside) if depth < 0.0 else -depth) - radius[a]
            else:
                bound = np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - radius[a] - radius[b]
            if bound <= threshold:
                bound = max(bound, _refined(d, local, against_cell[k], kind[a], extent[a], radius[a], ra,
                                            kind[b], extent[b], radius[b], rb, box_half[b]))
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
