"""Path segments in the path frame F_p: lines, arcs and helices in any plane, with exact derivatives.

A segment is parametrised by its arc length s (m). Given s and its time derivatives ṡ, s̈, a
segment gives the exact position, velocity, classical acceleration and unit tangent of the tool
point. An arc lies in the plane of two unit axes u, v through its centre and turns about their
normal n = u × v (anticlockwise, seen from +n, for a positive sweep); a helix also moves along n,
in proportion to the angle turned, by ``rise_m`` over the whole arc::

    p(s) = c + r·(cos a·u + sin a·v) + rise·(s / L)·n,   a = a0 + sweep·s / L,
    L = sqrt((r·sweep)² + rise²).

A segment may also carry the tool's orientation, turning uniformly (a slerp) from ``rotation``
at its start by the rotation vector ``turn_rad`` (in the start frame) at its end:
R(s) = rotation·exp((s / L)·turn), whose angular velocity in F_p is rotation·turn·ṡ / L.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

XY_PLANE = np.eye(3)  # columns u, v, n of the X_p Y_p plane (G17)
CORNER_ANGLE_RAD = np.radians(1.0)  # a tangent turn above this is a corner (exact stop)
EXACT_PATH_ANGLE_RAD = 1e-6  # in exact path mode (G61) a tangent turn above this is a corner
GAP_M = 1e-9  # segments whose ends are farther apart leave a gap (a skipped rapid) between them
TURNING_RATE_TOLERANCE_RAD_M = 1e-9  # a larger change of turning rate between segments is an orientation corner


@dataclass(frozen=True)
class Segment:
    """A line (no centre) or an arc or helix of the path, in metres, in the path frame.

    Attributes:
        start_m, end_m: (3,) end points.
        center_m: (3,) the arc's centre at its start (None: a line).
        radius_m: The arc's radius.
        start_angle_rad: Angle of the start point from u, about n.
        sweep_rad: Signed angle turned (positive anticlockwise about n).
        plane: (3, 3) columns u, v, n of the arc's plane (None: X_p, Y_p, Z_p).
        rise_m: A helix's motion along n over the whole arc (0 for a plane arc).
        feed_ratio: This segment's feed as a share of the path's feed (ToolPath.feed_m_s).
        rapid: A rapid move (G0), timed at the path's rapid feed and loaded by rapid forces.
        rotation: (3, 3) tool orientation in F_p at the start (None: no orientation).
        turn_rad: (3,) rotation vector from the start orientation to the end one, in the start frame.
        exact_path: The tool stops at the segment's end if the next segment's tangent differs at all (G61,
            drilling cycles), not only at a corner above CORNER_ANGLE_RAD.
        exact_stop: The tool stops at the segment's end (G61.1, a program pause M0, M1, M60).
    """

    start_m: np.ndarray
    end_m: np.ndarray
    center_m: np.ndarray | None = None
    radius_m: float = 0.0
    start_angle_rad: float = 0.0
    sweep_rad: float = 0.0
    plane: np.ndarray | None = None
    rise_m: float = 0.0
    feed_ratio: float = 1.0
    rapid: bool = False
    rotation: np.ndarray | None = None
    turn_rad: np.ndarray | None = None
    exact_path: bool = False
    exact_stop: bool = False

    @cached_property
    def length_m(self) -> float:
        """Arc length of the segment (computed once)."""
        if self.center_m is None:
            return float(np.linalg.norm(self.end_m - self.start_m))
        return float(np.hypot(abs(self.sweep_rad) * self.radius_m, self.rise_m))

    @property
    def axes(self) -> np.ndarray:
        """(3, 3) columns u, v, n of the arc's plane."""
        return XY_PLANE if self.plane is None else self.plane

    def point(self, s: np.ndarray, s_dot: np.ndarray, s_ddot: np.ndarray) -> tuple[np.ndarray, ...]:
        """Position, velocity, acceleration (N, 3) and unit tangent at arc lengths ``s`` (m)."""
        s, s_dot, s_ddot = (np.asarray(x, dtype=float)[:, None] for x in (s, s_dot, s_ddot))
        if self.center_m is None:
            tangent = (self.end_m - self.start_m) / self.length_m
            tangent = np.broadcast_to(tangent, (len(s), 3))
            return self.start_m + s * tangent, s_dot * tangent, s_ddot * tangent, tangent
        u, v, n = self.axes.T
        length = self.length_m
        turn_rate = self.sweep_rad / length  # da/ds (rad/m)
        angle = self.start_angle_rad + turn_rate * s
        radial = np.cos(angle) * u + np.sin(angle) * v
        across = -np.sin(angle) * u + np.cos(angle) * v
        tangent = self.radius_m * turn_rate * across + self.rise_m / length * n
        position = self.center_m + self.radius_m * radial + self.rise_m * s / length * n
        curvature = -self.radius_m * turn_rate**2 * radial  # d²p/ds²
        return position, s_dot * tangent, s_ddot * tangent + s_dot**2 * curvature, tangent

    def orientation(self, s: np.ndarray, s_dot: np.ndarray,
                    s_ddot: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Tool rotation (N, 3, 3), angular velocity (N, 3) rad/s and acceleration (N, 3) rad/s² in F_p.

        A segment without orientation holds the identity.
        """
        s, s_dot, s_ddot = (np.asarray(x, dtype=float) for x in (s, s_dot, s_ddot))
        start = np.eye(3) if self.rotation is None else self.rotation
        turn = np.zeros(3) if self.turn_rad is None else self.turn_rad
        axis_in_path = start @ turn / self.length_m  # dω/dṡ: constant along a slerp
        rotation = start @ rotation_matrices(s[:, None] / self.length_m * turn)
        return rotation, s_dot[:, None] * axis_in_path, s_ddot[:, None] * axis_in_path


def rotation_matrices(vectors: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotation matrices of (N, 3) rotation vectors (rad), by Rodrigues' formula."""
    angle = np.linalg.norm(vectors, axis=1)
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    sine = np.where(small, 1.0 - angle**2 / 6, np.sin(angle) / safe)
    versine = np.where(small, 0.5 - angle**2 / 24, (1.0 - np.cos(angle)) / safe**2)
    x, y, z = vectors.T
    zero = np.zeros_like(x)
    skew = np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)], -2)
    return np.eye(3) + sine[:, None, None] * skew + versine[:, None, None] * skew @ skew


