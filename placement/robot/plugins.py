"""A robot's kinematics plug-in: a Python file beside its sidecar with a closed-form solver.

Loading a robot folder that names a plug-in runs that file, as installing a package would; so the
file must be a ``.py`` file inside the sidecar's own folder (code from elsewhere comes as an
installed package, through the kinematics solvers' entry points).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType
from typing import Any

import pinocchio as pin

from placement.robot.exceptions import RobotFileError

# A closed-form solver: platform coordinates (Taylor2 or arrays, m) -> {joint name: value (m, rad)}.
ClosedFormFunction = Any


def load_plugin(sidecar_path: Path, plugin: str | None) -> ModuleType | None:
    """Import the plug-in file named by the sidecar (None when it names none)."""
    if plugin is None:
        return None
    folder = sidecar_path.parent.resolve()
    file = (folder / plugin).resolve()
    if file.suffix != ".py" or not file.is_relative_to(folder):
        raise RobotFileError(sidecar_path, "kinematics_plugin", f"expected a .py file in the sidecar's own folder "
                             f"{folder}, got '{plugin[:80]}' (install other code as a package with a kinematics "
                             "solver entry point)")
    if not file.is_file():
        raise RobotFileError(sidecar_path, "kinematics_plugin", f"file not found: {file}")
    spec = importlib.util.spec_from_file_location(f"placement_plugin_{file.stem}", file)
    if spec is None or spec.loader is None:
        raise RobotFileError(sidecar_path, "kinematics_plugin", f"not a Python file: {file}")
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except (Exception, SystemExit) as error:  # any error in the user's plug-in code, even an exit
        raise RobotFileError(file, "", f"the kinematics plug-in failed to load: {type(error).__name__}: {error}") from None
    if not hasattr(module, "make_closed_form"):
        raise RobotFileError(file, "", "a kinematics plug-in must define make_closed_form(model)")
    return module


def make_closed_form(plugin: ModuleType | None, model: pin.Model, sidecar_path: Path) -> ClosedFormFunction | None:
    """The plug-in's closed-form solver for ``model`` (None without a plug-in)."""
    if plugin is None:
        return None
    try:
        solve = plugin.make_closed_form(model)
    except (Exception, SystemExit) as error:  # any error in the user's plug-in code, even an exit
        raise RobotFileError(sidecar_path, "kinematics_plugin",
                             f"make_closed_form failed: {type(error).__name__}: {error}") from None
    if not callable(solve):
        raise RobotFileError(sidecar_path, "kinematics_plugin", f"make_closed_form must return a function of the "
                             f"end-effector position, got {type(solve).__name__}")
    return solve
