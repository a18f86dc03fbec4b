"""3-D scenes in the browser (meshcat): the robot, its workspace, placed paths and maps of an objective.

A :class:`Scene` draws the robot from its URDF visuals (Pinocchio's meshcat visualiser), with its
tool body and its cell's obstacles and keep-out zones as they are checked for collisions, the
workspace box as a wireframe with its named points, placed paths as coloured lines, a map
as coloured points, and animates the robot along a path. Its camera looks at the centre of the
box that holds everything drawn (the robot at its reference configuration: every frame origin and
the bounding box of every visual; the workspace; paths and map points), from far enough that the
sphere around that box fits meshcat's default camera, 75° vertical field of view (a window wider
than tall sees at least as much across). It records the scene and writes a
self-contained HTML page that opens in a browser with no server and no network; :class:`PageServer`
serves that page on this machine (loopback only, unless asked otherwise). Everything that comes
from input files (path names, point names) is escaped in the page.
"""

from __future__ import annotations

import base64
import html
import http.server
import shutil
import subprocess
import tempfile
import threading
from pathlib import Path

import matplotlib
import meshcat
import meshcat.geometry as g
import numpy as np
import pinocchio as pin
import umsgpack
from meshcat.animation import Animation
from meshcat.servers.tree import SceneTree, find_node, walk
from pinocchio.visualize import MeshcatVisualizer

from placement.cell.geometry import package_dirs
from placement.kinematics.batched import jump_steps
from placement.limits.collision import collision_scene
from placement.robot.exceptions import RobotFileError
from placement.robot.model import Robot
from placement.search.space import box_corners

VIEWER_SCRIPT = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
POINT_COLORS = {"O_b": 0x1F77B4, "C": 0x2CA02C, "Q_plus": 0xD62728, "Q_minus": 0xFF7F0E}
BEST_COLOR, WORST_COLOR, AT_COLOR, CUBE_COLOR = 0x00B050, 0xE00000, 0x0070FF, 0x303030
CELL_COLORS = {"tool": (0x505A64, "tool"), "obstacle": (0xB08850, "obstacles"), "keep_out": (0xFF4040, "keep-out zones")}
CELL_OPACITY = {"tool": 1.0, "obstacle": 0.5, "keep_out": 0.12}
NEAREST_COLOR, REGION_COLOR = 0xFF00FF, 0x2080C0
ANIMATION_FPS = 30
CAMERA_DIRECTION = np.array([-0.45, -0.45, 0.35]) / np.linalg.norm([-0.45, -0.45, 0.35])  # from the target
CAMERA_FOV_DEG = 75.0  # meshcat's default camera: PerspectiveCamera(75, aspect, 0.01, 100), vertical
CAMERA_MARGIN = 1.1  # the fitted sphere fills at most 1/1.1 of the view's half-height
CAMERA_NEAR_M = 0.01  # meshcat's near clipping distance


class _RecordingWindow:
    """Stands in for meshcat's server: keeps the scene tree so it can be written as a page."""

    def __init__(self) -> None:
        self.tree = SceneTree()

    def send(self, command) -> None:
        data = command.lower()
        node = find_node(self.tree, [p for p in data["path"].split("/") if p])
        packed = umsgpack.packb(data)
        if data["type"] == "set_object":
            node.object, node.properties = packed, []
        elif data["type"] == "set_transform":
            node.transform = packed
        elif data["type"] == "set_property":
            node.properties.append(packed)
        elif data["type"] == "set_animation":
            node.animation = packed
        elif data["type"] == "delete":
            parts = [p for p in data["path"].split("/") if p]
            parent = find_node(self.tree, parts[:-1])
            parent.pop(parts[-1], None)

    def commands(self) -> list[bytes]:
        packed = []
        for node in walk(self.tree):
            packed += ([node.object] if node.object else []) + node.properties
            packed += [item for item in (node.transform, node.animation) if item]
        return packed