@dataclass(frozen=True)
class Hold:
    """The tool held at rest for a while (a G-code dwell): at the end of segment ``after`` - 1 (at the start of the
    first segment if ``after`` is 0), for ``duration_s`` seconds."""

    after: int
    duration_s: float


@dataclass(frozen=True)
class Run:
    """Consecutive segments the tool runs through without stopping: no corner, gap or change of the tool's
    turning rate between them (where the realistic and optimal timing laws stop).

    Attributes:
        segments: The segments, in order.
        after_gap: Whether a gap (a skipped rapid) comes before the run.
    """

    segments: tuple[Segment, ...]
    after_gap: bool = False

    @property
    def length_m(self) -> float:
        """The run's length."""
        return sum(segment.length_m for segment in self.segments)

    @cached_property
    def bounds_m(self) -> np.ndarray:
        """(n + 1,) arc length of each segment's start from the run's start, then the run's length (computed once)."""
        return np.cumsum([0.0] + [segment.length_m for segment in self.segments])

    def along(self, s: np.ndarray, s_dot: np.ndarray, s_ddot: np.ndarray,
              oriented: bool = False) -> dict[str, np.ndarray]:
        """Motion along the run at increasing arc lengths ``s`` (m) from its start, moved at ṡ and s̈.

        Returns:
            position, velocity, acceleration, tangent (N, 3) and rapid (N,): whether on a rapid segment;
            if ``oriented``, also rotation (N, 3, 3), angular_velocity and angular_acceleration (N, 3).
        """
        run, bounds = self.segments, self.bounds_m
        index = np.clip(np.searchsorted(bounds, s, side="right") - 1, 0, len(run) - 1)
        return segments_motion(run, index, s - bounds[index], s_dot, s_ddot, oriented)


