"""Errors of robots: their files (kinematics plug-ins too), their names, the closing of their loops,
example-robot-data arms."""

from __future__ import annotations

from placement.exceptions import InputFileError, PlacementError, PluginError


class RobotFileError(InputFileError):
    """A robot description (URDF or sidecar YAML) is missing, malformed or inconsistent."""


class KinematicsPluginError(RobotFileError, PluginError):
    """A robot's kinematics plug-in file fails to load or breaks the contract (no ``make_closed_form``, a maker
    that fails or makes no function, joints that are not the model's): located as a :class:`RobotFileError`, and a
    :class:`~placement.exceptions.PluginError`."""


class UnknownRobotError(PlacementError):
    """A robot name is neither a built-in robot nor a path to a sidecar file."""

    def __init__(self, name: str, known: list[str], suggestions: list[str] | None = None) -> None:
        self.name = name
        self.known = known
        self.suggestions = suggestions or []
        hint = f" (did you mean {' or '.join(self.suggestions)}?)" if self.suggestions else ""
        super().__init__(
            f"unknown robot '{name}'{hint}: expected one of {', '.join(known)} "
            "or the path to a robot sidecar YAML file"
        )


class AssemblyError(PlacementError):
    """A robot's loops cannot be closed, or its assembled configuration cannot be written."""


class ExampleRobotError(PlacementError):
    """An example-robot-data robot cannot be used as asked: unknown name or frame, or an arm outside the rules."""
