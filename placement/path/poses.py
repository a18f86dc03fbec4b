"""Pose lists: tool positions, and optionally orientations and times, read from CSV or JSON.

A pose list is a table with a header row (CSV) or a list of objects with the same names (JSON).
Its columns are x, y, z (the tool point in the path frame, in the path file's units), the
orientation columns of the file's ``orientation`` kind, and optionally t (s):

    none: no orientation columns; the tool keeps the path frame's orientation.
    quaternion_xyzw: qx, qy, qz, qw, a unit quaternion with the scalar last (scipy's order),
        normalised after a check that its norm is 1 within QUATERNION_NORM_TOLERANCE.
    rpy_deg: roll_deg, pitch_deg, yaw_deg, R = Rz(yaw)·Ry(pitch)·Rx(roll): roll about the fixed
        x axis first, then pitch about the fixed y axis, then yaw about the fixed z axis (as the
        sidecars' rpy), in degrees.

The orientation is the tool frame's in the path frame: the identity means the tool frame's axes
are the path frame's (its z axis Z_p, out of the workpiece).

Without t the list is a polyline timed by the path's feed and timing law, the orientation turning
uniformly from each pose to the next (:class:`~placement.path.segments.Segment`). With t the poses are
passed through at their times by a C² interpolation: a cubic spline of the positions (not-a-knot
ends) and scipy's RotationSpline of the orientations (:class:`TimedPoses`).
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.spatial.transform import Rotation, RotationSpline

from placement.path.exceptions import PoseFileError
from placement.path.segments import Segment

ORIENTATION_COLUMNS = {"none": (), "quaternion_xyzw": ("qx", "qy", "qz", "qw"),
                       "rpy_deg": ("roll_deg", "pitch_deg", "yaw_deg")}
QUATERNION_NORM_TOLERANCE = 1e-3
MAX_FILE_BYTES = 50_000_000
SAME_POINT_M = 1e-9


@dataclass(frozen=True)
class PoseTable:
    """The rows of a pose list, in SI units.

    Attributes:
        position_m: (N, 3) tool points in the path frame.
        rotation: (N, 3, 3) tool orientations in the path frame (None: no orientation columns).
        t_s: (N,) times (None: no t column).
    """

    position_m: np.ndarray
    rotation: np.ndarray | None
    t_s: np.ndarray | None


def read_poses(file: Path, orientation: str, metres_per_unit: float) -> PoseTable:
    """Read a pose list (module docstring).

    Args:
        file: The CSV or JSON file (by its suffix: .json is JSON, anything else CSV).
        orientation: The orientation kind: none, quaternion_xyzw or rpy_deg.
        metres_per_unit: The length unit of x, y, z.

    Raises:
        PoseFileError: A missing or unknown column, a value that is not a finite number, a
            quaternion whose norm is not 1, times that do not increase; names file, row and column.
        PathFileError: The file is missing or not readable.
    """
    names = ("x", "y", "z", *ORIENTATION_COLUMNS[orientation])
    header, rows = _read_rows(file)
    optional = ("t",)
    unknown = [name for name in header if name not in names + optional]
    if unknown:
        raise PoseFileError(file, 0, unknown[0], f"unknown column; with orientation '{orientation}' the columns are "
                                                 f"{', '.join(names)} and optionally t")
    missing = [name for name in names if name not in header]
    if missing:
        raise PoseFileError(file, 0, missing[0], f"missing column; with orientation '{orientation}' the columns are "
                                                 f"{', '.join(names)} and optionally t")
    if len(rows) < 2:
        raise PoseFileError(file, 0, "", f"a pose list needs at least 2 rows, got {len(rows)}")
    table = {name: _column(file, rows, name) for name in header}
    position = np.stack([table[a] for a in "xyz"], axis=1) * metres_per_unit
    rotation = _rotations(file, table, orientation)
    t = table.get("t")
    if t is not None:
        step = np.flatnonzero(np.diff(t) <= 0)
        if len(step):
            raise PoseFileError(file, int(step[0]) + 2, "t", f"the times must increase: {t[step[0] + 1]:g} s follows "
                                                             f"{t[step[0]]:g} s")
    return PoseTable(position, rotation, t)


def _read_rows(file: Path) -> tuple[list[str], list[dict[str, object]]]:
    """The column names and the rows (name -> raw value) of a CSV or JSON pose list."""
    if not file.is_file():
        raise PoseFileError(file, 0, "", "pose list not found" if not file.exists() else "not a regular file")
    if file.stat().st_size > MAX_FILE_BYTES:
        raise PoseFileError(file, 0, "", f"the file is larger than {MAX_FILE_BYTES // 1_000_000} MB")
    try:
        text = file.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise PoseFileError(file, 0, "", "not a text file in UTF-8") from None
    if file.suffix.lower() == ".json":
        return _json_rows(file, text)
    reader = csv.reader(io.StringIO(text))
    lines = [row for row in reader if any(cell.strip() for cell in row)]
    if not lines:
        raise PoseFileError(file, 0, "", "empty file: expected a header row (x, y, z, ...) and rows of numbers")
    header = [cell.strip() for cell in lines[0]]
    rows: list[dict[str, object]] = []
    for k, line in enumerate(lines[1:], start=1):
        if len(line) != len(header):
            raise PoseFileError(file, k, "", f"{len(line)} values for the {len(header)} columns of the header")
        rows.append({name: cell.strip() for name, cell in zip(header, line)})
    return header, rows


def _json_rows(file: Path, text: str) -> tuple[list[str], list[dict[str, object]]]:
    try:
        document = json.loads(text)
    except json.JSONDecodeError as error:
        raise PoseFileError(file, 0, "", f"not valid JSON: {error.msg} at line {error.lineno}") from None
    if not isinstance(document, list) or not all(isinstance(item, dict) for item in document):
        raise PoseFileError(file, 0, "", "expected a list of objects, one per pose, e.g. [{\"x\": 0, \"y\": 0, \"z\": 0}]")
    header = list(document[0]) if document else []
    for k, item in enumerate(document, start=1):
        if list(item) != header and set(item) != set(header):
            raise PoseFileError(file, k, "", f"the names {sorted(item)} differ from the first pose's {sorted(header)}")
    return header, document


def _column(file: Path, rows: list[dict[str, object]], name: str) -> np.ndarray:
    """One column as finite numbers."""
    values = np.empty(len(rows))
    for k, row in enumerate(rows, start=1):
        raw = row[name]
        try:
            if isinstance(raw, bool) or not isinstance(raw, (str, int, float)):
                raise ValueError
            values[k - 1] = float(raw)
        except ValueError:
            raise PoseFileError(file, k, name, f"expected a number, got {str(raw)[:40]!r}") from None
        if not np.isfinite(values[k - 1]):
            raise PoseFileError(file, k, name, f"expected a finite number, got {str(raw)[:40]!r}")
    return values


def _rotations(file: Path, table: dict[str, np.ndarray], orientation: str) -> np.ndarray | None:
    if orientation == "none":
        return None
    if orientation == "rpy_deg":
        angles = np.radians(np.stack([table["roll_deg"], table["pitch_deg"], table["yaw_deg"]], axis=1))
        return Rotation.from_euler("xyz", angles).as_matrix()  # extrinsic x, y, z: Rz(yaw)·Ry(pitch)·Rx(roll)
    quaternion = np.stack([table[name] for name in ("qx", "qy", "qz", "qw")], axis=1)
    norm = np.linalg.norm(quaternion, axis=1)
    bad = np.flatnonzero(np.abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE)
    if len(bad):
        raise PoseFileError(file, int(bad[0]) + 1, "qw", f"the quaternion (qx, qy, qz, qw) has norm {norm[bad[0]]:.6g}; "
                                                         f"expected 1 within {QUATERNION_NORM_TOLERANCE:g}")
    return Rotation.from_quat(quaternion / norm[:, None]).as_matrix()


def pose_segments(file: Path, table: PoseTable) -> tuple[Segment, ...]:
    """The polyline through the poses, each segment turning the orientation uniformly to the next pose's.

    Raises:
        PoseFileError: Two successive poses at one point with different orientations (a turn on the
            spot has no length to be timed by a feed).
    """
    segments = []
    rotations = table.rotation
    for k in range(len(table.position_m) - 1):
        start, end = table.position_m[k], table.position_m[k + 1]
        turn = None if rotations is None else Rotation.from_matrix(rotations[k].T @ rotations[k + 1]).as_rotvec()
        if np.linalg.norm(end - start) <= SAME_POINT_M:
            if turn is not None and np.linalg.norm(turn) > 0:
                raise PoseFileError(file, k + 2, "", f"the tool turns on the spot (rows {k + 1} and {k + 2} are at one "
                                                     "point): without t a pose list is timed by the feed along its "
                                                     "length; give times (t) or move the point")
            continue
        segments.append(Segment(start, end, rotation=None if rotations is None else rotations[k], turn_rad=turn))
    return tuple(segments)


@dataclass(frozen=True)
class TimedPoses:
    """A pose list with times, interpolated C² (module docstring).

    Attributes:
        t_s: (N,) the poses' times, from the first.
        position_m: (N, 3) their points.
        rotation: (N, 3, 3) their orientations (None: none given).
    """

    t_s: np.ndarray
    position_m: np.ndarray
    rotation: np.ndarray | None

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1] - self.t_s[0])

    @property
    def mean_speed_m_s(self) -> float:
        """Length of the polyline through the points over the duration: the list's own feed."""
        return float(np.linalg.norm(np.diff(self.position_m, axis=0), axis=1).sum()) / self.duration_s

    def sample(self, count: int, speed_scale: float) -> dict[str, np.ndarray]:
        """``count`` samples evenly spaced in time, run ``speed_scale`` times as fast as the list says.

        Returns:
            t (from 0), position, velocity, acceleration, tangent (N, 3), and rotation (N, 3, 3),
            angular velocity and acceleration (N, 3) in the path frame when the list has orientations.
        """
        times = np.linspace(self.t_s[0], self.t_s[-1], count)
        times[-1] = self.t_s[-1]
        spline = CubicSpline(self.t_s, self.position_m, axis=0)
        velocity = spline(times, 1) * speed_scale
        speed = np.linalg.norm(velocity, axis=1)
        chord = self.position_m[-1] - self.position_m[0]
        fallback = chord / np.linalg.norm(chord) if np.linalg.norm(chord) > 0 else np.array([1.0, 0.0, 0.0])
        tangent = np.where(speed[:, None] > 0, velocity / np.where(speed > 0, speed, 1.0)[:, None], fallback)
        out = {"t": (times - self.t_s[0]) / speed_scale, "position": spline(times), "velocity": velocity,
               "acceleration": spline(times, 2) * speed_scale**2, "tangent": tangent,
               "rapid": np.zeros(count, dtype=bool), "piece": np.zeros(count, dtype=int)}
        if self.rotation is not None:
            turning = RotationSpline(self.t_s, Rotation.from_matrix(self.rotation))
            rotation = turning(times).as_matrix()
            # scipy gives the rates in the moving frame: the path frame's are R·ω and R·α (ω × ω = 0).
            out["rotation"] = rotation
            out["angular_velocity"] = np.einsum("nij,nj->ni", rotation, turning(times, 1)) * speed_scale
            out["angular_acceleration"] = np.einsum("nij,nj->ni", rotation, turning(times, 2)) * speed_scale**2
        return out
