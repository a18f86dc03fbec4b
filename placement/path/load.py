"""Reading a path file: the schema checked, the shape, G-code program or pose list turned into segments."""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path as FilePath
from typing import Any

import numpy as np

from placement.path.exceptions import PathFileError
from placement.path.gcode import MM_M, Machine, Program, read_program
from placement.path.path_file import LENGTH_SCALE, Circle, Gcode, PathFile, Polyline, Poses, Rapids, Rectangle, Slot
from placement.path.poses import TimedPoses, pose_segments, read_poses
from placement.path.samples import default_time_step_s
from placement.path.segments import Hold, Segment
from placement.path.toolpath import MIN_LENGTH_M, ToolPath
from placement.schema import read_yaml, validate_document

DICT_NAME = "<dict>"  # a path given as a dict, in errors
# A program given in place of a path file: G-code, and the suffixes of controllers that may hold G-code or their own
# language (Heidenhain's .h, Sinumerik's .mpf and .spf, ISO's .iso, Mazak's and Okuma's .eia and .min), which the
# reader refuses by name when it is not G-code.
GCODE_SUFFIXES = (".ngc", ".nc", ".tap", ".gcode", ".gc", ".gco", ".g", ".cnc", ".h", ".mpf", ".spf", ".iso", ".eia",
                  ".min")


@dataclass(frozen=True)
class ControllerSettings:
    """What RS-274 leaves to the controller, given outside the path file (the command line's --initial-feed and
    --tool-diameter): each overrides the path file's field of a G-code shape, tool by tool for the diameters.

    Attributes:
        initial_feed_m_s: The controller's modal feed when the program starts (m/s; None: the path file's).
        tool_diameters_mm: Each tool's diameter by its number (mm; a negative one swaps the side, as in LinuxCNC).
    """

    initial_feed_m_s: float | None = None
    tool_diameters_mm: Mapping[int, float] = field(default_factory=dict)

    def given(self) -> bool:
        """Whether any setting is given."""
        return self.initial_feed_m_s is not None or bool(self.tool_diameters_mm)


def load_path(path: str | FilePath | dict[str, Any], folder: str | FilePath = ".",
              controller: ControllerSettings | None = None) -> ToolPath:
    """Read and validate a path file (and the G-code program it names, if any), or a path file's fields as a dict.

    Args:
        path: The YAML file (or a G-code program, by its suffix: read with the defaults, and a note saying so),
            or its fields as a dict (``{"units": "mm", "shape": {"type": "circle", "radius": 20},
            "feed_m_s": 0.2}``), named ``<dict>`` in errors.
        folder: Where the files a dict names (a G-code program, a pose list) are; a file's are beside it.
        controller: The initial feed and tool diameters a G-code program is run with, over the path file's (a note
            says when the path is no program, which they do not apply to).

    Returns:
        The path, in metres.

    Raises:
        PathFileError: The file (or its program) is missing, malformed, or breaks the schema;
            a G-code program's errors (GcodeError) name its line and word.
    """
    bare = False  # a G-code program given in place of a path file
    if isinstance(path, dict):
        document = path
        path = FilePath(folder) / DICT_NAME
        spec = validate_document(document, path, PathFile, PathFileError)
    else:
        path = FilePath(path)
        bare = path.suffix.lower() in GCODE_SUFFIXES
        spec = (validate_document({"shape": {"type": "gcode", "file": path.name}}, path, PathFile, PathFileError)
                if bare else read_yaml(path, PathFile, PathFileError))
    _check_fields(path, spec)
    rapid_feed, timed = None, None
    holds: tuple[Hold, ...] = ()
    notes: tuple[str, ...] = ()
    if controller is not None and controller.given():
        if isinstance(spec.shape, Gcode):
            spec = spec.model_copy(update={"shape": _with_controller(spec.shape, controller)})
        else:
            notes = (f"the initial feed and tool diameters given for G-code programs do not apply to {path.name}, "
                     f"a {spec.shape.type}: not used",)
    if isinstance(spec.shape, Gcode):
        program = read_program(path.parent / spec.shape.file, _machine(spec.shape))
        notes = program.notes
        if bare:
            notes = (f"{path.name} is a G-code program given in place of a path file: it runs with no process "
                     "forces, its rapids left out, in the paper timing law; a path file naming it gives these "
                     "(docs/paths.md)", *notes)
        rapids = spec.rapids or Rapids()
        segments, holds = _kept(program, rapids.mode == "timed")
        feed, rapid_feed = program.feed_m_s, rapids.feed_m_s
    elif isinstance(spec.shape, Poses):
        assert spec.units is not None  # _check_fields
        file = path.parent / spec.shape.file
        table = read_poses(file, spec.shape.orientation, LENGTH_SCALE[spec.units])
        # A timed list is sampled by its splines; its polyline (length, report) needs no orientation.
        segments = pose_segments(file, table if table.t_s is None else dataclasses.replace(table, rotation=None))
        if table.t_s is not None:
            timed = TimedPoses(table.t_s, table.position_m, table.rotation)
            _check_timed(path, spec, timed)
            feed = timed.mean_speed_m_s
        else:
            _check_untimed(path, spec)
            assert spec.feed_m_s is not None  # _check_untimed
            feed = spec.feed_m_s
    else:
        segments = _segments(spec)
        assert spec.feed_m_s is not None  # _check_fields
        feed = spec.feed_m_s
    if not segments:
        raise PathFileError(path, "shape.file" if isinstance(spec.shape, Poses) else "shape.points",
                            "the points must not all coincide")
    if sum(segment.length_m for segment in segments) < MIN_LENGTH_M:
        raise PathFileError(path, "shape", f"the path is shorter than {MIN_LENGTH_M * 1e6:g} µm")
    return ToolPath(name=spec.name or ("path" if path.name == DICT_NAME else path.stem), segments=segments, feed_m_s=feed,
                    forces=spec.process_forces_N.resolve(), timing=spec.timing,
                    time_step_s=(spec.time_step_s if spec.time_step_s is not None
                                 else default_time_step_s(feed, sum(s.length_m for s in segments))),
                    rapid_feed_m_s=rapid_feed, timed=timed, notes=notes, holds=holds,
                    max_deflection_m=None if spec.max_deflection_um is None else spec.max_deflection_um * 1e-6,
                    loaded_stiffness=spec.loaded_stiffness)


