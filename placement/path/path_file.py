"""The path file's schema: shapes, feeds, process forces and timing law, in the path frame F_p.

A path file (YAML) describes the path in the path frame (the tool axis is Z_p, pointing out of the
workpiece; the origin is the frame origin the placement moves), the feed rate, the process forces
and the timing law. Lengths are in the file's ``units`` (m or mm); speeds, accelerations and
forces carry their unit in their field name. The shapes (docs/paths.md has the whole format):

    rectangle (with rounded corners: corner_radius), slot, polyline, circle, arc: geometry written in the
        file, run at ``feed_m_s``.
    gcode: a G-code program (:mod:`placement.path.gcode`), which sets its own units (G20/G21) and the
        feed of each move (F): ``units`` and ``feed_m_s`` are refused. ``rapids`` says whether its
        G0 moves are skipped (left out, leaving gaps) or timed at a rapid feed; ``machine`` gives the
        machine positions G28, G30 and G53 moves need (left out, with a note, without them);
        ``initial_feed_m_s`` the controller's modal feed for feed moves before the program's first F.
    poses: a pose list (:mod:`placement.path.poses`) in the file's units: without times, a polyline
        run at ``feed_m_s`` whose tool orientation turns uniformly along each segment; with times
        (a t column), a C² interpolation through the poses at their times, with no ``feed_m_s``
        or ``timing``.

Process forces are the forces on the tool from the workpiece, in the path frame, with t the unit
feed direction and z = Z_p the tool axis (pointing out of the workpiece)::

    F = -feed·t + radial·(z × t) + axial·z

so positive ``feed`` opposes the motion, positive ``radial`` pushes the tool to the left of the
feed direction, and positive ``axial`` pushes it back along the tool axis. Negative values flip
a component. The radial direction lies in the X_p Y_p plane: it vanishes on a segment along Z_p
(a plunge), where only the feed and axial forces act. One set of forces acts on every feed move
(rapids are force-free), or a set per kind of move: ``rapid`` on G0 moves, ``plunging`` where a
feed move runs within 45° of -Z_p (into the workpiece: t·Z_p < -cos 45°, decided sample by
sample), ``cutting`` elsewhere.

Timing laws (a timed pose list has its own times instead):
    paper: constant feed on each segment, each segment independent (corners ignored), as in
        Ur-Rehman et al.; energies are integrated segment by segment. Each segment runs at its
        own feed (a G-code move at its F).
    realistic: the tool stops at every sharp corner, at every gap a skipped rapid leaves, and
        wherever a pose list's orientation changes its rate of turning; between such stops it
        follows a jerk-limited feed profile with look-ahead (:mod:`placement.path.realistic_law`):
        each segment runs at its own feed where its length allows, slowed only where the
        geometry requires it (on arcs, until the tangential and centripetal acceleration and
        jerk together stay within the bounds; where the curvature jumps), and accelerates
        again after. One continuous motion between gaps, each gap starting a new piece.
    optimal: the fastest motion the robot allows at each placement (:mod:`placement.timing`):
        stops where the realistic law stops, and in between the feed is as high as the robot's
        joint speed and acceleration, motor speed and torque (and drive voltage, where given)
        allow, never above the segment's feed. It depends on the placement, so the path is
        sampled along its arc length here (at unit speed) and timed by the evaluator. The
        acceleration and jerk bounds, which shape the realistic law's feed profile, are not used.

A segment's feed is ``feed_ratio`` times the path's ``feed_m_s`` (for G-code, the program's
highest F), so replacing ``feed_m_s`` (the feed command) scales every feed but the rapid feed;
for a timed pose list it scales the list's speeds (times shrink by the same factor).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Literal

from pydantic import Field, field_validator, model_validator

from placement.schema import Number, Strict, Text

Positive = Annotated[Number, Field(gt=0.0)]
MAX_FEED_M_S = 100.0  # the largest feed a path may ask for (m/s): above it, a unit mistake
MM_PER_MIN = 1e-3 / 60  # m/s in one mm/min
MM_PER_MIN_M_S = 60e3  # mm/min in one m/s


LENGTH_SCALE = {"m": 1.0, "mm": 1e-3, "in": 0.0254}


class Rectangle(Strict):
    """W x L rectangle centred on the origin, W along X_p; run A(-W/2,-L/2) -> B -> C -> D, anticlockwise.

    With ``corner_radius`` r > 0 its corners are quarter circles of radius r (tangent to the sides): the run
    starts at (-W/2 + r, -L/2) and never stops (no sharp corner).
    """

    type: Literal["rectangle"]
    width: Positive
    length: Positive
    corner_radius: Annotated[Number, Field(ge=0.0)] = 0.0

    @model_validator(mode="after")
    def _radius_fits(self) -> Rectangle:
        if 2 * self.corner_radius > min(self.width, self.length):
            raise ValueError(f"corner_radius {self.corner_radius:g} must be at most half the shorter side "
                             f"({min(self.width, self.length) / 2:g})")
        return self


class Slot(Strict):
    """A slot's outline (a stadium) centred on the origin: ``length`` end to end along X_p, ``width`` along Y_p,
    half circles of radius width/2 at the ends; run anticlockwise from (-length/2 + width/2, -width/2)."""

    type: Literal["slot"]
    length: Positive
    width: Positive

    @model_validator(mode="after")
    def _longer_than_wide(self) -> Slot:
        if self.length < self.width:
            raise ValueError(f"length {self.length:g} must be at least the width {self.width:g} (a slot's ends are "
                             "half circles of the width's diameter)")
        return self


class Polyline(Strict):
    """Straight segments through points [x, y] or [x, y, z] of the path frame."""

    type: Literal["polyline"]
    points: Annotated[list[tuple[Number, Number] | tuple[Number, Number, Number]], Field(min_length=2, max_length=100_000)]
    closed: bool = False


class Circle(Strict):
    """Full circle centred on the origin, from (r, 0) anticlockwise about Z_p."""

    type: Literal["circle"]
    radius: Positive


class Arc(Strict):
    """Arc centred on the origin from angle start_deg, turning sweep_deg (positive anticlockwise)."""

    type: Literal["arc"]
    radius: Positive
    start_deg: Number = 0.0
    sweep_deg: Annotated[Number, Field(ge=-360.0, le=360.0)]

    @model_validator(mode="after")
    def _nonzero(self) -> Arc:
        if self.sweep_deg == 0:
            raise ValueError("sweep_deg must not be 0")
        return self


Point = tuple[Number, Number, Number]


class MachinePositions(Strict):
    """Positions only the machine holds, in machine coordinates (mm): where the program's origin (the path
    frame's) is, and the reference positions G28 and G30 move to (each left out with a note when not given)."""

    work_offset_mm: Point = (0.0, 0.0, 0.0)
    g28_mm: Point | None = None
    g30_mm: Point | None = None


