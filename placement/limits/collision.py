"""Limits of a robot working in a cell: clearance between bodies, and the workpiece region.

- ``collision``: every checked pair of bodies (a robot link or its tool against an obstacle or a
  keep-out zone, or two robot links) keeps its clearance at every sample: the cell's ``margin_m``
  from obstacles, 0 from keep-out zones and between links (see :mod:`placement.collision.distances`). The
  margin is (distance − clearance)/``CLEARANCE_SCALE_M``: negative where the bodies come closer
  than allowed, and inside one another. In a search's batch, distances above ``EXACT_BAND_M``
  beyond the largest clearance (and the margin kept, ``EvaluatorSettings.margin``) may be cheap lower
  bounds (bounding spheres, or how far the joints' motion since a nearby sample can move the
  bodies): never above the exact distance, so a pair they clear is clear, and every
  distance that decides feasibility is exact. A batch that only feasibility is read from (a global
  search's, a tolerance box's: ``feasibility_only``) has no band: only distances up to the clearance
  and margin are exact; a gradient-based polish differentiates the margins near zero, which the band
  keeps exact.
  Since a margin is the smallest over the samples, only each pair's smallest distance along a
  placement's path is computed exactly; at its other samples the batch's distances may be lower
  bounds, at least that smallest one (:meth:`placement.collision.distances.CollisionScene.distances`, in
  runs). Such a batch is also checked only at samples ``CHECK_SPACING_M`` apart along the path
  (and at its ends; the field's rows, each standing for the samples up to the next), and asks
  each pair for ``CHECK_SPACING_M`` more clearance: the bodies near the tool move about that much
  between two checked samples, so the placement it finds keeps the real clearance in between. A
  batch marked exact (a report's, a re-check's) checks every sample against the real clearances,
  in runs too, and also each placement's smallest distance over all pairs is exact however far,
  at the sample where it is reached: the tightest collision that a report shows.
- ``workpiece region``: every tool point inside the cell's ``workpiece_region`` box; the scale
  is the box's side, as for the robot's workspace.

Both apply to a robot equipped with a cell (:func:`placement.robot.equip.equip`).
"""

from __future__ import annotations

import weakref
from weakref import WeakKeyDictionary

import numpy as np

from placement.collision.distances import CollisionScene
from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, MarginField
from placement.limits.workspace import box_field
from placement.robot.model import Robot

CLEARANCE_SCALE_M = 0.1  # a margin of 1 is 100 mm of clearance beyond what is required
EXACT_BAND_M = 0.05  # distances within this of the largest clearance are exact, not bounds
CHECK_SPACING_M = 0.001  # a search's batch checks samples this far apart along the path

_SCENES: WeakKeyDictionary[Robot, CollisionScene] = WeakKeyDictionary()
_CHECKED: dict[int, np.ndarray] = {}  # checked_samples() of each positions array alive, by its id


def collision_scene(robot: Robot) -> CollisionScene:
    """The collision scene of a robot and its cell (built once per robot object)."""
    if robot not in _SCENES:
        _SCENES[robot] = CollisionScene(robot, robot.cell)
    return _SCENES[robot]


def closest_points(robot: Robot, configuration: np.ndarray, pair: str) -> tuple[np.ndarray, np.ndarray]:
    """The two bodies' nearest points (base frame, m) of the pair labelled ``pair`` ("a / b") in one configuration."""
    scene = collision_scene(robot)
    index = [f"{a} / {b}" for a, b in scene.pairs].index(pair)
    witnesses = scene.closest(configuration)
    return witnesses.first_m[index], witnesses.second_m[index]


def checked_samples(position_m: np.ndarray) -> np.ndarray:
    """Indices of the samples a search checks: the first, then each one ``CHECK_SPACING_M`` of path beyond the
    last checked, and the last (positions (N, 3) in the path frame, m; found once per array: an evaluator's
    batches share their path's samples)."""
    key = id(position_m)
    if key not in _CHECKED:
        _CHECKED[key] = _spaced(position_m)
        _CHECKED[key].flags.writeable = False
        weakref.finalize(position_m, _CHECKED.pop, key, None)
    return _CHECKED[key]


def _spaced(position_m: np.ndarray) -> np.ndarray:
    travelled = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(position_m, axis=0), axis=1))])
    marks = np.floor(travelled / CHECK_SPACING_M)
    first_of_mark = np.flatnonzero(np.concatenate([[True], np.diff(marks) > 0]))
    return np.union1d(first_of_mark, [len(position_m) - 1])


def exact_up_to(required_m: np.ndarray, required_margin: float, band_m: float) -> float:
    """The distance (m) up to which a batch's distances are exact: the largest clearance required, plus the
    margin a feasible placement keeps (a share of ``CLEARANCE_SCALE_M``), plus ``band_m``."""
    return float(required_m.max()) + CLEARANCE_SCALE_M * required_margin + band_m


class Collision(Limit):
    """Every checked pair of bodies keeps its clearance."""

    def applies_to(self, robot: Robot) -> bool:
        return robot.cell is not None

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        scene = collision_scene(batch.robot)
        k, n = batch.reachable.shape
        if not scene.pairs:
            return []
        required = scene.required_m
        band = 0.0 if batch.feasibility_only else EXACT_BAND_M
        if batch.exact:
            threshold = exact_up_to(required, batch.required_margin, band)
            distance = scene.distances(batch.joints.q, threshold_m=threshold, run=n, least=True).reshape(k, n, -1)
            checked = None
        else:
            required = required + CHECK_SPACING_M
            checked = checked_samples(batch.samples.position_m)
            q = batch.joints.q.reshape(k, n, -1)[:, checked].reshape(k * len(checked), -1)
            threshold = exact_up_to(required, batch.required_margin, band)
            distance = scene.distances(q, threshold_m=threshold, run=len(checked)).reshape(k, len(checked), -1)
        required = np.broadcast_to(required, distance.shape)
        return [MarginField("collision", (distance - required) / CLEARANCE_SCALE_M, distance, required,
                            tuple(f"{a} / {b}" for a, b in scene.pairs), ("m",) * len(scene.pairs), checked)]


class WorkpieceRegion(Limit):
    """Every tool point inside the cell's workpiece region; the scale is the region's side."""

    def applies_to(self, robot: Robot) -> bool:
        return robot.cell is not None and robot.cell.workpiece_region is not None

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        assert batch.robot.cell is not None and batch.robot.cell.workpiece_region is not None  # applies_to
        region = batch.robot.cell.workpiece_region
        return [box_field("workpiece region", batch, region.min_m, region.max_m)]


LIMITS.add("collision", Collision())
LIMITS.add("workpiece_region", WorkpieceRegion())
