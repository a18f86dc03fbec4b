"""The static scene page as a browser shows it: every triangle of the robot's mesh files drawn, the camera orbiting
about the centre of what is drawn and seeing all of it, and legend colours that no one confuses.

The triangles are read back from the page in headless Chromium (three.js counts what WebGL draws) and compared
with the mesh files as pycollada reads them; the camera is read from the page's orbit controls and compared with
the box three.js computes around the scene's content. Without Chromium the browser tests skip, under CI they fail.
"""

import html
import itertools
import re

import numpy as np
import pinocchio as pin
import pytest
from PIL import Image
from selenium.webdriver.common.by import By

from placement import load_robot
from placement.output.scene import Scene
from placement.robot.packages import description_geometry
from tests.support.browser import chromium
from tests.support.paths import EXAMPLE

WINDOW = (1000, 700)
DRAWN_TRIANGLES = """
var robot = viewer.scene_tree.find(["meshcat", "robot"]).object;
robot.visible = false; viewer.render(); var without = viewer.renderer.info.render.triangles;
robot.visible = true; viewer.render(); return viewer.renderer.info.render.triangles - without;
"""
CAMERA = """
viewer.render();
var T = MeshCat.THREE, box = new T.Box3().setFromObject(viewer.scene_tree.find(["meshcat"]).object);
var corners = [];
for (var i = 0; i < 8; i++) {
  var p = new T.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z);
  corners.push(p.clone().project(viewer.camera).toArray());
}
var position = new T.Vector3(), direction = new T.Vector3();
viewer.camera.getWorldPosition(position); viewer.camera.getWorldDirection(direction);
return {target: viewer.controls.target.toArray(), low: box.min.toArray(), high: box.max.toArray(), corners: corners,
        position: position.toArray(), direction: direction.toArray(), aspect: viewer.camera.aspect};
"""


@pytest.fixture(scope="module")
def browser():
    driver = chromium(WINDOW, "the scene page")
    try:
        yield driver
    finally:
        driver.quit()


def load(browser, scene: Scene, folder) -> None:
    page = folder / "scene.html"
    page.write_text(scene.html("test"))
    browser.get(page.absolute().as_uri())


def triangles_in_mesh_files(robot) -> int:
    """The triangles of every visual's Collada file, each geometry counted as often as the file's scene places it."""
    import collada

    visual = description_geometry(robot, pin.GeometryType.VISUAL)
    total = 0
    for item in visual.geometryObjects:
        assert item.meshPath.lower().endswith(".dae")  # the robots chosen draw Collada files only
        document = collada.Collada(item.meshPath)
        for geometry in document.scene.objects("geometry"):
            for primitive in geometry.primitives():
                if isinstance(primitive, collada.triangleset.BoundTriangleSet):
                    total += len(primitive)
                elif isinstance(primitive, collada.polylist.BoundPolylist):  # polygons: their triangles
                    total += len(primitive.triangleset())
    return total


@pytest.mark.parametrize("name", ["ur5", "panda"])  # example-robot-data's meshes; meshcat's own loader drew 80 % of the UR5's
def test_every_triangle_of_the_mesh_files_is_drawn(browser, tmp_path, name):
    robot = load_robot(name)
    load(browser, Scene(robot), tmp_path)
    expected = triangles_in_mesh_files(robot)
    assert expected > 50_000
    assert browser.execute_script(DRAWN_TRIANGLES) == expected


def test_everything_orbits_about_the_contents_centre_and_the_content_fills_the_view(browser, tmp_path):
    robot = load_robot("ur5")
    scene = Scene(robot)
    scene.add_workspace()
    low, high = np.array(robot.workspace.min_m), np.array(robot.workspace.max_m)
    angle = np.linspace(0, 2 * np.pi, 100)
    scene.add_path("p", (low + high) / 2 + 0.1 * np.column_stack([np.cos(angle), np.sin(angle), 0 * angle]), 0x009E73)
    load(browser, scene, tmp_path)
    browser.find_element(By.CSS_SELECTOR, '#views [data-view="everything"]').click()
    seen = browser.execute_script(CAMERA)
    centre, size = (np.array(seen["low"]) + np.array(seen["high"])) / 2, np.linalg.norm(np.subtract(seen["high"],
                                                                                                   seen["low"]))
    target, position = np.array(seen["target"]), np.array(seen["position"])
    assert np.linalg.norm(target - centre) < 0.01 * size  # the orbit's centre is the content's
    to_target = (target - position) / np.linalg.norm(target - position)
    assert np.dot(to_target, seen["direction"]) > 1 - 1e-9  # and the camera looks at it
    corners = np.array(seen["corners"])[:, :2]
    assert np.all(np.abs(corners) <= 1.0)  # every corner of the content's box is in view
    assert max(np.abs(corners[:, 1]).max(), np.abs(corners[:, 0]).max() * seen["aspect"]) > 0.85  # and it fills it


LABELS = """
var found = {};
document.querySelectorAll("#labels div").forEach(function (d) {
  found[d.textContent] = [parseFloat(d.style.left), parseFloat(d.style.top), d.style.display];
});
["labels", "legend", "views"].forEach(function (id) {  // the screenshot shows the scene alone (no swatch, no text)
  document.getElementById(id).style.display = "none"; });
viewer.render();
return found;
"""


