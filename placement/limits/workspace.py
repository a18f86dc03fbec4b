"""The tool inside the robot's workspace box, and every sample reachable."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, MarginField
from placement.robot.model import Robot


class Workspace(Limit):
    """The tool point inside the robot's workspace box; the scale is the box's side."""

    def applies_to(self, robot: Robot) -> bool:
        return robot.workspace is not None

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        workspace = batch.robot.workspace
        assert workspace is not None  # applies_to
        return [box_field("workspace", batch, workspace.min_m, workspace.max_m)]


def box_field(kind: str, batch: EvaluatedBatch, min_m: Sequence[float], max_m: Sequence[float]) -> MarginField:
    """Margins of the batch's tool points inside an axis-aligned box of the base frame, at its distinct samples
    (:meth:`placement.contract.batch.EvaluatedBatch.distinct`); the scale is the box's side."""
    low, high = np.array(min_m, dtype=float), np.array(max_m, dtype=float)
    side, axes = high - low, np.moveaxis(batch.distinct(batch.tool_position_m), -1, 0)  # (3, K, N)
    value, margin = np.empty((6, *axes.shape[1:])), np.empty((6, *axes.shape[1:]))
    for axis in range(3):  # axis by axis (numpy broadcasts along a last axis of three slowly), each laid out along
        value[axis] = value[3 + axis] = axes[axis]  # the samples (sample_rows says why)
        np.subtract(axes[axis], low[axis], out=margin[axis])
        np.subtract(high[axis], axes[axis], out=margin[3 + axis])
        margin[axis] /= side[axis]
        margin[3 + axis] /= side[axis]
    margin, value = np.moveaxis(margin, 0, -1), np.moveaxis(value, 0, -1)
    return MarginField(kind, margin, value, np.broadcast_to(np.concatenate([low, high]), margin.shape),
                       ("x min", "y min", "z min", "x max", "y max", "z max"), ("m",) * 6, batch.distinct_samples)


class Reachability(Limit):
    """Every sample has a configuration: margin 1 where it does, −1 where it does not."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        reached = batch.distinct(batch.reachable[..., None]).astype(float)
        return [MarginField("reachability", 2 * reached - 1, reached, np.ones_like(reached), ("path",), ("",),
                            batch.distinct_samples)]


LIMITS.add("workspace", Workspace())
LIMITS.add("reachability", Reachability())


def workspace_misfit(min_m: Sequence[float], max_m: Sequence[float], points_m: np.ndarray,
                     phi_range_rad: tuple[float, float],
                     origin_bounds_m: tuple[Sequence[float], Sequence[float]] | None = None) -> str | None:
    """Why a path cannot lie inside the workspace box at any placement turned by phi about Z_p alone (no tilt), or
    None when it may fit (a necessary condition, not a sufficient one).

    Args:
        min_m, max_m: The box's corners in the base frame (m).
        points_m: (N, 3) the path's points in its own frame (m).
        phi_range_rad: The turns about Z_p the search may take.
        origin_bounds_m: Where the search may put the path frame's origin (lower and upper x, y, z in the base
            frame, m), or None for anywhere.

    Returns:
        The path's extent and the box's, in mm, when no turn in the range makes the path's bounding box fit
        (to within 1 % of the path's diameter, more than the step of the turns tried can miss), or when it fits
        only with the origin outside its bounds (a program whose origin lies far from its part); else None.
    """
    side = np.asarray(max_m, dtype=float) - np.asarray(min_m, dtype=float)
    points = np.asarray(points_m, dtype=float)
    extent = np.ptp(points, axis=0)
    slack = 0.01 * float(np.linalg.norm(extent))
    low, high = phi_range_rad
    turns = np.linspace(low, min(high, low + np.pi), 181)  # a half turn covers every bounding box
    cos, sin = np.cos(turns)[:, None], np.sin(turns)[:, None]
    spans = np.stack([np.ptp(cos * points[:, 0] - sin * points[:, 1], axis=1),
                      np.ptp(sin * points[:, 0] + cos * points[:, 1], axis=1)], axis=1)
    fits = np.all(spans <= side[:2] + slack, axis=1) & (extent[2] <= side[2] + slack)
    if fits.any() and origin_bounds_m is None:
        return None
    if fits.any():
        assert origin_bounds_m is not None
        return _origin_misfit(np.asarray(min_m, dtype=float), np.asarray(max_m, dtype=float), points,
                              turns[fits], origin_bounds_m, slack)
    return (f"it does not fit in the workspace at any placement: the path spans {extent[0] * 1e3:.1f} x "
            f"{extent[1] * 1e3:.1f} x {extent[2] * 1e3:.1f} mm and no turn about Z_p brings it within the workspace "
            f"box, {side[0] * 1e3:.1f} x {side[1] * 1e3:.1f} x {side[2] * 1e3:.1f} mm; scale the path down (in the "
            "CAM system) or choose a robot with a larger workspace")


def _origin_misfit(low: np.ndarray, high: np.ndarray, points: np.ndarray, turns: np.ndarray,
                   origin_bounds_m: tuple[Sequence[float], Sequence[float]], slack: float) -> str | None:
    """Why no turn of ``turns`` (each of which fits the path's extent) brings the path within the box [low, high] with
    its origin within its bounds, or None when one may (the origin's range along each axis that keeps the path's
    bounding box inside meets the bounds)."""
    lower, upper = (np.asarray(bound, dtype=float) for bound in origin_bounds_m)
    cos, sin = np.cos(turns)[:, None], np.sin(turns)[:, None]
    turned = np.stack([cos * points[:, 0] - sin * points[:, 1], sin * points[:, 0] + cos * points[:, 1],
                       np.broadcast_to(points[:, 2], (len(turns), len(points)))], axis=2)  # (T, N, 3)
    first, last = np.maximum(lower, low - turned.min(axis=1)), np.minimum(upper, high - turned.max(axis=1))
    if np.all(first <= last + slack, axis=1).any():
        return None
    near, far = points.min(axis=0) * 1e3, points.max(axis=0) * 1e3
    bounds = ", ".join(f"{name} {a * 1e3:.1f} to {b * 1e3:.1f} mm" for name, a, b in zip("xyz", lower, upper))
    return ("it does not fit in the workspace at any placement the search may take: the path lies from "
            f"({near[0]:.1f}, {near[1]:.1f}, {near[2]:.1f}) to ({far[0]:.1f}, {far[1]:.1f}, {far[2]:.1f}) mm in its own "
            f"frame, and the placement's bounds keep its origin within {bounds}; put the program's origin "
            "on the part (in the CAM system), or widen the bounds (--free x=MIN:MAX,...)")
