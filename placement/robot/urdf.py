"""URDF files: reading, checking and the one-angle rewrite.

A sidecar names its URDF by a path relative to itself or as ``example-robot-data:KEY``
(:func:`resolve_urdf`). The standard library's XML parser reads what loading checks (inertials,
link and joint names, link masses, :func:`read_urdf`), rewrites the ``continuous`` joints as one-angle
revolute ones (:func:`one_angle_urdf`) and puts in the inertials a sidecar gives (its ``links``);
Pinocchio builds the model from the rewritten text (:func:`pinocchio_model`). A URDF library would add
a second of imports to every command.
"""

from __future__ import annotations

import os
import re
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin

from placement.robot.exceptions import RobotFileError

if TYPE_CHECKING:
    from placement.robot.sidecar import LinkInertial

ERD_PREFIX = "example-robot-data:"
CLOSING = re.compile(r"closing_(.+)_([12])")  # onshape-to-robot's loop frames: closing_NAME_1 and closing_NAME_2
NO_LIMIT = 1e10  # a position limit this large (m or rad) is Pinocchio's stand-in for none


def resolve_urdf(sidecar_path: Path, urdf: str) -> Path:
    """The URDF file a sidecar's ``urdf`` field names.

    Args:
        sidecar_path: The sidecar: its folder resolves a relative path, and errors name it.
        urdf: The field: a path relative to the sidecar's folder, or ``example-robot-data:KEY``.

    Returns:
        The URDF's absolute path.

    Raises:
        RobotFileError: No such robot or file, or the path cannot be followed (field ``urdf``).
    """
    if urdf.startswith(ERD_PREFIX):
        from example_robot_data.robots_loader import ROBOTS

        key = urdf.removeprefix(ERD_PREFIX)
        if key not in ROBOTS:
            raise RobotFileError(sidecar_path, "urdf", f"example-robot-data has no robot '{key}'")
        return erd_urdf_path(ROBOTS[key])
    try:
        path = (sidecar_path.parent / urdf).resolve()
    except (OSError, RuntimeError) as error:  # a symbolic-link loop, say
        raise RobotFileError(sidecar_path, "urdf", f"cannot follow '{urdf[:80]}': {error}") from None
    if not path.is_file():
        raise RobotFileError(sidecar_path, "urdf", f"URDF file not found: {path}")
    return path


def erd_urdf_path(loader: Any) -> Path:
    """The URDF file of an example-robot-data loader class, found as its constructor finds it but without building
    the robot, which loads every mesh (0.5 s for the Panda)."""
    from example_robot_data.robots_loader import getModelPath

    if not loader.urdf_filename:  # an SDF robot: only its constructor knows
        return Path(loader().df_path).resolve()
    relative = os.path.join(loader.path, loader.urdf_subpath, loader.urdf_filename)
    return Path(os.path.join(loader.model_path or getModelPath(relative), relative)).resolve()


def erd_package_folder() -> Path:
    """example-robot-data's own package folder (its ``package.xml`` names it ``example-robot-data``), which its URDFs'
    ``package://example-robot-data/...`` meshes are relative to; a description made from one of its robots (the
    built-in ``ur5_track``) names its meshes so too."""
    from example_robot_data.robots_loader import ROBOTS

    urdf = erd_urdf_path(ROBOTS["ur5"])
    return next((folder for folder in urdf.parents if (folder / "package.xml").is_file()), urdf.parent)


def pinocchio_model(path: Path, inertials: Mapping[str, LinkInertial] | None = None) -> pin.Model:
    """Pinocchio's model of the URDF, every ``continuous`` joint read as a ``revolute`` one without position limits
    (:func:`one_angle_urdf`), and the links named in ``inertials`` given those instead of the URDF's.

    Args:
        path: The URDF file.
        inertials: Inertials by link name (a sidecar's ``links``), each replacing the link's ``<inertial>``; the
            names must be the URDF's links (:func:`read_urdf` lists them).

    Returns:
        The model, one coordinate per revolute or prismatic joint.

    Raises:
        RobotFileError: The file is not XML, or Pinocchio's parser refuses it; its complaints (printed by C++)
            become the message.
    """
    try:
        root = ElementTree.fromstring(path.read_bytes())
    except ElementTree.ParseError as error:
        raise _not_xml(path, error) from None
    _one_angle(root)
    _replace_inertials(root, inertials or {})
    text = ElementTree.tostring(root, encoding="unicode")
    with tempfile.TemporaryFile(mode="w+") as capture:
        saved = os.dup(2)
        os.dup2(capture.fileno(), 2)
        try:
            return pin.buildModelFromXML(text)
        except (ValueError, RuntimeError) as error:
            os.dup2(saved, 2)
            capture.seek(0)
            said = [line.strip().removeprefix("Error:").strip() for line in capture.read().splitlines()
                    if line.strip() and not line.strip().startswith("at line")]
            reason = next((line for line in said if line), str(error))
            raise RobotFileError(path, "", f"Pinocchio cannot build a model from it: {reason[:200]}") from None
        finally:
            os.dup2(saved, 2)
            os.close(saved)


