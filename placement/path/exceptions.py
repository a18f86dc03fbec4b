"""Errors of path files, the G-code programs and the pose lists they name; the G-code reader's own, private,
which it turns into located :class:`GcodeError` before they leave it; and the warning it gives for a controller's
words it reads by that controller's manual."""

from __future__ import annotations

from pathlib import Path

from placement.exceptions import InputFileError, PlacementWarning


class PathFileError(InputFileError):
    """A path file is missing, malformed or inconsistent."""


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


class GcodeDialectWarning(PlacementWarning):
    """A G-code program holds a controller's own words (grbl's ``$`` lines, Haas's M88, Centroid's M25, ...) that the
    reader skips or reads as that controller does: one warning per kind, naming the words and their lines."""


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


class _ReaderError(Exception):
    """Inside the G-code reader only: a fault that the reader turns into a :class:`GcodeError` naming its line.

    Private, and no PlacementError: a caller catching PlacementError sees the located error only, and one of these
    escaping the reader would show as the bug it is.
    """


class _CycleError(_ReaderError):
    """A drilling cycle line that cannot be run (the reader names its line in a GcodeError); ``letter`` is the word
    at fault ("" for the cycle word)."""

    def __init__(self, letter: str, problem: str) -> None:
        super().__init__(problem)
        self.letter, self.problem = letter, problem


class _ExpressionError(_ReaderError):
    """Inside the reader (which names the line in a GcodeError): a line that cannot be read or evaluated; ``text``
    is the part at fault as written ("" for the line), ``index`` the line (from 0) once it is known."""

    def __init__(self, text: str, problem: str) -> None:
        super().__init__(problem)
        self.text = text
        self.problem = problem
        self.index = 0


class _FlowError(_ReaderError):
    """Inside the reader (which names the line in a GcodeError): a control-flow error at a line (index from 0),
    blaming a text as written."""

    def __init__(self, index: int, text: str, problem: str) -> None:
        super().__init__(problem)
        self.index, self.text, self.problem = index, text, problem
