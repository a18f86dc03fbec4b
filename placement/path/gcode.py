"""G-code programs (RS-274/NGC as LinuxCNC reads it, and what CAM posts write) read into path segments.

The program's coordinates are the path frame's: its X, Y, Z are X_p, Y_p, Z_p (Z_p the tool
axis, pointing out of the workpiece) and its origin is the path frame's origin, which the
placement moves. Lines are read by :mod:`placement.path.ngc_expressions` (parameters,
expressions, functions) and run in the order of :mod:`placement.path.ngc_flow` (O-word
subroutines, conditions, loops); :mod:`placement.path.ngc_words` says which words are read,
:mod:`placement.path.arcs` makes the arcs, :mod:`placement.path.canned` the drilling
cycles' moves and :mod:`placement.path.compensation` the tool centre's path under cutter radius
compensation (G41, G42). On each line the words act in the order of RS-274/NGC (feed
mode, F, S, dwell, plane, units, ..., then the move), whatever their order on the line, and
words of one modal group may not appear twice on a line. docs/paths.md lists every word with
what it does to the energy and the time.

Where the tool starts: an axis the program never gives stays at the path frame's origin (a 2-D
program runs in the X_p Y_p plane). An axis given somewhere in the program is unknown until it
is given (or after a return to a reference point the path file does not give): a move from an
unknown position is left out (a feed move with a note). Work offsets (G10, G54-G59.3) and G92's
shift the program's coordinates into the path frame (:mod:`placement.path.ngc_offsets`). Other
controllers' words are read as their controller does, with warnings (:mod:`placement.path.ngc_dialects`).
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from placement.path.arcs import SAME_POINT_M, arc_segment, shifted
from placement.path.canned import CYCLES, CycleState, expand_cycle, first_hole
from placement.path.compensation import Compensation, begin, circular, end_compensation, straight, tool_diameter_m
from placement.path.exceptions import GcodeDialectWarning, GcodeError, PathFileError, _CycleError, _ExpressionError, _FlowError
from placement.path.ngc_dialects import Extruder, dialect_notes, dialect_words, grbl_command, marlin_program
from placement.path.ngc_expressions import Block, Parameters, read_line
from placement.path.ngc_flow import run_blocks
from placement.path.ngc_offsets import Offsets, additional_system, g10, g92, select_system
from placement.path.ngc_text import program_text
from placement.path.ngc_words import EXTRA_AXES, check_unused, extra_axes, polar_words, sorted_words
from placement.path.segments import Segment

MM_M = 1e-3
INCH_M = 0.0254
MAX_LINE_CHARS = 1000
INITIAL_FEED_HOW = ("--initial-feed MM_PER_MIN on the command line, or shape.initial_feed_m_s (m/s) in the path file "
                    "(docs/paths.md)")
STOPS_M = {0, 1, 60}  # program pauses: the tool stops there


@dataclass(frozen=True)
class Machine:
    """Positions the program may refer to that only the machine holds, in machine coordinates (metres).

    Attributes:
        work_offset_m: (3,) where the path frame's origin (the program's origin) is in machine coordinates.
        g28_m, g30_m: (3,) the reference positions G28 and G30 move to (None: not given).
        given: Whether the path file gave these (G53 needs it; without, G53 moves are left out).
        tool_diameters_m: Each tool's diameter by its number (what G41 and G42 offset the path by).
        initial_feed_m_s: The controller's modal feed when the program starts, which feed moves before the
            program's first F run at (None: such a move is refused).
    """

    work_offset_m: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))
    g28_m: np.ndarray | None = None
    g30_m: np.ndarray | None = None
    given: bool = False
    tool_diameters_m: dict[int, float] = dataclasses.field(default_factory=dict)
    initial_feed_m_s: float | None = None


@dataclass(frozen=True)
class Dwell:
    """A hold of the tool at rest (G4, or a canned cycle's P).

    Attributes:
        after: The number of segments before it (it holds at the end of the last one).
        duration_s: How long.
        line: The program line.
    """

    after: int
    duration_s: float
    line: int


@dataclass(frozen=True)
class Program:
    """The moves of a G-code program in the path frame.

    Attributes:
        segments: Every move from the first known point on, rapids included (``rapid``),
            each feed move's ``feed_ratio`` its feed as a share of ``feed_m_s``.
        feed_m_s: The highest feed rate of the program's feed moves.
        dwells: The program's dwells, in order.
        notes: What the reader left out and why, once per kind.
    """

    segments: tuple[Segment, ...]
    feed_m_s: float
    dwells: tuple[Dwell, ...] = ()
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class _Move:
    """A move as executed: its segment, feed (None: rapid), line and word, and the axes unknown at its start."""

    segment: Segment
    feed_m_s: float | None
    line: int
    word: str
    unknown: frozenset[int]


@dataclass
class _State:
    """The modal state of the interpreter between lines."""

    machine: Machine
    length_m: float = MM_M  # metres per program length unit
    units_given: bool = False  # a G20 or G21 was read
    incremental: bool = False
    absolute_centres: bool = False  # G90.1 (else G91.1, offsets from the start)
    plane: int = 17
    motion: int | None = None  # in tenths
    plain_motion: int | None = None  # the last G0-G3: the motion after G80, as on Fanuc-style controls
    feed_mode: int = 940
    feed: float | None = None  # F as given, in ...
    feed_unit_m: float = MM_M  # ... the length unit of its line
    spindle_rpm: float | None = None
    exact_path: bool = False  # G61
    exact_stop: bool = False  # G61.1
    cycle: CycleState = dataclasses.field(default_factory=CycleState)
    stored: dict[int, np.ndarray] = dataclasses.field(default_factory=dict)  # 280, 300 -> G28.1, G30.1's (path frame)
    offsets: Offsets = dataclasses.field(default_factory=lambda: Offsets(np.full(3, np.nan)))  # G10, G54-G59.3, G92
    offset_m: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))  # path frame - program's (offsets')
    extra_axes: dict[str, float] = dataclasses.field(default_factory=dict)  # A, B, C, U, V, W: the one value held
    extruder: Extruder = dataclasses.field(default_factory=Extruder)  # a 3D printer's E, which must stay put
    position_m: list[float | None] = dataclasses.field(default_factory=lambda: [None, None, None])
    given: set[int] = dataclasses.field(default_factory=set)  # the axes given a value so far
    moves: list[_Move] = dataclasses.field(default_factory=list)
    dwells: list[Dwell] = dataclasses.field(default_factory=list)
    notes: dict[str, str] = dataclasses.field(default_factory=dict)
    dialect: dict[str, list[int]] = dataclasses.field(default_factory=dict)  # a controller's words read: their lines
    line: int = 0  # the line being run
    tool_selected: int | None = None  # T
    tool_loaded: int | None = None  # M6
    compensation: Compensation | None = None  # G41, G42 under way
    tool_start_m: np.ndarray | None = None  # after G40: where the next move starts (the tool's offset point)


def read_program(file: Path, machine: Machine | None = None) -> Program:
    """Read a G-code program.

    Args:
        file: The program.
        machine: The reference positions and work offset the path file gives (default: none).

    Returns:
        Its moves, in metres and m/s.

    Raises:
        PathFileError: The file is missing or unreadable.
        GcodeError: A line breaks the supported dialect (docs/paths.md); names line and word.
    """
    text = program_text(file)
    blocks: list[Block] = []
    for number, line in enumerate(text.splitlines(), start=1):
        if len(line) > MAX_LINE_CHARS and len(line.partition(";")[0]) > MAX_LINE_CHARS:  # (a long comment is read)
            raise GcodeError(file, number, "", f"the line is longer than {MAX_LINE_CHARS} characters")
        blocks.append(read_line(line))
    machine = machine or Machine()
    state = _State(machine, offsets=Offsets(np.array(machine.work_offset_m, dtype=float) if machine.given
                                            else np.full(3, np.nan)))

    def execute(index: int, words: list[tuple[str, float, str]], depth: int) -> bool:
        def fail(word: str, problem: str) -> GcodeError:
            return GcodeError(file, index + 1, word, problem)

        return _execute(fail, index + 1, words, state, depth)

    def system(index: int, text: str) -> None:
        _system_command(lambda problem: GcodeError(file, index + 1, text, problem), index + 1, text, state)

    try:
        run_blocks(blocks, Parameters(), execute, system)
    except (_FlowError, _ExpressionError) as error:  # (a line that cannot be run, or read)
        raise GcodeError(file, error.index + 1, error.text, error.problem) from None
    if marlin_program(state.dialect):  # Marlin's G4 P is in milliseconds
        in_ms = set(state.dialect.get("G4 P", []))
        state.dwells = [dataclasses.replace(d, duration_s=d.duration_s * 1e-3) if d.line in in_ms else d
                        for d in state.dwells]
    program = _program(file, state)
    for text in dialect_notes(state.dialect, state.machine.g28_m is not None, state.machine.initial_feed_m_s):
        warnings.warn(f"{file}: {text}", GcodeDialectWarning, stacklevel=2)
    return program


def _program(file: Path, state: _State) -> Program:
    """The moves kept: a move from an unknown position is left out (a feed move with a note)."""
    kept: list[tuple[Segment, float | None]] = []
    dwells, next_dwell = [], 0
    for number, move in enumerate(state.moves):
        while next_dwell < len(state.dwells) and state.dwells[next_dwell].after <= number:
            dwells.append(dataclasses.replace(state.dwells[next_dwell], after=len(kept)))
            next_dwell += 1
        unknown = move.unknown & state.given
        if unknown and move.feed_m_s is not None:
            missing = ", ".join("XYZ"[k] for k in sorted(unknown))
            _note(state, "unknown start", f"the feed move of line {move.line} starts from an unknown position "
                                          f"({missing} not given yet), where the machine happens to be: it is "
                                          "left out (move to a point with G0 first to count it)")
        if unknown or (move.segment.center_m is None and move.segment.length_m <= SAME_POINT_M):  # (compensation's)
            continue
        kept.append((move.segment, move.feed_m_s))
    dwells += [dataclasses.replace(d, after=len(kept)) for d in state.dwells[next_dwell:]]
    feeds = [feed for _, feed in kept if feed is not None]
    if not feeds:
        raise PathFileError(file, "", "no tool motion: the program has no feed move (G1, G2, G3 or a drilling "
                                      "cycle) from a known point, so there is no path to place")
    if not state.units_given:
        _note(state, "units", "the program never gives its units (G20 inches, G21 mm): read in millimetres")
    top = max(feeds)
    segments = tuple(dataclasses.replace(segment, feed_ratio=feed / top) if feed is not None else segment
                     for segment, feed in kept)
    return Program(segments, top, tuple(dwells), tuple(state.notes.values()))


def _execute(fail: Callable[[str, str], GcodeError], line: int, words: list[tuple[str, float, str]],
             state: _State, depth: int = 0) -> bool:
    """Apply one line's words to the state, in RS-274/NGC's order; False at the program's end (M2, M30, M99 in
    the main program)."""
    state.line = line
    codes, m_codes, values, written = sorted_words(fail, words)
    for kind in dialect_words(fail, codes, m_codes, values, written, depth, state.extruder):
        state.dialect.setdefault(kind, []).append(line)
    if "feed mode" in codes:
        state.feed_mode = codes["feed mode"][0]
    if "units" in codes:  # before F and the axes: their numbers are in the line's units (G70, G71: Mach3's)
        state.length_m, state.units_given = INCH_M if codes["units"][0] in (200, 700) else MM_M, True
    if "F" in values:
        if not values["F"] > 0:
            raise fail(written["F"], "the feed rate must be > 0")
        state.feed, state.feed_unit_m = values["F"], state.length_m
    if "S" in values:
        if values["S"] < 0:
            raise fail(written["S"], "the spindle speed must be ≥ 0")
        state.spindle_rpm = values["S"]
    non_modal = codes.get("non-modal")
    if non_modal is not None and non_modal[0] == 40:
        if "P" not in values or values["P"] < 0:
            raise fail(non_modal[1], "a dwell needs its duration P ≥ 0 (seconds)")
        state.dwells.append(Dwell(len(state.moves), values["P"], line))
    state.tool_selected = round(values["T"]) if "T" in values else state.tool_selected
    if 6 in m_codes:
        if state.compensation is not None:
            raise fail(m_codes[6], "a tool change while cutter radius compensation is on: turn it off first (G40)")
        state.tool_loaded = state.tool_selected
    if "plane" in codes:
        if state.compensation is not None and codes["plane"][0] // 10 != state.plane:
            raise fail(codes["plane"][1], "the plane changes while cutter radius compensation is on")
        state.plane = codes["plane"][0] // 10
    if "cutter compensation" in codes:
        _compensation_mode(fail, codes["cutter compensation"], values, written, state)
    if "coordinate system" in codes:
        if codes["coordinate system"][0] in (541, 1540):
            state.dialect.setdefault("G54.1 P", []).append(line)
        select_system(fail, additional_system(fail, codes["coordinate system"], values, written), state.offsets,
                      state.compensation is not None)
        state.offset_m = state.offsets.total_m()
    if "path control" in codes:
        code = codes["path control"][0]
        state.exact_path, state.exact_stop = code == 610, code == 611
    if "distance" in codes:
        state.incremental = codes["distance"][0] == 910
    if "arc distance" in codes:
        state.absolute_centres = codes["arc distance"][0] == 901
    if "retract mode" in codes:
        state.cycle.retract_to_r = codes["retract mode"][0] == 990
    if non_modal is not None and non_modal[0] == 100:  # G10's extra axis words are offsets of axes the path has not
        for letter in EXTRA_AXES:
            values.pop(letter, None)
            written.pop(letter, None)
    for letter, word, held in extra_axes(fail, values, written, state.extra_axes, state.incremental):
        _note(state, letter, f"{word} (line {line}): the axis {letter} holds {held:g}; the path has X, Y, Z only, so "
                             "it is ignored while it holds that value")
    motion = codes["motion"][0] if "motion" in codes else state.motion
    check_unused(fail, codes, values, written, motion, m_codes)
    if ("@" in values or "^" in values) and not (motion is not None and motion // 10 in CYCLES):
        here = [None if p is None else p - o for p, o in zip(state.position_m[:2], state.offset_m[:2])]
        polar_words(fail, values, written, here, state.length_m, state.incremental)
    axes = [values.get(letter) for letter in "XYZ"]
    if non_modal is not None and non_modal[0] in (921, 922, 923):  # before the line's move, which they leave alone
        state.offsets.clear_g92(non_modal[0])
        state.offset_m = state.offsets.total_m()
    if non_modal is not None and non_modal[0] in (280, 300) and state.compensation is not None:
        raise fail(non_modal[1], "G28 and G30 cannot run under cutter radius compensation: G40 first")
    if non_modal is not None and non_modal[0] in (280, 300):
        _reference(fail, non_modal, axes, written, line, state)
    elif non_modal is not None and non_modal[0] == 920:  # its axis words are the offset's, not a move
        g92(fail, non_modal[1], axes, state.length_m, state.position_m, state.given, state.offsets)
        state.offset_m = state.offsets.total_m()
    elif non_modal is not None and non_modal[0] == 100:  # its axis words are the offsets', not a move
        known = g10(fail, non_modal[1], values, written, state.length_m, state.position_m,
                    state.compensation is not None, line, state.offsets)
        for axis, value in known.items():
            state.position_m[axis] = value
            state.given.add(axis)
        state.offset_m = state.offsets.total_m()
    elif non_modal is not None and non_modal[0] in (281, 301):
        if any(value is None for value in state.position_m) and state.given:
            raise fail(non_modal[1], "the position to store is not known yet")
        state.stored[non_modal[0] - 1] = np.array([p if p is not None else 0.0 for p in state.position_m])
    else:
        if "canned cycle" in codes:
            state.motion = state.plain_motion
            state.cycle.initial_level_m = None
        if "motion" in codes:
            previous, state.motion = state.motion, codes["motion"][0]
            if state.motion // 10 not in CYCLES:
                state.cycle.initial_level_m = None
                state.plain_motion = state.motion
        else:
            previous = state.motion
        arc_words = [letter for letter in "IJKR" if letter in values and not (letter == "R" and 19 in m_codes)]
        if arc_words and state.motion not in (20, 30) and (state.motion is None or state.motion // 10 not in CYCLES):
            raise fail(written[arc_words[0]], "I, J, K and R belong to arcs (G2, G3), R also to drilling cycles and "
                                              "M19")
        if any(value is not None for value in axes) or "@" in values or "^" in values or (
                state.motion in (20, 30) and any(letter in values for letter in "IJK")):  # (a full circle)
            _motion(fail, codes, axes, values, written, line, state, previous)
    if 25 in m_codes:
        _z_home(fail, m_codes[25], line, state)
    if any(code in m_codes for code in STOPS_M) and state.moves:
        state.moves[-1] = dataclasses.replace(state.moves[-1], segment=dataclasses.replace(
            state.moves[-1].segment, exact_stop=True))
    return not (2 in m_codes or 30 in m_codes or 99 in m_codes)


def _compensation_mode(fail: Callable[[str, str], GcodeError], code_word: tuple[int, str],
                       values: dict[str, float], written: dict[str, str], state: _State) -> None:
    """G40 ends cutter radius compensation; G41 (left), G42 (right) start it with tool D's (else the loaded tool's)
    diameter from the path file, G41.1 and G42.1 with the diameter D (program units)."""
    code, word = code_word
    if code == 400:
        if state.compensation is not None:
            state.tool_start_m = state.compensation.axes @ end_compensation(state.compensation, state.moves,
                                                                            lambda problem: fail(word, problem))
            state.compensation = None
        return
    if state.compensation is not None:
        raise fail(word, "cutter radius compensation is already on: turn it off (G40) before changing it")
    diameter = tool_diameter_m(fail, code_word, values, written, state.tool_loaded, state.machine.tool_diameters_m,
                               state.length_m)
    if diameter != 0:
        state.compensation = begin(lambda problem: fail(word, problem), code in (410, 411), diameter,
                                   state.length_m, state.position_m, state.given, state.tool_start_m, state.plane)


def _compensated(fail: Callable[[str, str], GcodeError], values: dict[str, float], written: dict[str, str],
                 target: list[float | None], line: int, move_word: str, state: _State) -> None:
    """A G0-G3 move under cutter radius compensation (:mod:`placement.path.compensation`)."""
    comp, end = state.compensation, np.array([0.0 if value is None else value for value in target])
    assert comp is not None  # (an axis still None is the plane's normal, never given yet: at the origin)
    local_end = comp.axes.T @ end
    blame: Callable[[str], GcodeError] = lambda problem: fail(move_word, problem)  # noqa: E731
    if state.motion in (0, 10):
        feed = None if state.motion == 0 else _feed(fail, state, move_word,
                                                    float(np.linalg.norm(local_end - comp.programmed_m)), values)
    else:
        programmed = arc_segment(lambda problem, letter=None: fail(written.get(letter or "", move_word), problem),
                                 comp.axes @ comp.programmed_m - state.offset_m, end - state.offset_m, values, state.plane,
                                 state.motion == 30, state.length_m, state.absolute_centres)
        assert programmed.center_m is not None
        feed = _feed(fail, state, move_word, programmed.length_m, values)
        turns = int(np.ceil(abs(programmed.sweep_rad) / (2 * np.pi) - 1e-9))
        centre = (comp.axes.T @ (programmed.center_m + state.offset_m))[:2]

    def add(segment: Segment) -> None:
        made = dataclasses.replace(segment, exact_path=state.exact_path, exact_stop=state.exact_stop)
        state.moves.append(_Move(made, feed, line, move_word, frozenset(k for k in range(3) if target[k] is None)))

    if state.motion in (0, 10):
        straight(comp, state.moves, local_end, state.motion == 0, blame, add)
    else:
        circular(comp, state.moves, local_end, centre, turns if state.motion == 30 else -turns, blame, add)
    state.position_m = [None if value is None else float(e) for value, e in zip(target, end)]
    state.offsets.bind({k for k in range(3) if target[k] is not None})


def _note(state: _State, key: str, text: str) -> None:
    """A note printed once per kind."""
    state.notes.setdefault(key, text)


def _z_home(fail: Callable[[str, str], GcodeError], word: str, line: int, state: _State) -> None:
    """M25, as Centroid's controls read it: Z alone to the machine's home at rapid (the home the path file gives as
    the G28 reference, shape.machine.g28_mm); without it Z is unknown after it, like a retract that ends the cut."""
    if state.compensation is not None:
        raise fail(word, "M25 (Z home) cannot run under cutter radius compensation: G40 first")
    state.dialect.setdefault("M25", []).append(line)
    home = state.machine.g28_m
    z = None if home is None else float(home[2] - state.offsets.origin()[2])
    end = list(state.position_m)
    end[2] = None if z is None or np.isnan(z) else z
    _add(state, end, None, line, word)


def _system_command(fail: Callable[[str], GcodeError], line: int, text: str, state: _State) -> None:
    """A grbl system command or Marlin's homing (:func:`~placement.path.ngc_dialects.grbl_command`): homing leaves the
    position unknown."""
    homed = grbl_command(fail, text, state.compensation is not None)
    for k in homed:
        state.position_m[k] = None
    state.tool_start_m = None if homed else state.tool_start_m
    state.dialect.setdefault("G28 homing" if text.startswith("G") else "$H" if homed else "$", []).append(line)


def _target(axes: list[float | None], state: _State, fail: Callable[[str, str], GcodeError], word: str,
            machine_coordinates: bool = False) -> list[float | None]:
    """The end point of a move to the given axes (None: not given), in metres."""
    target: list[float | None] = []
    for k, value in enumerate(axes):
        if value is None:
            target.append(state.position_m[k])
        elif machine_coordinates:
            target.append(value * state.length_m - float(state.offsets.origin()[k]))
        elif state.incremental:
            start = state.position_m[k]
            if start is None and value == 0:  # "G28 G91 Z0": no move along an unknown axis
                target.append(None)
            elif start is None:
                raise fail(word, f"an incremental {'XYZ'[k]} move from an unknown position: give the absolute "
                                 "position first (G90)")
            else:
                target.append(start + value * state.length_m)
        else:
            target.append(value * state.length_m + state.offset_m[k])
    return target


def _add(state: _State, end: list[float | None], feed: float | None, line: int, word: str,
         segment: Callable[[np.ndarray, np.ndarray], Segment | None] | None = None, exact: bool = False) -> None:
    """Record a move to ``end`` (a line, or ``segment(start, end)``) and move there; None in ``end`` leaves the
    axis unknown."""
    start: list[float | None] = state.position_m if state.tool_start_m is None else [
        None if here is None else float(tool) for here, tool in zip(state.position_m, state.tool_start_m)]
    state.tool_start_m = None
    unknown = frozenset(k for k in range(3) if start[k] is None)
    state.position_m = list(end)
    state.given |= {k for k in range(3) if end[k] is not None}
    state.offsets.bind({k for k in range(3) if end[k] is not None})
    if any(end[k] is None and start[k] is not None for k in range(3)):
        return  # to an unknown place (a reference position not given)
    # An axis unknown at both ends is at the origin if the program never gives it (else the move is left out).
    begin = np.array([value if value is not None else 0.0 for value in start])
    finish = np.array([value if value is not None else 0.0 for value in end])
    if segment is None:
        if np.linalg.norm(finish - begin) <= SAME_POINT_M:
            return
        made: Segment | None = Segment(begin, finish, rapid=feed is None)
    else:
        made = segment(begin, finish)
    if made is None:
        return
    if state.exact_path or exact or state.exact_stop:  # (a segment is made without either)
        made = dataclasses.replace(made, exact_path=state.exact_path or exact, exact_stop=state.exact_stop)
    state.moves.append(_Move(made, feed, line, word, unknown))


def _reference(fail: Callable[[str, str], GcodeError], non_modal: tuple[int, str], axes: list[float | None],
               written: dict[str, str], line: int, state: _State) -> None:
    """G28, G30: a rapid to the point given (if any), then the given axes (all if none) to the reference."""
    code, word = non_modal
    move_word = next((written[a] for a in "XYZ" if a in written), word)
    if any(value is not None for value in axes):
        _add(state, _target(axes, state, fail, move_word), None, line, move_word)
    machine_point = state.machine.g28_m if code == 280 else state.machine.g30_m  # NaN: its origin is not known
    reference = state.stored.get(code, None if machine_point is None else machine_point - state.offsets.origin())
    moved = [k for k in range(3) if axes[k] is not None] or [0, 1, 2]
    end = list(state.position_m)
    for k in moved:
        end[k] = None if reference is None or np.isnan(reference[k]) else float(reference[k])
    if reference is None:
        _note(state, f"G{code // 10}", f"G{code // 10} (line {line}) moves to the machine's reference position, "
                                       f"which the path file does not give (shape.machine.g{code // 10}_mm): the "
                                       "rapids to and from it are left out")
    elif any(end[k] is None for k in moved):
        _note(state, f"G{code // 10}", f"G{code // 10} (line {line}) goes to the machine's reference position, not "
                                       f"known in the path frame (G10 L20 at line {state.offsets.set_where_unknown} set "
                                       "the origin where the machine happened to be): the rapids are left out")
    _add(state, end, None, line, word)


def _feed(fail: Callable[[str, str], GcodeError], state: _State, word: str, length_m: float,
          values: dict[str, float]) -> float:
    """The feed (m/s) of a feed move of the given length in the current feed mode."""
    if state.feed_mode == 930:
        if "F" not in values:
            raise fail(word, "in inverse time mode (G93) every feed move gives its F (1/minutes)")
        return length_m * values["F"] / 60.0
    if state.feed is None and state.feed_mode == 940 and state.machine.initial_feed_m_s is not None:
        state.dialect.setdefault("initial feed", []).append(state.line)
        return state.machine.initial_feed_m_s
    if state.feed is None:
        given = ("F (per revolution in G95) first" if state.feed_mode == 950 else
                 f"F first, or the controller's modal feed it runs at: {INITIAL_FEED_HOW}")
        raise fail(word, f"a feed move (G{(state.motion or 0) // 10}) before any feed rate: give {given}")
    if state.feed_mode == 950:
        if not state.spindle_rpm:
            raise fail(word, "feed per revolution (G95) needs the spindle speed S > 0")
        return state.feed * state.feed_unit_m * state.spindle_rpm / 60.0
    return state.feed * state.feed_unit_m / 60.0


def _motion(fail: Callable[[str, str], GcodeError], codes: dict[str, tuple[int, str]], axes: list[float | None],
            values: dict[str, float], written: dict[str, str], line: int, state: _State,
            previous: int | None) -> None:
    """The line's move: G0, G1, G2, G3 (in machine coordinates with G53) or a drilling cycle."""
    move_word = next((written[a] for a in "XYZ" if a in written), codes.get("motion", ("", ""))[1])
    if state.motion is None:  # grbl, Fanuc, Haas and Mach3 controls start in G0 (LinuxCNC in none: it refuses this)
        state.motion = state.plain_motion = 0
        state.dialect.setdefault("G0 at start", []).append(line)
    if state.incremental and not state.given:  # a program that starts in G91: from where the tool stands, its origin
        state.position_m = [float(o) if p is None else p for p, o in zip(state.position_m, state.offset_m)]
        state.dialect.setdefault("G91 at start", []).append(line)
    if state.compensation is not None and (codes.get("non-modal", (0, ""))[0] == 530 or state.motion // 10 in CYCLES):
        raise fail(move_word, "G53 moves and drilling cycles cannot run under cutter radius compensation: G40 first")
    if codes.get("non-modal", (0, ""))[0] == 530:
        if state.motion not in (0, 10) or state.incremental:
            raise fail(codes["non-modal"][1], "G53 moves in machine coordinates with G0 or G1, in G90")
        origin = state.offsets.origin()
        if any(np.isnan(origin[k]) for k in range(3) if axes[k] is not None):
            cause = ("the path file does not give (shape.machine.work_offset_mm)" if not state.offsets.set_where_unknown
                     else f"G10 L20 at line {state.offsets.set_where_unknown} set where the machine happened to be")
            _note(state, "G53", f"G53 (line {line}) moves in machine coordinates, whose offset from the program's "
                                f"origin {cause}: those moves are left out")
            _add(state, [None if a is not None else p for a, p in zip(axes, state.position_m)], None, line, move_word)
            return
        target = _target(axes, state, fail, move_word, machine_coordinates=True)
    elif state.motion // 10 in CYCLES:
        _cycle(fail, codes, values, written, line, state, previous, move_word)
        return
    else:
        target = _target(axes, state, fail, move_word)
    if state.compensation is not None:
        _compensated(fail, values, written, target, line, move_word, state)
        return
    if state.motion == 0:
        _add(state, target, None, line, move_word)
        return
    if state.motion == 10:
        start = np.array([v if v is not None else 0.0 for v in state.position_m])
        end = np.array([v if v is not None else 0.0 for v in target])
        _add(state, target, _feed(fail, state, move_word, float(np.linalg.norm(end - start)), values), line,
             move_word)
        return
    start = np.array([v if v is not None else 0.0 for v in state.position_m]) - state.offset_m
    finish = np.array([v if v is not None else 0.0 for v in target]) - state.offset_m
    segment = shifted(arc_segment(lambda problem, letter=None: fail(written.get(letter or "", move_word), problem),
                                   start, finish, values, state.plane, state.motion == 30, state.length_m,
                                   state.absolute_centres), state.offset_m)
    _add(state, target, _feed(fail, state, move_word, segment.length_m, values), line, move_word,
         lambda begin, end: segment)


def _cycle(fail: Callable[[str, str], GcodeError], codes: dict[str, tuple[int, str]], values: dict[str, float],
           written: dict[str, str], line: int, state: _State, previous: int | None, move_word: str) -> None:
    """A drilling cycle's moves (:mod:`placement.path.canned`), in exact path mode as LinuxCNC runs them."""
    word = codes.get("motion", ("", move_word))[1]
    assert state.motion is not None
    if state.feed_mode == 930:
        raise fail(word, "drilling cycles cannot run in inverse time mode (G93)")
    if any(value is None for value in state.position_m):  # the rapids over the first hole, from an unknown point
        try:
            over_hole = first_hole(state.plane, state.incremental, state.length_m, state.position_m, state.offset_m,
                                   values)
        except _CycleError as error:
            raise fail(word, error.problem) from None
        _add(state, list(over_hole), None, line, word)
    position = [float(v - o) for v, o in zip(state.position_m, state.offset_m) if v is not None]  # program's
    try:
        steps = expand_cycle(state.motion // 10, state.plane, state.incremental, state.length_m,
                             state.length_m == INCH_M, position, values, previous == state.motion, state.cycle)
    except _CycleError as error:
        raise fail(written.get(error.letter, word), error.problem) from None
    feed = _feed(fail, state, word, 1.0, values)
    for step in steps:
        if step.kind == "dwell":
            state.dwells.append(Dwell(len(state.moves), step.dwell_s, line))
        else:
            assert step.target_m is not None
            _add(state, list(np.asarray(step.target_m) + state.offset_m), feed if step.kind == "feed" else None, line,
                 word, exact=True)