def one_angle_urdf(document: str | bytes) -> str:
    """A URDF with every ``continuous`` joint made ``revolute`` without position limits, as the URDF defines a
    continuous joint (read as missing, see :func:`urdf_limits_missing`).

    Pinocchio models a continuous joint by two coordinates (cos θ, sin θ); the solvers and limits here use one
    angle θ per joint. The kinematics and dynamics are the same.

    The robot's joints are the ``<joint>`` children of ``<robot>``; a ``<joint>`` inside a ``<transmission>`` only
    names one, and is left alone. A continuous joint's ``<limit>`` loses ``lower`` and ``upper`` and keeps the
    effort and velocity; a revolute joint needs a ``<limit>``, so one without gets ``effort="0" velocity="0"``
    (none given, as loading then says). The standard library's XML parser reads the document and writes it back:
    without comments, processing instructions or XML declaration, and with the namespaces declared on the root
    element under the prefixes it chooses (``ns0``, ...); elements, attributes and text are kept.

    Args:
        document: The URDF's XML: text, or the file's bytes (decoded as its XML declaration says).

    Returns:
        The rewritten URDF's XML text.

    Raises:
        xml.etree.ElementTree.ParseError: ``document`` is not well-formed XML.
    """
    root = ElementTree.fromstring(document)
    _one_angle(root)
    return ElementTree.tostring(root, encoding="unicode")


def _one_angle(root: ElementTree.Element) -> None:
    """:func:`one_angle_urdf` on the parsed document, in place."""
    for joint in root.findall("joint"):
        if joint.get("type") != "continuous":
            continue
        joint.set("type", "revolute")
        limits = joint.findall("limit")
        for limit in limits:
            for bound in ("lower", "upper"):
                limit.attrib.pop(bound, None)
        if not limits:
            ElementTree.SubElement(joint, "limit", effort="0", velocity="0")


def _replace_inertials(root: ElementTree.Element, inertials: Mapping[str, LinkInertial]) -> None:
    """Each link named in ``inertials`` given that inertial instead of its own, in place (numbers written exactly)."""
    for link in root.findall("link"):
        given = inertials.get(str(link.get("name")))
        if given is None:
            continue
        for old in link.findall("inertial"):
            link.remove(old)
        inertial = ElementTree.SubElement(link, "inertial")
        ElementTree.SubElement(inertial, "origin", xyz=" ".join(repr(float(c)) for c in given.com_m), rpy="0 0 0")
        ElementTree.SubElement(inertial, "mass", value=repr(float(given.mass_kg)))
        (xx, xy, xz), (_, yy, yz), (_, _, zz) = given.inertia_kg_m2
        ElementTree.SubElement(inertial, "inertia", {key: repr(float(value)) for key, value in (
            ("ixx", xx), ("ixy", xy), ("ixz", xz), ("iyy", yy), ("iyz", yz), ("izz", zz))})


@dataclass(frozen=True)
class UrdfContents:
    """What loading reads of a URDF besides Pinocchio's model.

    Attributes:
        names: The names of the ``link`` and of the ``joint`` elements, by kind.
        masses: The mass of every link that has an inertial, by link name (kg); a sidecar's ``links`` replace the
            URDF's.
    """

    names: dict[str, set[str]]
    masses: dict[str, float]