def _kept(program: Program, rapids: bool) -> tuple[tuple[Segment, ...], tuple[Hold, ...]]:
    """A program's segments (its rapids only if timed) and its dwells as holds, each after the segment it follows
    among those kept; the segment before a hold ends in an exact stop (the tool rests during the dwell)."""
    kept = [segment for segment in program.segments if not segment.rapid or rapids]
    before = list(itertools.accumulate((not s.rapid or rapids for s in program.segments), initial=0))  # kept ones
    holds = []
    for dwell in program.dwells:
        after = before[dwell.after]
        holds.append(Hold(after, dwell.duration_s))
        if after:
            kept[after - 1] = dataclasses.replace(kept[after - 1], exact_stop=True)
    return tuple(kept), tuple(holds)


def _with_controller(shape: Gcode, controller: ControllerSettings) -> Gcode:
    """The G-code shape with the controller settings given over its own fields."""
    tools = {**(shape.tool_diameters_mm or {}), **controller.tool_diameters_mm}
    feed = controller.initial_feed_m_s if controller.initial_feed_m_s is not None else shape.initial_feed_m_s
    return shape.model_copy(update={"tool_diameters_mm": tools or None, "initial_feed_m_s": feed})


def _machine(shape: Gcode) -> Machine:
    """The machine positions, tool diameters and initial feed a path file gives a program, in metres (and m/s)."""
    given = shape.machine
    tools = {tool: diameter * MM_M for tool, diameter in (shape.tool_diameters_mm or {}).items()}
    if given is None:
        return Machine(tool_diameters_m=tools, initial_feed_m_s=shape.initial_feed_m_s)

    def point(value: tuple[float, float, float] | None) -> np.ndarray | None:
        return None if value is None else np.array(value, dtype=float) * MM_M

    offset = point(given.work_offset_mm)
    assert offset is not None
    return Machine(offset, point(given.g28_mm), point(given.g30_mm), given=True, tool_diameters_m=tools,
                   initial_feed_m_s=shape.initial_feed_m_s)


def _check_fields(path: FilePath, spec: PathFile) -> None:
    """The fields a shape requires or refuses: a G-code program has its own units and feeds."""
    if isinstance(spec.shape, Gcode):
        if spec.units is not None:
            raise PathFileError(path, "units", "a G-code program sets its own units (G21 mm, the default, or G20 "
                                               "inches): remove units")
        if spec.feed_m_s is not None:
            raise PathFileError(path, "feed_m_s", "a G-code program's feeds are its F words: remove feed_m_s (the "
                                                  "feed command scales them all)")
        return
    for name in ("units",) if isinstance(spec.shape, Poses) else ("units", "feed_m_s"):
        if getattr(spec, name) is None:
            raise PathFileError(path, name, "required field is missing")
    if spec.rapids is not None:
        raise PathFileError(path, "rapids", f"rapids belong to G-code programs, not to a {spec.shape.type}")


