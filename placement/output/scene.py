"""3-D scenes in the browser (meshcat): the robot, its workspace, placed paths and maps of an objective.

A :class:`Scene` draws the robot from its URDF visuals (Pinocchio's meshcat visualiser, with every
triangle of the mesh files: :mod:`placement.output.meshes`), with its tool body and its cell's
obstacles and keep-out zones as they are checked for collisions, the workspace box as a wireframe
with its named points (drawn over everything, labelled), the base frame's axes (labelled x, y, z),
placed paths as coloured tubes drawn over everything else (the robot never hides them), a map as
coloured points, and animates the robot along a path, interpolated at 30 frames a second. Colours
come from :mod:`placement.output.palette`. On a robot whose workpiece rides on a chain (a positioner's
table, ``Robot.workpiece_frame``), the paths are drawn on the workpiece: children of a node posed as
that frame (``WORKPIECE_NODE``), which the animation moves with the robot, so that the seam turns with
the part rather than the torch's track standing still in the base frame.

The page has three views, a button each: the workpiece (the placed paths, or a map's points, with
as much room around them again), the workspace (its box and the paths) and everything (the robot at
its reference configuration: every frame origin and the bounding box of every visual; the workspace
and its points; paths and map points). It opens on the first of them that has something in it. Each
view's camera looks at the centre of its box and orbits about it, from as close as the box's corners
all stay in meshcat's 75° view (a window wider than tall sees at least as much across). It records
the scene and writes a self-contained HTML page
that opens in a browser with no server and no network; :class:`PageServer` serves that page on this
machine (loopback only, unless asked otherwise). Everything that comes from input files (path
names, point names) is escaped in the page.
"""

from __future__ import annotations

import base64
import html
import http.server
import json
import shutil
import subprocess
import tempfile
import threading
from pathlib import Path

from placement.distribution import SCENE, require

# Optional dependencies: the [viz] extra, checked first so that a missing one is named with the extra that brings
# it; the imports below follow that check, not the top of the module.
# ruff: noqa: E402
require(SCENE)

import matplotlib
import meshcat
import meshcat.geometry as g
import numpy as np
import pinocchio as pin
import umsgpack
from meshcat.animation import Animation
from meshcat.servers.tree import SceneTree, find_node, walk

from placement.kinematics.batched import jump_steps
from placement.kinematics.tree import frame_kinematics
from placement.limits.collision import collision_scene
from placement.output.camera import (
    CAMERA_DIRECTION,
    CAMERA_NEAR_M,
    framing,
    swept,
    three_frame,
    workpiece_direction,
)
from placement.output.meshes import OverlayMesh, WholeMeshVisualizer, overlay_material, tube
from placement.output.palette import (
    CELL_COLORS,
    CELL_OPACITY,
    CUBE_COLOR,
    MAP_COLOR,
    NEAREST_COLOR,
    POINT_COLORS,
    REGION_COLOR,
    rgb,
)
from placement.robot.model import Robot
from placement.robot.packages import description_geometry
from placement.search.space import box_corners

