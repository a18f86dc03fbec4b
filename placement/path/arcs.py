"""Arcs and helices of G2/G3 lines: the centre from I, J, K or R, the radius checked, the turn.

An arc lies in the plane of G17, G18 or G19 (columns u, v, n of ``PLANES``) and turns about the
normal n, clockwise (G2) or anticlockwise (G3) seen from its positive end.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from placement.path.exceptions import GcodeError
from placement.path.segments import Segment

RADIUS_TOLERANCE_M = 2e-6  # an R arc's radius may be this much shorter than half its chord ...
RADIUS_TOLERANCE_SHARE = 1e-3  # ... or this share of it, whichever is larger
# An I/J/K arc's end may lie farther from (or nearer to) the centre than its start, as LinuxCNC's interpreter allows
# (interp_internal.hh, its defaults): by CENTER_TOLERANCE_M of the program's units (an end point and centre rounded
# to 0.001 in or 0.01 mm), or by SPIRAL_SHARE of the larger radius, but never by more than CENTER_CAP times the first.
CENTER_TOLERANCE_M = {0.0254: 2 * 0.001 * np.sqrt(2) * 0.0254, 1e-3: 2 * 0.01 * np.sqrt(2) * 1e-3}  # by unit (m)
SPIRAL_SHARE = 1e-3
CENTER_CAP = 100.0
SAME_POINT_M = 1e-9  # closer points are one point (a full circle, a move of no length)
PLANES = {17: np.eye(3)[:, [0, 1, 2]], 18: np.eye(3)[:, [2, 0, 1]], 19: np.eye(3)[:, [1, 2, 0]]}  # columns u, v, n
OFFSET_LETTERS = {17: "IJ", 18: "IK", 19: "JK"}


def arc_segment(fail: Callable[..., GcodeError], start: np.ndarray, end: np.ndarray, values: dict[str, float],
                plane: int, anticlockwise: bool, unit: float, absolute_centres: bool) -> Segment:
    """The arc or helix of a G2/G3 line.

    Args:
        fail: ``fail(problem, letter)`` makes the error blaming a word.
        start, end: (3,) its ends in the path frame (m).
        values: The line's words by letter (I, J, K, R in program units; P the turns).
        plane: 17, 18 or 19.
        anticlockwise: G3 (else G2).
        unit: Metres per program length unit.
        absolute_centres: G90.1: I, J, K are the centre's coordinates (else offsets from the start).

    Returns:
        The segment, in metres.
    """
    axes = PLANES[plane]
    s, e = start @ axes, end @ axes  # (u, v, n) coordinates
    chord = e[:2] - s[:2]
    distance = float(np.linalg.norm(chord))
    turns = values.get("P", 1.0)
    if turns != int(turns) or turns < 1:
        raise fail("the number of turns P must be a whole number ≥ 1", "P")
    if "R" in values:
        if set("IJK") & set(values):
            raise fail("give either R or I, J, K, not both", "R")
        if distance <= SAME_POINT_M:
            raise fail("R cannot describe a full circle (the end is the start): use I, J or K", "R")
        radius, half = abs(values["R"]) * unit, distance / 2
        if radius < half - max(RADIUS_TOLERANCE_M, RADIUS_TOLERANCE_SHARE * half):
            raise fail(f"the radius {radius / unit:.6g} is smaller than half the chord ({half / unit:.6g})", "R")
        height = np.sqrt(max(radius**2 - half**2, 0.0))
        left = np.array([-chord[1], chord[0]]) / distance
        center = (s[:2] + e[:2]) / 2 + (height if (values["R"] > 0) == anticlockwise else -height) * left
    else:
        allowed = OFFSET_LETTERS[plane]
        # A zero offset along the normal (FreeCAD's posts write G17 arcs with K0.000) is accepted; LinuxCNC refuses it.
        wrong = [letter for letter in "IJK" if letter in values and letter not in allowed
                 and (absolute_centres or values[letter] != 0.0)]
        if wrong:
            raise fail(f"G{plane} arcs take centre offsets {' and '.join(allowed)}", wrong[0])
        if not any(letter in values for letter in allowed):
            raise fail(f"an arc needs its centre: R, or offsets {' and '.join(allowed)}")
        offset = np.array([values.get(letter, 0.0) for letter in "IJK"]) * unit
        if absolute_centres:  # G90.1: I, J, K are the centre's coordinates (a missing one: the start's)
            offset = np.array([offset[k] - start[k] if "IJK"[k] in values else 0.0 for k in range(3)])
        center = s[:2] + (offset @ axes)[:2]
        radius = float(np.linalg.norm(s[:2] - center))
        end_radius = float(np.linalg.norm(e[:2] - center))
        if radius <= SAME_POINT_M:
            raise fail("the arc's centre is its start point (radius 0)", allowed[0])
        absolute = CENTER_TOLERANCE_M[unit]
        tolerance = min(max(absolute, SPIRAL_SHARE * max(radius, end_radius)), CENTER_CAP * absolute)
        if abs(end_radius - radius) > tolerance:
            raise fail(f"the end is {end_radius / unit:.6g} from the centre but the start {radius / unit:.6g}: the "
                       f"radius does not fit (tolerance {tolerance / unit:.3g}, LinuxCNC's)", allowed[0])
        if distance > SAME_POINT_M:  # onto the chord's perpendicular bisector: both ends on one circle
            across = np.array([-chord[1], chord[0]]) / distance
            middle = (s[:2] + e[:2]) / 2
            center = middle + ((center - middle) @ across) * across
            radius = float(np.linalg.norm(s[:2] - center))
    start_angle = float(np.arctan2(s[1] - center[1], s[0] - center[0]))
    end_angle = float(np.arctan2(e[1] - center[1], e[0] - center[0]))
    turn = (end_angle - start_angle) % (2 * np.pi) if anticlockwise else -((start_angle - end_angle) % (2 * np.pi))
    if distance <= SAME_POINT_M:
        turn = 2 * np.pi if anticlockwise else -2 * np.pi
    turn += (turns - 1) * (2 * np.pi if anticlockwise else -2 * np.pi)
    center_m = axes @ np.array([center[0], center[1], s[2]])
    return Segment(start, end, center_m, radius, start_angle, turn, plane=axes, rise_m=float(e[2] - s[2]))


def shifted(segment: Segment, offset_m: np.ndarray) -> Segment:
    """A segment computed in the program's coordinates, moved into the path frame by the offsets (G92, G54-G59.3)."""
    if not offset_m.any():
        return segment
    return dataclasses.replace(segment, start_m=segment.start_m + offset_m, end_m=segment.end_m + offset_m,
                               center_m=None if segment.center_m is None else segment.center_m + offset_m)
