"""A robot folder's URDF generator (its ``make_urdf.py``), loaded as a module for the test that the committed URDF is
what it writes."""

import importlib.util
from pathlib import Path
from types import ModuleType


def urdf_generator(folder: Path) -> ModuleType:
    """The ``make_urdf.py`` script of a robot's ``folder``, loaded (not run as a script)."""
    spec = importlib.util.spec_from_file_location("make_urdf", folder / "make_urdf.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
