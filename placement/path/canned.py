"""Canned drilling cycles G73, G81, G82, G83, G85, G89 expanded into their moves, as LinuxCNC does.

In the plane of G17 (G18, G19) the hole is at X, Y (Z, X; Y, Z) and the cycle drills along Z (Y;
X), the third axis, from the retract level R down to the bottom Z (Y; X). With ``G90`` the words
are positions; with ``G91`` X and Y are steps from the current position, repeated ``L`` times,
R is measured from the initial level and the bottom from R. In G17 the polar words @ (radius)
and ^ (angle) may place the holes about the origin instead (in G91, each hole turned by ^ and
moved out by @ from the last). The initial level is the drilling
axis' position when the first of consecutive cycle lines starts. Each hole:

    a rapid up to R if the tool starts below it (the first line only), a rapid to the hole at the
    clear level, a rapid down to R, then
    G81: feed to the bottom;                                   rapid out to the clear level
    G82: feed to the bottom, dwell P seconds;                  rapid out
    G83: pecks of Q: feed Q deeper, rapid out to R, rapid back to PECK_CLEARANCE above the last
         depth, ... then feed to the bottom;                   rapid out
    G73: pecks of Q: feed Q deeper, rapid back PECK_CLEARANCE (chip break) ... then the bottom;
                                                               rapid out
    G85: feed to the bottom, feed back to R;                   rapid out
    G89: feed to the bottom, dwell P seconds, feed out to the clear level.

The clear level is R in ``G99`` mode (LinuxCNC's default) and the initial level in ``G98`` mode
(never below R). R, the bottom, Q and P are remembered from one cycle line to the next; L is not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.path.exceptions import _CycleError

CYCLES = (73, 81, 82, 83, 85, 89)
PLANE_AXES = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}  # hole's first, second axis, drilling axis
PECK_CLEARANCE = {"mm": 0.254, "inch": 0.010}  # LinuxCNC's retract above the last depth in G73 and G83


@dataclass
class CycleState:
    """What a cycle remembers between lines (program units, except the positions in metres)."""

    initial_level_m: float | None = None  # set by the first of consecutive cycle lines
    r_m: float | None = None
    bottom_m: float | None = None
    q_m: float | None = None
    p_s: float | None = None
    retract_to_r: bool = True  # G99 (LinuxCNC's default) or G98


@dataclass(frozen=True)
class Step:
    """One move or dwell of an expanded cycle: a rapid or feed to ``target_m`` (path frame), or a dwell."""

    kind: str  # "rapid", "feed" or "dwell"
    target_m: tuple[float, float, float] | None = None
    dwell_s: float = 0.0


def first_hole(plane: int, incremental: bool, unit_m: float, position_m: list[float | None], offset_m: np.ndarray,
               values: dict[str, float]) -> list[float]:
    """Where LinuxCNC's preliminary rapids bring a cycle that starts where the machine happens to be (an axis of its
    plane not given yet): up to R if the tool is below it, then over the first hole (path frame, m).

    Known only from the hole on, those rapids are left out as any rapid from an unknown position (FreeCAD's posts
    start a job's first cycle right after ``G0 Z5``).

    Args:
        plane: 17, 18 or 19.
        incremental: G91 (else G90).
        unit_m: Metres per program length unit.
        position_m: The tool's position (path frame, m; None where not known).
        offset_m: The program's origin in the path frame (m).
        values: The line's words by letter (program units).

    Raises:
        _CycleError: The hole or the drilling axis' level is not known: in G91 or with polar words, without the
            hole's position on the line, or without R.
    """
    first, second, drill = PLANE_AXES[plane]
    missing = [k for k in range(3) if position_m[k] is None]
    level = position_m[drill]
    hole_given = all("XYZ"[k] in values for k in missing if k != drill)
    if level is None or not hole_given or incremental or "@" in values or "^" in values or "R" not in values:
        names = ", ".join("XYZ"[k] for k in missing)
        raise _CycleError("", f"a drilling cycle from an unknown position ({names} not given yet): move to a point "
                              "with G0 first")
    target = [float(v) if v is not None else 0.0 for v in position_m]
    for k in (first, second):
        if "XYZ"[k] in values:
            target[k] = values["XYZ"[k]] * unit_m + float(offset_m[k])
    target[drill] = max(level, values["R"] * unit_m + float(offset_m[drill]))
    return target


def expand_cycle(code: int, plane: int, incremental: bool, unit_m: float, inch: bool, position_m: list[float],
                 values: dict[str, float], continuing: bool, state: CycleState) -> list[Step]:
    """The moves of one canned-cycle line.

    Args:
        code: 73, 81, 82, 83, 85 or 89.
        plane: 17, 18 or 19.
        incremental: G91 (else G90).
        unit_m: Metres per program length unit.
        inch: Whether the program is in inches (G20), for the peck clearance.
        position_m: The tool's position (path frame, metres).
        values: The line's words by letter (program units; P in seconds).
        continuing: Whether the previous motion was this same cycle (R, Q, P may be left out).
        state: The remembered values, updated.

    Raises:
        _CycleError: A missing or impossible R, Z, Q, P or L.
    """
    first, second, drill = PLANE_AXES[plane]
    letters = "XYZ"
    bottom_letter = letters[drill]
    if not continuing and bottom_letter not in values:
        raise _CycleError("", f"a canned cycle needs the bottom of the hole ({bottom_letter}) on its first line")
    if "R" in values:
        state.r_m = values["R"] * unit_m
    elif not continuing or state.r_m is None:
        raise _CycleError("", "a canned cycle needs its retract level R on its first line")
    if bottom_letter in values:
        state.bottom_m = values[bottom_letter] * unit_m
    for letter, needed in (("Q", (73, 83)), ("P", (82, 89))):
        if letter in values:
            if letter == "Q":
                if values["Q"] <= 0:
                    raise _CycleError("Q", "the peck depth Q must be > 0")
                state.q_m = values["Q"] * unit_m
            else:
                if values["P"] < 0:
                    raise _CycleError("P", "the dwell P must be ≥ 0 s")
                state.p_s = values["P"]
        elif code in needed and (not continuing or (state.q_m if letter == "Q" else state.p_s) is None):
            raise _CycleError("", f"G{code} needs {letter} on its first line")
    repeats = values.get("L", 1.0)
    if repeats != int(repeats) or repeats < 1:
        raise _CycleError("L", "the repeat count L must be a whole number ≥ 1")
    assert state.r_m is not None and state.bottom_m is not None
    current = position_m[drill]
    if state.initial_level_m is None:  # the first of consecutive cycle lines (the machine clears it)
        state.initial_level_m = current
    old = state.initial_level_m
    polar = "@" in values or "^" in values
    if polar and plane != 17:
        raise _CycleError("@" if "@" in values else "^", "polar words (@, ^) in a drilling cycle need the XY plane (G17)")
    step_radius, step_angle = values.get("@", 0.0) * unit_m, np.radians(values.get("^", 0.0))
    if incremental:
        step_a, step_b = (values.get(letters[k], 0.0) * unit_m for k in (first, second))
        r = state.r_m + old
        bottom = r + state.bottom_m
        a, b = position_m[first], position_m[second]
    else:
        step_a = step_b = 0.0
        r, bottom = state.r_m, state.bottom_m
        a = values[letters[first]] * unit_m if letters[first] in values else position_m[first]
        b = values[letters[second]] * unit_m if letters[second] in values else position_m[second]
        if polar:
            radius = values["@"] * unit_m if "@" in values else float(np.hypot(a, b))
            angle = np.radians(values["^"]) if "^" in values else float(np.arctan2(b, a))
            a, b = radius * np.cos(angle), radius * np.sin(angle)
    if r < bottom:
        raise _CycleError("R", f"the retract level R ({r / unit_m:g}) is below the bottom of the hole "
                              f"({bottom / unit_m:g})")
    steps: list[Step] = []

    def move(kind: str, u: float, v: float, w: float) -> None:
        target = [0.0, 0.0, 0.0]
        target[first], target[second], target[drill] = u, v, w
        steps.append(Step(kind, (target[0], target[1], target[2])))

    if old < r:
        move("rapid", position_m[first], position_m[second], r)
        old = current = r
    clear = r if state.retract_to_r else old
    clearance = PECK_CLEARANCE["inch" if inch else "mm"] * unit_m
    for repeat in range(int(repeats)):
        a, b = a + step_a, b + step_b
        if incremental and polar:  # each hole turns and moves out from the last, about the origin
            if a == 0 and b == 0:
                raise _CycleError("@" if "@" in values else "^", "incremental polar motion is indeterminate at the "
                                                                 "origin")
            radius, angle = float(np.hypot(a, b)) + step_radius, float(np.arctan2(b, a)) + step_angle
            a, b = radius * np.cos(angle), radius * np.sin(angle)
        if repeat == 0 and current > r:
            move("rapid", a, b, current)
            move("rapid", a, b, r)
        else:
            move("rapid", a, b, clear)
            if clear > r:
                move("rapid", a, b, r)
        if code in (73, 83):
            assert state.q_m is not None
            depth = r - state.q_m
            while depth > bottom:
                move("feed", a, b, depth)
                if code == 83:
                    move("rapid", a, b, r)
                move("rapid", a, b, depth + clearance)
                depth -= state.q_m
        move("feed", a, b, bottom)
        if code in (82, 89):
            assert state.p_s is not None
            steps.append(Step("dwell", dwell_s=state.p_s))
        if code == 85:
            move("feed", a, b, r)
        move("feed" if code == 89 else "rapid", a, b, clear)
    return steps
