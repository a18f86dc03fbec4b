"""Errors of the command line: options with values they cannot take."""

from __future__ import annotations

from placement.exceptions import SettingsError


class UsageError(SettingsError):
    """A command-line option has a value it cannot take."""
