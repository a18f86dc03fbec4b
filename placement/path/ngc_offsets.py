"""Work coordinate systems (G54-G59.3), their offsets set in the program (G10 L2, G10 L20) and axis offsets (G92).

Read as LinuxCNC reads them. A program's coordinates in system k are its machine coordinates less the
offset of k's origin and less the G92 offset; the path frame is the system the program runs in, its
origin where that system's origin is when each axis is first given a position (the path file's
``machine.work_offset_mm`` says where that is on the machine, when it gives it). So:

- ``G10 L2 P<k>`` sets k's offset in machine coordinates (P0 the active system, P1-P9 G54-G59.3);
  given before an axis has a position, for the active system, it moves the path frame with it (the
  path frame is where the program's origin is); after, the moves in k shift by the change, which the
  path frame knows only if it knows where its origin is on the machine (the path file's work offset,
  or an earlier G10 L2 of that system).
- ``G10 L20 P<k>`` sets k's offset so that the current point reads the given coordinates in k (G92
  counted); from a point not known yet (the program's start) in the active system, the current point
  becomes that point of the path frame, where the machine happens to be.
- Switching to a system is read when its offset from the path frame is known along every axis that has
  had a position (G10 set it, or the program has not moved yet); else the switch is refused.

The G92 offset (``g92_m``) applies in every system. Each axis is "bound" once it has had a position:
from then on the path frame's origin along it is fixed.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from placement.path.exceptions import GcodeError

SYSTEMS = {540: 1, 550: 2, 560: 3, 570: 4, 580: 5, 590: 6, 591: 7, 592: 8, 593: 9}  # G code (tenths) -> G10's P
BY_NUMBER = {number: code for code, number in SYSTEMS.items()}
NAMES = {540: "G54", 550: "G55", 560: "G56", 570: "G57", 580: "G58", 590: "G59", 591: "G59.1", 592: "G59.2",
         593: "G59.3"}


ADDITIONAL = {541: ("G54.1", 48), 1540: ("G154", 99)}  # Fanuc's and Haas's additional work offsets: P1 to P48 or P99
ADDITIONAL_BASE = 100_000  # an additional system's number: this plus its P


def additional_system(fail: Callable[[str, str], GcodeError], code_word: tuple[int, str], values: dict[str, float],
                      written: dict[str, str]) -> tuple[int, str]:
    """The system a line selects: G54.1 P<n> (Fanuc, P1-P48) and G154 P<n> (Haas, P1-P99) an additional work offset,
    read as G54-G59.3 are (its offset is the program's to set: none, G10 does not reach it), their P taken off the
    line; any other code as it is."""
    code, word = code_word
    if code not in ADDITIONAL:
        return code_word
    name, last = ADDITIONAL[code]
    number = values.pop("P", None)
    written.pop("P", None)
    if number is None or number != round(number) or not 1 <= number <= last:
        raise fail(word, f"{name} selects an additional work offset by P, a whole number from 1 to {last}")
    return ADDITIONAL_BASE + round(number), word


def system_name(system: int) -> str:
    """A system's G code as written: G54, ..., G59.3, or an additional one's G54.1 P<n> (Haas's G154 P<n>)."""
    return NAMES.get(system, f"G54.1 P{system - ADDITIONAL_BASE}")


def _nan3() -> np.ndarray:
    return np.full(3, np.nan)


@dataclass
class Offsets:
    """The offsets of the work coordinate systems and G92, in metres.

    Attributes:
        work_offset_m: (3,) where the program's origin is in machine coordinates, as the path file gives it (NaN:
            not given).
        active: The active system (G code in tenths: 540 is G54).
        machine_m: Per system, each axis's offset set by G10 in machine coordinates (NaN: set to a value not known,
            by G10 L20 where the machine happened to be).
        frame_m: Per system, along the bound axes, where its origin is in the path frame (NaN: not known).
        origin_m: (3,) along the bound axes, where the path frame's origin is in machine coordinates (NaN: not known).
        bound: The axes that have had a position.
        g92_m, saved_g92_m: (3,) the G92 offset (the program's coordinates less it, in every system) and the one
            G92.3 restores.
        set_where_unknown: The line of a G10 L20 that set the active system's origin where the machine happened to
            be (0: none), which leaves the machine's positions out of reach.
    """

    work_offset_m: np.ndarray
    active: int = 540
    machine_m: dict[int, dict[int, float]] = dataclasses.field(default_factory=dict)
    frame_m: dict[int, np.ndarray] = dataclasses.field(default_factory=dict)
    origin_m: np.ndarray = dataclasses.field(default_factory=_nan3)
    bound: set[int] = dataclasses.field(default_factory=set)
    g92_m: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))
    saved_g92_m: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))
    set_where_unknown: int = 0

    def _machine(self, system: int, axis: int) -> float:
        """Along an axis not yet bound: the system's origin in machine coordinates (NaN: not known)."""
        given = self.machine_m.get(system, {})
        if axis in given:
            return given[axis]
        return float(self.work_offset_m[axis]) if system == self.active else np.nan

    def shift_m(self, system: int) -> np.ndarray:
        """(3,) where a system's origin is in the path frame (NaN: not known)."""
        out = np.empty(3)
        for axis in range(3):
            if axis in self.bound:
                out[axis] = self.frame_m.get(system, _nan3())[axis]
            elif system == self.active:
                out[axis] = 0.0
            else:
                out[axis] = self._machine(system, axis) - self._machine(self.active, axis)
        return out

    def total_m(self) -> np.ndarray:
        """(3,) the path frame's coordinates less the program's: the active system's shift plus G92's."""
        return self.shift_m(self.active) + self.g92_m

    def origin(self) -> np.ndarray:
        """(3,) where the path frame's origin is in machine coordinates (NaN: not known)."""
        return np.array([self.origin_m[axis] if axis in self.bound else self._machine(self.active, axis)
                         for axis in range(3)])

    def bind(self, axes: set[int]) -> None:
        """The axes get their first position: the path frame's origin along them is fixed."""
        for axis in sorted(axes - self.bound):
            systems = {self.active, *self.machine_m, *self.frame_m}
            shifts = {system: self.shift_m(system)[axis] for system in systems}
            self.origin_m[axis] = self._machine(self.active, axis)
            for system, shift in shifts.items():
                self.frame_m.setdefault(system, _nan3())[axis] = shift
            self.bound.add(axis)

    def select(self, system: int) -> list[int]:
        """Make a system active; the bound axes along which its offset is not known (then nothing changes)."""
        shift = self.shift_m(system)
        unknown = [axis for axis in sorted(self.bound) if np.isnan(shift[axis])]
        if not unknown:
            self.active = system
        return unknown

    def set_machine(self, system: int, values_m: dict[int, float]) -> list[int]:
        """G10 L2: the system's origin at these machine coordinates; the bound axes of the active system whose
        offset becomes unknown (the path file does not say where the path frame's origin is on the machine)."""
        lost = []
        for axis, value in values_m.items():
            self.machine_m.setdefault(system, {})[axis] = value
            if axis in self.bound:
                self.frame_m.setdefault(system, _nan3())[axis] = value - self.origin_m[axis]
                if system == self.active and np.isnan(self.origin_m[axis]):
                    lost.append(axis)
        return lost

    def set_current(self, system: int, values_m: dict[int, float], position_m: list[float | None], line: int
                    ) -> tuple[list[int], dict[int, float]]:
        """G10 L20: the system's offset such that the current point reads these coordinates in it.

        Returns:
            The bound axes whose position is not known (nothing is set along them), and the positions (path
            frame) of the axes not yet bound that the active system's new origin makes known.
        """
        unknown, known = [], {}
        for axis, value in values_m.items():
            here = position_m[axis]
            if here is not None:
                shift = here - value - self.g92_m[axis]
                self.frame_m.setdefault(system, _nan3())[axis] = shift
                self.machine_m.setdefault(system, {})[axis] = shift + self.origin_m[axis]
            elif axis in self.bound:
                unknown.append(axis)
            else:  # the machine is wherever it is: the system's origin is not known on it
                self.machine_m.setdefault(system, {})[axis] = np.nan
                if system == self.active:
                    known[axis] = value + self.g92_m[axis]
                    self.set_where_unknown = line
        return unknown, known

    def set_g92(self, values_m: dict[int, float], position_m: list[float | None]) -> None:
        """G92: the current point reads these coordinates (axes not given keep their offset)."""
        shift = self.shift_m(self.active)
        for axis, value in values_m.items():
            here = position_m[axis]
            self.g92_m[axis] = (here if here is not None else 0.0) - value - shift[axis]
        self.saved_g92_m = self.g92_m.copy()

    def clear_g92(self, code: int) -> None:
        """G92.1 (forget the offset), G92.2 (off, kept for G92.3), G92.3 (restore it)."""
        if code == 923:
            self.g92_m = self.saved_g92_m.copy()
            return
        self.g92_m = np.zeros(3)
        if code == 921:
            self.saved_g92_m = np.zeros(3)


