"""``package://`` and ``file://`` URIs of a robot description, resolved to files, saying where they were looked for.

A URDF names its meshes ``package://NAME/PATH`` (ROS), ``file:///ABSOLUTE/PATH`` or a path relative to
itself. A package NAME is a folder: one whose ``package.xml`` says ``<name>NAME</name>``, or one called
NAME. It is looked for, in this order:

1. in the folders the user gives (``--package-path DIR``, a sidecar's ``package_paths``): each is the
   package itself, or holds it;
2. above the URDF: its folder and every folder above it (a description cloned from its repository
   resolves without any setting, even where the repository's folder is not called NAME);
3. in ``ROS_PACKAGE_PATH`` (folders that hold packages, or are packages) and under
   ``AMENT_PREFIX_PATH``'s ``share`` folders (ROS 2 installs);
4. in example-robot-data's own folder, for its robots and descriptions made from them (the built-in
   ``ur5_track`` names the UR5's meshes ``package://example-robot-data/...``).

``resolve-robotics-uri-py`` resolves such URIs too, but only where a package's folder bears its name
and without saying where it looked; a cloned description (``Universal_Robots_ROS2_Description`` holds
``ur_description``) needs both.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from functools import cache
from pathlib import Path
from urllib.parse import unquote, urlparse
from xml.etree import ElementTree

import pinocchio as pin

from placement.exceptions import listed
from placement.robot.exceptions import RobotFileError
from placement.robot.mjcf import is_mjcf, mjcf_geometry
from placement.robot.model import Robot
from placement.robot.urdf import erd_package_folder

PACKAGE_VARIABLES = ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH")
_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")


def package_name(folder: Path) -> str | None:
    """The name a folder's ``package.xml`` gives its package, or None (no such file, or no name)."""
    return _package_name(folder.resolve())


@cache
def _package_name(folder: Path) -> str | None:
    try:
        found = _NAME.search((folder / "package.xml").read_text(encoding="utf-8", errors="replace")[:20_000])
    except OSError:
        return None
    return found.group(1) if found else None


def search_folders(description: Path, given: Sequence[Path] = ()) -> list[Path]:
    """The folders a package is looked for in, in order (module docstring): given, above the description, ROS's."""
    folders = [Path(folder).expanduser().resolve() for folder in given]
    folders += [description.resolve().parent, *description.resolve().parent.parents]
    for variable in PACKAGE_VARIABLES:
        for entry in filter(None, os.environ.get(variable, "").split(os.pathsep)):
            folder = Path(entry).expanduser()
            folders.append(folder / "share" if variable == "AMENT_PREFIX_PATH" else folder)
    folders.append(erd_package_folder())
    return list(dict.fromkeys(folder for folder in folders if folder.is_dir()))


def find_package(name: str, folders: Sequence[Path]) -> Path | None:
    """The folder of package ``name``: one of ``folders`` or a folder in one of them, named ``name`` or whose
    ``package.xml`` names it; None when none is."""
    for folder in folders:
        if folder.name == name or package_name(folder) == name:
            return folder
        inside = folder / name
        if inside.is_dir():
            return inside
        try:
            children = sorted(child for child in folder.iterdir() if child.is_dir())
        except OSError:
            continue
        for child in children:
            if (child / "package.xml").is_file() and package_name(child) == name:
                return child
    return None


def resolve_uri(uri: str, description: Path, folders: Sequence[Path], field: str) -> Path:
    """The file a URI of the description names.

    Args:
        uri: ``package://NAME/PATH``, ``file:///PATH``, an absolute path or one relative to the description's folder.
        description: The URDF naming it (errors name it).
        folders: Where packages are looked for (:func:`search_folders`).
        field: Where the URI stands in the description, for errors (``urdf.link.NAME.visual``).

    Raises:
        RobotFileError: The package or the file is not found; the message lists the folders looked in.
    """
    parsed = urlparse(uri)
    if parsed.scheme == "package":
        package = find_package(parsed.netloc, folders)
        if package is None:
            looked = listed(folders, 6) or "(no folder)"
            raise RobotFileError(description, field, f"package '{parsed.netloc}' of '{uri[:120]}' not found in {looked}; "
                                 "give the folder that holds it with --package-path DIR (the sidecar's package_paths), "
                                 "or set ROS_PACKAGE_PATH")
        path = package / unquote(parsed.path).lstrip("/")
    elif parsed.scheme == "file":
        path = Path(unquote(parsed.path))
    elif len(parsed.scheme) <= 1:  # a path (a Windows drive letter is not a scheme)
        path = description.parent / uri
    else:
        raise RobotFileError(description, field, f"'{uri[:120]}': expected package://, file:// or a file path")
    if not path.is_file():
        raise RobotFileError(description, field, f"'{uri[:120]}' names {path}, which does not exist")
    return path.resolve()


def resolved_description(description: Path, folders: Sequence[Path]) -> str:
    """The URDF's text with every mesh's URI replaced by its file's absolute path (for Pinocchio's geometry).

    Raises:
        RobotFileError: A mesh is not found (the message names the link and lists the folders looked in).
    """
    root = ElementTree.fromstring(description.read_bytes())
    for link in root.iter("link"):
        for kind in ("visual", "collision"):
            for element in link.iter(kind):
                for mesh in element.iter("mesh"):
                    uri = mesh.get("filename")
                    if uri:
                        field = f"urdf.link.{link.get('name')}.{kind}"
                        mesh.set("filename", str(resolve_uri(uri, description, folders, field)))
    return ElementTree.tostring(root, encoding="unicode")


def description_geometry(robot: Robot, kind: pin.GeometryType) -> pin.GeometryModel:
    """Pinocchio's geometry model of the URDF's collision or visual elements on the robot's (reduced) model, every
    mesh found as this module says (an MJCF's: :func:`placement.robot.mjcf.mjcf_geometry`).

    Raises:
        RobotFileError: A mesh is not found, or cannot be read (the message names the link and the folders).
    """
    if is_mjcf(robot.urdf_path):
        return mjcf_geometry(robot.model, robot.urdf_path, kind)
    folders = search_folders(robot.urdf_path, robot.package_paths)
    text = resolved_description(robot.urdf_path, folders)
    try:
        return pin.buildGeomFromUrdfString(robot.model, text, kind)
    except ValueError as error:  # a mesh Pinocchio cannot read
        raise RobotFileError(robot.urdf_path, "", f"cannot build the geometry: {str(error)[:200]}") from None
