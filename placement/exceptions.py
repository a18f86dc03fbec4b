"""Exceptions raised by placement.

Every error a user can cause derives from :class:`PlacementError`, so a caller (or the command
line) can catch one type and report its message, which always says what was wrong and where.
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


class RobotFileError(InputFileError):
    """A robot description (URDF or sidecar YAML) is missing, malformed or inconsistent."""


class PathFileError(InputFileError):
    """A path file is missing, malformed or inconsistent."""


class UnknownRobotError(PlacementError):
    """A robot name is neither a built-in robot nor a path to a sidecar file."""

    def __init__(self, name: str, known: list[str]) -> None:
        self.name = name
        self.known = known
        super().__init__(
            f"unknown robot '{name}': expected one of {', '.join(known)} "
            "or the path to a robot sidecar YAML file"
        )


class UnreachableError(PlacementError):
    """Some samples of a task-space trajectory have no valid robot configuration.

    Attributes:
        sample_indices: Indices of the unreachable samples (at most the first 20 are kept).
        n_unreachable: How many samples are unreachable.
        reason: Why the first one failed.
    """

    def __init__(self, sample_indices: list[int], n_unreachable: int, reason: str) -> None:
        self.sample_indices = sample_indices[:20]
        self.n_unreachable = n_unreachable
        self.reason = reason
        super().__init__(
            f"{n_unreachable} sample(s) unreachable, first at index {sample_indices[0]}: {reason}"
        )


class AssemblyError(PlacementError):
    """A robot's loops cannot be closed, or its assembled configuration cannot be written."""


class CellFileError(InputFileError):
    """A robot cell file (obstacles, keep-out zones, tool body) is missing, malformed or inconsistent."""


class GcodeError(PathFileError):
    """A G-code program named by a path file has a word, number or move that cannot be followed.

    Attributes:
        line: The line number in the program (counted from 1).
        word: The word at fault as written ("" when the whole line is).
    """

    def __init__(self, path: str | Path, line: int, word: str, problem: str) -> None:
        super().__init__(path, f"line {line}", problem)
        self.line = line
        self.word = word
        Exception.__init__(self, f"{self.path}, line {line}{f', word {word!r}' if word else ''}: {problem}")


class PoseFileError(PathFileError):
    """A pose list named by a path file has a missing column, a bad value or a bad row.

    Attributes:
        row: The data row at fault, counted from 1 after a CSV header (0: the header or the whole file).
        column: The column at fault ("" when the whole row or file is).
    """

    def __init__(self, path: str | Path, row: int, column: str, problem: str) -> None:
        super().__init__(path, f"row {row}" if row else "", problem)
        self.row = row
        self.column = column
        where = (f", row {row}" if row else "") + (f", column {column!r}" if column else "")
        Exception.__init__(self, f"{self.path}{where}: {problem}")