def select_system(fail: Callable[[str, str], GcodeError], code_word: tuple[int, str], offsets: Offsets,
                  compensating: bool) -> None:
    """G54-G59.3: the program's coordinates are in that system from here; refused when its offset from the path
    frame is not known along an axis that has had a position, or under cutter radius compensation."""
    system, word = code_word
    if system == offsets.active:
        return
    if compensating:
        raise fail(word, "the work coordinate system changes while cutter radius compensation is on: G40 first")
    unknown = offsets.select(system)
    if not unknown:
        return
    axes = ", ".join("XYZ"[k] for k in unknown)
    name, active = system_name(system), system_name(offsets.active)
    if system in offsets.machine_m:
        raise fail(word, f"the program changes work coordinate system to {name}, whose offset G10 sets in machine "
                         f"coordinates ({axes}), but where the path frame's origin ({active}'s) is on the machine is not "
                         "known: give it in the path file (shape.machine.work_offset_mm), or set that system's offset "
                         "too (G10 L2) before the first move")
    how = (f"set it before (G10 L2 P{SYSTEMS[system]} or G10 L20 P{SYSTEMS[system]}), or write the program in one "
           "system, the path frame" if system in SYSTEMS else "write the program in one system, the path frame")
    raise fail(word, f"the program changes work coordinate system to {name}, whose offset ({axes}) is not in the "
                     f"program: {how}")


