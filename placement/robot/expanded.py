"""Descriptions expanded from another file (a xacro's URDF, an MJCF with its loops cut), cached as files.

The robot's readers (Pinocchio, the collision geometry) read files, so an expanded description is written
to ``$XDG_CACHE_HOME/placement/xacro`` (``~/.cache`` by default), named after its source and a hash of
its text: the same expansion is written once.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from placement.files import staged


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
