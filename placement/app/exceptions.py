"""Errors of the workbench: actions that come too early."""

from __future__ import annotations

from placement.exceptions import PlacementError


class NotReadyError(PlacementError):
    """A workbench action needs a result not computed yet (optimise, map or search the front first), or its job is
    still running."""