TOOL_DIAMETER_HOW = ("give each tool's diameter with --tool-diameter T=MM on the command line or in the path file "
                     "(shape.tool_diameters_mm)")


def g10(fail: Callable[[str, str], GcodeError], word: str, values: dict[str, float], written: dict[str, str],
        length_m: float, position_m: list[float | None], compensating: bool, line: int, offsets: Offsets
        ) -> dict[int, float]:
    """G10, as LinuxCNC reads it: L2 sets a work coordinate system's offset (machine coordinates), L20 sets it so
    that the current point reads the given coordinates; L1, L10, L11 write the tool table, whose lengths do not move
    the tool tip's path (their R, a radius in LinuxCNC but a length or wear on Fanuc and Haas, is refused).

    Returns:
        The positions (path frame) of the axes G10 L20 makes known: the current point, not known yet, becomes the
        given point of the active system.
    """
    if "L" not in values or values["L"] != round(values["L"]):
        raise fail(word, "G10 needs L: L2 or L20 (a work coordinate system's offset), L1, L10 or L11 (a tool's)")
    form = round(values["L"])
    if form in (1, 10, 11) and "R" in values:
        raise fail(written["R"], f"G10 L{form}'s R is a tool's radius in LinuxCNC but a length or a wear on Fanuc "
                                 f"and Haas controls: {TOOL_DIAMETER_HOW}")
    if form in (1, 10, 11):
        return {}  # the program's coordinates are the tool tip's, whatever the tool's length
    if form in (12, 13):
        raise fail(written["L"], f"G10 L{form} sets a cutter radius or diameter offset (Fanuc, Haas), read differently "
                                 f"by each: {TOOL_DIAMETER_HOW}")
    if form not in (2, 20):
        raise fail(written["L"], f"G10 L{form} is not read: G10 L2 and L20 (work offsets) and L1, L10, L11 (tool "
                                 "lengths) are")
    number = values.get("P")
    if number is None or number != round(number) or not 0 <= number <= 9:
        extra = (" (Fanuc's and Haas's G10 L20 P sets an additional work offset, G54.1 P or G154 P, which is not "
                 "read)" if form == 20 and number is not None and number > 9 else "")
        raise fail(written.get("P", word), f"G10 L{form} needs P, the coordinate system: 0 the active one, 1-9 "
                                           f"G54-G59.3{extra}")
    if values.get("R", 0.0) != 0.0:
        raise fail(written["R"], "a rotated coordinate system (G10 L2 or L20 with R) is not read")
    system = offsets.active if number == 0 else BY_NUMBER[round(number)]
    if compensating and system == offsets.active:
        raise fail(word, "the work coordinate system's offset changes while cutter radius compensation is on: G40 "
                         "first")
    given = {k: values[letter] * length_m for k, letter in enumerate("XYZ") if letter in values}
    if form == 2:
        lost = offsets.set_machine(system, given)
        if lost:
            raise fail(word, f"G10 L2 moves {system_name(system)}, the system the program runs in, after it has moved "
                             f"({', '.join('XYZ'[k] for k in lost)}): where its origin was on the machine is not known, "
                             "so neither is the shift; give it in the path file (shape.machine.work_offset_mm)")
        return {}
    unknown, known = offsets.set_current(system, given, position_m, line)
    if unknown:
        raise fail(word, "G10 L20 sets the offset from the current position, which is not known here "
                         f"({', '.join('XYZ'[k] for k in unknown)}): move to a point first")
    offsets.bind(set(known))
    return known


def g92(fail: Callable[[str, str], GcodeError], word: str, axes: list[float | None], length_m: float,
        position_m: list[float | None], given: set[int], offsets: Offsets) -> None:
    """G92: the current point gets the given coordinates (the program's origin moves; G92.1-G92.3 are
    :meth:`Offsets.clear_g92`'s); refused without an axis word or from a position not known. Along an axis the program
    has not given yet ("G92 X0 Y0 Z0 (you are here)" at its start), the current point is the path frame's origin and
    known from here on (``position_m`` and ``given`` are updated)."""
    if all(value is None for value in axes):
        raise fail(word, "G92 needs the coordinates the current point gets (X, Y or Z)")
    for k, value in enumerate(axes):
        if value is not None and position_m[k] is None and k in given:
            raise fail(word, f"G92 from an unknown position ({'XYZ'[k]} not known here): move to a point first")
    offsets.set_g92({k: value * length_m for k, value in enumerate(axes) if value is not None}, position_m)
    here = {k for k, value in enumerate(axes) if value is not None and position_m[k] is None}
    for k in here:
        position_m[k] = 0.0  # (set_g92 took the unknown point as the path frame's origin)
    given |= here
    offsets.bind(here)
