"""Errors of the evaluation: a Dask cluster that cannot be used."""

from __future__ import annotations

from placement.exceptions import PlacementError


class ClusterError(PlacementError):
    """A Dask scheduler was given but cannot be used: it cannot be reached, or Dask's distributed package is
    missing."""