def segments_motion(segments: Sequence[Segment], index: np.ndarray, s: np.ndarray, s_dot: np.ndarray,
                    s_ddot: np.ndarray, oriented: bool = False) -> dict[str, np.ndarray]:
    """Motion of each sample on its own segment, all segments at once: :meth:`Segment.point` and
    :meth:`Segment.orientation` of ``segments[index[i]]`` at arc length ``s[i]`` (m, from that segment's start)
    moved at ``s_dot[i]`` and ``s_ddot[i]``, with numpy over the samples instead of a call per segment.

    Returns:
        position, velocity, acceleration, tangent (N, 3) and rapid (N,); if ``oriented``, also rotation (N, 3, 3),
        angular_velocity and angular_acceleration (N, 3) (as :meth:`Run.along`).
    """
    present, inverse = np.unique(np.asarray(index, dtype=int), return_inverse=True)
    chosen = [segments[k] for k in present]
    s, s_dot, s_ddot = (np.asarray(x, dtype=float)[:, None] for x in (s, s_dot, s_ddot))
    length = np.array([segment.length_m for segment in chosen])[:, None]
    start = np.array([segment.start_m for segment in chosen], dtype=float).reshape(-1, 3)
    line_tangent = (np.array([segment.end_m for segment in chosen], dtype=float).reshape(-1, 3) - start) / length
    position, tangent = start[inverse] + s * line_tangent[inverse], line_tangent[inverse]
    acceleration = s_ddot * tangent
    arcs = np.array([segment.center_m is not None for segment in chosen])
    on_arc = arcs[inverse]
    if on_arc.any():
        position[on_arc], tangent[on_arc], curvature = _arc_points(
            [segment for segment in chosen if segment.center_m is not None], (np.cumsum(arcs) - 1)[inverse[on_arc]],
            s[on_arc])
        acceleration[on_arc] = s_ddot[on_arc] * tangent[on_arc] + s_dot[on_arc] ** 2 * curvature
    out = {"position": position, "velocity": s_dot * tangent, "acceleration": acceleration, "tangent": tangent,
           "rapid": np.array([segment.rapid for segment in chosen], dtype=bool)[inverse]}
    if oriented:
        rotation = np.array([np.eye(3) if seg.rotation is None else seg.rotation for seg in chosen]).reshape(-1, 3, 3)
        turn = np.array([np.zeros(3) if seg.turn_rad is None else seg.turn_rad for seg in chosen]).reshape(-1, 3)
        axis_in_path = (rotation @ turn[:, :, None])[:, :, 0] / length  # dω/dṡ: constant along a slerp
        out["rotation"] = rotation[inverse] @ rotation_matrices(s / length[inverse] * turn[inverse])
        out["angular_velocity"] = s_dot * axis_in_path[inverse]
        out["angular_acceleration"] = s_ddot * axis_in_path[inverse]
    return out


def _arc_points(arcs: list[Segment], index: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position, unit tangent and curvature vector d²p/ds² (N, 3) of samples at arc lengths ``s`` (N, 1) on the arcs
    ``arcs[index]``, as :meth:`Segment.point` computes them."""
    axes = np.array([arc.axes for arc in arcs])[index]
    u, v, n = axes[:, :, 0], axes[:, :, 1], axes[:, :, 2]
    length, radius, rise, start_angle, sweep = (np.array([getattr(arc, name) for arc in arcs])[index][:, None] for name
                                                in ("length_m", "radius_m", "rise_m", "start_angle_rad", "sweep_rad"))
    turn_rate = sweep / length  # da/ds (rad/m)
    angle = start_angle + turn_rate * s
    radial = np.cos(angle) * u + np.sin(angle) * v
    across = -np.sin(angle) * u + np.cos(angle) * v
    tangent = radius * turn_rate * across + rise / length * n
    position = np.array([arc.center_m for arc in arcs])[index] + radius * radial + rise * s / length * n
    return position, tangent, -radius * turn_rate**2 * radial


def split_runs(segments: tuple[Segment, ...]) -> list[Run]:
    """Consecutive segments grouped into runs without a corner, a gap or a change of turning rate between them
    (an orientation that turns at another rate per metre would jump in angular velocity); a segment in exact
    stop mode ends its run, and one in exact path mode ends it at any turn of the tangent."""
    grouped: list[tuple[list[Segment], bool]] = [([segments[0]], False)]
    for previous, segment in zip(segments, segments[1:]):
        gap = bool(np.linalg.norm(segment.start_m - previous.end_m) > GAP_M)
        end_tangent = previous.point(np.array([previous.length_m]), np.ones(1), np.zeros(1))[3][0]
        start_tangent = segment.point(np.zeros(1), np.ones(1), np.zeros(1))[3][0]
        turn = np.arccos(np.clip(end_tangent @ start_tangent, -1.0, 1.0))
        kink = np.linalg.norm(turning_rate(segment) - turning_rate(previous)) > TURNING_RATE_TOLERANCE_RAD_M
        corner = EXACT_PATH_ANGLE_RAD if previous.exact_path else CORNER_ANGLE_RAD
        if gap or kink or turn > corner or previous.exact_stop:
            grouped.append(([segment], gap))
        else:
            grouped[-1][0].append(segment)
    return [Run(tuple(run), after_gap) for run, after_gap in grouped]


def turning_rate(segment: Segment) -> np.ndarray:
    """The tool's angular velocity per unit feed speed on a segment, in the path frame (rad/m)."""
    if segment.rotation is None or segment.turn_rad is None:
        return np.zeros(3)
    return segment.rotation @ segment.turn_rad / segment.length_m