class Scene:
    """A meshcat scene of one robot.

    Args:
        robot: The robot to draw.
    """

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.window = _RecordingWindow()
        self.viewer = meshcat.Visualizer(window=self.window)
        self.legend: list[tuple[str, int]] = [("robot", 0x999999)]
        self.results: list[str] = []  # lines of the page's results panel (add_results)
        try:
            visual = pin.buildGeomFromUrdf(robot.model, str(robot.urdf_path), pin.GeometryType.VISUAL,
                                           package_dirs=package_dirs(robot))
        except ValueError as error:  # a mesh the URDF names is not there
            raise RobotFileError(robot.urdf_path, "", f"cannot draw the robot: {str(error)[:200]}") from None
        self.drawn_points_m: list[np.ndarray] = [robot_points(robot, visual)]  # the camera frames the robot, not the cell
        if robot.cell is not None or robot.tool is not None:
            self._add_cell_shapes(visual)
        self.visualizer = MeshcatVisualizer(robot.model, pin.GeometryModel(), visual)
        self.visualizer.initViewer(viewer=self.viewer)
        self.visualizer.loadViewerModel(rootNodeName="robot")
        self.visualizer.display(robot.reference_q)
        self.viewer["/Grid"].set_property("visible", False)
        self.viewer["/Background"].set_property("top_color", [1.0, 1.0, 1.0])
        self.viewer["/Background"].set_property("bottom_color", [0.82, 0.84, 0.88])
        self.camera_m: tuple[np.ndarray, np.ndarray] = (np.zeros(3), CAMERA_DIRECTION)
        self.fit_camera()

    def _add_cell_shapes(self, visual: pin.GeometryModel) -> None:
        """The tool body (moving with its joint) and the cell's obstacles and keep-out zones, as they are checked."""
        scene = collision_scene(self.robot)
        for body in scene.bodies:
            if body.kind == "link":
                continue
            color, label = CELL_COLORS[body.kind]
            for index in body.objects:
                item = scene.geometry_model.geometryObjects[index].copy()
                item.meshColor = np.array([((color >> s) & 255) / 255 for s in (16, 8, 0)] + [CELL_OPACITY[body.kind]])
                visual.addGeometryObject(item)
            if all(entry[0] != label for entry in self.legend):
                self.legend.append((label, color))

    def add_nearest(self, name: str, first_m: np.ndarray, second_m: np.ndarray, label: str) -> None:
        """The nearest points of two bodies (base frame, m), joined by a line, with the label in the legend."""
        points = np.array([first_m, second_m], dtype=np.float32).T
        self.viewer[f"nearest/{name}/line"].set_object(
            g.Line(g.PointsGeometry(points), g.LineBasicMaterial(color=NEAREST_COLOR, linewidth=3)))
        for k, point in enumerate((first_m, second_m)):
            self.viewer[f"nearest/{name}/end_{k}"].set_object(g.Sphere(0.004), g.MeshLambertMaterial(color=NEAREST_COLOR))
            self.viewer[f"nearest/{name}/end_{k}"].set_transform(pin.SE3(np.eye(3), np.asarray(point)).homogeneous)
        self.legend.append((label, NEAREST_COLOR))

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        """The box holding everything drawn so far: lowest and highest corners (m, base frame)."""
        points = np.vstack(self.drawn_points_m)
        return points.min(axis=0), points.max(axis=0)

    def fit_camera(self) -> None:
        """Aim the camera at the centre of :meth:`extent`, far enough that the whole box is in view."""
        low, high = self.extent()
        radius = max(float(np.linalg.norm(high - low)) / 2, CAMERA_NEAR_M)
        distance = CAMERA_MARGIN * radius / np.sin(np.radians(CAMERA_FOV_DEG / 2))
        self.look_at((low + high) / 2, CAMERA_DIRECTION * distance)

    def look_at(self, target_m: np.ndarray, offset_m: np.ndarray) -> None:
        """Point the camera at ``target_m`` from ``target_m + offset_m`` (base frame, Z up; kept in ``camera_m``)."""
        target = np.asarray(target_m, dtype=float)
        self.camera_m = (target, target + offset_m)
        self.viewer["/Cameras/default"].set_transform(pin.SE3(np.eye(3), target).homogeneous)
        dx, dy, dz = (float(v) for v in offset_m)  # the camera node is Y-up (three.js): (x, y, z) -> (x, z, -y)
        self.viewer["/Cameras/default/rotated/<object>"].set_property("position", [dx, dz, -dy])

    def add_workspace(self) -> None:
        """The workspace box as a wireframe, and its named points as coloured spheres."""
        workspace = self.robot.workspace
        if workspace is None:
            return
        low, high = np.array(workspace.min_m), np.array(workspace.max_m)
        self._wire_box("workspace/cube", low, high, CUBE_COLOR, "workspace")
        region = self.robot.cell.workpiece_region if self.robot.cell is not None else None
        if region is not None:
            self._wire_box("cell/workpiece_region", np.array(region.min_m), np.array(region.max_m), REGION_COLOR,
                           "workpiece region")
        radius = 0.03 * float(np.max(high - low))
        for name, point in workspace.points_m.items():
            color = POINT_COLORS.get(name, 0x7F7F7F)
            self.viewer[f"workspace/{name}"].set_object(g.Sphere(radius), g.MeshLambertMaterial(color=color))
            self.viewer[f"workspace/{name}"].set_transform(pin.SE3(np.eye(3), np.array(point)).homogeneous)
            self.legend.append((name.replace("_plus", "+").replace("_minus", "-"), color))

    def _wire_box(self, name: str, low: np.ndarray, high: np.ndarray, color: int, label: str) -> None:
        """An axis-aligned box of the base frame (m) as a wireframe, framed by the camera."""
        corners = box_corners(low, high)
        self.drawn_points_m.append(corners)
        edges = [(i, j) for i in range(8) for j in range(i + 1, 8) if bin(i ^ j).count("1") == 1]
        segments = np.array([corners[k] for edge in edges for k in edge]).T
        self.viewer[name].set_object(
            g.LineSegments(g.PointsGeometry(segments), g.LineBasicMaterial(color=color, linewidth=2)))
        self.legend.append((label, color))

    def add_path(self, name: str, tool_position_m: np.ndarray, color: int, label: str | None = None,
                 width_m: float = 0.006) -> None:
        """A placed path through its tool points (base frame, m), drawn as a line of dots; the gap a skipped rapid
        leaves (a jump, as the kinematics finds it) is not drawn."""
        positions = np.asarray(tool_position_m, dtype=float).reshape(-1, 3)
        self.drawn_points_m.append(positions)
        points = positions.T.astype(np.float32)
        rgb = np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255], dtype=np.float32)[:, None] / 255
        steps = np.linalg.norm(np.diff(positions, axis=0), axis=1)
        drawn = np.setdiff1d(np.arange(len(steps)), jump_steps(steps)) if len(steps) else np.zeros(0, dtype=int)
        pairs = points[:, np.stack([drawn, drawn + 1], axis=1).reshape(-1)]
        self.viewer[f"paths/{name}/line"].set_object(
            g.LineSegments(g.PointsGeometry(pairs), g.LineBasicMaterial(color=color)))
        self.viewer[f"paths/{name}/dots"].set_object(
            g.PointCloud(points, np.repeat(rgb, points.shape[1], axis=1), size=width_m))
        if label and all(entry[0] != label for entry in self.legend):
            self.legend.append((label, color))

    def add_value_points(self, points_m: np.ndarray, value: np.ndarray, subject: str = "energy",
                         size_m: float = 0.004) -> None:
        """Placement origins coloured by an objective's value (viridis: dark = low)."""
        self.drawn_points_m.append(np.asarray(points_m, dtype=float).reshape(-1, 3))
        span = np.ptp(value) or 1.0
        colors = matplotlib.colormaps["viridis"]((value - value.min()) / span)[:, :3]
        self.viewer["value_map"].set_object(g.PointCloud(np.asarray(points_m, dtype=np.float32).T,
                                                         colors.T.astype(np.float32), size=size_m))
        self.legend.append((f"{subject} map (dark: low)", 0x440154))

    def animate(self, q: np.ndarray, t_s: np.ndarray, repetitions: int = 1000) -> None:
        """Play the robot along joint configurations ``q`` (N, nq) sampled at times ``t_s``."""
        frames = np.arange(0.0, t_s[-1] + 1e-12, 1.0 / ANIMATION_FPS)
        index = np.clip(np.searchsorted(t_s, frames), 0, len(t_s) - 1)
        animation = Animation(default_framerate=ANIMATION_FPS)
        viewer = self.visualizer.viewer
        try:
            for frame, k in enumerate(index):
                with animation.at_frame(viewer, frame) as frame_viewer:
                    self.visualizer.viewer = frame_viewer  # record the placements into the frame
                    self.visualizer.display(q[k])
        finally:
            self.visualizer.viewer = viewer
        self.viewer.set_animation(animation, play=True, repetitions=repetitions)

    def add_results(self, lines: list[str]) -> None:
        """Lines of text for the page's results panel (the answer beside the picture: energies, placements, gain)."""
        self.results.extend(lines)

    def html(self, title: str = "placement") -> str:
        """A self-contained page of the recorded scene (three.js viewer inlined, no network), the camera fitted."""
        self.fit_camera()
        commands = "".join(
            f'fetch("data:application/octet-binary;base64,{base64.b64encode(c).decode()}").then(r => r.arrayBuffer())'
            ".then(b => viewer.handle_command_bytearray(new Uint8Array(b)));\n"
            for c in self.window.commands())
        legend = "".join(f'<div><span style="background:#{color:06x}"></span>{html.escape(name)}</div>'
                         for name, color in self.legend)
        results = "".join(f"<div>{html.escape(line)}</div>" for line in self.results)
        return _PAGE.format(title=html.escape(title), script=VIEWER_SCRIPT.read_text(), commands=commands,
                            legend=legend, results=f'<div id="results">{results}</div>' if results else "")


