"""Exceptions raised by placement: the root of every error, and those every package shares.

Every error a user can cause derives from :class:`PlacementError`, so a caller (or the command
line) can catch one type and report its message, which always says what was wrong and where.
Each package defines its own errors beside its code, in its ``exceptions`` module:

- :mod:`placement.path.exceptions`: path files, G-code programs, pose lists;
- :mod:`placement.timing.exceptions`: timing laws the objectives or the path cannot take;
- :mod:`placement.robot.exceptions`: robot files, robot names, assembly, example-robot-data arms;
- :mod:`placement.kinematics.exceptions`: unreachable samples;
- :mod:`placement.workshop.exceptions`: measured logs;
- :mod:`placement.cell.exceptions`: cell files;
- :mod:`placement.cli.exceptions`: command-line options.

This module holds the root, :class:`InputFileError` (the located error of any input file, whose
subclasses the packages define), and :class:`UnknownMemberError`, which every plug-in family
(:mod:`placement.registry`) raises.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


class PlacementError(Exception):
    """Base class of every error raised by placement for a user-facing reason.

    Errors travel between processes whole (a worker's error reaches the caller as raised).
    """

    def __reduce__(self) -> tuple[Any, ...]:
        return _rebuild, (type(self), str(self), self.__dict__)


def _rebuild(cls: type[PlacementError], message: str, attributes: dict[str, Any]) -> PlacementError:
    """An error as pickled by :meth:`PlacementError.__reduce__`, without calling its constructor."""
    error = cls.__new__(cls)
    Exception.__init__(error, message)
    error.__dict__.update(attributes)
    return error


class InputFileError(PlacementError):
    """An input file is missing, malformed or inconsistent.

    Attributes:
        path: The file at fault.
        field: Dotted path of the offending field inside the file ("" for the whole file).
        problem: What is wrong, including what was expected.
    """

    def __init__(self, path: str | Path, field: str, problem: str) -> None:
        self.path = Path(path)
        self.field = field
        self.problem = problem
        where = f"{self.path}" + (f", field '{field}'" if field else "")
        super().__init__(f"{where}: {problem}")


class SettingsError(PlacementError):
    """A setting or an option has a value it cannot take (a placement value, a bound, a name, a count)."""


class UnknownMemberError(PlacementError):
    """A name that no member of a family has; the message lists the known names."""

    def __init__(self, family: str, name: str, known: list[str]) -> None:
        self.family, self.name, self.known = family, name, known
        super().__init__(f"unknown {family} '{name}': expected one of {', '.join(known) or '(none registered)'}")
