"""The workbench's drawing of a robot and its cell (placement.app.drawing), without a browser."""

from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("viser")
pytest.importorskip("trimesh")

from placement import load_robot  # noqa: E402
from placement.app.drawing import CELL_OPACITY, RobotDrawing  # noqa: E402
from placement.cell.cell_file import load_cell  # noqa: E402
from placement.limits.collision import collision_scene  # noqa: E402
from placement.robot.equip import equip  # noqa: E402
from tests.support.paths import EXAMPLES  # noqa: E402


class _Recorder:
    """Stands for viser's scene: records each shape added under its name, with its opacity."""

    def __init__(self) -> None:
        self.added: dict[str, float] = {}

    def __getattr__(self, method: str):
        def add(name, *args, opacity=1.0, **kwargs):
            self.added[name] = opacity
            return SimpleNamespace(position=None, wxyz=None)
        return add


def test_a_robot_in_a_cell_is_drawn_with_the_cells_shapes():
    """Each obstacle and keep-out shape of the cell is drawn (was: the collision scene shadowed viser's, and any robot
    with a cell or a tool failed to open with 'CollisionScene' object has no attribute 'add_box'), at its checked
    opacity, and posed."""
    robot = equip(load_robot("ur5"), load_cell(EXAMPLES / "cell_ur5_table_wall.yaml"))
    recorder = _Recorder()
    drawing = RobotDrawing(SimpleNamespace(scene=recorder), robot)
    checked = collision_scene(robot)
    cell_objects = sum(len(body.objects) for body in checked.bodies if body.kind != "link")
    assert cell_objects > 0
    alone = RobotDrawing(SimpleNamespace(scene=_Recorder()), load_robot("ur5"))
    assert len(drawing.handles) == len(alone.handles) + cell_objects
    assert set(CELL_OPACITY.values()) & set(recorder.added.values()) - {1.0}
    drawn = {k for k, _ in drawing.handles}
    assert all(k in drawn for k in range(len(alone.handles), len(drawing.handles)))
    assert np.all(np.isfinite([handle.position for _, handle in drawing.handles]))