class PageServer:
    """Serves one page over HTTP from a background thread, on loopback unless another host is given.

    Args:
        page: The HTML text.
        host: Address to listen on (127.0.0.1: this machine only).
        port: Port (0: any free one).
    """

    def __init__(self, page: str, host: str = "127.0.0.1", port: int = 0) -> None:
        body = page.encode("utf-8")

        class Handler(http.server.BaseHTTPRequestHandler):
            def do_GET(self) -> None:  # noqa: N802 (the http.server name)
                self.send_response(200)
                self.send_header("Content-Type", "text/html; charset=utf-8")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

            def log_message(self, format: str, *args: object) -> None:  # quiet
                pass

        self.server = http.server.ThreadingHTTPServer((host, port), Handler)
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    @property
    def url(self) -> str:
        """The page's address."""
        host, port = str(self.server.server_address[0]), self.server.server_address[1]
        return f"http://{host if ':' not in host else f'[{host}]'}:{port}/"

    def close(self) -> None:
        """Stop serving."""
        self.server.shutdown()
        self.server.server_close()


BROWSERS = ("chromium", "chromium-browser", "google-chrome")
BROWSER_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
                 "--proxy-server=127.0.0.1:9"]  # any network request fails: the page must be self-contained


def find_browser() -> str | None:
    """A Chromium-family browser on this machine, if any."""
    return next((shutil.which(name) for name in BROWSERS if shutil.which(name)), None)


