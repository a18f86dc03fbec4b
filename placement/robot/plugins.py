"""A robot's kinematics plug-in: a Python file beside its sidecar with a closed-form solver.

The file defines ``make_closed_form(model)``, and may define ``make_compiled_closed_form(model)``: the same solver
compiled over samples (see ``CompiledClosedForm``), which the ``closed_form`` kinematics then runs instead.

Loading a robot folder that names a plug-in runs that file, as installing a package would; so the
file must be a ``.py`` file inside the sidecar's own folder (code from elsewhere comes as an
installed package, through the kinematics solvers' entry points).
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pinocchio as pin

from placement.robot.exceptions import KinematicsPluginError, RobotFileError

# A closed-form solver: platform coordinates (Taylor2 or arrays, m) -> {joint name: value (m, rad)}.
ClosedFormFunction = Any
# The same compiled over samples: (N, 3) platform positions, velocities, accelerations (base frame, SI) -> the joints'
# names (J,), values (N, J), rates (N, J), accelerations (N, J) and gradients by the platform position (N, J, 3).
CompiledClosedForm = Any


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
    # A name of its own per content: the module is registered under it, for numba's on-disk cache of a compiled
    # plug-in, which finds a function's module by name when it loads the function in a later process; a copy of
    # the file (a robot folder copied with its cache) finds the same name there.
    name = f"placement_plugin_{file.stem}_{hashlib.sha1(file.read_bytes()).hexdigest()[:12]}"
    spec = importlib.util.spec_from_file_location(name, file)
    if spec is None or spec.loader is None:
        raise RobotFileError(sidecar_path, "kinematics_plugin", f"not a Python file: {file}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except (Exception, SystemExit) as error:  # any error in the user's plug-in code, even an exit
        del sys.modules[name]
        raise KinematicsPluginError(file, "", f"the kinematics plug-in failed to load: {type(error).__name__}: {error}") from None
    if not hasattr(module, "make_closed_form"):
        raise KinematicsPluginError(file, "", "a kinematics plug-in must define make_closed_form(model)")
    return module


def make_closed_form(plugin: ModuleType | None, model: pin.Model, sidecar_path: Path) -> ClosedFormFunction | None:
    """The plug-in's closed-form solver for ``model`` (None without a plug-in)."""
    if plugin is None:
        return None
    return _made(plugin, "make_closed_form", model, sidecar_path, "position")


def make_compiled_closed_form(plugin: ModuleType | None, model: pin.Model,
                              sidecar_path: Path) -> CompiledClosedForm | None:
    """The plug-in's compiled closed-form solver for ``model`` (None when it has none)."""
    if plugin is None or not hasattr(plugin, "make_compiled_closed_form"):
        return None
    return _made(plugin, "make_compiled_closed_form", model, sidecar_path, "motion")


def _made(plugin: ModuleType, maker: str, model: pin.Model, sidecar_path: Path, argument: str) -> Any:
    """The function the plug-in's ``maker`` makes for ``model``, a function of the end effector's ``argument``.

    Raises:
        KinematicsPluginError: The maker failed, or made no function.
    """
    try:
        solve = getattr(plugin, maker)(model)
    except (Exception, SystemExit) as error:  # any error in the user's plug-in code, even an exit
        raise KinematicsPluginError(sidecar_path, "kinematics_plugin",
                                    f"{maker} failed: {type(error).__name__}: {error}") from None
    if not callable(solve):
        raise KinematicsPluginError(sidecar_path, "kinematics_plugin", f"{maker} must return a function of the "
                                    f"end-effector {argument}, got {type(solve).__name__}")
    return solve
