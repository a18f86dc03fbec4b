"""Which robot file a path holds: a sidecar, or a ``robot.yaml`` of Gepetto's example-parallel-robots.

A Gepetto folder holds ``robot.yaml`` (the loops, the motors, the end effector) and ``robot.urdf``;
``placement assemble FOLDER --write`` writes the sidecar ``placement.yaml`` beside them
(:mod:`placement.workshop.gepetto` reads the format).
"""

from __future__ import annotations

from pathlib import Path

import yaml

from placement.schema import MAX_FILE_BYTES

YAML_NAME = "robot.yaml"
URDF_NAME = "robot.urdf"
SIDECAR_NAME = "placement.yaml"
GEPETTO_KEYS = ("closed_loop", "type", "name_mot", "joint_name", "joint_type")


def is_gepetto(path: Path) -> bool:
    """Whether ``path`` is a ``robot.yaml`` in the Gepetto format: a mapping with its keys and no ``urdf``."""
    try:
        if not path.is_file() or path.stat().st_size > MAX_FILE_BYTES:
            return False
        document = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError, RecursionError):
        return False
    return isinstance(document, dict) and "urdf" not in document and any(key in document for key in GEPETTO_KEYS)
