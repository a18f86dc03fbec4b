"""The workbench's page (viser): the robot, its cell and workspace, the placed path with a gizmo, and the numbers.

Every number on the page comes from :class:`placement.app.evaluations.Bench`: while the path's gizmo is
dragged, readings on the search's coarse sampling (objective, feasibility, tightest limit,
per-actuator energy, the robot posed along the path); on release, or when a value is typed, the
exact value at the path's own sampling, the number ``--at`` prints. Whatever the user types that
is not valid is answered by a message in the page; the server goes on.
"""

from __future__ import annotations

import functools
import html
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pinocchio as pin

from placement.app.compare import ComparePanel, ExportPanel
from placement.app.drawing import RobotDrawing, rotation_of, snapped, wxyz_of
from placement.app.evaluations import Bench, Choices, Reading, shown_value, si_value
from placement.app.exceptions import NotReadyError
from placement.app.guard import guarded_server
from placement.app.motion import SPEEDS, playback_speed, power_range, power_with_cursor, speed_text
from placement.app.names import name_controls
from placement.app.numbers import number_html, readable
from placement.app.panels import JobPanel
from placement.app.searches import FrontPanel, MapPanel, OptimisePanel
from placement.app.shown import ShownTexts, check_viser
from placement.contract.objective import OBJECTIVES, wording
from placement.energy.regeneration import REGENERATION
from placement.evaluation.results import PlacementDetail
from placement.exceptions import PlacementError, SettingsError
from placement.placing.transform import ANGLES, VARIABLES, placement_pose
from placement.placing.values import parse_values
from placement.search.space import box_corners

PATH_COLOR, CUBE_COLOR = (230, 0, 200), (48, 48, 48)  # the workpiece: a magenta that no robot, cell or limit uses
FAILING_COLOR = (220, 0, 0)  # the workpiece where the placement is infeasible, and its failing sample
TIMINGS = ("path file's", "paper", "realistic", "optimal")
TYPING_PAUSE_S = 1.5  # a field's values are read this long after the last key, if Enter was not pressed
UNDO_DEPTH = 20  # placements Undo goes back through


def shown_text(name: str, value: float) -> str:
    """A variable's value as the page writes it (mm or degrees to 1e-6; typed back, it gives the value again)."""
    return format(round(shown_value(name, value), 6) + 0.0, ".12g")


def at_text(placement: np.ndarray) -> str:
    """The placement evaluated, as ``--at`` takes it (mm, degrees): the page says which values it read, so a
    value the browser never sent is seen, not silently replaced by an earlier one."""
    return ",".join(f"{name}={shown_text(name, placement[k])}" for k, name in enumerate(VARIABLES))


