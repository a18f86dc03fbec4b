"""The tool inside the robot's workspace box, and every sample reachable."""

from __future__ import annotations

import numpy as np

from placement.batch import EvaluatedBatch
from placement.limits.base import LIMITS, Limit, MarginField
from placement.robot.model import Robot


class Workspace(Limit):
    """The tool point inside the sidecar's workspace box; the scale is the box's side."""

    def applies_to(self, robot: Robot) -> bool:
        return robot.sidecar.workspace is not None

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        workspace = batch.robot.sidecar.workspace
        assert workspace is not None  # applies_to
        lo, hi = np.array(workspace.min_m), np.array(workspace.max_m)
        side, tool = hi - lo, batch.tool_position_m
        margin = np.concatenate([(tool - lo) / side, (hi - tool) / side], axis=-1)
        return [MarginField("workspace", margin, np.concatenate([tool, tool], axis=-1),
                            np.broadcast_to(np.concatenate([lo, hi]), margin.shape),
                            ("x min", "y min", "z min", "x max", "y max", "z max"), ("m",) * 6)]


class Reachability(Limit):
    """Every sample has a configuration: margin 1 where it does, −1 where it does not."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        reached = batch.reachable[..., None].astype(float)
        return [MarginField("reachability", 2 * reached - 1, reached, np.ones_like(reached), ("path",), ("",))]


LIMITS.add("workspace", Workspace())
LIMITS.add("reachability", Reachability())