VIEWER_SCRIPT = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
ANIMATION_FPS = 30
ANIMATION_PLAY_S = (4.0, 20.0)  # one pass of the animation lasts the path's duration, kept within these (s)
PATH_RADIUS, EDGE_RADIUS = 0.0025, 0.0015  # tube radii of paths and of box edges, fractions of the drawn box's diagonal
AXIS_RADIUS, AXIS_LENGTH = 0.002, 0.15  # the base frame's axes: radius and length, fractions of the drawn box's diagonal
AXIS_COLORS = (0xE41A1C, 0x4DAF4A, 0x377EB8)  # x red, y green, z blue (the usual order), labelled on the page
WORKPIECE_ROOM = 1.0  # the workpiece view's box: the workpiece's, widened by this share of its largest side each way
WORKPIECE_MIN_M = 0.02  # ... and at least this wide (m), so that a point-like path is not looked at from 1 cm
POINT_RADIUS = (0.03, 0.01)  # the named points' spheres: shares of the workspace's largest side, of the drawn diagonal
MARKS_RENDER_ORDER = 5  # the axes and the named points show through the robot, the paths over them (10)
VIEWS = ("workpiece", "workspace", "everything")  # the page's views, in the order of its buttons
DASH_RADII = 6  # a dashed path's dashes and gaps, in path radii
WORKPIECE_NODE = "workpiece"  # the node posed as the robot's workpiece frame, parent of the paths drawn on it


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
        self.legend: list[tuple[str, int | None]] = []  # (label, colour); no colour: a line of text
        self.results: list[str] = []  # lines of the page's results panel (add_results)
        self.result_blocks = 0  # calls of add_results: the paths answered
        visual = description_geometry(robot, pin.GeometryType.VISUAL)
        self.drawn_points_m: list[np.ndarray] = [robot_points(robot, visual)]  # the camera frames the robot, not the cell
        self.workpiece_points_m: list[np.ndarray] = []  # the placed paths and map points: the workpiece view
        self.workspace_points_m: list[np.ndarray] = []  # the workspace box (and the paths): the workspace view
        self.labels: list[tuple[str, np.ndarray, int]] = []  # (text, point m in the base frame, colour): on the page
        if robot.cell is not None or robot.tool is not None:
            self._add_cell_shapes(visual)
        self.visualizer = WholeMeshVisualizer(robot.model, pin.GeometryModel(), visual)
        self.visualizer.initViewer(viewer=self.viewer)
        self.visualizer.loadViewerModel(rootNodeName="robot")
        self.visualizer.display(robot.reference_q)
        if robot.workpiece_frame is not None:  # the paths ride on it; still, where the robot is drawn
            self.viewer[WORKPIECE_NODE].set_transform(self._workpiece_placement().homogeneous)
        self.viewer["/Grid"].set_property("visible", False)
        self.viewer["/Axes"].set_property("visible", False)  # meshcat's 0.5 m axes: the base frame's, sized, drawn instead
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
                item.meshColor = np.array([*rgb(color), CELL_OPACITY[body.kind]])
                item.overrideMaterial = True  # the kind's colour, not the mesh file's
                visual.addGeometryObject(item)
            self._legend(label, color)

    def _legend(self, label: str, color: int | None) -> None:
        """A legend entry, once per label."""
        if all(entry[0] != label for entry in self.legend):
            self.legend.append((label, color))

    def _radius(self, fraction: float) -> float:
        """A tube radius: ``fraction`` of the diagonal of what is drawn so far (m)."""
        low, high = self.extent()
        return fraction * max(float(np.linalg.norm(high - low)), CAMERA_NEAR_M)

    def add_nearest(self, name: str, first_m: np.ndarray, second_m: np.ndarray, label: str) -> None:
        """The nearest points of two bodies (base frame, m), joined by a line, with the label in the legend."""
        vertices, faces = tube(np.array([[first_m, second_m]]), self._radius(EDGE_RADIUS))
        self.viewer[f"nearest/{name}/line"].set_object(
            OverlayMesh(g.TriangularMeshGeometry(vertices, faces), overlay_material(NEAREST_COLOR)))
        for k, point in enumerate((first_m, second_m)):
            self.viewer[f"nearest/{name}/end_{k}"].set_object(g.Sphere(0.004), g.MeshLambertMaterial(color=NEAREST_COLOR))
            self.viewer[f"nearest/{name}/end_{k}"].set_transform(pin.SE3(np.eye(3), np.asarray(point)).homogeneous)
        self._legend(label, NEAREST_COLOR)

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        """The box holding everything drawn so far: lowest and highest corners (m, base frame)."""
        points = np.vstack(self.drawn_points_m)
        return points.min(axis=0), points.max(axis=0)

    def view_box(self, view: str) -> tuple[np.ndarray, np.ndarray] | None:
        """The box a view frames (lowest and highest corners, m, base frame), None if it has nothing to show.

        Args:
            view: One of ``VIEWS``: the workpiece (paths or map points, widened by ``WORKPIECE_ROOM`` of their largest
                side each way, at least ``WORKPIECE_MIN_M`` wide), the workspace (its box and the paths), everything.
        """
        if view == "everything":
            return self.extent()
        parts = self.workpiece_points_m + (self.workspace_points_m if view == "workspace" else [])
        if view not in VIEWS or not parts or (view == "workspace" and not self.workspace_points_m):
            return None
        points = np.vstack(parts)
        low, high = points.min(axis=0), points.max(axis=0)
        if view == "workpiece":
            room = max(WORKPIECE_ROOM * float(np.max(high - low)), WORKPIECE_MIN_M / 2)
            low, high = low - room, high + room
        return low, high

    def views_m(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """The page's views that have something to show, in ``VIEWS`` order: each its camera's target and position
        (m, base frame)."""
        views = {}
        for view in VIEWS:
            box = self.view_box(view)
            if box is not None:
                direction = CAMERA_DIRECTION
                if view == "workpiece":
                    direction = workpiece_direction(*box, carried=self.robot.workpiece_frame is not None)
                views[view] = framing(*box, direction)
        return views

    def fit_camera(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Aim the camera as the page opens: the first of ``VIEWS`` that has something to show; the views
        (:meth:`views_m`)."""
        views = self.views_m()
        target, position = next(iter(views.values()))
        self.look_at(target, position - target)
        return views

    def add_label(self, text: str, point_m: np.ndarray, color: int) -> None:
        """A text on the page beside a point of the scene (base frame, m), following it as the view turns."""
        self.labels.append((text, np.asarray(point_m, dtype=float), color))

    def _draw_axes(self) -> list[tuple[str, np.ndarray, int]]:
        """The base frame's axes from its origin, sized to what is drawn and drawn over everything; their labels."""
        length = AXIS_LENGTH * max(float(np.linalg.norm(np.subtract(*self.extent()))), CAMERA_NEAR_M)
        radius = self._radius(AXIS_RADIUS)
        labels = []
        for axis, (name, color) in enumerate(zip("xyz", AXIS_COLORS)):
            end = np.eye(3)[axis] * length
            vertices, faces = tube(np.array([[np.zeros(3), end]]), radius)
            self.viewer[f"axes/{name}"].set_object(
                OverlayMesh(g.TriangularMeshGeometry(vertices, faces), overlay_material(color), MARKS_RENDER_ORDER))
            labels.append((name, end, color))
        return labels

    def look_at(self, target_m: np.ndarray, offset_m: np.ndarray) -> None:
        """Point the camera at ``target_m`` from ``target_m + offset_m`` (base frame, Z up; kept in ``camera_m``),
        and orbit about ``target_m``.

        meshcat's orbit controls turn about their target and the camera looks at it, both in three.js' world frame
        (Y up, :func:`three_frame`), which the camera's own frame matches when its node "/Cameras/default" is not
        moved: the camera is placed there and the page sets the controls' target (:meth:`html`).
        """
        target = np.asarray(target_m, dtype=float)
        self.camera_m = (target, target + offset_m)
        self.viewer["/Cameras/default/rotated/<object>"].set_property("position", three_frame(target + offset_m))

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
        self.workspace_points_m.append(box_corners(low, high))
        radius = max(POINT_RADIUS[0] * float(np.max(high - low)), self._radius(POINT_RADIUS[1]))
        for name, point in workspace.points_m.items():
            color, label = POINT_COLORS.get(name, 0x7F7F7F), name.replace("_plus", "+").replace("_minus", "-")
            self.viewer[f"workspace/{name}"].set_object(OverlayMesh(g.Sphere(radius), overlay_material(color),
                                                                                MARKS_RENDER_ORDER))
            self.viewer[f"workspace/{name}"].set_transform(pin.SE3(np.eye(3), np.array(point)).homogeneous)
            self.drawn_points_m.append(box_corners(np.array(point) - radius, np.array(point) + radius))
            self.add_label(label, np.array(point), color)
            self._legend(label, color)

    def _wire_box(self, name: str, low: np.ndarray, high: np.ndarray, color: int, label: str) -> None:
        """An axis-aligned box of the base frame (m) as a wireframe of thin tubes, framed by the camera."""
        corners = box_corners(low, high)
        self.drawn_points_m.append(corners)
        edges = [(i, j) for i in range(8) for j in range(i + 1, 8) if bin(i ^ j).count("1") == 1]
        vertices, faces = tube(corners[np.array(edges)], self._radius(EDGE_RADIUS))
        self.viewer[name].set_object(g.Mesh(g.TriangularMeshGeometry(vertices, faces), g.MeshBasicMaterial(color=color)))
        self._legend(label, color)

    def add_path(self, name: str, tool_position_m: np.ndarray, color: int, label: str | None = None,
                 dashed: bool = False, configuration: np.ndarray | None = None) -> None:
        """A placed path through its tool points (base frame, m), drawn as a tube over everything else (the robot
        never hides it); the gap a skipped rapid leaves (a jump, as the kinematics finds it) is not drawn.

        On a robot whose workpiece rides on a chain (``Robot.workpiece_frame``), given the robot's ``configuration``
        at each tool point, the path is drawn on the workpiece: each tool point as seen from the workpiece frame
        at its own sample, a child of ``WORKPIECE_NODE``, which :meth:`animate` moves. The workpiece views frame it
        wherever the motion carries it.

        Args:
            name: The path's node name in the scene.
            tool_position_m: (N, 3) tool points (m, base frame).
            color: The tube's colour.
            label: Its legend entry (none if None or already there).
            dashed: Draw every other stretch of six radii only (a second placement of a path drawn in one colour).
            configuration: (N, nq) the robot's configuration at each tool point (m, rad), or None: the path is drawn
                in the base frame.
        """
        positions = np.asarray(tool_position_m, dtype=float).reshape(-1, 3)
        node = f"paths/{name}/line"
        if self.robot.workpiece_frame is not None and configuration is not None:
            rotation, origin = workpiece_poses(self.robot, configuration)
            on_workpiece = ((positions - origin)[:, None, :] @ rotation)[:, 0]  # R^T·(p - o), row by row
            self.drawn_points_m.append(np.vstack([positions, swept(on_workpiece, rotation, origin)]))
            self.workpiece_points_m.append(self.drawn_points_m[-1])
            positions, node = on_workpiece, f"{WORKPIECE_NODE}/{node}"
            self.add_note(f"paths drawn on the workpiece (frame {self.robot.workpiece_frame}), moving with it")
        else:
            self.drawn_points_m.append(positions)
            self.workpiece_points_m.append(positions)
        radius = self._radius(PATH_RADIUS)
        steps = np.linalg.norm(np.diff(positions, axis=0), axis=1)
        drawn = np.setdiff1d(np.arange(len(steps)), jump_steps(steps)) if len(steps) else np.zeros(0, dtype=int)
        if dashed:
            along = np.concatenate([[0.0], np.cumsum(steps)])[drawn]  # each step's start along the path
            drawn = drawn[(along // (DASH_RADII * radius)) % 2 == 0]
        if len(drawn):
            vertices, faces = tube(np.stack([positions[drawn], positions[drawn + 1]], axis=1), radius)
            self.viewer[node].set_object(OverlayMesh(g.TriangularMeshGeometry(vertices, faces), overlay_material(color)))
        if label:
            self._legend(label, color)

    def _workpiece_placement(self) -> pin.SE3:
        """The workpiece frame's placement in the base frame where the visualiser last drew the robot."""
        model, data = self.robot.model, self.visualizer.data
        return pin.updateFramePlacement(model, data, model.getFrameId(self.robot.workpiece_frame)).copy()

    def add_note(self, text: str) -> None:
        """A line of text in the legend (what a line style means, the animation's speed)."""
        self._legend(text, None)

    def add_value_points(self, points_m: np.ndarray, value: np.ndarray, subject: str = "energy",
                         size_m: float = 0.004) -> None:
        """Placement origins coloured by an objective's value (viridis: dark = low)."""
        self.drawn_points_m.append(np.asarray(points_m, dtype=float).reshape(-1, 3))
        self.workpiece_points_m.append(self.drawn_points_m[-1])
        span = np.ptp(value) or 1.0
        colors = matplotlib.colormaps["viridis"]((value - value.min()) / span)[:, :3]
        self.viewer["value_map"].set_object(g.PointCloud(np.asarray(points_m, dtype=np.float32).T,
                                                         colors.T.astype(np.float32), size=size_m))
        self._legend(f"{subject} map (dark: low)", MAP_COLOR)

    def animate(self, q: np.ndarray, t_s: np.ndarray, repetitions: int = 1000) -> None:
        """Play the robot along joint configurations ``q`` (N, nq) sampled at times ``t_s`` (s).

        One pass lasts the path's duration, kept within ``ANIMATION_PLAY_S`` (a slower or faster play rate is said
        in the legend), drawn at ``ANIMATION_FPS`` frames a second; each frame's configuration is interpolated
        between the two samples around its time (on the configuration space: ``pinocchio.interpolate``). On a robot
        whose workpiece rides on a chain, ``WORKPIECE_NODE`` (the paths drawn on the workpiece) takes that frame's pose
        at each frame.
        """
        times = np.asarray(t_s, dtype=float)
        duration = float(times[-1] - times[0])
        play_s = float(np.clip(duration, *ANIMATION_PLAY_S))
        frame_times = times[0] + np.linspace(0.0, duration, max(2, round(play_s * ANIMATION_FPS) + 1))
        after = np.clip(np.searchsorted(times, frame_times, side="right"), 1, len(times) - 1)
        span = np.maximum(times[after] - times[after - 1], 1e-12)
        weight = np.clip((frame_times - times[after - 1]) / span, 0.0, 1.0)
        animation = Animation(default_framerate=ANIMATION_FPS)
        viewer = self.visualizer.viewer
        try:
            for frame, (k, w) in enumerate(zip(after, weight)):
                with animation.at_frame(viewer, frame) as frame_viewer:
                    self.visualizer.viewer = frame_viewer  # record the placements into the frame
                    self.visualizer.display(pin.interpolate(self.robot.model, q[k - 1], q[k], float(w)))
                    if self.robot.workpiece_frame is not None:
                        frame_viewer[WORKPIECE_NODE].set_transform(self._workpiece_placement().homogeneous)
        finally:
            self.visualizer.viewer = viewer
        self.viewer.set_animation(animation, play=True, repetitions=repetitions)
        if duration > 0 and abs(play_s / duration - 1) > 1e-9:
            self.add_note(f"animation: the {duration:.3g} s path played over {play_s:.3g} s")

    def add_results(self, lines: list[str]) -> None:
        """Lines of text for the page's results panel (the answer beside the picture: energies, placements, gain),
        one call per path; the panel of several paths opens on a click, so that it does not cover the scene."""
        self.results.extend(lines)
        self.result_blocks += 1

    def html(self, title: str = "placement") -> str:
        """A self-contained page of the recorded scene (three.js viewer inlined, no network), with the base frame's
        axes, the labels, and a button for each of the views (:meth:`views_m`), opening on the first."""
        labels = self.labels + self._draw_axes()
        views = {name: {"target": three_frame(target), "position": three_frame(position)}
                 for name, (target, position) in self.fit_camera().items()}
        commands = "".join(f'run("{base64.b64encode(c).decode()}");\n' for c in self.window.commands())
        legend = "".join(f'<div><span style="background:#{color:06x}"></span>{html.escape(name)}</div>'
                         for name, color in self.legend if color is not None)
        legend += "".join(f"<div>{html.escape(name)}</div>" for name, color in self.legend if color is None)  # notes last
        results = "".join(f"<div>{html.escape(line)}</div>" for line in self.results)
        if self.result_blocks > 1:
            results = f'<details id="results"><summary>the answers for {self.result_blocks} paths</summary>{results}</details>'
        elif results:
            results = f'<div id="results">{results}</div>'
        legend += "<div>base frame: x red, y green, z blue</div>"
        buttons = "".join(f'<button type="button" data-view="{name}" title="frame the {name}">{name}</button>'
                          for name in views)
        marks = [{"text": text, "at": three_frame(point), "color": f"#{color:06x}"} for text, point, color in labels]
        return _PAGE.format(title=html.escape(title), script=VIEWER_SCRIPT.read_text(), commands=commands,
                            views=script_json(views), labels=script_json(marks), buttons=buttons, legend=legend,
                            results=results)


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

def workpiece_poses(robot: Robot, configuration: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The robot's workpiece frame (``Robot.workpiece_frame``) in the base frame at each configuration: rotations
    (N, 3, 3) and origins (N, 3) (m), by the compiled tree kinematics, batched."""
    q = np.atleast_2d(np.asarray(configuration, dtype=float))
    frame = robot.model.getFrameId(robot.workpiece_frame)
    rotation, origin, _, _ = frame_kinematics(robot.model, [frame], q, np.zeros((len(q), robot.model.nv)))
    return rotation[:, 0], origin[:, 0]


def script_json(value: object) -> str:
    """``value`` as JSON to write inside a page's script: no ``<``, ``>`` or ``&`` that could end the script early."""
    return json.dumps(value).replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


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
body {{ margin: 0; overflow: hidden; }}
#meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
#legend {{ position: absolute; left: 10px; bottom: 10px; background: rgba(255,255,255,0.85); padding: 6px 10px;
          font: 13px sans-serif; border-radius: 4px; }}
#legend span {{ display: inline-block; width: 12px; height: 12px; margin-right: 6px; vertical-align: middle; }}
#views {{ position: absolute; right: 10px; bottom: 10px; font: 13px sans-serif; }}
#views button {{ font: inherit; padding: 4px 10px; border: 1px solid #888; background: #fff; border-radius: 4px; }}
#views button[aria-pressed="true"] {{ background: #333; color: #fff; }}
#labels div {{ position: absolute; transform: translate(6px, -100%); font: bold 14px sans-serif; pointer-events: none;
              text-shadow: 0 0 3px #fff, 0 0 3px #fff; }}
#results {{ position: absolute; left: 10px; top: 10px; background: rgba(255,255,255,0.9); padding: 6px 10px;
           font: 14px sans-serif; border-radius: 4px; white-space: pre; max-height: 40vh; overflow-y: auto; }}
</style></head>
<body>
<div id="meshcat-pane"></div>
<div id="legend"><b>{title}</b>{legend}</div>
<div id="views" role="group" aria-label="views">{buttons}</div>
<div id="labels" aria-hidden="true"></div>
{results}
<script>{script}</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
function run(packed) {{
  var text = atob(packed), bytes = new Uint8Array(text.length);
  for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
  viewer.handle_command_bytearray(bytes);
}}
{commands}
var views = {views}, marks = {labels};
function showView(name) {{
  var view = views[name];
  viewer.camera.position.fromArray(view.position);
  viewer.controls.target.fromArray(view.target);
  viewer.controls.update();
  positionLabels();
  document.querySelectorAll("#views button").forEach(function (b) {{
    b.setAttribute("aria-pressed", String(b.dataset.view === name)); }});
}}
document.querySelectorAll("#views button").forEach(function (b) {{
  b.addEventListener("click", function () {{ showView(b.dataset.view); }}); }});
var pane = document.getElementById("labels");
marks.forEach(function (mark) {{
  var div = document.createElement("div");
  div.textContent = mark.text; div.style.color = mark.color; mark.div = pane.appendChild(div);
}});
function positionLabels() {{
  var at = new MeshCat.THREE.Vector3(), width = window.innerWidth, height = window.innerHeight;
  viewer.camera.updateMatrixWorld();  // the camera as it is now, even before the next frame is drawn
  marks.forEach(function (mark) {{
    at.fromArray(mark.at).project(viewer.camera);
    mark.div.style.display = at.z < 1 ? "" : "none";
    mark.div.style.left = ((at.x + 1) / 2 * width).toFixed(1) + "px";
    mark.div.style.top = ((1 - at.y) / 2 * height).toFixed(1) + "px";
  }});
}}
function placeLabels() {{ positionLabels(); requestAnimationFrame(placeLabels); }}
showView(Object.keys(views)[0]);
placeLabels();
</script>
</body>
</html>
"""