class Workbench:
    """The page of one bench: built on a viser server, updated from the bench's evaluations.

    Args:
        bench: The model.
        host: Address to listen on (127.0.0.1: this machine only).
        port: Port (0: the first free one from 8080).
        origins: Origins besides this server's own whose pages may use it (``--allow-origin``), see
            :mod:`placement.app.guard`.
    """

    def __init__(self, bench: Bench, host: str = "127.0.0.1", port: int = 0, origins: tuple[str, ...] = ()) -> None:
        check_viser()
        self.bench, self.robot = bench, bench.robot
        self.shown = ShownTexts()  # the text fields, read from the tab that acts
        self.server, self.gate = guarded_server(host, port or 8080, origins)
        self.server.on_client_connect(lambda client: self.guard(lambda: self._client_connected(client)))
        self.placement = bench.start()
        self.reading: Reading | None = None
        self.exact_detail: PlacementDetail | None = None
        self.history: list[np.ndarray] = []  # the placements evaluated before, the latest last (Undo)
        self._undoing = False
        self._plotted: PlacementDetail | None = None  # the detail whose power the plot's axis was set for
        self._syncing = False
        self._wanted: np.ndarray | None = None  # the latest placement asked for a live reading
        self._wake = threading.Condition()
        self._typing: threading.Timer | None = None  # reads the fields once typing pauses
        self._moving = threading.RLock()  # one placement change at a time, each shown whole (never a stale one last)
        self._closed = False
        self._draw_scene()
        self._build_gui()
        threading.Thread(target=self._live_loop, daemon=True).start()
        self.set_placement(self.placement, exact=True)

    @property
    def url(self) -> str:
        """The page's address, with the session's token (the page is served to no other)."""
        host = self.server.get_host()
        return f"http://{host if ':' not in host else f'[{host}]'}:{self.server.get_port()}/?token={self.gate.token}"

    def _client_connected(self, client: Any) -> None:
        name_controls(client)
        self._tell_sharing()

    def _tell_sharing(self) -> None:
        """Every tab shows the one placement of this workbench: a tab opened beside another is told so, and so are
        the others."""
        clients = self.server.get_clients()
        if len(clients) < 2:
            return
        for other in clients.values():
            other.add_notification(
                "Shared workbench", f"{len(clients)} tabs show this workbench: a value typed or a search started in "
                "one shows in all of them (one placement per workbench; start another 'placement app' for another).",
                auto_close_seconds=12.0, color="yellow")

    # --- the scene -------------------------------------------------------------------------------------
    def _draw_scene(self) -> None:
        scene: Any = self.server.scene
        scene.set_up_direction("+z")
        # Lit by viser's default lights alone, without shadows or an environment map: the robot stands out from the
        # white page, and a browser without a GPU (software WebGL) draws a frame several times faster.
        scene.configure_default_lights(enabled=True, cast_shadow=False)
        scene.configure_environment_map(None)
        self.drawing = RobotDrawing(self.server, self.robot)
        workspace = self.robot.workspace
        if workspace is not None:
            self._wire_box("/workspace/cube", np.array(workspace.min_m), np.array(workspace.max_m), CUBE_COLOR)
            radius = 0.02 * float(np.max(np.subtract(workspace.max_m, workspace.min_m)))
            for name, point in workspace.points_m.items():
                scene.add_icosphere(f"/workspace/{name}", radius=radius, color=(31, 119, 180), position=tuple(point))
                scene.add_label(f"/workspace/{name}/label", name.replace("_plus", "+").replace("_minus", "-"))
        region = self.robot.cell.workpiece_region if self.robot.cell is not None else None
        if region is not None:
            self._wire_box("/cell/workpiece_region", np.array(region.min_m), np.array(region.max_m), (32, 128, 192))
        turn, origin = placement_pose(np.zeros(6), self.robot.plane)
        self.plane_frame = scene.add_frame("/plane", show_axes=False, position=tuple(origin[0]), wxyz=wxyz_of(turn[0]))
        free = set(self.bench.space.free)
        lower, upper = self._bounds()
        self.gizmo = scene.add_transform_controls(
            "/plane/path", scale=0.08, depth_test=False,
            active_axes=tuple(name in free for name in ("x", "y", "z")), disable_rotations=not free & set(ANGLES),
            disable_axes=not free & {"x", "y", "z"}, disable_sliders=len(free & {"x", "y", "z"}) < 2,
            translation_limits=tuple((lower[k], upper[k]) for k in range(3)),
            rotation_limits=tuple((lower[k], upper[k]) for k in (5, 4, 3)))
        local = self._path_in_frame()
        segments = np.stack([local[:-1], local[1:]], axis=1)
        self._segments_shape = segments.shape
        self.path_line = scene.add_line_segments("/plane/path/line", segments, PATH_COLOR, thickness=10,
                                                 thickness_units="screen")
        self.failing_mark = scene.add_icosphere("/failing_sample", radius=self._path_size() * 0.06, color=FAILING_COLOR,
                                                visible=False)
        self._aim_camera()
        self.gizmo.on_update(self._gizmo_event)

    def _gizmo_event(self, event: object) -> None:
        """Live readings while the gizmo moves; the exact value when it is let go."""
        self.guard(self._gizmo_moved)
        if getattr(event, "phase", None) == "end":
            self.guard(lambda: self.set_placement(self.placement, exact=True, move_gizmo=False))

    def _aim_camera(self) -> None:
        """The first view looks at the centre of the robot and its workspace, from far enough to see them whole."""
        data = self.drawing.data
        points = [np.array([placement.translation for placement in self.drawing.geometry_data.oMg]),
                  np.array([frame.translation for frame in data.oMi])]
        if self.robot.workspace is not None:
            points.append(box_corners(self.robot.workspace.min_m, self.robot.workspace.max_m))
        cloud = np.vstack(points)
        low, high = cloud.min(axis=0), cloud.max(axis=0)
        centre, radius = (low + high) / 2, max(float(np.linalg.norm(high - low)) / 2, 0.05)
        direction = np.array([1.0, -1.2, 0.8]) / np.linalg.norm([1.0, -1.2, 0.8])
        camera = self.server.initial_camera
        camera.look_at = tuple(centre)
        camera.position = tuple(centre + direction * 2.0 * radius)
        camera.up = (0.0, 0.0, 1.0)

    def _path_size(self) -> float:
        """The path's largest extent (m)."""
        local = self._path_in_frame()
        return max(float(np.max(local.max(axis=0) - local.min(axis=0))), 1e-3)

    def frame_workpiece(self) -> None:
        """Every tab's camera looks at the placed path from close enough to see its shape."""
        reading = self.reading
        if reading is None:
            return
        points = reading.tool_position_m
        centre = (points.min(axis=0) + points.max(axis=0)) / 2
        direction = np.array([1.0, -1.2, 0.8]) / np.linalg.norm([1.0, -1.2, 0.8])
        for client in self.server.get_clients().values():  # the position first: viser moves look_at with it
            client.camera.position = tuple(centre + direction * 4.0 * self._path_size())
            client.camera.look_at = tuple(centre)
            client.camera.up_direction = (0.0, 0.0, 1.0)

    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Each variable's bounds (fixed ones: their value), m and rad."""
        space = self.bench.space
        lower, upper = np.array(space.fixed, dtype=float), np.array(space.fixed, dtype=float)
        lower[space.indices], upper[space.indices] = space.lower, space.upper
        return lower, upper

    def _path_in_frame(self) -> np.ndarray:
        """The path's samples in its own frame (m)."""
        zero = np.zeros(6)
        points = self.bench.live(zero).tool_position_m
        turn, origin = placement_pose(zero, self.robot.plane)
        return (points - origin[0]) @ turn[0]

    def _wire_box(self, name: str, low: np.ndarray, high: np.ndarray, color: tuple[int, int, int]) -> None:
        corners = box_corners(low, high)
        edges = [(i, j) for i in range(8) for j in range(i + 1, 8) if bin(i ^ j).count("1") == 1]
        self.server.scene.add_line_segments(name, np.array([[corners[i], corners[j]] for i, j in edges]), color,
                                            thickness=2, thickness_units="screen")

    # --- the controls ----------------------------------------------------------------------------------
    def _build_gui(self) -> None:
        gui: Any = self.server.gui  # handles whose values are set by the page too
        path, robot = self.bench.path, self.robot
        gui.add_markdown(f"**{html.escape(robot.name)}**: {html.escape(path.name)}")
        self.frame_button = gui.add_button("Frame the workpiece", hint="look at the placed path from close by")
        self.frame_button.on_click(lambda _: self.guard(self.frame_workpiece))
        self.snap = gui.add_checkbox("snap a drag to 1 mm / 1 deg", False,
                                     hint="the gizmo moves by whole millimetres and degrees")
        self.undo_button = gui.add_button("Undo", disabled=True, hint=f"back to the placement before (up to {UNDO_DEPTH})")
        self.undo_button.on_click(lambda _: self.guard(self.undo))
        lower, upper = self._bounds()
        self.fields: dict[str, Any] = {}
        self._written: dict[str, str] = {}  # each field's text as the page last wrote it
        self._last_read: dict[str, str] = {}  # the fields' texts when they were last read
        with gui.add_form("Placement (mm, degrees)") as form:
            for k, name in enumerate(VARIABLES):
                unit = "deg" if name in ANGLES else "mm"
                free = name in self.bench.space.free
                bounds = (f"from {shown_value(name, lower[k]):.6g} to {shown_value(name, upper[k]):.6g} {unit}" if free
                          else f"fixed at {shown_value(name, lower[k]):.6g} {unit}")
                field = gui.add_text(f"{name} ({unit})", "", disabled=not free,
                                     hint=f"{name}, {bounds}: type a number (1e3 is 1000) and press Enter")
                field.on_update(lambda event: self._typed(event))
                self.fields[name] = field
            self.go_button = gui.add_button("Go to these values", hint="evaluate the values typed above (or press Enter)")
        form.on_submit(lambda event: self.acted(event, self._fields_given))
        self.go_button.on_click(lambda event: self.acted(event, self._fields_given))
        with gui.add_form(None) as at_form:
            self.at_text = gui.add_text("--at", "", hint="a placement as --at takes it: x=0,y=0,z=-20,phi=30 (mm, deg); "
                                                         "values left out keep the current ones")
            self.at_button = gui.add_button("Evaluate")
        at_form.on_submit(lambda event: self.acted(event, self._at_given))
        self.at_button.on_click(lambda event: self.acted(event, self._at_given))
        self.message = gui.add_html("")
        with gui.add_folder("Live (coarse sampling)"):
            self.live_html = gui.add_html("")
        with gui.add_folder("Exact (the path's own sampling)"):
            self.exact_html = gui.add_html("")
        with gui.add_folder("Model"):
            self.objective = gui.add_dropdown("objective", tuple(OBJECTIVES.names()), initial_value=self.bench.choices.objective)
            self.regen = gui.add_dropdown("regeneration", tuple(REGENERATION.names()),
                                          initial_value=self.bench.choices.regeneration)
            self.timing = gui.add_dropdown("timing", TIMINGS, initial_value=self.bench.choices.timing or TIMINGS[0])
            self.model_note = gui.add_html("")
            for control in (self.objective, self.regen, self.timing):
                control.on_update(lambda _: self.guard(self._choices_changed))
        with gui.add_folder("Optimise"):
            self.optimise = OptimisePanel(self)
        with gui.add_folder("Compare", expand_by_default=False):
            self.compare = ComparePanel(self)
        with gui.add_folder("Export", expand_by_default=False):
            self.export = ExportPanel(self)
        with gui.add_folder("Map", expand_by_default=False):
            self.map = MapPanel(self)
        self.shown.watch(*self.fields.values(), self.at_text, self.map.points)
        with gui.add_folder("Front", expand_by_default=False):
            self.front = FrontPanel(self)
        with gui.add_folder("Motion"):
            self.time = gui.add_slider("time (s)", min=0.0, max=1.0, step=0.001, initial_value=0.0)
            self.play = gui.add_checkbox("play", False)
            duration_s = float(self.bench.live(self.placement).t_s[-1])  # a pass at the first placement
            self.speed = gui.add_dropdown("speed", tuple(speed_text(s) for s in SPEEDS),
                                          initial_value=speed_text(playback_speed(duration_s)),
                                          hint="of real time: a short pass is played slower, to be followed")
            colors = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b")
            series = ({"label": "t (s)"},) + tuple(
                {"label": actuator.joint, "stroke": colors[i % len(colors)], "width": 1.5}
                for i, actuator in enumerate(self.robot.actuators)) + ({"label": "now", "stroke": "#000", "width": 1},)
            empty = tuple(np.zeros(2) for _ in series)
            self.power_plot = gui.add_uplot(empty, series, title="electric power per actuator (W), exact",
                                            scales={"x": {"time": False}}, aspect=1.6)
            self.time.on_update(lambda _: self.guard(self._show_time))
            self.play.on_update(lambda _: self.guard(self._start_playing))

    def guard(self, action: Callable[[], None], beside: JobPanel | None = None) -> None:
        """Run a page action; what goes wrong is said in the page, beside the panel that acted (a search's state
        line, or under the placement's fields), and the server goes on."""
        try:
            action()
            if beside is None:
                self.message.content = ""
            return
        except PlacementError as error:
            text = str(error)
        except Exception as error:  # the last resort: the page says it, the server lives
            text = f"unexpected {type(error).__name__}: " + " ".join(str(error).split())[:300]
        if beside is not None:
            beside.say(text, error=True)
        else:
            self.message.content = f'<p id="message" style="color:#c00">{html.escape(text)}</p>'

    # --- placements --------------------------------------------------------------------------------------
    def set_placement(self, placement: np.ndarray, exact: bool, move_gizmo: bool = True,
                      write_fields: bool = True) -> None:
        """Go to a placement (clamped to the free variables' bounds): the fields (unless they hold what was just
        typed), the gizmo, the readings."""
        with self._moving:
            self.placement = self.bench.clamp(placement)
            self._syncing = True
            try:
                if write_fields:
                    self._write_fields(self.placement)
                if move_gizmo:
                    self.gizmo.position = tuple(self.placement[:3])
                    self.gizmo.wxyz = tuple(wxyz_of(placement_pose(self.placement)[0][0]))
            finally:
                self._syncing = False
            self._show_live(self.bench.live(self.placement))
            self.map.placement_moved(self.placement)
            if exact:
                self._show_exact(self.bench.exact(self.placement))

    def _gizmo_moved(self) -> None:
        if self._syncing:
            return
        rotation = rotation_of(self.gizmo.wxyz)
        psi, theta, phi = pin.rpy.matrixToRpy(rotation)  # R = Rz(phi) Ry(theta) Rx(psi)
        wanted = np.array([*self.gizmo.position, phi, theta, psi], dtype=float)
        if self.snap.value:
            wanted = snapped(wanted)
        self.placement = self.bench.clamp(wanted)
        if not np.allclose(self.placement, wanted, atol=1e-9):  # held within the free variables and their bounds
            self._syncing = True
            self.gizmo.position = tuple(self.placement[:3])
            self.gizmo.wxyz = tuple(wxyz_of(placement_pose(self.placement)[0][0]))
            self._syncing = False
        with self._wake:
            self._wanted = self.placement.copy()
            self._wake.notify()

    def _live_loop(self) -> None:
        """Evaluate the latest dragged placement, never a backlog of stale ones."""
        while not self._closed:
            with self._wake:
                while self._wanted is None and not self._closed:
                    self._wake.wait(0.5)
                wanted, self._wanted = self._wanted, None
            if wanted is None:
                continue
            self.guard(functools.partial(self._dragged_to, wanted))

    def _dragged_to(self, placement: np.ndarray) -> None:
        self._syncing = True
        try:
            self._write_fields(placement)
        finally:
            self._syncing = False
        self._show_live(self.bench.live(placement))
        self.map.placement_moved(placement)

    def _write_fields(self, placement: np.ndarray) -> None:
        """The fields show a placement (mm and degrees to 1e-6, as typed back they give it again)."""
        for k, name in enumerate(VARIABLES):
            text = shown_text(name, placement[k])
            self._written[name] = self._last_read[name] = text
            self.fields[name].value = text

    def acted(self, event: object, action: Callable[[], None], beside: JobPanel | None = None) -> None:
        """A tab's Enter or button: its text fields are read from the tab first (the keys typed last may never have
        reached the server, see :mod:`placement.app.shown`), then the action runs on what the tab shows."""
        def caught_up() -> None:
            self.shown.catch_up(getattr(event, "client", None))
            action()

        self.guard(caught_up, beside)

    def _typed(self, event: object) -> None:
        """A key typed in a field: nothing is written back while typing; the values are read on Enter, on "Go to
        these values", or once typing pauses for TYPING_PAUSE_S (from the tab that typed)."""
        client = getattr(event, "client", None)
        if self._syncing or client is None:
            return
        with self._wake:
            if self._typing is not None:
                self._typing.cancel()
            self._typing = threading.Timer(TYPING_PAUSE_S, self._typing_paused, args=(client,))
            self._typing.daemon = True
            self._typing.start()

    def _typing_paused(self, client: object) -> None:
        """Read the fields if they changed since they were last read (Enter may have read them already)."""
        self.shown.catch_up(client)  # a tab that cannot be read is logged, its fields kept
        if self._field_texts() != self._last_read:
            self.guard(self._fields_given)

    def _field_texts(self) -> dict[str, str]:
        return {name: str(field.value).strip() for name, field in self.fields.items()}

    def _fields_given(self) -> None:
        """Go to the values typed in the fields, read literally (1e3 is 1000); a value that is no number or lies
        beyond its bound is named with the bound, its text kept, and nothing moves."""
        with self._moving:  # the fields read by the last change to run
            self._go_to_fields()

    def _go_to_fields(self) -> None:
        values, problems = self.placement.copy(), []
        lower, upper = self._bounds()
        self._last_read = texts = self._field_texts()
        for k, name in enumerate(VARIABLES):
            text = texts[name]
            if text == self._written.get(name) or name not in self.bench.space.free:
                continue  # as the page wrote it: the exact current value, not its rounded text
            unit = "deg" if name in ANGLES else "mm"
            try:
                shown = float(text)
            except ValueError:
                shown = float("nan")
            if not np.isfinite(shown):
                problems.append(f"{name}: {text!r} is not a number of {unit}")
                continue
            value = si_value(name, shown)
            for bound, beyond, word in ((lower[k], value < lower[k] - 1e-12, "below its lower"),
                                        (upper[k], value > upper[k] + 1e-12, "above its upper")):
                if beyond:
                    problems.append(f"{name} = {text} {unit} is {word} bound {shown_value(name, bound):.6g} {unit}")
            values[k] = value
        if problems:
            raise SettingsError("; ".join(problems) + " (the text is kept; the placement did not move)")
        if not np.array_equal(values, self.placement) or self.exact_detail is None:
            self.set_placement(values, exact=True, write_fields=False)
        self._written.update(texts)  # each text now gives the current placement: read again, it keeps it

    def _at_given(self) -> None:
        text = self.at_text.value.strip()
        given = parse_values(text, "--at")
        if not given:
            raise SettingsError("--at: give at least one value, e.g. x=0,phi=30")
        fixed = [name for name in given if name not in self.bench.space.free
                 and given[name] != self.bench.space.fixed[VARIABLES.index(name)]]
        if fixed:
            raise SettingsError(f"--at: {', '.join(fixed)} is fixed here (free: {', '.join(self.bench.space.free)})")
        placement = np.array([given.get(name, self.placement[k]) for k, name in enumerate(VARIABLES)])
        clamped = self.bench.clamp(placement)
        if not np.allclose(clamped, placement, atol=1e-12):
            outside = [name for k, name in enumerate(VARIABLES) if abs(clamped[k] - placement[k]) > 1e-12]
            raise SettingsError(f"--at: {', '.join(outside)} outside the bounds of the search (see the fields' limits)")
        self.set_placement(placement, exact=True)

    # --- the readings --------------------------------------------------------------------------------------
    def _show_live(self, reading: Reading) -> None:
        words = wording(self.bench.choices.objective)
        unit = OBJECTIVES.get(self.bench.choices.objective).unit
        if not reading.reachable:
            sample, t = reading.first_unreachable
            lines = [f'<p id="live-state" style="color:#c00"><b>unreachable</b>: sample {sample} (t = {t:.4f} s) has no '
                     "configuration; the robot is drawn where it last could be</p>"]
        else:
            state = "feasible" if reading.feasible else "INFEASIBLE"
            label, margin = reading.tightest
            kept = f" (to keep: {self.bench.margin * 100:g} %)" if self.bench.margin else ""
            lines = [f'<p id="live-value">{html.escape(words.subject)} {readable(reading.value)} {html.escape(unit)} '
                     f'<b style="color:{"#080" if reading.feasible else "#c00"}">{state}</b></p>',
                     f'<p id="live-tightest">tightest: {html.escape(label)}, margin {margin * 100:.1f} %{kept}</p>']
            energies = reading.energy_per_actuator_J
            top = max(float(np.nanmax(np.abs(energies))), 1e-12)
            for actuator, energy in zip(self.robot.actuators, energies):
                width = 100 * abs(float(energy)) / top
                lines.append(f'<div style="font:12px sans-serif">{html.escape(actuator.joint)} {readable(energy, 4)} J'
                             f'<div style="background:#0070ff;height:8px;width:{width:.1f}%"></div></div>')
        lines.append(f'<p id="live-why" style="font-size:11px;color:#555">{len(reading.t_s)} samples, to follow a drag; '
                     "Exact below is --at's value on the path's own sampling (they differ in the last digits)</p>")
        self.live_html.content = "".join(lines)
        self._mark_failing(reading)
        self.reading = reading  # after the text: a reading in place is a reading shown
        self.time.max = max(float(reading.t_s[-1]), 1e-3)
        self._show_time()

    def _mark_failing(self, reading: Reading) -> None:
        """The workpiece red where the placement is infeasible, with a ball on its failing sample (the first
        unreachable one, or where the tightest limit is broken)."""
        color = FAILING_COLOR if not reading.feasible else PATH_COLOR
        self.path_line.colors = np.broadcast_to(np.array(color, dtype=np.uint8), self._segments_shape).copy()
        sample = reading.first_unreachable[0] if not reading.reachable else reading.tightest_sample
        if reading.feasible or sample < 0:
            self.failing_mark.visible = False
            return
        self.failing_mark.position = tuple(reading.tool_position_m[sample])
        self.failing_mark.visible = True

    def _show_exact(self, detail: PlacementDetail) -> None:
        before = self.exact_detail
        if before is not None and not self._undoing and not np.array_equal(before.placement, detail.placement):
            self.history = [*self.history, before.placement.copy()][-UNDO_DEPTH:]
        self.undo_button.disabled = not self.history
        self.exact_detail = detail
        self.compare.show(detail)
        self.power_plot.visible = detail.reachable
        self._plot_power()
        words = wording(detail.objective)
        unit = OBJECTIVES.get(detail.objective).unit
        if not detail.reachable:
            first = int(detail.unreachable_samples[0])
            self.exact_html.content = (f'<p id="exact-state" style="color:#c00">unreachable: {len(detail.unreachable_samples)} '
                                       f"of {len(detail.samples)} samples have no configuration (first at t = "
                                       f"{detail.samples.t_s[first]:.4f} s)</p>")
            return
        tight = min(detail.margins, key=lambda m: m.margin, default=None)
        where = f"{tight.kind} {tight.where}, margin {tight.margin * 100:.1f} %" if tight is not None else "none"
        self.exact_html.content = (
            f'<p id="exact-at">at {html.escape(at_text(detail.placement))}</p>'
            f'<p>{html.escape(words.subject)} <b>{number_html("exact-value", detail.value, unit)}</b>'
            f' ({"feasible" if detail.feasible else "INFEASIBLE"})</p>'
            + ("" if detail.objective == "energy" else
               f'<p>energy {number_html("exact-energy", float(detail.energy.total_J), "J")}</p>') +
            f"<p>tightest: {html.escape(where)}</p>")

    def _plot_power(self) -> None:
        """The exact power of each actuator, with the time shown as a cursor."""
        detail = self.exact_detail
        if detail is None or not detail.reachable:
            return
        power_W = np.asarray(detail.power_W, dtype=float)
        if detail is not self._plotted:  # the power axis fixed: uPlot ranges no axis over the cursor's NaN
            self.power_plot.scales = {"x": {"time": False}, "y": {"auto": False, "range": power_range(power_W)}}
            self._plotted = detail
        self.power_plot.data = power_with_cursor(np.asarray(detail.samples.t_s, dtype=float), power_W,
                                                 float(self.time.value))

    def undo(self) -> None:
        """Go back to the placement evaluated before the current one."""
        if not self.history:
            raise NotReadyError("nothing to undo: no placement was evaluated before this one")
        placement = self.history.pop()
        self._undoing = True
        try:
            self.set_placement(placement, exact=True)
        finally:
            self._undoing = False
        self.undo_button.disabled = not self.history

    def _show_time(self) -> None:
        self._plot_power()
        reading = self.reading
        if reading is None:
            return
        index = int(np.clip(np.searchsorted(reading.t_s, float(self.time.value)), 0, len(reading.t_s) - 1))
        if not reading.reachable and reading.first_unreachable[0] >= 0:
            index = max(0, min(index, reading.first_unreachable[0] - 1))
            if reading.first_unreachable[0] == 0:
                self.drawing.pose(self.robot.reference_q)
                return
        self.drawing.pose(reading.configuration[index])

    def _start_playing(self) -> None:
        if self.play.value:
            threading.Thread(target=self._play, daemon=True).start()

    def _play(self) -> None:
        """Play the pass in a loop, at the speed chosen (a fraction of real time), about 20 frames a second."""
        shown_s, last = float(self.time.value), time.monotonic()
        while self.play.value and not self._closed:
            reading = self.reading
            now = time.monotonic()
            if reading is not None:
                speed = SPEEDS[[speed_text(s) for s in SPEEDS].index(self.speed.value)]
                shown_s = (shown_s + (now - last) * float(speed)) % max(float(reading.t_s[-1]), 1e-3)
                self.time.value = shown_s
            last = now
            time.sleep(1 / 20)

    # --- choices and searches ----------------------------------------------------------------------------------
    def _choices_changed(self) -> None:
        timing = None if self.timing.value == TIMINGS[0] else self.timing.value
        choices = Choices(objective=self.objective.value, regeneration=self.regen.value, timing=timing)
        try:
            self.bench.choose(choices)
        except PlacementError:
            old = self.bench.choices
            self.objective.value, self.regen.value = old.objective, old.regeneration
            self.timing.value = old.timing or TIMINGS[0]
            raise
        note = self.bench.note
        self.model_note.content = f'<p id="model-note">note: {html.escape(note)}</p>' if note else ""
        self.optimise.forget()
        self.compare.forget()
        for panel in (self.map, self.front):
            panel.mark_stale("the model's choices changed since")
        self.set_placement(self.placement, exact=True)

    def close(self) -> None:
        """Stop the server, the search and the evaluators."""
        self._closed = True
        for panel in (self.optimise, self.map, self.front):
            panel.cancel()
        self.server.stop()
        self.bench.close()