def read_urdf(path: Path, inertials: Mapping[str, LinkInertial] | None = None) -> UrdfContents:
    """Parse the URDF, check every inertial is physical, and return its link and joint names and link masses.

    Args:
        path: The URDF file.
        inertials: Inertials by link name (a sidecar's ``links``) replacing the URDF's, which are then not checked.

    Returns:
        The names of the ``link`` and ``joint`` elements, and the links' masses.

    Raises:
        RobotFileError: The file is not XML, not a URDF, or an inertial is not physical (the field names the link).
    """
    inertials = inertials or {}
    try:
        root = ElementTree.parse(path).getroot()
    except (ElementTree.ParseError, UnicodeDecodeError) as error:
        raise _not_xml(path, error) from None
    if root.tag != "robot":
        raise RobotFileError(path, "", f"not a URDF: the root element is <{root.tag[:40]}>, expected <robot>")
    masses = {}
    for link in root.findall("link"):
        name, inertial = str(link.get("name")), link.find("inertial")
        if name in inertials:
            masses[name] = float(inertials[name].mass_kg)
        elif inertial is not None:
            masses[name] = _check_inertial(path, f"link '{name}' inertial", inertial)
    return UrdfContents({kind: {str(element.get("name")) for element in root.findall(kind)} for kind in ("link", "joint")},
                        masses)


def _not_xml(path: Path, error: Exception) -> RobotFileError:
    """The error for a file the XML parser refuses, with its reason (and line and column)."""
    return RobotFileError(path, "", f"not an XML file: {str(error)[:200]}")


def _check_inertial(path: Path, field: str, inertial: ElementTree.Element) -> float:
    """A finite mass >= 0 and a physical inertia tensor (principal moments >= 0, triangle inequality); the mass (kg)."""
    mass = _attribute(path, field, inertial.find("mass"), "value")
    if not np.isfinite(mass) or mass < 0:
        raise RobotFileError(path, field, f"mass must be a finite number >= 0 kg (got {mass})")
    inertia = inertial.find("inertia")
    if inertia is None:
        return mass
    xx, xy, xz, yy, yz, zz = (_attribute(path, field, inertia, key) for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
    tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    moments = np.linalg.eigvalsh(tensor) if np.isfinite(tensor).all() else np.full(3, np.nan)
    if not moments.min() >= -1e-12 or moments.sum() - 2 * moments.max() < -1e-12:
        raise RobotFileError(path, field, f"inertia tensor must be physical: principal moments >= 0 "
                             f"and satisfying the triangle inequality (got {moments.tolist()} kg m^2)")
    return mass


def _attribute(path: Path, field: str, element: ElementTree.Element | None, key: str) -> float:
    """A number attribute of an inertial's element."""
    text = None if element is None else element.get(key)
    try:
        return float(text)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        tag = "mass" if key == "value" else "inertia"
        raise RobotFileError(path, field, f"<{tag} {key}=...> must be a number (got {text!r})") from None


def urdf_limits_missing(model: pin.Model, joint_id: int) -> bool:
    """Whether a one-coordinate joint has no position limits in its URDF.

    Pinocchio reads a ``<limit>`` without ``lower`` and ``upper`` as [0, 0], and no limits at all
    as a huge range (beyond ``NO_LIMIT``, m or rad).

    Args:
        model: Pinocchio's model of the URDF (:func:`pinocchio_model`).
        joint_id: The joint's id in ``model``.
    """
    index = model.joints[joint_id].idx_q
    low, high = float(model.lowerPositionLimit[index]), float(model.upperPositionLimit[index])
    return (low == 0.0 and high == 0.0) or not max(abs(low), abs(high)) < NO_LIMIT


def closing_pairs(path: Path) -> list[tuple[str, str, str]]:
    """The loops of a URDF exported by onshape-to-robot: its links ``closing_NAME_1`` and ``closing_NAME_2``, two frames
    on the two parts a loop's last mate joins, which must coincide (a point closure).

    Returns:
        (NAME, first frame, second frame) for each pair, in the order of their first link.

    Raises:
        RobotFileError: A ``closing_NAME_1`` without its ``closing_NAME_2``, or the other way round.
    """
    root = ElementTree.parse(path).getroot()
    names = [str(link.get("name")) for link in root.findall("link")]
    found: dict[str, dict[str, str]] = {}
    for name in names:
        match = CLOSING.fullmatch(name)
        if match:
            found.setdefault(match.group(1), {})[match.group(2)] = name
    for loop, ends in found.items():
        if len(ends) != 2:
            have, lacking = next(iter(ends.values())), f"closing_{loop}_{'2' if '1' in ends else '1'}"
            raise RobotFileError(path, f"urdf.link.{have}", f"onshape-to-robot closes a loop with two frames: "
                                 f"'{have}' has no '{lacking}' to coincide with")
    return [(loop, ends["1"], ends["2"]) for loop, ends in found.items()]
