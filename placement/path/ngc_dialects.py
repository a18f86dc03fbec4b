"""Other controllers' words that the G-code reader reads as their controller does, and the warnings naming them.

grbl's system commands (``$H``, ``$X``, ``$$``, ...) and status query (``?``) are the sender's and grbl's, not
moves; homing sends the machine to its home, which the program does not know. A jog (``$J=``), check mode
(``$C``), sleep (``$SLP``) and a reset of the settings (``$RST=``) are refused by name. Fanuc's and Haas's
smoothing and look-ahead modes (``G05 P``, ``G05.1 Q``, ``G08 P``, ``G103``, ``G187``) leave the programmed path.
Marlin's and RepRapFirmware's M codes that do not move the tool (temperatures, fans, messages, the firmware's limits:
``MARLIN_M``) take the line's other words as their parameters; ``G28 X Y`` (axis letters without numbers) homes those
axes, as ``$H`` does; ``G4 S`` dwells S seconds; the extruder ``E`` is read while it stays put (``G92 E0``, ``G90
E0``), and a print, where it moves, is refused where it first moves (:class:`Extruder`).
Each kind read gets one :class:`~placement.path.exceptions.GcodeDialectWarning` naming its lines
(:func:`dialect_notes`); docs/paths.md lists them all.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from placement.exceptions import listed
from placement.path.exceptions import GcodeError
from placement.path.ngc_expressions import MARLIN_HOMING
from placement.path.ngc_words import CONTROLLER_G, CONTROLLER_M, IO_M, MARLIN_M, MODES_OFF, OKUMA_G15, USER_M
from placement.path.path_file import MM_PER_MIN_M_S

MAX_LISTED_LINES = 8  # a warning names at most this many lines of each kind
LONG_DWELL_S = 10.0  # a dwell this long with a whole-number P is warned of: Fanuc and Haas read P2000 as 2 s
GRBL_SKIPPED = re.compile(r"\$(|\$|#|G|I|N|X|N\d+=.*|\d+=.*|I=.*)|\?")  # reports, settings, startup lines, unlock
GRBL_HOMING = re.compile(r"\$H([XYZABCUVW]*)")
PRINT = ("the program is a 3D print (Marlin, RepRapFirmware), whose nozzle lays plastic as it moves; the reader places "
         "tool paths (a cutter, a pen, a laser)")
GRBL_REFUSED = {
    "$J=": "a grbl jog ('$J=') is an operator's positioning move, which grbl accepts only while idle, not among a "
           "job's moves: remove it, or write the move as G0 or G1",
    "$C": "grbl's check mode ('$C') runs the lines after it without moving the machine: remove it",
    "$SLP": "grbl's sleep ('$SLP') disables the machine until it is reset: remove it",
    "$RST=": "'$RST=' restores grbl's defaults, which may erase its work offsets (G54-G59, G28, G30) and so move the "
             "program: remove it"}
SPLINES = {50: "a cubic spline (G5) is not read: output it as G1, G2 or G3 moves",
           51: "a quadratic spline (G5.1) is not read: output it as G1, G2 or G3 moves",
           80: "lathe words (radius mode, G8) are not read: the path is a mill's X, Y, Z"}


def grbl_command(fail: Callable[[str], GcodeError], text: str, compensating: bool) -> list[int]:
    """A grbl system command (upper case, no spaces), or Marlin's homing (``G28XY``: axis letters, no numbers).

    Returns:
        The axes it homes (0, 1, 2; $H: all), whose position is unknown after it; [] for a command skipped.

    Raises:
        GcodeError: A jog, check mode, sleep, a reset of the settings or an unknown command; homing under cutter
            radius compensation.
    """
    for start, problem in GRBL_REFUSED.items():
        if text == start or (start.endswith("=") and text.startswith(start)):
            raise fail(problem)
    homing = GRBL_HOMING.fullmatch(text) or MARLIN_HOMING.fullmatch(text)
    if homing is not None:
        if compensating:
            raise fail("homing ($H, or Marlin's G28 X) cannot run under cutter radius compensation: G40 first")
        axes = homing.group(homing.re.groups)
        return [k for k, letter in enumerate("XYZ") if not axes or letter in axes]
    if GRBL_SKIPPED.fullmatch(text):
        return []
    raise fail("an unknown grbl system command: those read are $H (homing), $X, $$, $#, $G, $I, $N and settings "
               "($100=...); a jog ($J=) is refused")


@dataclass
class Extruder:
    """A 3D printer's extruder as Marlin tracks it: where E stands (0 when the firmware starts) and whether E is
    relative."""

    position: float = 0.0
    relative: bool = False


def extruder_word(fail: Callable[[str, str], GcodeError], codes: dict[str, tuple[int, str]], m_codes: dict[int, str],
                  values: dict[str, float], written: dict[str, str], extruder: Extruder) -> bool:
    """The line's E word (an extruder's; Haas's G187 keeps its E), taken off the values: G92 E sets where E stands;
    elsewhere E must stay put, else the program is a print, refused where E first moves. G90 and G91, M82 and M83
    set whether E is relative, as Marlin does. Whether the line had an E word read."""
    if "distance" in codes:
        extruder.relative = codes["distance"][0] == 910
    if 82 in m_codes or 83 in m_codes:
        extruder.relative = 83 in m_codes
    if "E" not in values or codes.get("controller mode", (0, ""))[0] == 1870:
        return False
    value, word = values.pop("E"), written.pop("E")
    if codes.get("non-modal", (0, ""))[0] == 920:
        extruder.position = value
        if not any(letter in values for letter in "XYZABCUVW"):  # G92 E0 sets the extruder alone: no offset
            del codes["non-modal"]
        return True
    if (value != 0.0) if extruder.relative else (value != extruder.position):
        raise fail(word, f"the extruder (E) moves here: {PRINT}")
    return True


def marlin_words(fail: Callable[[str, str], GcodeError], codes: dict[str, tuple[int, str]], m_codes: dict[int, str],
                 values: dict[str, float], written: dict[str, str]) -> list[str]:
    """A Marlin M code that does not move the tool (MARLIN_M) takes the line's other words as its parameters (M104 S200,
    M205 X8 Y8, M106 P1 S255), as Marlin reads one command a line: they are taken off; its kind, for the note."""
    marlin = sorted(set(m_codes) & set(MARLIN_M))
    if not marlin:
        return []
    if codes or len(m_codes) > 1:
        raise fail(m_codes[marlin[0]], f"M{marlin[0]} ({MARLIN_M[marlin[0]]}) takes the line's words as its parameters, "
                                       "as Marlin reads one command a line: put it on a line of its own")
    values.clear()
    written.clear()
    return [f"M{marlin[0]}"]


def dialect_words(fail: Callable[[str, str], GcodeError], codes: dict[str, tuple[int, str]], m_codes: dict[int, str],
                  values: dict[str, float], written: dict[str, str], depth: int, extruder: Extruder) -> list[str]:
    """A line's words read as another controller reads them: the kinds to note (``M88``, ``G187``, ``G71``, ``M99``,
    ``long dwell``, ``M104``, ``G4 S``, ``E``); refuses M99 and LinuxCNC's M73 in a subroutine, G70 and G71 as lathe
    cycles, an extruder that moves."""
    if 99 in m_codes and depth:
        raise fail(m_codes[99], "M99 inside an O-word subroutine (LinuxCNC refuses it): end the subroutine with "
                                "O<name> endsub or O<name> return")
    if 73 in m_codes and depth:
        raise fail(m_codes[73], "M73 inside an O-word subroutine restores the modal state when it returns (LinuxCNC's "
                                "M73), which is not read: set the modes again after the call")
    kinds = [f"M{code}" for code in sorted(set(m_codes) & {*CONTROLLER_M, 99})]
    kinds += marlin_words(fail, codes, m_codes, values, written)
    if any(code in IO_M for code in m_codes):  # their P, E, L and Q are their arguments (E no extruder's)
        for letter in "PELQ":
            values.pop(letter, None), written.pop(letter, None)
        kinds.append("M62-M68")
    if any(code in USER_M and code not in MARLIN_M for code in m_codes):  # their P and Q are their arguments
        values.pop("P", None), values.pop("Q", None), written.pop("P", None), written.pop("Q", None)
        kinds.append("user M")
    if extruder_word(fail, codes, m_codes, values, written, extruder):
        kinds.append("E")
    if codes.get("non-modal", (0, ""))[0] == 40 and "S" in values and "P" not in values:  # Marlin's dwell in seconds
        values["P"], written["P"] = values.pop("S"), written.pop("S")
        kinds.append("G4 S")
    if codes.get("non-modal", (0, ""))[0] == 40 and "X" in values and "P" not in values:  # Fanuc's dwell in seconds
        values["P"], written["P"] = values.pop("X"), written.pop("X")
        kinds.append("G4 X")
    if "controller mode" in codes:
        kinds.append(controller_mode(fail, codes["controller mode"], values))
    for group in MODES_OFF:
        if group in codes:
            if group == "polar coordinates" and "H" in values:
                raise fail(codes[group][1], OKUMA_G15)
            kinds.append(MODES_OFF[group][0])
    units = codes.get("units", (0, ""))
    if units[0] in (700, 710) and ("P" in values or "Q" in values):
        raise fail(units[1], "lathe words (turning cycles G70, G71) are not read: the path is a mill's X, Y, Z")
    if units[0] in (700, 710):
        kinds.append(f"G{units[0] // 10}")
    dwell = codes.get("non-modal", (0, ""))[0] == 40 and "P" in values
    if dwell and written["P"].startswith("P"):  # (not G4 S)
        kinds.append("G4 P")  # milliseconds in a Marlin program (marlin_program)
    if dwell and values["P"] >= LONG_DWELL_S and re.fullmatch(r"P\d+", written["P"]):  # 2000 s, or Fanuc's 2 s?
        kinds.append("long dwell")
    return kinds


def controller_mode(fail: Callable[[str, str], GcodeError], code_word: tuple[int, str], values: dict[str, float]) -> str:
    """A smoothing or look-ahead mode (G5 P, G5.1 Q, G8 P, G103, G187): its name, for the note; G5, G5.1 and G8 as
    LinuxCNC reads them (splines, a lathe's radius mode) are refused."""
    code, word = code_word
    name, _, needs = CONTROLLER_G[code]
    if (needs and needs not in values) or (code in (50, 51) and any(letter in values for letter in "XYZIJ")):
        raise fail(word, SPLINES[code])
    return name


def marlin_program(dialect: dict[str, list[int]]) -> bool:
    """Whether the program holds words only Marlin-style firmware reads (its M codes, homing by letters, G4 S, E), whose
    G4 P is in milliseconds (Marlin, RepRapFirmware, Klipper and Smoothieware read P so)."""
    return any(kind in ("G28 homing", "G4 S", "E") or (kind[1:].isdigit() and int(kind[1:]) in MARLIN_M)
               for kind in dialect)


def marlin_notes(dialect: dict[str, list[int]]) -> list[str]:
    """The notes of Marlin's words: its M codes that do not move the tool, its homing, G4 S and an extruder kept still."""
    notes = []
    codes = sorted(int(key[1:]) for key in dialect if key[1:].isdigit() and int(key[1:]) in MARLIN_M)
    if codes:
        listed = "; ".join(f"M{code}, {MARLIN_M[code]} ({lines_text(dialect[f'M{code}'])})" for code in codes)
        waits = (" (the waits for a temperature are not timed)" if {109, 190} & set(codes) else "")
        notes.append(f"Marlin's and RepRapFirmware's M codes that do not move the tool are ignored, with the words of "
                     f"their lines as their parameters{waits}: {listed}")
    if "M62-M68" in dialect:
        notes.append(f"LinuxCNC's digital and analog outputs and input waits M62-M68 ({lines_text(dialect['M62-M68'])}: "
                     "a laser's or a torch's power and switching, as laser and plasma posts write them) do not move the "
                     "tool: ignored (an M66 wait is not timed)")
    if "user M" in dialect:
        notes.append(f"user-defined M codes M100-M199 ({lines_text(dialect['user M'])}) run a program of the "
                     "controller's (LinuxCNC: the file M1nn in its PROGRAM_PREFIX folder, given P and Q; Mr Beam: its "
                     "air compressor): read as not moving the tool")
    if "G28 homing" in dialect:
        notes.append(f"G28 with axis letters and no numbers ({lines_text(dialect['G28 homing'])}) is Marlin's homing of "
                     "those axes: the position is unknown after it until the program gives one")
    if "G4 S" in dialect:
        notes.append(f"G4 S ({lines_text(dialect['G4 S'])}) dwells S seconds, as Marlin and RepRapFirmware read it "
                     "(LinuxCNC refuses a dwell without P)")
    if "E" in dialect:
        notes.append(f"the extruder's E ({lines_text(dialect['E'])}) stays where it is: ignored (no plastic is laid)")
    if "G4 P" in dialect and marlin_program(dialect):
        notes.append(f"G4 P ({lines_text(dialect['G4 P'])}) dwells P milliseconds, as Marlin reads it (the program holds "
                     "Marlin's words; LinuxCNC and grbl read P in seconds)")
    return notes


def lines_text(lines: list[int]) -> str:
    """'line 4' or 'lines 4, 9, 12', at most MAX_LISTED_LINES of them."""
    unique = sorted(set(lines))
    return f"line{'s' if len(unique) > 1 else ''} {listed(unique, MAX_LISTED_LINES)}"


def dialect_notes(dialect: dict[str, list[int]], home_given: bool, initial_feed_m_s: float | None) -> list[str]:
    """One note per kind of controller word read, naming its lines.

    Args:
        dialect: The lines of each kind ("$", "$H", "M88", "G187", "M25", "M99", "long dwell", "G0 at start",
            "G91 at start", "initial feed", Marlin's "M104", "G28 homing", "G4 S", "G4 P", "E", ...).
        home_given: Whether the path file gives the machine's home (shape.machine.g28_mm), where M25 goes.
        initial_feed_m_s: The initial feed given (the command line's or the path file's; m/s).
    """
    notes = []
    if "$" in dialect or "$H" in dialect:
        skipped = [*dialect.get("$", []), *dialect.get("$H", [])]
        homing = (f"; $H ({lines_text(dialect['$H'])}) sends the machine home, so the position is unknown after it "
                  "until the program gives one" if "$H" in dialect else "")
        notes.append(f"grbl system commands and status queries ({lines_text(skipped)}) are the sender's and grbl's, "
                     f"not moves: skipped{homing}")
    codes = sorted(int(key[1:]) for key in dialect if key[1:].isdigit() and int(key[1:]) in CONTROLLER_M)
    if codes:
        listed = "; ".join(f"M{code}, {CONTROLLER_M[code]} ({lines_text(dialect[f'M{code}'])})" for code in codes)
        notes.append(f"other controllers' M codes that do not move the tool are ignored: {listed}")
    notes += marlin_notes(dialect)
    modes = [(name, meaning) for name, meaning, _ in CONTROLLER_G.values() if name in dialect]
    if modes:
        listed = "; ".join(f"{name}, {meaning} ({lines_text(dialect[name])})" for name, meaning in modes)
        notes.append(f"other controllers' smoothing and look-ahead modes leave the programmed path as it is, and their "
                     f"effect on the feed is not modelled: {listed}")
    ended = [f"{name}, {meaning} ({lines_text(dialect[name])})" for name, meaning in MODES_OFF.values() if name in dialect]
    if ended:
        notes.append(f"Fanuc's words that end a mode which is not read change nothing: {'; '.join(ended)}")
    units = [f"G{code} ({lines_text(dialect[f'G{code}'])})" for code in (70, 71) if f"G{code}" in dialect]
    if units:
        notes.append(f"{' and '.join(units)} {'are' if len(units) > 1 else 'is'} read as Mach3's (and older "
                     "controls') units, G70 inches and G71 millimetres, as G20 and G21 (LinuxCNC reads G70 and G71 as "
                     "lathe cycles)")
    if "M25" in dialect:
        where = ("to the Z of shape.machine.g28_mm, the machine's home" if home_given else
                 "to the machine's home, which the path file does not give (shape.machine.g28_mm): the retract is left "
                 "out and Z is unknown after it until the program gives it")
        notes.append(f"M25 ({lines_text(dialect['M25'])}) is Centroid's Z home: Z alone moves at rapid {where}")
    if "M99" in dialect:
        notes.append(f"M99 ({lines_text(dialect['M99'])}) ends the main program, as M2 (LinuxCNC's reading; "
                     "Fanuc-style controls run the program again from its start: the path is one pass)")
    if "long dwell" in dialect and not marlin_program(dialect):
        notes.append(f"the dwells of {lines_text(dialect['long dwell'])} (G4 P with a whole number of at least "
                     f"{LONG_DWELL_S:g}) last P seconds, as LinuxCNC and grbl read P; Fanuc, Haas and some Mach3 "
                     "controls read a P without a decimal point in milliseconds: if the program is theirs, write "
                     "P in seconds (P2000 -> P2.)")
    if "G54.1 P" in dialect:
        notes.append(f"G54.1 P and G154 P ({lines_text(dialect['G54.1 P'])}) select an additional work offset, as Fanuc "
                     "and Haas controls read them: read as G54-G59.3 are (LinuxCNC has none)")
    if "G4 X" in dialect:
        notes.append(f"G4 X ({lines_text(dialect['G4 X'])}) dwells X seconds, as Fanuc and Haas controls read it "
                     "(LinuxCNC refuses a dwell without P)")
    if "G0 at start" in dialect:
        verb = "give" if len(set(dialect["G0 at start"])) > 1 else "gives"
        notes.append(f"{lines_text(dialect['G0 at start'])} {verb} an end point before any motion word: read as G0, the "
                     "motion mode grbl, Fanuc, Haas and Mach3 controls start in (LinuxCNC starts in none and refuses it)")
    if "G91 at start" in dialect:
        notes.append(f"the program's first move ({lines_text(dialect['G91 at start'])}) is incremental (G91): it starts "
                     "where the tool stands when the program starts, read as the program's origin (as LinuxCNC's "
                     "interpreter starts at its origin)")
    if "initial feed" in dialect:
        assert initial_feed_m_s is not None
        notes.append(f"the feed moves of {lines_text(dialect['initial feed'])} come before the program's first F: they "
                     f"run at the controller's modal feed given for the program (--initial-feed, or shape.initial_feed_m_s "
                     f"in the path file): {initial_feed_m_s * MM_PER_MIN_M_S:g} mm/min = {initial_feed_m_s:g} m/s")
    return notes
