"""G-code programs (a subset of RS-274/NGC) read into path segments.

The program's coordinates are the path frame's: its X, Y, Z are X_p, Y_p, Z_p (Z_p the tool
axis, pointing out of the workpiece) and its origin is the path frame's origin, which the
placement moves. Lines are read one at a time; on each line the words act in the order of
RS-274/NGC (units and feed before the move, whatever their order on the line), and words of one
modal group may not appear twice on a line.

Supported words:
    G0, G1: rapid and feed moves in a straight line.
    G2, G3: clockwise and anticlockwise arcs (seen from the positive end of the plane's normal),
        by centre offsets I, J, K (from the start point, always incremental) or by radius R
        (R > 0: the arc of at most 180°, R < 0: the longer one); I/J/K give full circles when
        the end is the start; a move along the plane's normal during an arc makes a helix.
    G17, G18, G19: arc plane XY (normal Z), ZX (normal Y), YZ (normal X).
    G20, G21: inches or millimetres (default G21) for the numbers of their line and after.
    G90, G91: absolute or incremental X, Y, Z (default G90).
    F: feed rate in the units per minute, for every later G1, G2, G3.
    G54-G59: the work coordinate system the program is written in, which is the path frame; a
        program switches between them at most once (from the default G54 to another).
    G80: cancels a canned cycle (none is ever active), as on Fanuc controls, where it does not
        share the motion words' group: the safety line "G0 G90 G40 G21 G17 G94 G80" is read.
    Accepted and ignored, as they do not change the tool path: N (line numbers), O (program
    numbers), % (tape marks), S (spindle speed), T (tool), H (a length offset's register), M2,
    M3, M4, M5, M6, M7, M8, M9, M30 (program end, spindle, tool change, coolant), G94 (feed per
    minute, the only feed mode), G40 (no cutter compensation), G43, G49 (tool length offset on
    and off: the program's coordinates are the tool tip's either way), and comments in
    parentheses or after a semicolon.

Anything else is an error naming the line and the word: other G and M words (cutter
compensation G41/G42, a second work coordinate system and G92 move the path by amounts the
program does not hold; canned cycles G81-G89 are not expanded), other letters (rotary axes A, B, C...),
parameters and expressions, a feed move before any F, and an arc whose ends do not fit its
radius (the end's distance from the I/J/K centre differs from the start's by more than
RADIUS_TOLERANCE_M and RADIUS_TOLERANCE_SHARE of the radius; |R| smaller than half the chord by as
much). Within the tolerance the I/J/K centre is moved onto the chord's perpendicular bisector.

Moves count from the first point where X, Y and Z are all known: a rapid before it is left out
(it starts from an unknown place) and a feed move before it is an error.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from placement.path.exceptions import GcodeError, PathFileError
from placement.path.segments import Segment

MM_M = 1e-3
INCH_M = 0.0254
RADIUS_TOLERANCE_M = 2e-6  # an I/J/K arc's end may be this much farther from the centre than its start ...
RADIUS_TOLERANCE_SHARE = 1e-3  # ... or this share of the radius, whichever is larger
SAME_POINT_M = 1e-9  # closer points are one point (a full circle, a move of no length)
MAX_PROGRAM_BYTES = 50_000_000
MAX_LINE_CHARS = 1000
PLANES = {17: np.eye(3)[:, [0, 1, 2]], 18: np.eye(3)[:, [2, 0, 1]], 19: np.eye(3)[:, [1, 2, 0]]}  # columns u, v, n
OFFSET_LETTERS = {17: "IJ", 18: "IK", 19: "JK"}
G_GROUPS = {0: "motion", 1: "motion", 2: "motion", 3: "motion", 80: "canned cycle", 17: "plane", 18: "plane",
            19: "plane", **{code: "coordinate system" for code in range(54, 60)},
            20: "units", 21: "units", 90: "distance", 91: "distance", 94: "feed mode", 40: "cutter compensation",
            43: "tool length offset", 49: "tool length offset"}
IGNORED_M = {2, 3, 4, 5, 6, 7, 8, 9, 30}
IGNORED_LETTERS = set("NOSTH")
VALUE_LETTERS = set("XYZIJKRF")
UNSUPPORTED_G = {
    41: "cutter radius compensation offsets the path by the tool radius: let the CAM post-processor output the "
        "compensated path (G40)",
    42: "cutter radius compensation offsets the path by the tool radius: let the CAM post-processor output the "
        "compensated path (G40)",
    92: "a coordinate system offset moves the program's origin: write the program in one work coordinate "
        "system, the path frame (its origin is the one the placement moves)",
    **{code: "canned cycles are not expanded: output them as G0/G1 moves" for code in range(81, 90)},
}
WORD = re.compile(r"([A-Z])([+-]?(?:\d+\.?\d*|\.\d+))")


@dataclass(frozen=True)
class Program:
    """The moves of a G-code program in the path frame.

    Attributes:
        segments: Every move from the first fully known point on, rapids included (``rapid``),
            each feed move's ``feed_ratio`` its F as a share of ``feed_m_s``.
        feed_m_s: The highest feed rate of the program's feed moves.
    """

    segments: tuple[Segment, ...]
    feed_m_s: float


@dataclass
class _State:
    """The modal state of the interpreter between lines."""

    length_m: float = MM_M  # metres per program length unit
    incremental: bool = False
    plane: int = 17
    motion: int | None = None
    coordinate_system: int | None = None  # G54-G59, once given
    feed_m_s: float | None = None
    position_m: list[float | None] = dataclasses.field(default_factory=lambda: [None, None, None])


def read_program(file: Path) -> Program:
    """Read a G-code program.

    Args:
        file: The program.

    Returns:
        Its moves, in metres and m/s.

    Raises:
        PathFileError: The file is missing or unreadable.
        GcodeError: A line breaks the supported subset (module docstring); names line and word.
    """
    if not file.is_file():
        raise PathFileError(file, "", "G-code program not found" if not file.exists() else "not a regular file")
    if file.stat().st_size > MAX_PROGRAM_BYTES:
        raise PathFileError(file, "", f"the program is larger than {MAX_PROGRAM_BYTES // 1_000_000} MB")
    try:
        text = file.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise PathFileError(file, "", "not a text file in UTF-8 (or ASCII)") from None
    state, moves = _State(), []
    for number, line in enumerate(text.splitlines(), start=1):
        move = _execute(file, number, _words(file, number, line), state)
        if move is not None:
            moves.append(move)
    feeds = [feed for _, feed in moves if feed is not None]
    if not feeds:
        raise PathFileError(file, "", "the program has no feed move (G1, G2 or G3) from a known point")
    top = max(feeds)
    return Program(tuple(dataclasses.replace(segment, feed_ratio=feed / top) if feed is not None else segment
                         for segment, feed in moves), top)


def _words(file: Path, number: int, line: str) -> list[tuple[str, str]]:
    """The words of a line as (letter, number text), comments and spaces removed."""
    if len(line) > MAX_LINE_CHARS:
        raise GcodeError(file, number, "", f"the line is longer than {MAX_LINE_CHARS} characters")
    code, depth = [], 0
    for char in line:
        if char == "(":
            if depth:
                raise GcodeError(file, number, "", "a comment may not hold '(' (nested comments)")
            depth = 1
        elif char == ")" and depth:
            depth = 0
        elif char == ";" and not depth:
            break
        elif not depth:
            code.append(char)
    if depth:
        raise GcodeError(file, number, "", "the comment opened by '(' is not closed on its line")
    compact = "".join(code).upper().replace(" ", "").replace("\t", "")
    if compact in ("", "%"):
        return []
    words, at = [], 0
    while at < len(compact):
        match = WORD.match(compact, at)
        if match is None or (match.end() < len(compact) and not compact[match.end()].isalpha()):
            end = at + 1
            while end < len(compact) and not compact[end].isalpha():
                end += 1
            text = compact[at:end]
            if not compact[at].isalpha():
                raise GcodeError(file, number, text, "expected a word: a letter and a number")
            raise GcodeError(file, number, text, "expected a number after the letter (e.g. X12.5, G1), without "
                                                 "parameters or expressions")
        words.append((match.group(1), match.group(2)))
        at = match.end()
    return words


def _sorted_words(fail: Callable[[str, str], GcodeError],
                  words: list[tuple[str, str]]) -> tuple[dict[str, tuple[int, str]], dict[str, float], dict[str, str]]:
    """A line's G words by modal group (code, word), its values by letter and their words as written; refuses
    words outside the subset and two words of one group or letter."""
    codes: dict[str, tuple[int, str]] = {}  # modal group -> (code, word)
    values: dict[str, float] = {}
    written: dict[str, str] = {}  # letter -> its word as written
    for letter, text in words:
        word = letter + text
        if letter == "G":
            code = _whole(text)
            if code not in G_GROUPS:
                raise fail(word, UNSUPPORTED_G.get(code if code is not None else -1,
                                                   "not in the supported G-code subset (docs/paths.md)"))
            group = G_GROUPS[code]
            if group in codes:
                raise fail(word, f"a second {group} word on the line (after {codes[group][1]})")
            codes[group] = (code, word)
        elif letter == "M":
            if _whole(text) not in IGNORED_M:
                raise fail(word, "not in the supported M-code subset (M2-M9, M30; docs/paths.md)")
        elif letter in VALUE_LETTERS:
            if letter in values:
                raise fail(word, f"{letter} is given twice on the line")
            values[letter], written[letter] = float(text), word
        elif letter not in IGNORED_LETTERS:
            raise fail(word, "unknown word: the supported letters are G, M, X, Y, Z, I, J, K, R, F, and N, O, S, T, "
                             "H (ignored)")
    return codes, values, written


def _execute(file: Path, number: int, words: list[tuple[str, str]], state: _State) -> tuple[Segment, float | None] | None:
    """Apply one line's words to the state; the move it makes, with its feed (None for a rapid), if any."""

    def fail(word: str, problem: str) -> GcodeError:
        return GcodeError(file, number, word, problem)

    codes, values, written = _sorted_words(fail, words)
    if "units" in codes:
        state.length_m = INCH_M if codes["units"][0] == 20 else MM_M
    if "F" in values:
        if not values["F"] > 0:
            raise fail(written["F"], "the feed rate must be > 0")
        state.feed_m_s = values["F"] * state.length_m / 60.0
    if "plane" in codes:
        state.plane = codes["plane"][0]
    if "distance" in codes:
        state.incremental = codes["distance"][0] == 91
    if "coordinate system" in codes:
        system, word = codes["coordinate system"]
        if state.coordinate_system not in (None, system) or (state.coordinate_system is None and system != 54
                                                            and state.position_m != [None, None, None]):
            raise fail(word, "the program changes work coordinate system: their offsets are not in the program; "
                             "write it in one system, the path frame")
        state.coordinate_system = system
    if "motion" in codes:
        state.motion = codes["motion"][0]
    axes = [values.get(letter) for letter in "XYZ"]
    arc_words = [letter for letter in "IJKR" if letter in values]
    if arc_words and state.motion not in (2, 3):
        raise fail(written[arc_words[0]], "I, J, K and R belong to arcs (G2, G3)")
    if all(value is None for value in axes):
        if arc_words:
            raise fail(written[arc_words[0]], "an arc needs its end point: at least one of X, Y, Z")
        return None
    move_word = next(written[a] for a in "XYZ" if a in written)  # the words below blame for the move
    if state.motion is None:
        raise fail(move_word, "an end point but no motion mode (G0, G1, G2, G3) is active")
    start = list(state.position_m)
    target: list[float | None] = []
    for k, value in enumerate(axes):
        if value is None:
            target.append(start[k])
        elif state.incremental:
            if start[k] is None:
                raise fail(move_word, f"an incremental {'XYZ'[k]} move from an unknown position: give the absolute "
                                  "position first (G90)")
            target.append(start[k] + value * state.length_m)  # type: ignore[operator]
        else:
            target.append(value * state.length_m)
    state.position_m = target
    if any(value is None for value in start):
        if state.motion != 0:
            missing = ", ".join("XYZ"[k] for k, value in enumerate(start) if value is None)
            raise fail(move_word, f"a feed move (G{state.motion}) from an unknown position ({missing} not given yet): "
                                  "move to a point with G0 first")
        return None
    if state.motion != 0 and state.feed_m_s is None:
        raise fail(move_word, f"a feed move (G{state.motion}) before any feed rate: give F (units per minute) first")
    begin, end = np.array(start, dtype=float), np.array(target, dtype=float)
    if state.motion in (0, 1):
        if np.linalg.norm(end - begin) <= SAME_POINT_M:
            return None
        return Segment(begin, end, rapid=state.motion == 0), (None if state.motion == 0 else state.feed_m_s)
    return _arc(lambda problem, letter=None: fail(written.get(letter or "", move_word), problem), begin, end, values,
                state), state.feed_m_s


