"""Errors of the drives: measured logs that a calibration cannot read or use."""

from __future__ import annotations

from placement.exceptions import InputFileError, PlacementError


class LogFileError(InputFileError):
    """A measured log is missing, malformed or does not match the robot."""


class CalibrationError(PlacementError):
    """A measured log cannot determine the constants asked: it lacks the quantity they need, shows no motion, or
    leaves them loose."""
