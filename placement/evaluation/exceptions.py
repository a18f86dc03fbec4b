"""Errors of the evaluation: a Dask cluster that cannot be used."""

from __future__ import annotations

from placement.exceptions import PlacementError


class ClusterError(PlacementError):
    """A Dask scheduler was given but cannot be reached (Dask's distributed package missing is a
    :class:`~placement.exceptions.MissingExtraError`: the ``cluster`` extra)."""