class Gcode(Strict):
    """A G-code program, its file named relative to the path file (:mod:`placement.path.gcode`); ``machine`` gives
    what G28, G30, G53 and M25 moves need, ``tool_diameters_mm`` each tool's diameter by its number (T, D), which
    cutter radius compensation (G41, G42) offsets the path by, ``initial_feed_m_s`` the controller's modal feed when
    the program starts, which feed moves before the program's first F run at (without it they are refused)."""

    type: Literal["gcode"]
    file: Text
    machine: MachinePositions | None = None
    tool_diameters_mm: dict[int, Number] | None = None
    initial_feed_m_s: Positive | None = None

    @field_validator("initial_feed_m_s")
    @classmethod
    def _plausible_initial_feed(cls, feed: float | None) -> float | None:
        """At most MAX_FEED_M_S, as the path's feed_m_s."""
        return _plausible(feed)


class Poses(Strict):
    """A pose list (CSV or JSON), its file named relative to the path file (:mod:`placement.path.poses`)."""

    type: Literal["poses"]
    file: Text
    orientation: Literal["none", "quaternion_xyzw", "rpy_deg"] = "none"  # poses.ORIENTATION_COLUMNS


class ProcessForces(Strict):
    """Forces on the tool from the workpiece (N): see the module docstring for signs."""

    feed: Number = 0.0
    radial: Number = 0.0
    axial: Number = 0.0


