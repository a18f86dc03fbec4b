"""The best and worst placements of the latest Optimise drawn as ghosts beside the live robot.

Each ghost is the robot posed where the pass starts at that placement (the configuration of the
optimum's first sample, as the search evaluated it) with the placed path, faint and in one colour:
the palette's best (bluish green) and worst (vermillion), apart from the live arm's own colours and
the workpiece's magenta. A ghost is drawn once per Optimise result, never during a drag; each has a
checkbox to hide it, and both are cleared when the model's choices change (the optima no longer
answer them).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import viser  # optional dependency: the [app] extra, checked by placement.app

from placement.app.drawing import RobotDrawing
from placement.evaluation.results import PlacementDetail
from placement.output.palette import BEST_COLOR, WORST_COLOR, rgb_255
from placement.robot.model import Robot

GHOST_OPACITY = 0.25  # faint: the live robot stays the one in front
GHOST_COLORS = {"best": BEST_COLOR, "worst": WORST_COLOR}


class Ghosts:
    """The robot and its path at the best and the worst placement found, each with a checkbox to hide it.

    Args:
        server: The page's viser server (the checkboxes go into its current GUI folder).
        robot: The robot.
    """

    def __init__(self, server: viser.ViserServer, robot: Robot) -> None:
        gui: Any = server.gui
        self.server, self.robot = server, robot
        self.toggles = {key: gui.add_checkbox(f"show the {key} ghost", True, visible=False,
                                              hint=f"the robot and its path at the {key} placement, faint")
                        for key in GHOST_COLORS}
        for key, toggle in self.toggles.items():
            toggle.on_update(lambda _, key=key: self._apply(key))
        self.drawings: dict[str, RobotDrawing] = {}  # drawn at the first result, posed again at the next ones
        self.paths: dict[str, Any] = {}
        self.details: dict[str, PlacementDetail] = {}

    def show(self, key: str, detail: PlacementDetail | None) -> None:
        """Draw the ghost at an optimum's placement ("best" or "worst"), or clear it (None)."""
        if detail is None:
            self.details.pop(key, None)
        else:
            self.details[key] = detail
            self._draw(key, detail)
        self.toggles[key].visible = detail is not None
        self._apply(key)

    def clear(self) -> None:
        """Both ghosts gone (the choices changed: the optima no longer answer them)."""
        for key in GHOST_COLORS:
            self.show(key, None)

    def _draw(self, key: str, detail: PlacementDetail) -> None:
        if key not in self.drawings:
            self.drawings[key] = RobotDrawing(self.server, self.robot, f"/ghosts/{key}/robot", color=rgb_255(GHOST_COLORS[key]),
                                              opacity=GHOST_OPACITY, cell=False)
        if detail.reachable:
            self.drawings[key].pose(detail.configuration[0])
        if key in self.paths:
            self.paths[key].remove()
        points = np.asarray(detail.tool_position_m, dtype=float)
        scene: Any = self.server.scene
        self.paths[key] = scene.add_line_segments(f"/ghosts/{key}/path", np.stack([points[:-1], points[1:]], axis=1),
                                                  rgb_255(GHOST_COLORS[key]), thickness=4, thickness_units="screen")

    def _apply(self, key: str) -> None:
        """Show the ghost if it exists and its checkbox is ticked; else hide it."""
        detail = self.details.get(key)
        shown = detail is not None and bool(self.toggles[key].value)
        if key in self.drawings:
            self.drawings[key].visible = shown and detail is not None and detail.reachable
        if key in self.paths:
            self.paths[key].visible = shown