def _whole(text: str) -> int | None:
    """A G or M number as an integer (None for G91.1 and the like)."""
    value = float(text)
    return int(value) if value == int(value) else None


def _arc(fail: Callable[..., GcodeError], start: np.ndarray, end: np.ndarray, values: dict[str, float],
         state: _State) -> Segment:
    """The arc or helix of a G2/G3 line, in metres; ``fail(problem, letter)`` makes the error blaming a word."""
    axes = PLANES[state.plane]
    s, e = start @ axes, end @ axes  # (u, v, n) coordinates
    chord = e[:2] - s[:2]
    distance = float(np.linalg.norm(chord))
    anticlockwise = state.motion == 3
    unit = state.length_m
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
        allowed = OFFSET_LETTERS[state.plane]
        wrong = [letter for letter in "IJK" if letter in values and letter not in allowed]
        if wrong:
            raise fail(f"G{state.plane} arcs take centre offsets {' and '.join(allowed)}", wrong[0])
        if not any(letter in values for letter in allowed):
            raise fail(f"an arc needs its centre: R, or offsets {' and '.join(allowed)}")
        offset = np.array([values.get(letter, 0.0) for letter in "IJK"]) * unit
        center = s[:2] + (offset @ axes)[:2]
        radius = float(np.linalg.norm(s[:2] - center))
        end_radius = float(np.linalg.norm(e[:2] - center))
        if radius <= SAME_POINT_M:
            raise fail("the arc's centre is its start point (radius 0)", allowed[0])
        tolerance = max(RADIUS_TOLERANCE_M, RADIUS_TOLERANCE_SHARE * radius)
        if abs(end_radius - radius) > tolerance:
            raise fail(f"the end is {end_radius / unit:.6g} from the centre but the start {radius / unit:.6g}: the "
                       f"radius does not fit (tolerance {tolerance / unit:.3g})", allowed[0])
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
    center_m = axes @ np.array([center[0], center[1], s[2]])
    return Segment(start, end, center_m, radius, start_angle, turn, plane=axes, rise_m=float(e[2] - s[2]))
