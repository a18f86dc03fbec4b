"""Collision distances of a robot in a cell, for many configurations at once.

``CollisionScene(robot, cell).distances(q)`` gives, for each configuration and each checked pair
of bodies (see :mod:`placement.collision.pairs`), the signed distance in metres between the two bodies:
positive when apart, negative when they overlap (coal's penetration depth, so that a margin stays
informative inside an obstacle). A body's distance is the smallest over its shapes.

Exact distances are coal's (GJK, EPA for penetration; converged to about 1e-6 m), computed by
Pinocchio, one configuration at a time. Speed: with ``threshold_m``, the compiled tree kinematics
place every shape of every configuration in one call, and a cheap lower bound, compiled too, spares
the exact computation of pairs far apart: the gap between the two shapes' bounding spheres (against
a cell body, from one shape's sphere to the other's bounding box), and, near the threshold, between
their projections on a few axes (:mod:`placement.collision.bounds`). A pair whose bound exceeds the
threshold returns the bound (a value above the threshold, never above the exact distance). Given
runs of configurations (a placement's samples along its path, whose margin is the smallest over
them), only each pair's smallest distance over a run needs to be exact, where at most the
threshold: an exact distance also bounds the pair's distance in the run's other configurations by
how far the bodies move in between, and the exact ones are computed lowest bound first until no
bound is below the smallest found (:mod:`placement.collision.bounds`). The run's smallest is then the same
number as with every distance exact, its other values lower bounds at least that smallest, and
checking ``distance >= required`` with a threshold at least the largest requirement decides
exactly as the exact distances would. Along runs (without ``least``), the shapes are placed at every
few configurations of a run first, and in between only where the joints' motion since could bring
a pair within the threshold; elsewhere a value above the threshold may be the bound that motion
leaves (:func:`placement.collision.bounds.lever_bounds`). A distance does not depend on the other
configurations or pairs computed with it (coal's warm start is off). A scene is not safe to share
between threads.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import coal
import numpy as np
import pinocchio as pin

from placement.cell.cell_file import Cell
from placement.cell.exceptions import CellFileError
from placement.collision.bounds import (
    ANCHOR_STRIDE,
    CHUNK,
    LIPSCHITZ_SLACK_M,
    anchor_rows,
    lever_bounds,
    lowest_open,
    pair_bounds,
    pending_rows,
    record,
    shape_centres,
    shape_supports,
    smallest_exact,
)
from placement.collision.geometry import Body, build_geometry
from placement.collision.pairs import Pair, select_pairs
from placement.kinematics import kernels
from placement.kinematics.kernels import TreeArrays
from placement.kinematics.tree import tree_arrays, unsupported_joints
from placement.robot.exceptions import RobotFileError
from placement.robot.model import Robot

TOUCHING_M = 1e-5  # two bodies closer than this at the reference configuration touch by design (m)
LONGEST_TRAVEL_M = 1e3  # a sliding joint limited beyond this is unlimited: its shapes' moves have no bound (m)
ROUNDING_M = 1e-9  # coal's distance may be this much below a bound equal to the distance (faces parallel) (m)


@dataclass(frozen=True)
class Witnesses:
    """The closest points of every pair in one configuration (base frame).

    Attributes:
        distance_m: (P,) signed distance of each pair (m).
        first_m: (P, 3) the point of the pair's first body nearest the second (m).
        second_m: (P, 3) the point of the pair's second body nearest the first (m); inside the first
            body when they overlap.
    """

    distance_m: np.ndarray
    first_m: np.ndarray
    second_m: np.ndarray


class CollisionScene:
    """The bodies of a robot, its tool and a cell, and the distances between those that must stay apart.

    Args:
        robot: The robot (its tool comes from the cell, else from its sidecar).
        cell: The cell, or None to check the robot against itself only.

    Attributes:
        geometry_model: Every shape (robot links, tool, cell bodies) as a Pinocchio GeometryModel,
            meshes as convex hulls; its collision pairs are the shape pairs checked.
        bodies: The bodies, links first, then the tool, then the cell's.
        pairs: (P,) the checked pairs, as (first body, second body) names: a robot body and a cell
            body, or two robot bodies.
        required_m: (P,) the clearance each pair needs (m): the cell's ``margin_m`` against
            obstacles, 0 against keep-out zones and between robot bodies.
        touching_at_reference: Pairs of robot bodies left out because they touch (or overlap) at
            the reference configuration.
        notices: Lines to tell the user: shapes taken from visuals, convex hulls, pairs left out.

    Raises:
        RobotFileError: A URDF mesh is missing, the sidecar's ``collision.ignore_pairs`` names an
            unknown link, or the robot has joints the compiled kinematics cannot place.
        CellFileError: The cell names unknown bodies in ``ignore``, reuses a link's name, or a
            body fixed to the base is closer to an obstacle than required in every configuration.
    """

    def __init__(self, robot: Robot, cell: Cell | None = None) -> None:
        self._source = (robot, cell)
        geometry = build_geometry(robot, cell)
        self.geometry_model = geometry.geometry_model
        self.bodies = geometry.bodies
        self._model, self._data = robot.model, robot.model.createData()
        self._tree = _shape_tree(robot, self.geometry_model)
        self._enclosures = shape_supports([item.geometry for item in self.geometry_model.geometryObjects])
        self._levers = _shape_levers(robot.model, self._tree, self._enclosures[1], self._enclosures[2])
        candidates = select_pairs(robot, cell, self.bodies)
        self._set_pairs(candidates)
        reference = self._per_pair(self._exact_everywhere(self._checked(robot.reference_q)))[0]
        _check_fixed(cell, self.bodies, candidates, reference)
        moving = [i for i, pair in enumerate(candidates) if self.bodies[pair.first].joint or self.bodies[pair.second].joint]
        touching = [i for i in moving if self.bodies[candidates[i].second].is_robot and reference[i] < TOUCHING_M]
        kept = [candidates[i] for i in moving if i not in touching]
        self._set_pairs(kept)
        self.pairs = tuple((self.bodies[p.first].name, self.bodies[p.second].name) for p in kept)
        self.required_m = np.array([p.required_m for p in kept], dtype=float)
        self.touching_at_reference = tuple((self.bodies[candidates[i].first].name, self.bodies[candidates[i].second].name)
                                           for i in touching)
        self.notices = geometry.notices + _touching_notice(self.touching_at_reference)

    def __reduce__(self) -> tuple:
        """For another process: the scene is built again there from its robot and cell."""
        return CollisionScene, self._source

    def distances(self, q: np.ndarray, threshold_m: float | None = None, run: int = 1, least: bool = False) -> np.ndarray:
        """Signed distances (m) of every pair in every configuration.

        Args:
            q: (M, nq) configurations (m, rad), or one (nq,).
            threshold_m: None for exact distances everywhere; else a pair whose cheap lower bound
                exceeds ``threshold_m`` may return that bound (above ``threshold_m``, at most the
                exact distance) instead of its exact distance.
            run: With ``threshold_m``, the configurations come in runs of this many (the samples of
                one placement's path, say; M is a multiple of it), of which only each pair's smallest
                distance is sure to be exact when it is at most ``threshold_m``; the pair's other
                distances in the run may be lower bounds, at least that smallest one.
            least: With ``threshold_m``, each run's smallest distance over all pairs is exact too, however
                far (where it is reached: the tightest of a report).

        Returns:
            (M, P) distances, pairs in the order of :attr:`pairs`; negative when the bodies overlap.

        Raises:
            ValueError: ``q`` is not finite or has the wrong width, or M is not a multiple of ``run``.
        """
        q = self._checked(q)
        if threshold_m is None:
            return self._per_pair(self._exact_everywhere(q))
        if run < 1 or len(q) % run:
            raise ValueError(f"{len(q)} configurations do not make runs of {run}")
        if run > ANCHOR_STRIDE and not least and self._levers is not None:
            rotation, centre_m, slot, values = self._bounds_from_anchors(q, threshold_m, run)
        else:
            rotation, centre_m = self._placed(q)
            slot, values = np.arange(len(q)), self._bounds(rotation, centre_m, threshold_m)
        self._settle(q, values, rotation, centre_m, slot, threshold_m, run, least)
        return self._per_pair(values)

    def closest(self, q: np.ndarray) -> Witnesses:
        """The exact distance and the two closest points (base frame) of every pair in one configuration.

        Args:
            q: (nq,) a configuration (m, rad).

        Raises:
            ValueError: ``q`` is not finite or has the wrong width.
        """
        self._exact_everywhere(self._checked(q))
        count = len(self.pairs)
        distance, first, second = np.full(count, np.inf), np.zeros((count, 3)), np.zeros((count, 3))
        for pair, result in zip(self._shape_pair, self._geometry_data.distanceResults):
            if result.min_distance < distance[pair]:
                distance[pair] = result.min_distance
                first[pair], second[pair] = result.getNearestPoint1(), result.getNearestPoint2()
        return Witnesses(distance, first, second)

    # ------------------------------------------------------------ internals

    def _checked(self, q: np.ndarray) -> np.ndarray:
        """Configurations as a C-contiguous (M, nq) array of floats."""
        q = np.ascontiguousarray(np.atleast_2d(q), dtype=float)
        if q.ndim != 2 or q.shape[1] != self._model.nq:
            raise ValueError(f"configurations must be (M, {self._model.nq}) or ({self._model.nq},), got shape {q.shape}")
        if not np.isfinite(q).all():
            raise ValueError("configurations must be finite to compute collision distances")
        return q

    def _set_pairs(self, pairs: list[Pair]) -> None:
        """Make the shape pairs of the body pairs (grouped by body pair) the geometry model's collision pairs.

        Coal's warm start from the previous call is turned off: a configuration's distances do not
        depend on what was computed before (it saves about a quarter of the time along a path).
        """
        shape_pairs = [(a, b, p) for p, pair in enumerate(pairs)
                       for a in self.bodies[pair.first].objects for b in self.bodies[pair.second].objects]
        self._shape_first = np.array([a for a, _, _ in shape_pairs], dtype=np.int64)
        self._shape_second = np.array([b for _, b, _ in shape_pairs], dtype=np.int64)
        self._shape_pair = np.array([p for _, _, p in shape_pairs], dtype=np.int64)
        self._pair_starts = np.searchsorted(self._shape_pair, np.arange(len(pairs)))
        self._later_shapes = [(int(k), int(p)) for k, p in enumerate(self._shape_pair) if k not in self._pair_starts]
        self._against_cell = np.array([not self.bodies[pairs[p].second].is_robot for _, _, p in shape_pairs], dtype=bool)
        self.geometry_model.removeAllCollisionPairs()
        for a, b, _ in shape_pairs:
            self.geometry_model.addCollisionPair(pin.CollisionPair(int(a), int(b)))
        self._geometry_data = pin.GeometryData(self.geometry_model)
        for request in self._geometry_data.distanceRequests:
            request.gjk_initial_guess = coal.GJKInitialGuess.DefaultGuess
            with warnings.catch_warnings():  # Pinocchio sets coal's older flag, which coal marks deprecated
                warnings.simplefilter("ignore", DeprecationWarning)
                request.enable_cached_gjk_guess = False

    def _exact_everywhere(self, q: np.ndarray) -> np.ndarray:
        """(M, K) exact distances of every shape pair in configurations q (M, nq), by Pinocchio's loop over pairs."""
        values = np.empty((len(q), len(self._shape_pair)))
        results = self._geometry_data.distanceResults
        for m in range(len(q)):
            pin.computeDistances(self._model, self._data, self.geometry_model, self._geometry_data, q[m])
            values[m] = [result.min_distance for result in results]
        return values

    def _settle(self, q: np.ndarray, values: np.ndarray, rotation: np.ndarray, centre_m: np.ndarray, slot: np.ndarray,
                threshold_m: float, run: int, least: bool) -> None:
        """Exact distances in ``values`` (M, K: bounds of the shape pairs in configurations q, whose shapes are
        placed by ``rotation[slot]`` and ``centre_m[slot]``, :meth:`_placed`) wherever a run's smallest of a body pair at most
        ``threshold_m`` may lie, and, if ``least``, its smallest over all pairs, round by round; the other values
        raised to the bounds that the exact ones give (:mod:`placement.collision.bounds`)."""
        exact = np.zeros(values.shape, dtype=bool)
        kind, _, radius, _, extent = self._enclosures
        runs, offsets = len(q) // run, np.arange(0, run, CHUNK)
        starts = np.append((np.arange(runs)[:, None] * run + offsets).ravel(), len(q))
        chunk_run = np.repeat(np.arange(runs), len(offsets))
        settings = [(self._shape_pair, len(self._pair_starts), threshold_m)]
        if least:
            settings.append((np.zeros_like(self._shape_pair), 1, np.inf))
        for column_group, groups, threshold in settings:
            smallest = smallest_exact(values, exact, column_group, groups, starts, chunk_run, runs)
            rows, count = pending_rows(values, exact, smallest, column_group, starts, chunk_run, threshold, ROUNDING_M)
            taken = np.zeros(count.shape, np.int64)
            while True:
                chosen, columns, chunk, alone = lowest_open(values, exact, rows, count, taken, smallest, column_group,
                                                            starts, chunk_run, threshold, ROUNDING_M)
                if not len(chosen):
                    break
                found, normal = self._exact_at(q, chosen, columns, alone)
                record(values, exact, rows, count, smallest, column_group, starts, chunk_run, chosen, columns, chunk,
                       alone, found, normal, centre_m, rotation, slot, kind, extent, radius, self._shape_first,
                       self._shape_second, LIPSCHITZ_SLACK_M)

    def _exact_at(self, q: np.ndarray, rows: np.ndarray, columns: np.ndarray,
                  normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The exact distances (m) of the shape pairs ``columns`` in the configurations ``rows`` (grouped by
        configuration), and, where ``normals``, the unit normal (base frame) along which coal found each (else 0)."""
        model, data, geometry_model, geometry_data = self._model, self._data, self.geometry_model, self._geometry_data
        found, normal, placed = np.empty(len(rows)), np.zeros((len(rows), 3)), -1
        for i, (m, k, with_normal) in enumerate(zip(rows.tolist(), columns.tolist(), normals.tolist())):
            if m != placed:
                pin.updateGeometryPlacements(model, data, geometry_model, geometry_data, q[m])
                placed = m
            result = pin.computeDistance(geometry_model, geometry_data, k)
            found[i] = result.min_distance
            if with_normal:
                normal[i] = result.normal
        return found, normal

    def _per_pair(self, values: np.ndarray) -> np.ndarray:
        """(M, P) the smallest of each body pair's shape-pair values (M, K) (a gather, then the pairs of several
        shapes: numpy's ``minimum.reduceat`` takes seven times as long)."""
        out = values[:, self._pair_starts]
        for column, pair in self._later_shapes:
            np.minimum(out[:, pair], values[:, column], out=out[:, pair])
        return out

    def _placed(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(M, G, 3, 3) every shape's rotation and (M, G, 3) its bounding-sphere centre (base frame, m) in
        configurations q (M, nq)."""
        rotation, origin = kernels.placements(self._tree, q)
        return rotation, shape_centres(rotation, origin, self._enclosures[1])

    def _bounds_from_anchors(self, q: np.ndarray, threshold_m: float,
                             run: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`_placed` and :meth:`_bounds` at the anchors of runs of ``run`` configurations, then at those of the
        others that the anchors' bounds and the levers do not keep above ``threshold_m``, or at every
        configuration if that is most of them; the rest take the levers' bounds (above the threshold: never
        pending in :meth:`_settle`, which reads no placement of theirs).

        Returns:
            The placements (S, G, 3, 3) and (S, G, 3) of the configurations placed, where each configuration's
            are (M,), and the bounds (M, K).
        """
        assert self._levers is not None  # distances() asks only then
        lever_start, lever_q, lever_m = self._levers
        anchors = anchor_rows(len(q), run, ANCHOR_STRIDE)
        anchor_rotation, anchor_centre_m = self._placed(q[anchors])
        values = np.empty((len(q), len(self._shape_pair)))
        values[anchors] = self._bounds(anchor_rotation, anchor_centre_m, threshold_m)
        rest = lever_bounds(q, values, run, ANCHOR_STRIDE, lever_start, lever_q, lever_m, self._shape_first,
                            self._shape_second, float(threshold_m), LIPSCHITZ_SLACK_M)
        if len(rest) > len(q) / 2:  # most of the configurations near the cell: place them all, anchors again, as
            # one block (joining the anchors' block and the rest's took longer than placing the anchors twice)
            rotation, centre_m = self._placed(q)
            return rotation, centre_m, np.arange(len(q)), self._bounds(rotation, centre_m, threshold_m)
        rest_rotation, rest_centre_m = self._placed(q[rest])
        values[rest] = self._bounds(rest_rotation, rest_centre_m, threshold_m)
        slot = np.full(len(q), -1)
        slot[anchors], slot[rest] = np.arange(len(anchors)), np.arange(len(anchors), len(anchors) + len(rest))
        return (np.concatenate([anchor_rotation, rest_rotation]), np.concatenate([anchor_centre_m, rest_centre_m]),
                slot, values)

    def _bounds(self, rotation: np.ndarray, centre_m: np.ndarray, threshold_m: float) -> np.ndarray:
        """(M, K) lower bounds of the shape pairs' distances with the shapes placed by ``rotation`` and ``centre_m``
        (:meth:`_placed`), refined up to ``threshold_m`` (:func:`placement.collision.bounds.pair_bounds`)."""
        kind, _, radius, box_half, extent = self._enclosures
        return pair_bounds(rotation, centre_m, self._shape_first, self._shape_second, self._against_cell,
                           kind, radius, box_half, extent, float(threshold_m))


def _shape_tree(robot: Robot, geometry_model: pin.GeometryModel) -> TreeArrays:
    """The compiled tree with one frame per shape (its parent joint and placement there)."""
    unsupported = unsupported_joints(robot.model)
    if unsupported:
        raise RobotFileError(robot.urdf_path, "", f"collision checking places links with the compiled tree kinematics, "
                             f"which handles revolute and prismatic joints only, not {', '.join(unsupported[:5])}")
    model = pin.Model(robot.model)
    frames = [model.addFrame(pin.Frame(f"shape:{item.name}", item.parentJoint, item.placement, pin.FrameType.OP_FRAME),
                             False) for item in geometry_model.geometryObjects]
    return tree_arrays(model, frames)


def _shape_levers(model: pin.Model, tree: TreeArrays, centre_m: np.ndarray,
                  radius_m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Each shape's levers (:mod:`placement.collision.bounds`): for each joint that moves it, the most a point of its
    bounding sphere moves per radian or metre of that joint, whatever the configuration, as (G + 1,) starts, then
    the joints' configuration indices and the lengths (m, or 1 for a sliding joint); None if a sliding joint that
    moves a shape has no finite travel."""
    travel = np.maximum(np.abs(model.lowerPositionLimit), np.abs(model.upperPositionLimit))
    starts, indices, lengths = [0], [], []
    for g, joint in enumerate(tree.frame_parent):
        chain = [int(j) for j in model.supports[int(joint)]][1:]
        reach = np.linalg.norm(tree.frame_translation[g] + tree.frame_rotation[g] @ centre_m[g]) + radius_m[g]
        for position in range(len(chain) - 1, -1, -1):  # from the shape's joint back to the root
            j = chain[position]
            if not tree.revolute[j] and not travel[tree.q_index[j]] <= LONGEST_TRAVEL_M:
                return None
            indices.append(tree.q_index[j])
            lengths.append(reach if tree.revolute[j] else 1.0)
            reach += np.linalg.norm(tree.constants[j, :, 10]) + (0.0 if tree.revolute[j] else travel[tree.q_index[j]])
        starts.append(len(indices))
    return np.array(starts, np.int64), np.array(indices, np.int64), np.array(lengths, float)


def _check_fixed(cell: Cell | None, bodies: tuple[Body, ...], pairs: list[Pair], reference: np.ndarray) -> None:
    """A robot body fixed to the base must clear the cell as required: its distance never changes."""
    for pair, distance in zip(pairs, reference):
        if bodies[pair.first].joint or bodies[pair.second].joint or distance >= pair.required_m:
            continue
        assert cell is not None  # only cell bodies pair with robot bodies fixed to the base
        first, second = bodies[pair.first].name, bodies[pair.second].name
        raise CellFileError(cell.path, "ignore", f"'{first}' is fixed to the base and {distance:.4g} m from "
                            f"'{second}' in every configuration, closer than the {pair.required_m:g} m required: "
                            f"move '{second}', or add [{first}, {second}] to ignore if they touch by design")


def _touching_notice(pairs: tuple[tuple[str, str], ...]) -> tuple[str, ...]:
    if not pairs:
        return ()
    return (f"{len(pairs)} pair(s) of robot bodies touch at the reference configuration and are not checked: "
            + ", ".join(f"{a}-{b}" for a, b in pairs),)
