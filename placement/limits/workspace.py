"""The tool inside the robot's workspace box, and every sample reachable."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from placement.evaluation.batch import EvaluatedBatch
from placement.limits.base import LIMITS, Limit, MarginField
from placement.robot.model import Robot


class Workspace(Limit):
    """The tool point inside the robot's workspace box; the scale is the box's side."""

    def applies_to(self, robot: Robot) -> bool:
        return robot.workspace is not None

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        workspace = batch.robot.workspace
        assert workspace is not None  # applies_to
        return [box_field("workspace", batch.tool_position_m, workspace.min_m, workspace.max_m)]


def box_field(kind: str, tool_position_m: np.ndarray, min_m: Sequence[float], max_m: Sequence[float]) -> MarginField:
    """Margins of the tool points (K, N, 3) inside an axis-aligned box of the base frame; the scale is its side."""
    low, high = np.array(min_m, dtype=float), np.array(max_m, dtype=float)
    side, tool = high - low, tool_position_m
    margin = np.concatenate([(tool - low) / side, (high - tool) / side], axis=-1)
    return MarginField(kind, margin, np.concatenate([tool, tool], axis=-1),
                       np.broadcast_to(np.concatenate([low, high]), margin.shape),
                       ("x min", "y min", "z min", "x max", "y max", "z max"), ("m",) * 6)


class Reachability(Limit):
    """Every sample has a configuration: margin 1 where it does, −1 where it does not."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        reached = batch.reachable[..., None].astype(float)
        return [MarginField("reachability", 2 * reached - 1, reached, np.ones_like(reached), ("path",), ("",))]


LIMITS.add("workspace", Workspace())
LIMITS.add("reachability", Reachability())
