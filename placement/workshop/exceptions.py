"""Errors of the drives: measured logs that a calibration cannot read or use."""

from __future__ import annotations

from placement.exceptions import InputFileError


class LogFileError(InputFileError):
    """A measured log is missing, malformed or does not match the robot."""
