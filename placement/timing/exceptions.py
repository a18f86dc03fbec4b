"""Errors of timing laws: one that the objectives do not allow, or that cannot time the path."""

from __future__ import annotations

from placement.exceptions import PlacementError


class TimingError(PlacementError):
    """A timing law conflicts with what the objectives (or a search) need, or lacks what it needs (the realistic law's
    bounds)."""
