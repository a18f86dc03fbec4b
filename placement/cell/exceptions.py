"""Errors of robot cell files."""

from __future__ import annotations

from placement.exceptions import InputFileError


class CellFileError(InputFileError):
    """A robot cell file (obstacles, keep-out zones, tool body) is missing, malformed or inconsistent."""
