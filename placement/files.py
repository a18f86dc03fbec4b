"""Files replaced safely: written to a temporary file beside the target, then renamed over it.

A reader never sees a half-written file, and a write that fails (or whose content is refused)
leaves the target as it was. An existing file keeps its mode; a new one gets the process's
default (0o666 less the umask).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def staged(path: str | Path, text: str) -> Iterator[Path]:
    """Write ``text`` (UTF-8) to a temporary file beside ``path`` and yield it; rename it to ``path`` when the
    block ends normally, remove it when the block raises.

    The temporary file stands in ``path``'s folder, so relative references in it (a sidecar's URDF)
    resolve as they will from ``path``.
    """
    path = Path(path)
    handle, name = tempfile.mkstemp(dir=path.parent if str(path.parent) else ".", prefix=f".{path.name}.",
                                    suffix=path.suffix)
    temporary = Path(name)
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="") as stream:
            stream.write(text)
        yield temporary
        os.chmod(temporary, path.stat().st_mode & 0o7777 if path.is_file() else 0o666 & ~_umask())
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def _umask() -> int:
    """The process's file-creation mask."""
    mask = os.umask(0)
    os.umask(mask)
    return mask