def screenshot(page: Path, image: Path, size: tuple[int, int] = (1000, 700), wait_ms: int = 3000) -> bool:
    """Render ``page`` in headless Chromium (software WebGL) and save a PNG; False if no browser.

    Args:
        page: A self-contained HTML file.
        image: The PNG to write.
        size: Window width and height in pixels.
        wait_ms: Virtual time given to the page (the animation plays meanwhile).
    """
    browser = find_browser()
    if browser is None:
        return False
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run([browser, *BROWSER_FLAGS, f"--window-size={size[0]},{size[1]}", f"--virtual-time-budget={wait_ms}",
                        f"--user-data-dir={profile}", f"--screenshot={Path(image).absolute()}", Path(page).absolute().as_uri()],
                       capture_output=True, timeout=180, check=False)
    return Path(image).is_file()


def robot_points(robot: Robot, visual: pin.GeometryModel) -> np.ndarray:
    """Points that bound the robot at its reference configuration (m, base frame).

    Every frame's origin, and the 8 corners of each visual's local bounding box (mesh scale
    applied) where the geometry can compute one.
    """
    model, q = robot.model, robot.reference_q
    data, geometry_data = model.createData(), visual.createData()
    pin.framesForwardKinematics(model, data, q)
    pin.updateGeometryPlacements(model, data, visual, geometry_data)
    points = [np.array([frame.translation for frame in data.oMf])]
    for item, placement in zip(visual.geometryObjects, geometry_data.oMg):
        try:
            item.geometry.computeLocalAABB()
            box = item.geometry.aabb_local
        except (AttributeError, RuntimeError):  # a geometry without a local box: its frame origin is counted
            continue
        corners = box_corners(np.asarray(box.min_) * item.meshScale, np.asarray(box.max_) * item.meshScale)
        points.append(corners @ placement.rotation.T + placement.translation)
    return np.vstack(points)


_PAGE = """<!DOCTYPE html>
<html>
<head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ margin: 0; }}
#meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
#legend {{ position: absolute; left: 10px; bottom: 10px; background: rgba(255,255,255,0.85); padding: 6px 10px;
          font: 13px sans-serif; border-radius: 4px; }}
#legend span {{ display: inline-block; width: 12px; height: 12px; margin-right: 6px; vertical-align: middle; }}
#results {{ position: absolute; left: 10px; top: 10px; background: rgba(255,255,255,0.9); padding: 6px 10px;
           font: 14px sans-serif; border-radius: 4px; white-space: pre; }}
</style></head>
<body>
<div id="meshcat-pane"></div>
<div id="legend"><b>{title}</b>{legend}</div>
{results}
<script>{script}</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
{commands}
</script>
</body>
</html>
"""
