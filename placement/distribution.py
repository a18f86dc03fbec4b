"""The installed distribution: its version, and the extras that bring the optional features.

``pip install path-placement`` installs the core: what the main command, maps, feed studies, studies,
``check``, ``assemble``, ``calibrate`` (without ``--png``) and ``export`` need. The rest comes as
extras (pyproject.toml's ``[project.optional-dependencies]``), each a :class:`Feature` here:

- ``viz``: the 3-D scene (``--html``, ``--show``: meshcat, trimesh, pycollada, matplotlib's colour
  maps) and the plots (``--png``: matplotlib);
- ``pareto``: Pareto fronts (``--objectives``: pymoo's NSGA-II);
- ``app``: the workbench (``placement app``: viser, and the meshes, pictures and fronts it shows);
- ``cluster``: a Dask cluster (``--scheduler``: dask's distributed);
- ``xacro``: robot descriptions in xacro, expanded without ROS (xacrodoc);
- ``all``: every one of them.

A module that needs an optional package imports it only where it is needed, after :func:`require`,
which raises :class:`~placement.exceptions.MissingExtraError` naming the feature and the extra when
it is not installed; ``import placement`` imports none of them.
"""

from __future__ import annotations

import importlib
import tomllib
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from placement.exceptions import MissingExtraError

NAME = "path-placement"  # the distribution's name, as pip knows it (the import name is placement)
UNKNOWN_VERSION = "0+unknown"  # neither installed nor in its source tree


@dataclass(frozen=True)
class Feature:
    """An optional feature: what the user asked for, the extra that brings it, the modules it imports.

    Attributes:
        words: The feature in the user's words, with the options that ask for it.
        extra: The extra of pyproject.toml that installs its modules.
        modules: The modules it imports (import names: ``collada`` is pycollada's).
    """

    words: str
    extra: str
    modules: tuple[str, ...]


SCENE = Feature("the 3-D scene (--html, --show)", "viz", ("meshcat", "trimesh", "collada", "matplotlib"))
PLOTS = Feature("plotting (--png)", "viz", ("matplotlib",))
FRONTS = Feature("the Pareto front search (--objectives)", "pareto", ("pymoo",))
WORKBENCH = Feature("the workbench (placement app)", "app", ("viser", "trimesh", "collada", "matplotlib", "pymoo"))
CLUSTER = Feature("a Dask cluster (--scheduler, PLACEMENT_SCHEDULER)", "cluster", ("distributed",))
XACRO = Feature("robot descriptions in xacro (.xacro, .urdf.xacro)", "xacro", ("xacrodoc",))
FEATURES = (SCENE, PLOTS, FRONTS, WORKBENCH, CLUSTER, XACRO)


def require(feature: Feature) -> None:
    """Import the optional modules ``feature`` needs, so that the imports that follow this call succeed.

    Python imports each module once; calling this again costs a dictionary look-up per module.

    Raises:
        MissingExtraError: A module cannot be imported (not installed, or broken): the message names the feature,
            the extra and the command that installs it.
    """
    for module in feature.modules:
        try:
            importlib.import_module(module)
        except ImportError as error:
            raise MissingExtraError(feature.words, feature.extra, module, NAME, str(error)) from error


def version() -> str:
    """The version of placement: the installed distribution's, else its source tree's pyproject.toml's, else
    ``0+unknown``. The one source is pyproject.toml's ``version``: installing copies it into the metadata."""
    try:
        return metadata.version(NAME)
    except metadata.PackageNotFoundError:
        pass
    project = Path(__file__).resolve().parent.parent / "pyproject.toml"
    try:
        table = tomllib.loads(project.read_text(encoding="utf-8")).get("project", {})
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return UNKNOWN_VERSION
    return str(table["version"]) if table.get("name") == NAME and "version" in table else UNKNOWN_VERSION
