"""xacro descriptions expanded to URDF without ROS (xacrodoc), once per content, into a cache folder.

Vendors publish their robots as xacro macros (``ur.urdf.xacro``, ``fr3.urdf.xacro``), often with
arguments (``ur_type:=ur5e``). :func:`expand_xacro` expands one with its arguments; ``$(find PKG)``
finds a package in the folders given and above the file (as :mod:`placement.robot.packages` does).
The URDF is written to ``$XDG_CACHE_HOME/placement/xacro`` (``~/.cache`` by default), named after
the file and a hash of its text, so that the robot's other readers (Pinocchio, the collision geometry)
read a file; the same expansion is written once.
"""

from __future__ import annotations

import hashlib
import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

from placement.distribution import XACRO, require
from placement.files import staged
from placement.robot.exceptions import RobotFileError

SUFFIXES = (".xacro",)  # ``.urdf.xacro`` ends so too


def is_xacro(path: Path) -> bool:
    """Whether ``path`` names a xacro file (by its suffix)."""
    return path.suffix.lower() in SUFFIXES


def cache_folder() -> Path:
    """Where expanded descriptions are written."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "placement" / "xacro"


def cached_description(stem: str, text: str, suffix: str) -> Path:
    """The cache's file holding ``text`` (an expanded description), named by ``stem`` and the text's digest, written
    once (atomically) and reused while the text is the same."""
    expanded = cache_folder() / f"{stem}-{hashlib.sha256(text.encode()).hexdigest()[:16]}{suffix}"
    if not expanded.is_file():
        expanded.parent.mkdir(parents=True, exist_ok=True)
        with staged(expanded, text):
            pass
    return expanded


def expand_xacro(path: Path, arguments: Mapping[str, str], package_paths: Sequence[Path], declaring: Path,
                 field: str) -> Path:
    """The URDF file that the xacro file ``path`` expands to with ``arguments``.

    Args:
        path: The xacro file.
        arguments: Its arguments (``ur_type: ur5e``), as ``--robot-arg NAME:=VALUE`` or a sidecar's ``xacro_args``.
        package_paths: Folders where ``$(find PKG)`` looks first (each a package, or a folder holding packages).
        declaring: The file that names ``path``, for errors (a sidecar, or ``path`` itself).
        field: Where it names it (``urdf``), for errors.

    Raises:
        MissingExtraError: xacrodoc is not installed (the ``xacro`` extra).
        RobotFileError: xacro cannot expand it (an argument missing, a package not found); the message says
            how to give an argument.
    """
    require(XACRO)
    import xacrodoc  # the [xacro] extra, checked above

    xacrodoc.packages.look_in([str(folder) for folder in package_paths])
    try:
        text = xacrodoc.XacroDoc.from_file(str(path), subargs=dict(arguments), walk_up=True).to_urdf_string()
    except Exception as error:  # xacro's own errors (XacroException, package look-ups) and XML errors
        said = " ".join(str(error).split())[:400] or type(error).__name__
        missing = re.match(r"Undefined substitution argument (\S+)", said)
        if missing:
            said = f"its argument '{missing.group(1)}' is not given{said[missing.end():]}"
            hint = " (give it with --robot-arg NAME:=VALUE, or in the sidecar's xacro_args)"
        else:  # an argument left at its default often names a file that does not exist (ur_type: ur5x)
            given = ", ".join(f"{name}:={value}" for name, value in arguments.items()) or "none"
            hint = (f" (arguments given: {given}; an argument left out takes the file's default: give it with "
                    "--robot-arg NAME:=VALUE, or in the sidecar's xacro_args)")
        raise RobotFileError(declaring, field, f"xacro cannot expand {path}: {said}{hint}") from None
    return cached_description(path.name.removesuffix(path.suffix).removesuffix(".urdf"), text, ".urdf")
