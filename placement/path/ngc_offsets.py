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
from dataclasses import dataclass

import numpy as np

SYSTEMS = {540: 1, 550: 2, 560: 3, 570: 4, 580: 5, 590: 6, 591: 7, 592: 8, 593: 9}  # G code (tenths) -> G10's P
BY_NUMBER = {number: code for code, number in SYSTEMS.items()}
NAMES = {540: "G54", 550: "G55", 560: "G56", 570: "G57", 580: "G58", 590: "G59", 591: "G59.1", 592: "G59.2",
         593: "G59.3"}


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
