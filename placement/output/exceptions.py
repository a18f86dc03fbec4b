"""Errors of the outputs: result files read back and controller exports."""

from placement.exceptions import InputFileError, PlacementError


class ResultFileError(InputFileError):
    """A result file (the main job's ``--json``) is missing, malformed or lacks the placement asked for."""


class ExportError(PlacementError):
    """A format cannot hold the placement (a G54 offset with G68 holds no tilt)."""