class ForceKinds(Strict):
    """Process forces: one set (feed, radial, axial) for cutting and plunging moves alike, rapids
    force-free; or a set per kind of move (cutting required, plunging as cutting and rapid free
    unless given)."""

    feed: Number | None = None
    radial: Number | None = None
    axial: Number | None = None
    cutting: ProcessForces | None = None
    plunging: ProcessForces | None = None
    rapid: ProcessForces | None = None

    @model_validator(mode="after")
    def _one_form(self) -> ForceKinds:
        flat = [name for name in ("feed", "radial", "axial") if getattr(self, name) is not None]
        kinds = [name for name in ("cutting", "plunging", "rapid") if getattr(self, name) is not None]
        if flat and kinds:
            raise ValueError(f"give either feed, radial, axial (cutting and plunging alike) or a set per kind of move "
                             f"(cutting, plunging, rapid), not both (got {', '.join(flat + kinds)})")
        if kinds and self.cutting is None:
            raise ValueError(f"the per-kind form needs cutting (got {', '.join(kinds)})")
        return self

    def resolve(self) -> ForceSet:
        """The forces of each kind of move."""
        if self.cutting is None:
            flat = ProcessForces(feed=self.feed or 0.0, radial=self.radial or 0.0, axial=self.axial or 0.0)
            return ForceSet(flat, flat, ProcessForces())
        return ForceSet(self.cutting, self.plunging or self.cutting, self.rapid or ProcessForces())


@dataclass(frozen=True)
class ForceSet:
    """Process forces by kind of move: cutting, plunging (module docstring) and rapid."""

    cutting: ProcessForces
    plunging: ProcessForces
    rapid: ProcessForces


class Rapids(Strict):
    """What a G-code program's rapids (G0) count for: nothing (skip) or their time at a rapid feed."""

    mode: Literal["skip", "timed"] = "skip"
    feed_m_s: Positive | None = None

    @model_validator(mode="after")
    def _feed(self) -> Rapids:
        if (self.mode == "timed") != (self.feed_m_s is not None):
            raise ValueError("timed rapids need feed_m_s (the machine's rapid feed), skipped ones take none")
        return self


class Timing(Strict):
    """Timing law; the realistic mode needs the acceleration and jerk bounds."""

    mode: Literal["paper", "realistic", "optimal"] = "paper"
    max_acceleration_m_s2: Positive | None = None
    max_jerk_m_s3: Positive | None = None

    @model_validator(mode="after")
    def _bounds(self) -> Timing:
        if self.mode == "realistic" and (self.max_acceleration_m_s2 is None or self.max_jerk_m_s3 is None):
            raise ValueError("the realistic timing law needs max_acceleration_m_s2 and max_jerk_m_s3")
        return self


class PathFile(Strict):
    """The whole path file; G-code has its own ``units`` and feeds, a timed pose list its own timing (load_path)."""

    name: Text = ""
    units: Literal["m", "mm", "in"] | None = None
    shape: Annotated[Rectangle | Slot | Polyline | Circle | Arc | Gcode | Poses, Field(discriminator="type")]
    feed_m_s: Positive | None = None
    rapids: Rapids | None = None
    process_forces_N: ForceKinds = ForceKinds()
    timing: Timing = Timing()
    time_step_s: Positive | None = None
    max_deflection_um: Positive | None = Field(None, description="the largest deflection of the tool under the "
                                               "process forces a placement may have (µm), if any")
    loaded_stiffness: bool = Field(False, description="the deflection at the nonlinear equilibrium under the finite "
                                   "process forces (the loaded, complementary correction), not the linear C·w; the "
                                   "report gives the change it makes")

    @field_validator("feed_m_s")
    @classmethod
    def _plausible_feed(cls, feed: float | None) -> float | None:
        """At most MAX_FEED_M_S, the bound of the command line's --feeds: beyond it, a feed in other units."""
        return _plausible(feed)


def _plausible(feed: float | None) -> float | None:
    """A feed (m/s) of at most MAX_FEED_M_S: beyond it, a value in mm/min is likely, and it is refused saying so."""
    if feed is not None and feed > MAX_FEED_M_S:
        raise ValueError(f"must be at most {MAX_FEED_M_S:g} m/s, got {feed:g}: a value in mm/min? "
                         f"{feed:g} mm/min = {feed * MM_PER_MIN:.4g} m/s")
    return feed


