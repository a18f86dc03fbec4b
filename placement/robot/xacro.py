"""xacro descriptions expanded to URDF without ROS (xacrodoc), once per content, into a cache folder.

Vendors publish their robots as xacro macros (``ur.urdf.xacro``, ``fr3.urdf.xacro``), often with
arguments (``ur_type:=ur5e``). :func:`expand_xacro` expands one with its arguments; ``$(find PKG)``
finds a package where :mod:`placement.robot.packages` finds a ``package://`` mesh's: in the folders given,
above the file and beside the folders above it (a ROS-Industrial repository's ``abb_resources`` beside its
``abb_irb2400_support``), and in ``ROS_PACKAGE_PATH``/``AMENT_PREFIX_PATH``.
The URDF is written to the cache folder (:mod:`placement.robot.expanded`), so that the robot's other
readers (Pinocchio, the collision geometry) read a file; the same expansion is written once.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from xml.etree import ElementTree

from placement.distribution import XACRO, require
from placement.exceptions import listed
from placement.robot.exceptions import RobotFileError
from placement.robot.expanded import cached_description
from placement.robot.packages import find_package, search_folders

SUFFIXES = (".xacro",)  # ``.urdf.xacro`` ends so too
XACRO_NAMESPACES = ("{http://www.ros.org/wiki/xacro}", "{http://ros.org/wiki/xacro}")  # both are in use
MAX_PACKAGES = 64  # packages one description may find (each found restarts the expansion)


def is_xacro(path: Path) -> bool:
    """Whether ``path`` names a xacro file (by its suffix)."""
    return path.suffix.lower() in SUFFIXES


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

    folders = search_folders(path, package_paths)
    xacrodoc.packages.reset()  # no package found for an earlier description
    for _ in range(MAX_PACKAGES):
        try:
            text = xacrodoc.XacroDoc.from_file(str(path), subargs=dict(arguments), walk_up=False).to_urdf_string()
        except Exception as error:  # xacro's own errors (XacroException, package look-ups) and XML errors
            package = missing_package(error, xacrodoc.packages.PackageNotFoundError)
            found = find_package(package, folders) if package else None
            if found is None:
                raise RobotFileError(declaring, field, expansion_failure(path, error, package, arguments,
                                                                         folders)) from None
            xacrodoc.packages.update_package_cache({package: found})
        else:
            return cached_description(path.name.removesuffix(path.suffix).removesuffix(".urdf"), text, ".urdf")
    raise RobotFileError(declaring, field, f"xacro cannot expand {path}: it names more than {MAX_PACKAGES} packages")


def missing_package(error: BaseException, not_found: type[BaseException]) -> str | None:
    """The package xacro did not find, if that is what ``error`` (or the error it was raised from) says."""
    cause: BaseException | None = error
    while cause is not None:
        if isinstance(cause, not_found) and cause.args:
            return str(cause.args[0])
        cause = cause.__cause__ or cause.__context__
    return None


def expansion_failure(path: Path, error: Exception, package: str | None, arguments: Mapping[str, str],
                      folders: Sequence[Path]) -> str:
    """What stopped xacro expanding ``path``, and what to do about it."""
    if package:
        return (f"xacro cannot expand {path}: its $(find {package}) or package://{package} names a package not found "
                f"in {listed(folders, 6) or '(no folder)'}; give the folder that holds it with --package-path DIR "
                "(the sidecar's package_paths), or set ROS_PACKAGE_PATH")
    said = " ".join(str(error).split())[:400] or type(error).__name__
    missing = re.match(r"Undefined substitution argument (\S+)", said)
    if missing:
        said = f"its argument '{missing.group(1)}' is not given{said[missing.end():]}"
        hint = " (give it with --robot-arg NAME:=VALUE, or in the sidecar's xacro_args)"
    else:  # an argument left at its default often names a file that does not exist (ur_type: ur5x, dof: "")
        given = ", ".join(f"{name}:={value}" for name, value in arguments.items()) or "none"
        empty = [name for name in empty_arguments(path) if name not in arguments]
        blank = f"; its arguments left empty: {listed(empty, 8)}" if empty else ""
        hint = (f" (arguments given: {given}{blank}; an argument left out takes the file's default: give it with "
                "--robot-arg NAME:=VALUE, or in the sidecar's xacro_args)")
    return f"xacro cannot expand {path}: {said}{hint}"


def empty_arguments(path: Path) -> list[str]:
    """The arguments the xacro file ``path`` declares with an empty default (``<xacro:arg name="dof" default=""/>``):
    often ones it cannot expand without; none when the file cannot be read."""
    try:
        root = ElementTree.parse(path).getroot()
    except (OSError, ElementTree.ParseError):
        return []
    return [element.get("name", "") for element in root.iter() if element.tag in {n + "arg" for n in XACRO_NAMESPACES}
            and element.get("name") and not element.get("default", "").strip()]
