"""The robots a name can stand for: built-in folders and robots that installed packages ship.

Built-in robots are the folders of ``placement.robots`` (the repository's top-level ``robots/``),
each with a sidecar named after its folder. A package ships robots under the entry-point group
``placement.robots``: each entry's name is the robot's name and its object a function returning
the path of the sidecar file. Listing reads names and one-line descriptions only; nothing is
loaded until a robot is asked for.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable
from importlib import resources
from pathlib import Path

import yaml

from placement.registry import Registry
from placement.robot.exceptions import UnknownRobotError
from placement.workshop.gepetto import folder_sidecar

ROBOTS: Registry[Callable[[], str | Path]] = Registry("robot", "placement.robots")
ERD_FORM = "erd:"  # a robot argument naming one of example-robot-data's arms: erd:NAME


def builtin_robots_dir() -> Path:
    """The folder of the built-in robots: inside the installed package, or the checkout's ``robots/``."""
    try:
        shipped = Path(str(resources.files("placement.robots")))
    except ModuleNotFoundError:  # a source checkout, where robots/ sits beside placement/
        shipped = Path(__file__).resolve().parents[2] / "robots"
    return shipped


def _builtin(folder: Path) -> Callable[[], Path]:
    return lambda: folder / f"{folder.name}.yaml"


for _folder in sorted(builtin_robots_dir().iterdir()):
    if (_folder / f"{_folder.name}.yaml").is_file():
        ROBOTS.add(_folder.name, _builtin(_folder))


def robot_names() -> list[str]:
    """Names of every robot known by name: built-in and installed."""
    return ROBOTS.names()


def sidecar_path(name_or_path: str | Path) -> Path:
    """The sidecar file of a robot name, or of a path: a file, or a robot folder (see
    :func:`placement.workshop.gepetto.folder_sidecar`: Gepetto's example-parallel-robots format too).

    Raises:
        UnknownRobotError: Neither a known name nor an existing file or folder.
        RobotFileError: A folder holds no robot file.
    """
    text = str(name_or_path)
    if text in ROBOTS:
        return Path(ROBOTS.get(text)())
    found = folder_sidecar(Path(text))
    if found is not None:
        return found
    raise UnknownRobotError(text, robot_names(), close_names(text))


def close_names(text: str) -> list[str]:
    """Robot arguments close to ``text`` (a misspelt name; an example-robot-data name without its ``erd:``)."""
    arms = [f"{ERD_FORM}{name}" for name in erd_names()]
    exact = [arm for arm in arms if arm == f"{ERD_FORM}{text}"]
    return exact or difflib.get_close_matches(text, robot_names() + arms, n=3, cutoff=0.75)


def erd_names() -> list[str]:
    """The robots example-robot-data ships (its list is imported only when asked for)."""
    from example_robot_data.robots_loader import ROBOTS as ERD_ROBOTS

    return sorted(ERD_ROBOTS)


def robot_description(name: str) -> str:
    """The one-line description in a named robot's sidecar, read without loading the robot."""
    try:
        document = yaml.safe_load(sidecar_path(name).read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError, UnicodeDecodeError):
        return "(sidecar unreadable)"
    return str(document.get("description", "")) if isinstance(document, dict) else ""
