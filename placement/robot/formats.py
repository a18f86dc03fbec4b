"""Which robot file a path holds: a sidecar, a description (URDF, xacro, MJCF), or a Gepetto ``robot.yaml``.

A Gepetto folder holds ``robot.yaml`` (the loops, the motors, the end effector) and ``robot.urdf``;
``placement assemble FOLDER --write`` writes the sidecar ``placement.yaml`` beside them
(:mod:`placement.workshop.gepetto` reads the format).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from placement.schema import MAX_FILE_BYTES

YAML_NAME = "robot.yaml"
URDF_NAME = "robot.urdf"
SIDECAR_NAME = "placement.yaml"
GEPETTO_KEYS = ("closed_loop", "type", "name_mot", "joint_name", "joint_type")
DESCRIPTION_SUFFIXES = (".urdf", ".xacro", ".xml", ".mjcf")  # URDF, xacro (``.urdf.xacro`` too), MuJoCo's MJCF


def is_description(path: Path) -> bool:
    """Whether ``path`` names a robot description (a URDF, xacro or MJCF file, by its suffix) rather than a
    sidecar."""
    return path.suffix.lower() in DESCRIPTION_SUFFIXES


def is_gepetto(path: Path) -> bool:
    """Whether ``path`` is a ``robot.yaml`` in the Gepetto format: a mapping with its keys and no ``urdf``."""
    try:
        if not path.is_file() or path.stat().st_size > MAX_FILE_BYTES:
            return False
        document = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError, RecursionError):
        return False
    return isinstance(document, dict) and "urdf" not in document and any(key in document for key in GEPETTO_KEYS)


@dataclass(frozen=True)
class DescriptionOptions:
    """How to read a robot description beyond what its files say: given on the command line or by a program.

    Attributes:
        package_paths: Folders where its ``package://`` meshes and a xacro's ``$(find PKG)`` are looked for first
            (``--package-path DIR``), before the sidecar's ``package_paths`` (:mod:`placement.robot.packages`).
        xacro_args: A xacro file's arguments (``--robot-arg NAME:=VALUE``), over the sidecar's ``xacro_args``.
        efforts: Effort bounds by joint name (N or N·m; ``--effort JOINT=VALUE``), over what the description gives:
            for a description that bounds no effort (onshape-to-robot's MJCF exports give their actuators a ``kp``
            only), so that drives can be estimated from it.
    """

    package_paths: tuple[Path, ...] = ()
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    efforts: Mapping[str, float] = field(default_factory=dict)