def _check_untimed(path: FilePath, spec: PathFile) -> None:
    """A pose list without times is timed by the path's feed."""
    if spec.feed_m_s is None:
        raise PathFileError(path, "feed_m_s", "required field is missing (a pose list without a t column is run at "
                                              "this feed)")


def _check_timed(path: FilePath, spec: PathFile, timed: TimedPoses) -> None:
    """A pose list with times is timed by them: no feed, no timing law."""
    for name in ("feed_m_s", "timing"):
        if name in spec.model_fields_set:
            raise PathFileError(path, name, "the pose list's t column times the path: remove this field (the feed "
                                            "command scales the list's speeds)")
    if timed.mean_speed_m_s <= 0:
        raise PathFileError(path, "shape.file", "the poses with times do not move: every point is the same")


def _segments(spec: PathFile) -> tuple[Segment, ...]:
    assert spec.units is not None and not isinstance(spec.shape, (Gcode, Poses))  # _check_fields
    scale = LENGTH_SCALE[spec.units]
    shape = spec.shape
    if isinstance(shape, Rectangle) and shape.corner_radius > 0:
        return _rounded(shape.width * scale, shape.length * scale, shape.corner_radius * scale)
    if isinstance(shape, Rectangle):
        w, l = shape.width * scale / 2, shape.length * scale / 2
        corners = [(-w, -l), (w, -l), (w, l), (-w, l)]
        return _lines([*corners, corners[0]])
    if isinstance(shape, Slot):
        return _rounded(shape.length * scale, shape.width * scale, shape.width * scale / 2)
    if isinstance(shape, Polyline):
        return _lines(shape.points + ([shape.points[0]] if shape.closed else []), scale)
    radius = shape.radius * scale
    start = 0.0 if isinstance(shape, Circle) else np.radians(shape.start_deg)
    sweep = 2 * np.pi if isinstance(shape, Circle) else np.radians(shape.sweep_deg)
    center = np.zeros(3)

    def on_circle(angle: float) -> np.ndarray:
        return np.array([radius * np.cos(angle), radius * np.sin(angle), 0.0])

    return (Segment(on_circle(start), on_circle(start + sweep), center, radius, start, sweep),)


def _rounded(width_m: float, length_m: float, radius_m: float) -> tuple[Segment, ...]:
    """A width x length rectangle centred on the origin with quarter-circle corners of radius r, anticlockwise from
    (-width/2 + r, -length/2): each side (left out where the corners meet, as on a slot's ends), then its corner."""
    w, l = width_m / 2 - radius_m, length_m / 2 - radius_m  # the corners' centres are at (±w, ±l)
    segments = []
    for k, (cx, cy) in enumerate([(w, -l), (w, l), (-w, l), (-w, -l)]):
        angle = np.radians(-90.0 + 90.0 * k)  # the corner's start, from its centre
        center = np.array([cx, cy, 0.0])
        start = center + radius_m * np.array([np.cos(angle), np.sin(angle), 0.0])
        end = center + radius_m * np.array([np.cos(angle + np.pi / 2), np.sin(angle + np.pi / 2), 0.0])
        previous = np.array([-cx, cy, 0.0]) if k % 2 == 0 else np.array([cx, -cy, 0.0])  # the side's other corner
        side_start = previous + radius_m * np.array([np.cos(angle), np.sin(angle), 0.0])
        if np.linalg.norm(start - side_start) > 0:
            segments.append(Segment(side_start, start))
        segments.append(Segment(start, end, center, radius_m, float(angle), np.pi / 2))
    return tuple(segments)


def _lines(points: list, scale: float = 1.0) -> tuple[Segment, ...]:
    """The polyline through points (x, y) or (x, y, z) times ``scale``, z 0 where not given, leaving out segments of
    no length."""
    xyz = np.array([[*p, 0.0, 0.0][:3] for p in points], dtype=float) * scale
    moves = np.flatnonzero(np.linalg.norm(np.diff(xyz, axis=0), axis=1) > 0)
    return tuple(Segment(xyz[k], xyz[k + 1]) for k in moves)