@pytest.mark.parametrize("view", ["workspace", "everything"])
def test_each_named_point_is_labelled_where_the_browser_draws_it(browser, tmp_path, view):
    """The labels follow the points as the page projects them; the spheres are drawn by WebGL: they must coincide."""
    from placement.output.palette import POINT_COLORS

    scene = Scene(load_robot("orthoglide"))
    scene.add_workspace()
    load(browser, scene, tmp_path)
    browser.find_element(By.CSS_SELECTOR, f'#views [data-view="{view}"]').click()
    labels = browser.execute_script(LABELS)
    assert {"O_b", "C", "Q+", "Q-", "x", "y", "z"} <= set(labels)
    shot = tmp_path / "labels.png"
    browser.save_screenshot(str(shot))
    pixels = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    scale = pixels.shape[1] / browser.execute_script("return window.innerWidth")
    for name in ("C", "Q+", "Q-"):  # O_b is behind the platform's centre, drawn over by the path-less scene's axes
        color = POINT_COLORS[name.replace("+", "_plus").replace("-", "_minus")]
        rgb = np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255])
        rows, cols = np.nonzero(np.abs(pixels - rgb).max(axis=-1) <= 12)
        assert len(rows) > 30, f"{name} not drawn"
        drawn = np.array([np.median(cols), np.median(rows)]) / scale
        left, top, display = labels[name]
        assert display == ""
        assert np.linalg.norm(drawn - [left, top]) < 6, f"{name}: label at {left, top}, drawn at {drawn}"


def lab(color: int) -> np.ndarray:
    """CIELAB (D65) of a 0xRRGGBB colour."""
    rgb = np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255]) / 255
    linear = np.where(rgb > 0.04045, ((rgb + 0.055) / 1.055) ** 2.4, rgb / 12.92)
    xyz = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]) @ linear
    t = xyz / [0.95047, 1.0, 1.08883]
    f = np.where(t > 0.008856, np.cbrt(t), 7.787 * t + 16 / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def legend_of(page: str) -> dict[str, int]:
    """Each legend entry with a colour swatch: its label and colour."""
    legend = page.split('<div id="legend">')[1].split("</div>\n")[0]
    return {html.unescape(label): int(color, 16)
            for color, label in re.findall(r'<span style="background:#([0-9a-f]{6})"></span>([^<]*)</div>', legend)}


def assert_apart(legend: dict[str, int]) -> None:
    for (first, a), (second, b) in itertools.combinations(legend.items(), 2):
        assert np.linalg.norm(lab(a) - lab(b)) >= 20, f"{first} #{a:06x} and {second} #{b:06x} look alike"


def test_legend_colours_are_apart_in_a_scene_with_everything(tmp_path):
    from placement import equip, load_cell
    from placement.cli.place import draw
    from placement.evaluation.evaluator import Evaluator
    from placement.path import load_path

    cell = tmp_path / "cell.yaml"
    cell.write_text((EXAMPLE.parent / "cell_orthoglide.yaml").read_text() + "keep_out:\n  corner: {type: sphere, "
                    "radius_m: 0.01, xyz_m: [0.3, 0.3, 0.3]}\n")
    robot = equip(load_robot("orthoglide"), load_cell(cell))
    evaluator = Evaluator(robot, load_path(EXAMPLE))
    details = {"best": evaluator.detail(np.zeros(6)), "worst": evaluator.detail(np.array([0.02, 0, 0, 0.5, 0, 0])),
               "at": evaluator.detail(np.array([-0.02, 0, 0, 0, 0, 0]))}
    scene = Scene(robot)
    scene.add_workspace()
    draw(scene, robot, 0, details, "rect", several=False)
    scene.add_value_points(np.zeros((3, 3)), np.arange(3.0))
    legend = legend_of(scene.html())
    assert {"tool", "obstacles", "keep-out zones", "workspace", "workpiece region", "O_b", "C", "Q+", "Q-",
            "least energy", "most energy", "--at", "energy map (dark: low)"} <= set(legend)
    assert_apart(legend)


def test_several_paths_have_a_colour_each(tmp_path):
    from placement.cli.place import draw
    from placement.evaluation.evaluator import Evaluator
    from placement.path import load_path

    robot = load_robot("orthoglide")
    scene = Scene(robot)
    scene.add_workspace()
    names = [f"rectangle {k}" for k in range(8)]
    for index, name in enumerate(names):
        evaluator = Evaluator(robot, load_path(EXAMPLE))
        draw(scene, robot, index, {"best": evaluator.detail(np.zeros(6)),
                                   "worst": evaluator.detail(np.array([0.01 * index, 0, 0, 0, 0, 0]))}, name, True)
    page = scene.html()
    legend = legend_of(page)
    assert set(names) <= set(legend)  # one entry per path, not one per kind of placement
    assert "solid: least energy, dashed: most energy" in html.unescape(page)
    assert_apart(legend)


def test_a_tube_is_a_ring_of_its_radius_about_each_segment_and_a_point_gives_a_finite_ring():
    """Every vertex lies at the radius from its segment's end, and a zero-length segment (a path's repeated point)
    gives a finite ring there, not NaN vertices that a browser would silently drop."""
    from placement.output.meshes import tube

    segments = np.array([[[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]], [[0.0, 0.0, 0.0], [0.0, 0.0, 0.2]],
                         [[0.05, 0.02, 0.01], [0.05, 0.02, 0.01]]])
    vertices, faces = tube(segments, 0.003, sides=6)
    assert np.isfinite(vertices).all() and faces.max() < len(vertices)
    ends = np.repeat(segments.reshape(-1, 3), 6, axis=0)
    assert np.allclose(np.linalg.norm(vertices - ends, axis=1), 0.003)
