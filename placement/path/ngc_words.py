"""The words of the G-code dialect: modal groups, what is accepted, what is refused and why.

G and M numbers are kept in tenths (G61.1 is 611). docs/paths.md lists every word with what it
does to the energy and the time.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from placement.path.canned import CYCLES
from placement.path.exceptions import GcodeError

# G codes (in tenths: G61.1 is 611) by modal group; G80 has its own group, as on Fanuc controls, so that a post's
# safety line "G0 G90 G40 G21 G17 G94 G80" is read.
G_GROUPS = {
    **dict.fromkeys((0, 10, 20, 30, 730, 810, 820, 830, 850, 890), "motion"), 800: "canned cycle",
    **dict.fromkeys((40, 100, 280, 281, 300, 301, 530, 920, 921, 922, 923), "non-modal"),
    **dict.fromkeys((170, 180, 190), "plane"),
    **dict.fromkeys((*range(540, 600, 10), 591, 592, 593, 541, 1540), "coordinate system"), 200: "units", 210: "units",
    700: "units", 710: "units", 900: "distance",
    910: "distance", 901: "arc distance", 911: "arc distance", **dict.fromkeys((930, 940, 950), "feed mode"),
    **dict.fromkeys((400, 410, 411, 420, 421), "cutter compensation"), 430: "tool length offset",
    490: "tool length offset", 980: "retract mode", 990: "retract mode", **dict.fromkeys((610, 611, 640), "path control"),
    **dict.fromkeys((50, 51, 80, 1030, 1870), "controller mode"), 150: "polar coordinates", 690: "coordinate rotation"}
CONTROLLER_G = {  # other controllers' smoothing and look-ahead modes: the path is the programmed one (a note)
    50: ("G5", "high-precision contour control (Fanuc, with P)", "P"),
    51: ("G5.1", "AI contour control (Fanuc, with Q)", "Q"),
    80: ("G8", "look-ahead (Fanuc, with P)", "P"),
    1030: ("G103", "look-ahead limit (Haas)", ""),
    1870: ("G187", "smoothness and corner tolerance (Haas)", "")}
MODES_OFF = {  # Fanuc's words that end a mode which is not read: they change nothing (a note); posts' safety lines write them
    "polar coordinates": ("G15", "polar coordinates off (G16, which turns them on, is not read)"),
    "coordinate rotation": ("G69", "coordinate rotation off (G68, which turns it on, is not read)")}
OKUMA_G15 = ("Okuma's G15 H selects a work coordinate system from the control's table, which the program does not hold: "
             "give the coordinates in G54-G59 (set by G10 L2 if need be)")
READ_G = ("not in the G-code dialect read: G0-G4, G10 L1/L2/L10/L11/L20, G17-G21, G28, G28.1, G30, G30.1, G40-G42, "
          "G41.1, G42.1, G43, G49, G53-G59, G59.1-G59.3, G61, G61.1, G64, G73, G80-G83, G85, G89, G90, G91, G90.1, "
          "G91.1, G92-G92.3, G93-G95, G98, G99; and other controllers' G5 P, G5.1 Q, G8 P, G15, G54.1 P, G69, G70, "
          "G71, G103, G154 P, G187 (docs/paths.md)")
ACCEPTED_M = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30, 48, 49, 60}  # RS-274/NGC's own: read without a note
CONTROLLER_M = {  # other controllers' M codes that do not move the tool: ignored, with a note (GcodeDialectWarning)
    10: "clamp or rotary brake on", 11: "clamp or rotary brake off", 12: "5th-axis brake on (Haas)",
    13: "5th-axis brake off (Haas), or spindle and coolant on", 19: "spindle orientation",
    31: "chip conveyor forward (Haas)", 33: "chip conveyor stop (Haas)", 34: "coolant spigot down (Haas)",
    35: "coolant spigot up (Haas)", 41: "spindle low gear", 42: "spindle high gear",
    73: "tool air blast on (Haas; in the main program, where LinuxCNC's M73 changes nothing)",
    74: "tool air blast off (Haas)", 83: "air jet on (Haas); relative extrusion (Marlin)",
    84: "air jet off (Haas); motors off (Marlin)",
    88: "through-spindle coolant on (Haas)", 89: "through-spindle coolant off (Haas)",
    888: "front-end module (Rotrics DexArm, M888 P: P0 the pen, P1 the laser, ...; the program gives the module's tip)",
    2000: "G0 moves in straight lines (Rotrics DexArm), as they are read"}
MARLIN_M = {  # Marlin's and RepRapFirmware's M codes that do not move the tool: their words are their parameters
    17: "motors on", 18: "motors off", 82: "absolute extrusion", 104: "hotend temperature",
    105: "temperature report", 106: "fan on (or a laser on the fan's output)", 107: "fan off",
    109: "wait for the hotend temperature", 110: "line number", 114: "position report", 115: "firmware report",
    117: "message on the display", 118: "message to the host", 140: "bed temperature",
    190: "wait for the bed temperature", 201: "the firmware's acceleration limits",
    203: "the firmware's feed limits", 204: "the firmware's accelerations", 205: "the firmware's jerk limits",
    300: "a beep (Marlin), or the pen servo (MakerBot Unicorn: S30 down, S50 up)",
    400: "wait for the moves to finish", 420: "bed levelling on or off"}
IO_M = range(62, 69)  # LinuxCNC's outputs and input wait (M62-M65 P, M66 P E L Q, M67 E Q, M68 E Q): no motion, a note
USER_M = range(100, 200)  # user-defined M codes (LinuxCNC's M100-M199 with P, Q) that are not Marlin's: a note
DIALECT_M = {25, 99}  # read as their controllers do (gcode._execute): Centroid's Z home, the main program's end
UNSUPPORTED_M = {
    97: "Haas local subprograms (M97 P) are not read: expand them in the CAM post, or use O-word subroutines (O100 "
        "sub ... O100 endsub, O100 call)",
    98: "Fanuc subprogram calls (M98 P) are not read: expand them in the CAM post, or use O-word subroutines (O100 "
        "sub ... O100 endsub, O100 call)",
    2001: "Rotrics DexArm's M2001 makes G0 moves turn the joints at once, not straight lines, whose path is not read: "
          "remove it (its default, M2000, moves straight)",
    220: "Marlin's feed override (M220 S) scales every feed: give the feeds in the program (F) instead",
    221: "Marlin's flow override (M221) scales the extrusion of a print, which is not a tool path"}
READ_M = ("not in the supported M-code dialect (M0, M1, M2, M3-M9, M30, M48, M49, M60; and other controllers' M10-M13, "
          "M19, M25, M31, M33-M35, M41, M42, M62-M68, M73, M74, M83, M84, M88, M89, M99, M100-M199, M888, M2000; Marlin's M17, "
          "M18, M82, "
          "M104-M107, M109, M110, M114, M115, M117, M118, M140, M190, M201, M203-M205, M300, M400, M420; docs/paths.md): "
          "an M code not known may move the tool")
UNSUPPORTED_G = {
    **dict.fromkeys((740, 760, 840, 860, 870, 880), "tapping and boring cycles (G74, G76, G84, G86-G88) need the "
                    "spindle's motion: output them as G0/G1 moves; the drilling cycles G73, G81-G83, G85, G89 are read"),
    **dict.fromkeys((650, 660, 661, 670), "a Fanuc Macro B macro call (G65, G66, G67) is not read: expand the macro in "
                    "the CAM post, or use O-word subroutines (O100 sub ... O100 endsub, O100 call)"),
    330: "spindle-synchronised motion (threading) is not read", 331: "spindle-synchronised motion is not read",
    430 + 1: "G43.1 (a tool length offset given in the program) changes where the tool tip is: give the tip's "
             "coordinates (G43 or G49)",
    **dict.fromkeys((382, 383, 384, 385), "probing moves until a sensor trips, which a program does not hold: give "
                    "the moves as G0/G1"),
    **dict.fromkeys((70, 711, 720, 721), "lathe words (diameter mode, turning cycles) are not read: "
                    "the path is a mill's X, Y, Z"),
    960: "constant surface speed (G96) is not read: the feeds are per minute (G94), inverse time (G93) or per "
         "revolution at S (G95)",
    160: "Fanuc's polar coordinates (G16) are not read: give X and Y (or LinuxCNC's polar words @ and ^)",
    **dict.fromkeys((680, 681, 682, 683, 684), "Fanuc's coordinate rotation (G68) and tilted working plane (G68.1-"
                    "G68.4) turn the program's coordinates by the control's rule, which is not read: output the moves "
                    "in the workpiece's coordinates (the CAM post's rotation off)"),
    **dict.fromkeys((434, 435), "5-axis tool centre point control (Fanuc's TCP, G43.4 and G43.5) moves the rotary "
                    "axes with the tool tip, which is not read: the path is the tool tip's X, Y, Z only (a 3-axis "
                    "post)")}
ALLOWED_LETTERS = set("GMXYZIJKRFSTPQLHDN@^$")  # $: LinuxCNC's spindle number (M3 $0), which the path does not use
EXTRA_AXES = "ABCUVW"  # rotary and extra axes: read only while they hold one value (extra_axes)


def code_of(fail: Callable[[str, str], GcodeError], value: float, word: str) -> int:
    """A G or M number in tenths (G61.1 is 611)."""
    tenths = round(value * 10)
    if abs(value * 10 - tenths) > 1e-6:
        raise fail(word, "not a G or M number (at most one decimal)")
    return tenths


def sorted_words(fail: Callable[[str, str], GcodeError], words: list[tuple[str, float, str]]
                  ) -> tuple[dict[str, tuple[int, str]], dict[int, str], dict[str, float], dict[str, str]]:
    """A line's G words by modal group (code, word), M words, values by letter and their words as written;
    refuses words outside the dialect and two words of one group or letter."""
    codes: dict[str, tuple[int, str]] = {}
    m_codes: dict[int, str] = {}
    values: dict[str, float] = {}
    written: dict[str, str] = {}
    for letter, value, word in words:
        letter = letter.upper()
        if letter == "G":
            code = code_of(fail, value, word)
            if code not in G_GROUPS:
                raise fail(word, UNSUPPORTED_G.get(code, READ_G))
            group = G_GROUPS[code]
            if group in codes:
                raise fail(word, f"a second {group} word on the line (after {codes[group][1]})")
            codes[group] = (code, word)
        elif letter == "M":
            code = code_of(fail, value, word)
            if code % 10 or code // 10 not in (*ACCEPTED_M, *CONTROLLER_M, *MARLIN_M, *IO_M, *USER_M, *DIALECT_M):
                raise fail(word, UNSUPPORTED_M.get(code // 10, READ_M) if not code % 10 else READ_M)
            m_codes[code // 10] = word
        elif letter in ALLOWED_LETTERS or letter in EXTRA_AXES or letter == "E":  # E: Haas's G187 E, or an extruder
            if letter in values:
                raise fail(word, f"{letter} is given twice on the line")
            if letter == "$" and (value != round(value) or value < -1):
                raise fail(word, "the spindle number $ is a whole number ≥ 0 (or -1, every spindle)")
            values[letter], written[letter] = value, word
        else:
            raise fail(word, "unknown word: the letters read are G, M, X, Y, Z, I, J, K, R, F, S, T, P, Q, L, H, D, "
                             "N, O, the extra axes A, B, C, U, V, W, an extruder's E, the polar @, ^ and the spindle number $")
    return codes, m_codes, values, written


def check_unused(fail: Callable[[str, str], GcodeError], codes: dict[str, tuple[int, str]],
                 values: dict[str, float], written: dict[str, str], motion: int | None, m_codes: dict[int, str]) -> None:
    """P, Q, L, D and H only where a word uses them."""
    motion = codes["motion"][0] if "motion" in codes else motion
    cycle = motion is not None and motion // 10 in CYCLES
    non_modal = codes.get("non-modal", (None, ""))[0]
    blending = codes.get("path control", (0, ""))[0] == 640
    mode = codes.get("controller mode", (None, ""))[0]
    users = {"P": non_modal in (40, 100) or cycle or blending or motion in (20, 30) or 19 in m_codes
             or 888 in m_codes or mode in (50, 80, 1030, 1870),
             "Q": cycle or blending or 19 in m_codes or mode == 51, "L": cycle or non_modal == 100,
             "H": "tool length offset" in codes or "polar coordinates" in codes,  # Okuma's G15 H: refused by name
             "D": codes.get("cutter compensation", (400, ""))[0] != 400}
    for letter, used in users.items():
        if letter in values and not used:
            raise fail(written[letter], {"P": "P belongs to G4 (dwell), G10, G64, G82, G89, G2/G3 (turns), M19 and M888",
                                         "Q": "Q belongs to G73, G83 (peck), G64 and M19",
                                         "L": "L belongs to G10 and canned cycles",
                                         "H": "H belongs to G43 (tool length offset)",
                                         "D": "D belongs to cutter radius compensation (G41, G42, G41.1, G42.1)"}[letter])


def polar_words(fail: Callable[[str, str], GcodeError], values: dict[str, float], written: dict[str, str],
                here: list[float | None], length_m: float, incremental: bool) -> None:
    """Polar words in place of X and Y, as LinuxCNC reads them: ``@`` the radius and ``^`` the angle (degrees) of
    the end point about the program's origin in the XY plane; in G91 both add to the current point's (``here``, X
    and Y in metres about the program's origin). Sets X and Y in ``values``."""
    word = written.get("@", written.get("^", ""))
    if "X" in values or "Y" in values:
        raise fail(word, "polar words (@, ^) replace X and Y: give one or the other")
    x, y = here
    if x is None or y is None:
        raise fail(word, "polar words need the current X and Y: move to a point first")
    radius, angle = float(np.hypot(x, y)) / length_m, float(np.degrees(np.arctan2(y, x)))
    if incremental:
        if radius == 0:
            raise fail(word, "incremental polar motion is indeterminate at the origin")
        radius, angle = radius + values.get("@", 0.0), angle + values.get("^", 0.0)
    else:
        radius, angle = values.get("@", radius), values.get("^", angle)
    end = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))]) * radius
    if incremental:
        end -= np.array([x, y]) / length_m
    values["X"], values["Y"] = float(end[0]), float(end[1])
    written["X"] = written["Y"] = word


def extra_axes(fail: Callable[[str, str], GcodeError], values: dict[str, float], written: dict[str, str],
               held: dict[str, float], incremental: bool) -> list[tuple[str, str, float]]:
    """Rotary and extra axes (A, B, C, U, V, W), taken off the line's words: the path has X, Y, Z only, so an axis
    that holds one value throughout (a 3-axis job on a 4-axis post) is ignored (the (letter, word, value held) of
    each, for a note), and one that moves is refused where it first moves. ``held`` keeps each axis's value."""
    ignored = []
    for letter in [letter for letter in EXTRA_AXES if letter in values]:
        value, word = values.pop(letter), written.pop(letter)
        kept = held.setdefault(letter, 0.0 if incremental else value)
        if (value != 0.0) if incremental else (value != kept):
            raise fail(word, f"the extra axis {letter} moves here (it held {kept:g} before): the path has X, Y, Z "
                             f"only, so rotary and extra axes (A, B, C, U, V, W) are read only while they hold one "
                             "value")
        ignored.append((letter, word, kept))
    return ignored
