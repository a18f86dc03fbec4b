"""Edited copies of a built-in robot's folder, for tests that change its sidecar."""

import shutil
from collections.abc import Callable
from pathlib import Path

import yaml

from placement.robot.catalog import builtin_robots_dir


def edited_copy(name: str, folder: Path, edit: Callable[[dict], None]) -> Path:
    """Copy robot ``name``'s folder into ``folder``, apply ``edit`` to its sidecar; returns the sidecar."""
    copy = folder / name
    shutil.copytree(builtin_robots_dir() / name, copy, ignore=shutil.ignore_patterns("__pycache__"))
    sidecar = copy / f"{name}.yaml"
    document = yaml.safe_load(sidecar.read_text())
    edit(document)
    sidecar.write_text(yaml.safe_dump(document))
    return sidecar


def orthoglide_motor(document: dict) -> dict:
    """The motor entry of the Orthoglide's (single) drive."""
    return next(iter(document["drives"].values()))["motor"]
