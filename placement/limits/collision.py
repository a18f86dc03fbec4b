"""Limits of a robot working in a cell: clearance between bodies, and the workpiece region.

- ``collision``: every checked pair of bodies (a robot link or its tool against an obstacle or a
  keep-out zone, or two robot links) keeps its clearance at every sample: the cell's ``margin_m``
  from obstacles, 0 from keep-out zones and between links (see :mod:`placement.cell.scene`). The
  margin is (distance − clearance)/``CLEARANCE_SCALE_M``: negative where the bodies come closer
  than allowed, and inside one another. In a batch of several placements (a search's), distances
  above ``EXACT_BAND_M`` beyond the largest clearance may be cheap lower bounds (bounding
  spheres): never above the exact distance, so a pair they clear is clear, and every distance that
  decides feasibility is exact. A single placement (the one a report details) gets exact
  distances everywhere.
- ``workpiece region``: every tool point inside the cell's ``workpiece_region`` box; the scale
  is the box's side, as for the robot's workspace.

Both apply to a robot equipped with a cell (:func:`placement.cell.tool.equip`).
"""

from __future__ import annotations

from weakref import WeakKeyDictionary

import numpy as np

from placement.batch import EvaluatedBatch
from placement.cell.scene import CollisionScene
from placement.limits.base import LIMITS, Limit, MarginField
from placement.limits.workspace import box_field
from placement.robot.model import Robot

CLEARANCE_SCALE_M = 0.1  # a margin of 1 is 100 mm of clearance beyond what is required
EXACT_BAND_M = 0.05  # distances within this of the largest clearance are exact, not bounds

_SCENES: WeakKeyDictionary[Robot, CollisionScene] = WeakKeyDictionary()


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


class Collision(Limit):
    """Every checked pair of bodies keeps its clearance."""

    def applies_to(self, robot: Robot) -> bool:
        return robot.cell is not None

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        scene = collision_scene(batch.robot)
        k, n = batch.reachable.shape
        if not scene.pairs:
            return []
        threshold = float(scene.required_m.max()) + EXACT_BAND_M if k > 1 else None
        distance = scene.distances(batch.joints.q, threshold_m=threshold).reshape(k, n, -1)
        required = np.broadcast_to(scene.required_m, distance.shape)
        return [MarginField("collision", (distance - required) / CLEARANCE_SCALE_M, distance, required,
                            tuple(f"{a} / {b}" for a, b in scene.pairs), ("m",) * len(scene.pairs))]


class WorkpieceRegion(Limit):
    """Every tool point inside the cell's workpiece region; the scale is the region's side."""

    def applies_to(self, robot: Robot) -> bool:
        return robot.cell is not None and robot.cell.workpiece_region is not None

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        assert batch.robot.cell is not None and batch.robot.cell.workpiece_region is not None  # applies_to
        region = batch.robot.cell.workpiece_region
        return [box_field("workpiece region", batch.tool_position_m, region.min_m, region.max_m)]

LIMITS.add("collision", Collision())
LIMITS.add("workpiece_region", WorkpieceRegion())
