"""Cutter radius compensation (G41, G42, G41.1, G42.1) in the XY or XZ plane, as LinuxCNC's interpreter computes it.

The program gives the contour; the tool centre runs at the tool radius r to the left (G41) or
right (G42) of the direction of travel. The first move after G41/G42 (the entry) ends at r from
its programmed end: a G0 or G1 square to its own direction, a G2 or G3 along the arc's radius
(the entry arc's centre moved so that it runs from the tool's point to there). Each later move
is offset by r; at a convex corner an arc of radius r about the programmed corner joins the two offset moves (a
straight rapid for a G0); at a concave corner the previous offset move's end is moved back to
where the two offset moves meet. Corners within TOLERANCE_CONCAVE_CORNER_RAD of straight join as
they are. A corner the tool cannot reach without cutting into the contour (the previous move
would run backwards, an arc whose offset radius is ≤ 0, a corner tighter than the tool) is
refused, as LinuxCNC refuses it. G40 ends compensation: the next move starts from the tool's
offset point.

The moves already recorded stay in the caller's list; the ones whose end a later corner may
still move (LinuxCNC's queue) are kept by index and changed in place.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from placement.path.arcs import PLANES
from placement.path.exceptions import GcodeError
from placement.path.segments import Segment

TOLERANCE_CONCAVE_CORNER_RAD = 0.05  # LinuxCNC's: corners this close to straight (or to a reversal) join as they are
TOLERANCE_EQUAL = 1e-6  # LinuxCNC's: an entry arc's chord this close to square to its radius has no centre
Fail = Callable[[str], GcodeError]


@dataclass
class Compensation:
    """Cutter radius compensation under way.

    Attributes:
        left: G41 (else G42).
        radius_m: The tool radius (> 0).
        sweep_slack_rad: How much farther a moved arc may turn than it did (LinuxCNC: 0.0254 in mm programs,
            0.001 in inch programs).
        radii_tolerance_m: How far off its circle a moved arc end may lie (LinuxCNC: 0.01 program units).
        programmed_m: (3,) the programmed point (the contour's).
        tool_m: (3,) the tool centre; at the start, the programmed point, which LinuxCNC offsets the entry move
            from even where a G40 just left the tool at its offset point ...
        entry_start_m: (3,) ... which is where the entry move starts.
        axes: (3, 3) the plane's columns u, v, n (arcs.PLANES: X, Y, Z in G17, Z, X, Y in G18); the points above
            and the queue are in these coordinates, the moves handed out in the path frame's.
        first: The next move is the entry move.
        queue: (index into the moves, line's direction (2,) or None for an arc, the arc's programmed sweep) of the
            moves whose end a corner may still move.
        start_xy_m: (2,) where the queued moves start (None: not known).
    """

    left: bool
    radius_m: float
    sweep_slack_rad: float
    radii_tolerance_m: float
    programmed_m: np.ndarray
    tool_m: np.ndarray
    entry_start_m: np.ndarray
    axes: np.ndarray = dataclasses.field(default_factory=lambda: PLANES[17])
    first: bool = True
    queue: list[tuple[int, np.ndarray | None, float]] = dataclasses.field(default_factory=list)
    start_xy_m: np.ndarray | None = None


def tool_diameter_m(fail: Callable[[str, str], GcodeError], code_word: tuple[int, str], values: dict[str, float],
                    written: dict[str, str], tool_loaded: int | None, diameters_m: dict[int, float],
                    length_m: float) -> float:
    """The tool diameter (m) of a G41, G42 (tool D, else the loaded one, from the path file's table) or a G41.1,
    G42.1 line (D itself, in program units); < 0 swaps the side, as in LinuxCNC."""
    code, word = code_word
    if code in (411, 421):
        if "D" not in values:
            raise fail(word, f"G{code / 10:g} needs the tool diameter D")
        return values["D"] * length_m
    tool = round(values["D"]) if "D" in values else tool_loaded
    if "D" in values and (values["D"] != tool or values["D"] < 0):
        raise fail(written["D"], "D is a tool number: a whole number ≥ 0")
    if tool is None:
        raise fail(word, "cutter radius compensation needs the tool: load one (T1 M6) or give its number (D1)")
    if tool not in diameters_m:
        raise fail(written.get("D", word), f"tool {tool}'s diameter is not given: cutter radius compensation offsets "
                                           "the path by the tool radius; give it: --tool-diameter "
                                           f"{tool}=MM on the command line, or shape.tool_diameters_mm: {{{tool}: 6.0}} "
                                           "in the path file (docs/paths.md)")
    return diameters_m[tool]


def begin(fail: Fail, left: bool, diameter_m: float, unit_m: float, position_m: list[float | None], given: set[int],
          tool_start_m: np.ndarray | None, plane: int) -> Compensation:
    """Start compensation (G41: ``left``) at the programmed position (m; None: unknown) with the tool diameter
    (< 0 swaps the side) in the plane of G17 or G18. An axis along the plane's normal that the program has not given
    yet is at the path frame's origin (a lathe program's Y); ``tool_start_m`` is where G40 left the tool (None: at
    the programmed point)."""
    if plane == 19:
        raise fail("cutter radius compensation is computed in the XY (G17) and XZ (G18) planes only, not G19")
    axes = PLANES[plane]
    normal = int(np.argmax(np.abs(axes[:, 2])))
    if any(position_m[k] is None and (k != normal or k in given) for k in range(3)):
        raise fail("cutter radius compensation from an unknown position: move to a point first")
    here = np.array([0.0 if value is None else value for value in position_m])
    start = here if tool_start_m is None else tool_start_m
    return Compensation(left == (diameter_m > 0), abs(diameter_m) / 2, 0.0254 if unit_m == 1e-3 else 0.001,
                        0.01 * unit_m, axes.T @ here, axes.T @ here, axes.T @ start, axes)


def find_turn(start: np.ndarray, centre: np.ndarray, turn: int, end: np.ndarray) -> float:
    """The signed sweep (rad) of an arc from start to end about centre, ``turn`` full or partial circles (< 0
    clockwise); an end at the start is a full circle (LinuxCNC's find_turn)."""
    alpha = float(np.arctan2(start[1] - centre[1], start[0] - centre[0]))
    beta = float(np.arctan2(end[1] - centre[1], end[0] - centre[0]))
    if turn > 0:
        if beta <= alpha:
            beta += 2 * np.pi
        return beta - alpha + (turn - 1) * 2 * np.pi
    if alpha <= beta:
        alpha += 2 * np.pi
    return beta - alpha + (turn + 1) * 2 * np.pi


def arc(start: np.ndarray, end: np.ndarray, centre_xy: np.ndarray, sweep_rad: float) -> Segment:
    """An XY arc (helix if the Z differs) from start to end (3,) about centre_xy, turning sweep_rad."""
    radius = float(np.hypot(*(start[:2] - centre_xy)))
    return Segment(start.copy(), end.copy(), np.array([centre_xy[0], centre_xy[1], start[2]]), radius,
                   float(np.arctan2(start[1] - centre_xy[1], start[0] - centre_xy[0])), sweep_rad, plane=PLANES[17],
                   rise_m=float(end[2] - start[2]))


def _frame(comp: Compensation, segment: Segment) -> Segment:
    """A segment in the plane's coordinates (u, v, n) in the path frame's."""
    axes = comp.axes
    return dataclasses.replace(segment, start_m=axes @ segment.start_m, end_m=axes @ segment.end_m,
                               center_m=None if segment.center_m is None else axes @ segment.center_m,
                               plane=None if segment.center_m is None else axes)


def _local(comp: Compensation, segment: Segment) -> Segment:
    """A segment of the path frame in the plane's coordinates (u, v, n)."""
    axes = comp.axes
    return dataclasses.replace(segment, start_m=axes.T @ segment.start_m, end_m=axes.T @ segment.end_m,
                               center_m=None if segment.center_m is None else axes.T @ segment.center_m,
                               plane=None if segment.center_m is None else PLANES[17])


def _turn(segment: Segment) -> int:
    """The turn count of an arc as LinuxCNC gives it (±1 for up to a circle, ±2 ...)."""
    return int(np.ceil(abs(segment.sweep_rad) / (2 * np.pi) - 1e-9)) * (1 if segment.sweep_rad > 0 else -1)


def _inside(comp: Compensation, turn: float) -> bool:
    """The tool runs inside the arc (LinuxCNC's TOOL_INSIDE_ARC)."""
    return (comp.left and turn > 0) or (not comp.left and turn < 0)


def _move_ends(comp: Compensation, moves: list[Any], xy: np.ndarray, fail: Fail) -> None:
    """Move the queued moves' XY end to ``xy`` and release them (LinuxCNC's move_endpoint_and_flush)."""
    for number, (index, direction, sweep) in enumerate(comp.queue):
        segment = _local(comp, moves[index].segment)
        if number:  # a later queued move (along Z) starts where the one before it now ends
            segment = dataclasses.replace(segment, start_m=np.array([xy[0], xy[1], segment.start_m[2]]))
        end = np.array([xy[0], xy[1], segment.end_m[2]])
        if direction is None:  # an arc: its end slides along its circle
            assert segment.center_m is not None
            centre = segment.center_m[:2]
            if abs(np.hypot(*(xy - centre)) - segment.radius_m) > comp.radii_tolerance_m:
                raise fail("cutter compensation made an arc whose ends are not on one circle")
            start = comp.start_xy_m if comp.start_xy_m is not None else segment.start_m[:2]
            turned = find_turn(start, centre, _turn(segment), xy)
            if sweep != 0.0 and comp.start_xy_m is not None and abs(turned) > abs(sweep) + comp.sweep_slack_rad:
                raise fail("arc move in a concave corner cannot be reached by the tool without gouging")
            moved = arc(segment.start_m, end, centre, find_turn(segment.start_m[:2], centre, _turn(segment), xy))
        else:
            if comp.start_xy_m is not None and float(direction @ (xy - comp.start_xy_m)) < 0:
                kind = "straight traverse" if segment.rapid else "straight feed"
                raise fail(f"{kind} in a concave corner cannot be reached by the tool without gouging (the move "
                           "would run backwards: the tool is larger than the corner)")
            moved = Segment(segment.start_m, end, rapid=segment.rapid)
        moved = dataclasses.replace(moved, exact_path=segment.exact_path, exact_stop=segment.exact_stop)
        moves[index] = dataclasses.replace(moves[index], segment=_frame(comp, moved))
    comp.queue.clear()
    comp.start_xy_m = xy.copy()
    comp.tool_m[:2] = xy


def _release(comp: Compensation, start_xy: np.ndarray | None) -> None:
    """Release the queued moves as they are (LinuxCNC's dequeue_canons), the next ones starting at start_xy."""
    comp.queue.clear()
    comp.start_xy_m = None if start_xy is None else start_xy.copy()


def straight(comp: Compensation, moves: list[Any], end_m: np.ndarray, rapid: bool, fail: Fail,
             add: Callable[[Segment], None]) -> None:
    """A compensated G0 or G1 to the programmed end (3,), its segments handed to ``add`` (which appends them to
    ``moves``)."""
    p, o, c = end_m, comp.programmed_m, comp.tool_m.copy()
    if comp.first:
        distance = float(np.hypot(*(p[:2] - c[:2])))
        if distance <= comp.radius_m:
            raise fail("length of cutter compensation entry move is not greater than the tool radius")
        alpha = float(np.arctan2(p[1] - c[1], p[0] - c[0])) + (np.pi / 2 if comp.left else -np.pi / 2)
        _release(comp, c[:2])
        normal = np.array([np.cos(alpha), np.sin(alpha)])
        _queue(comp, moves, add, Segment(comp.entry_start_m, np.array([*(p[:2] + comp.radius_m * normal), p[2]]),
                                         rapid=rapid), normal)
        comp.first = False
    elif p[0] == o[0] and p[1] == o[1]:  # along Z only
        _queue(comp, moves, add, Segment(c, np.array([c[0], c[1], p[2]]), rapid=rapid), np.zeros(2))
    else:
        theta = float(np.arctan2(c[1] - o[1], c[0] - o[0]))
        alpha = float(np.arctan2(p[1] - o[1], p[0] - o[0]))
        if comp.left:
            theta += 2 * np.pi if theta < alpha else 0.0
            beta, gamma = theta - alpha - np.pi / 2, np.pi / 2
        else:
            alpha += 2 * np.pi if alpha < theta else 0.0
            beta, gamma = alpha - theta - np.pi / 2, -np.pi / 2
        offset = comp.radius_m * np.array([np.cos(alpha + gamma), np.sin(alpha + gamma)])
        small = TOLERANCE_CONCAVE_CORNER_RAD
        previous = _local(comp, moves[comp.queue[0][0]].segment) if comp.queue else None
        last_arc = previous is not None and previous.center_m is not None
        concave = beta < -small or beta > np.pi + small or (
            beta > np.pi - small and last_arc and previous is not None
            and (previous.sweep_rad > 0) == (not comp.left))  # the "h" shape: stay above
        if not concave and beta > small:  # a convex corner: round it about the programmed corner
            _move_ends(comp, moves, c[:2], fail)
            corner = np.array([*(o[:2] + offset), c[2]])
            add(_frame(comp, Segment(c, corner, rapid=True) if rapid else
                       arc(c, corner, o[:2], find_turn(c[:2], o[:2], -1 if comp.left else 1, corner[:2]))))
            comp.tool_m = corner
            _release(comp, corner[:2])
        elif concave:
            _move_ends(comp, moves, _concave_line(comp, previous, p, o, c, theta, gamma, beta, fail), fail)
        else:
            _release(comp, c[:2])
        _queue(comp, moves, add, Segment(comp.tool_m.copy(), np.array([*(p[:2] + offset), p[2]]), rapid=rapid),
               p[:2] - o[:2])
    comp.programmed_m = p.copy()


def _concave_line(comp: Compensation, previous: Segment | None, p: np.ndarray, o: np.ndarray, c: np.ndarray,
                  theta: float, gamma: float, beta: float, fail: Fail) -> np.ndarray:
    """Where the previous offset move must end for a line into a concave corner."""
    r = comp.radius_m
    if previous is None or previous.center_m is None:  # line -> line
        half_corner = (beta + np.pi) / 2
        if half_corner == 0.0:
            raise fail("a zero degree inside corner is invalid for cutter compensation")
        retreat = r / np.tan(half_corner)
        return c[:2] + retreat * np.array([np.cos(theta + gamma), np.sin(theta + gamma)])
    centre = previous.center_m[:2]  # arc -> line
    old_radius = float(np.hypot(*(previous.end_m[:2] - centre)))
    base = float(np.arctan2(p[1] - o[1], p[0] - o[0]))
    turn = previous.sweep_rad
    across = base + np.pi / 2 if turn > 0 else base - np.pi / 2
    phi = float(np.arctan2(centre[1] - o[1], centre[0] - o[0]))
    inside = _inside(comp, turn)
    d = (old_radius + r if inside else old_radius - r) * np.cos(across - phi)
    share = (d - r if inside else d + r) / old_radius
    if abs(share) > 1.0:
        raise fail("arc to straight motion makes a corner the compensated tool can't fit in without gouging")
    sign = 1.0 if (turn > 0) != inside else -1.0
    angle = sign * np.arccos(share) + across + np.pi
    return centre + old_radius * np.array([np.cos(angle), np.sin(angle)])


def _queue(comp: Compensation, moves: list[Any], add: Callable[[Segment], None], segment: Segment,
           direction: np.ndarray | None, sweep: float = 0.0) -> None:
    """Record a move whose end a later corner may move."""
    add(_frame(comp, segment))
    comp.queue.append((len(moves) - 1, direction, sweep))
    comp.tool_m = segment.end_m.copy()


def circular(comp: Compensation, moves: list[Any], end_m: np.ndarray, centre_xy: np.ndarray, turn: int, fail: Fail,
             add: Callable[[Segment], None]) -> None:
    """A compensated G2/G3 (``turn`` > 0 anticlockwise) of the programmed arc from the programmed point to end_m
    (3,) about centre_xy; the entry move may not be an arc."""
    p, o, c, r = end_m, comp.programmed_m, comp.tool_m.copy(), comp.radius_m
    arc_radius = float(np.hypot(*(centre_xy - p[:2])))
    if comp.first:
        _entry_arc(comp, moves, end_m, centre_xy, turn, fail, add)
        return
    theta = float(np.arctan2(c[1] - o[1], c[0] - o[0])) + (-np.pi / 2 if comp.left else np.pi / 2)
    delta = float(np.arctan2(centre_xy[1] - o[1], centre_xy[0] - o[0]))
    alpha = delta - np.pi / 2 if turn > 0 else delta + np.pi / 2
    beta = theta - alpha if comp.left else alpha - theta
    beta = beta - 2 * np.pi if beta > 1.5 * np.pi else beta + 2 * np.pi if beta < -np.pi / 2 else beta
    inside = _inside(comp, turn)
    if inside:
        gamma = float(np.arctan2(centre_xy[1] - p[1], centre_xy[0] - p[0]))
        if arc_radius <= r:
            raise fail(f"the tool radius ({r / 1e-3:.6g} mm) is not less than the arc's radius "
                       f"({arc_radius / 1e-3:.6g} mm): the compensated arc has no radius left")
    else:
        gamma = float(np.arctan2(p[1] - centre_xy[1], p[0] - centre_xy[0]))
        delta += np.pi
    end = np.array([p[0] + r * np.cos(gamma), p[1] + r * np.sin(gamma), p[2]])
    small = TOLERANCE_CONCAVE_CORNER_RAD
    if beta < -small or beta > np.pi + small or (abs(beta - np.pi) < small and not inside):  # concave
        previous = _local(comp, moves[comp.queue[0][0]].segment) if comp.queue else None
        _move_ends(comp, moves, _concave_arc(comp, previous, centre_xy, arc_radius, turn, theta, beta, fail), fail)
    elif beta > small:  # convex: round the corner about the programmed point first
        _release(comp, None)
        corner = np.array([o[0] + r * np.cos(delta), o[1] + r * np.sin(delta), c[2]])
        add(_frame(comp, arc(c, corner, o[:2], find_turn(c[:2], o[:2], -1 if comp.left else 1, corner[:2]))))
        comp.tool_m = corner
        _release(comp, corner[:2])
    else:
        _release(comp, c[:2])
    start = comp.tool_m.copy()
    sweep = find_turn(o[:2], centre_xy, turn, p[:2])
    _queue(comp, moves, add, arc(start, end, centre_xy, find_turn(start[:2], centre_xy, turn, end[:2])), None, sweep)
    comp.programmed_m = p.copy()


def _entry_arc(comp: Compensation, moves: list[Any], end_m: np.ndarray, centre_xy: np.ndarray, turn: int, fail: Fail,
               add: Callable[[Segment], None]) -> None:
    """The entry move as an arc: from the tool's point to r off the programmed end, on an arc tangent to the tool
    there (LinuxCNC's convert_arc_comp1)."""
    p, c, r = end_m, comp.tool_m.copy(), comp.radius_m
    if np.abs(comp.entry_start_m - c).max() > 0:
        raise fail("an entry arc right after G40, from where the tool was left off the programmed point, is not "
                   "computed: move to a point first")
    if np.hypot(*(p[:2] - c[:2])) <= r:
        raise fail("radius of cutter compensation entry arc is not greater than the tool radius")
    inside = _inside(comp, turn)
    if inside and np.hypot(*(centre_xy - c[:2])) <= r:
        raise fail("the tool radius is not less than the arc's radius: the compensated arc has no radius left")
    towards = centre_xy - p[:2] if inside else p[:2] - centre_xy
    end = np.array([*(p[:2] + r * towards / np.hypot(*towards)), p[2]])
    half_chord = float(np.hypot(*(c[:2] - end[:2]))) / 2
    to_centre = float(np.arctan2(centre_xy[1] - end[1], centre_xy[0] - end[0]))
    angle = float(np.arctan2(c[1] - end[1], c[0] - end[0])) - to_centre
    if abs(np.cos(angle)) < TOLERANCE_EQUAL:
        raise fail("the tool radius is not less than the arc's radius: the entry arc cannot be compensated")
    centre = end[:2] + half_chord / np.cos(angle) * np.array([np.cos(to_centre), np.sin(to_centre)])
    comp.first = False
    _release(comp, c[:2])
    sweep = find_turn(c[:2], centre, turn, end[:2])
    _queue(comp, moves, add, arc(c, end, centre, sweep), None, sweep)
    comp.programmed_m = p.copy()


def _concave_arc(comp: Compensation, previous: Segment | None, centre: np.ndarray, arc_radius: float, turn: int,
                 theta: float, beta: float, fail: Fail) -> np.ndarray:
    """Where the previous offset move must end for an arc into a concave corner."""
    r, inside = comp.radius_m, _inside(comp, turn)
    if previous is None or previous.center_m is None:  # line -> arc
        toward = arc_radius * np.sin(beta - np.pi / 2)
        reach = arc_radius - r if inside else arc_radius + r
        share = (toward + r if inside else toward - r) / reach
        if abs(share) > 1.0:
            raise fail("arc move in a concave corner cannot be reached by the tool without gouging")
        if inside:
            angle = theta + np.arcsin(share) if turn > 0 else theta - np.arcsin(share)
        else:
            angle = theta + np.pi - np.arcsin(share) if turn > 0 else theta + np.pi + np.arcsin(share)
        return centre + reach * np.array([np.cos(angle), np.sin(angle)])
    old_centre = previous.center_m[:2]  # arc -> arc
    old_radius = float(np.hypot(*(old_centre - previous.end_m[:2])))
    new_radius = arc_radius - r if inside else arc_radius + r
    apart = float(np.hypot(*(centre - old_centre)))
    if old_radius == 0 or apart == 0:
        raise fail("arc to arc motion is invalid because the arcs have the same centre")
    share = (old_radius**2 + apart**2 - new_radius**2) / (2 * old_radius * apart)
    if abs(share) > 1.0:
        raise fail("arc to arc motion makes a corner the compensated tool can't fit in without gouging")
    pullback = float(np.arccos(share))
    towards = float(np.arctan2(centre[1] - old_centre[1], centre[0] - old_centre[0]))
    sign = 1.0 if _inside(comp, previous.sweep_rad) == (turn > 0) else -1.0
    direction = towards + sign * pullback
    return old_centre + old_radius * np.array([np.cos(direction), np.sin(direction)])


def end_compensation(comp: Compensation, moves: list[Any], fail: Fail) -> np.ndarray:
    """G40: the queued moves released (checked); returns the tool centre (3,), where the next move starts."""
    if not comp.first:
        _move_ends(comp, moves, comp.tool_m[:2].copy(), fail)
    return comp.tool_m.copy()
