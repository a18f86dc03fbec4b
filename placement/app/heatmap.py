"""The map drawn in the scene: a heat map on the plane it spans, each cell at the path's origin for its placement.

A map over two translations (x, y or z) spans a plane of the workspace: each cell is drawn where the path's
origin lies at that cell's placement, coloured by its value (cividis: navy at the best end, yellow at the
worst, no colour near the workpiece's magenta; infeasible cells grey). A click on a cell goes to its
placement; the best cell and the current placement are marked. A map over an angle spans no plane of the
scene and is drawn as its figure only.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import viser  # optional dependency: the [app] extra, checked by placement.app

from placement.contract.objective import OBJECTIVES
from placement.placing.transform import VARIABLES, placement_pose
from placement.search.sweep import SweepResult

TRANSLATIONS = ("x", "y", "z")
INFEASIBLE_COLOR = (190, 190, 190)
BEST_COLOR, CURRENT_COLOR = (0, 0, 0), (230, 0, 200)  # the current placement in the workpiece's magenta


def cell_colors(result: SweepResult) -> np.ndarray:
    """(cells, 3) RGB of each cell in the grid's flattened order: cividis from the best value (navy) to the worst
    feasible one (yellow), grey where infeasible."""
    from matplotlib import colormaps  # optional dependency: the [app] extra, checked by placement.app

    sign = OBJECTIVES.get(result.objective).sign
    feasible = result.feasible.ravel()
    score = sign * np.where(feasible, result.value.ravel(), np.nan)  # lower is better
    colors = np.tile(np.array(INFEASIBLE_COLOR, dtype=np.uint8), (feasible.size, 1))
    if feasible.any():
        low, high = np.nanmin(score), np.nanmax(score)
        unit = (score[feasible] - low) / max(high - low, 1e-300)
        colors[feasible] = (np.asarray(colormaps["cividis"](unit))[:, :3] * 255).round().astype(np.uint8)
    return colors


class HeatMap:
    """The latest map in the scene, its cells clickable.

    Args:
        server: The page's viser server.
        plane: The robot's plane (placements are in its frame), or None.
        go_to: Called with a cell's placement (m, rad) when the cell is clicked.
    """

    def __init__(self, server: viser.ViserServer, plane: Any, go_to: Callable[[np.ndarray], None]) -> None:
        self.server, self.plane, self.go_to = server, plane, go_to
        self.result: SweepResult | None = None
        self.placements = np.zeros((0, 6))
        self.origins = np.zeros((0, 3))
        self.steps = np.zeros((2, 3))  # the origin's move from one cell to the next along each grid axis (m)
        self.cells: Any = None
        scene: Any = server.scene
        self.best_mark = scene.add_icosphere("/map/best", radius=0.005, color=BEST_COLOR, visible=False)
        self.current_mark = scene.add_icosphere("/map/current", radius=0.005, color=CURRENT_COLOR, visible=False)

    def show(self, result: SweepResult) -> bool:
        """Draw a map (True), or hide the one drawn if this map is over an angle (False)."""
        self.hide()
        if not set(result.variables) <= set(TRANSLATIONS) or result.value.ndim != 2:
            return False
        self.result, self.placements = result, result.placements()
        self.origins = placement_pose(self.placements, self.plane)[1]
        grid = self.origins.reshape(*result.value.shape, 3)
        self.steps = np.array([grid[1, 0] - grid[0, 0], grid[0, 1] - grid[0, 0]])
        half_u, half_v = self.steps / 2
        square = np.array([-half_u - half_v, half_u - half_v, half_u + half_v, -half_u + half_v])
        count = len(self.placements)
        scene: Any = self.server.scene
        self.cells = scene.add_batched_meshes_simple(
            "/map/cells", square, np.array([[0, 1, 2], [0, 2, 3]]), np.tile([1.0, 0.0, 0.0, 0.0], (count, 1)),
            self.origins, batched_colors=cell_colors(result), side="double", opacity=0.6, lod="off",
            cast_shadow=False, receive_shadow=False)
        self.cells.on_click(lambda event: self.clicked(event.ray_origin, event.ray_direction))
        radius = 0.3 * float(min(np.linalg.norm(self.steps, axis=1)))
        best = result.best()
        if best is not None:
            self.best_mark.radius = radius
            self.best_mark.position = tuple(self.origins[best])
            self.best_mark.visible = True
        self.current_mark.radius = radius
        return True

    def hide(self) -> None:
        if self.cells is not None:
            self.cells.remove()
        self.cells, self.result = None, None
        self.best_mark.visible = self.current_mark.visible = False

    def cell_at(self, ray_origin: np.ndarray, ray_direction: np.ndarray) -> int | None:
        """The cell (its index in the grid's flattened order) a ray through the scene meets, or None."""
        if self.result is None:
            return None
        normal = np.cross(*self.steps)
        along = float(np.dot(ray_direction, normal))
        if abs(along) < 1e-15:
            return None
        point = np.asarray(ray_origin) + np.dot(self.origins[0] - ray_origin, normal) / along * np.asarray(ray_direction)
        (i, j), *_ = np.linalg.lstsq(self.steps.T, point - self.origins[0], rcond=None)
        n_u, n_v = self.result.value.shape
        i, j = int(round(i)), int(round(j))
        return i * n_v + j if 0 <= i < n_u and 0 <= j < n_v else None

    def clicked(self, ray_origin: tuple[float, ...], ray_direction: tuple[float, ...]) -> None:
        """Go to the placement of the cell clicked."""
        cell = self.cell_at(np.asarray(ray_origin, dtype=float), np.asarray(ray_direction, dtype=float))
        if cell is not None:
            self.go_to(self.placements[cell].copy())

    def placement_moved(self, placement: np.ndarray) -> None:
        """Mark the current placement on the map while it lies in the map's plane."""
        if self.result is None:
            return
        off = [k for k, name in enumerate(VARIABLES) if name not in self.result.variables]
        on_plane = np.allclose(placement[off], self.result.fixed[off], rtol=0, atol=1e-12)
        if on_plane:
            self.current_mark.position = tuple(placement_pose(placement, self.plane)[1][0])
        self.current_mark.visible = bool(on_plane)
