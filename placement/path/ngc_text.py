"""A G-code program file's text: found, not too large, and decoded as the CAM posts that write it encode it."""

from __future__ import annotations

import warnings
from pathlib import Path

from placement.path.exceptions import GcodeDialectWarning, PathFileError

MAX_PROGRAM_BYTES = 50_000_000


def program_text(file: Path) -> str:
    """The program's text: UTF-8 (a byte order mark, as Windows editors write, is no character of it), UTF-16 with its
    byte order mark, else Windows-1252 (Latin-1), the code page of Windows CAM posts whose comments hold Ø or °, with
    a warning; only comments may hold characters beyond ASCII (:mod:`placement.path.ngc_expressions`).

    Raises:
        PathFileError: The file is missing, not a regular file, larger than MAX_PROGRAM_BYTES, or binary (NUL bytes
            without a UTF-16 byte order mark).
    """
    if not file.is_file():
        raise PathFileError(file, "", "G-code program not found" if not file.exists() else "not a regular file")
    if file.stat().st_size > MAX_PROGRAM_BYTES:
        raise PathFileError(file, "", f"the program is larger than {MAX_PROGRAM_BYTES // 1_000_000} MB")
    raw = file.read_bytes()
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        return raw.decode("utf-16")
    if b"\x00" in raw:
        raise PathFileError(file, "", "not a text file in UTF-8 (or ASCII): it holds NUL bytes")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        pass
    try:
        text = raw.decode("cp1252")
    except UnicodeDecodeError:  # the five bytes Windows-1252 leaves undefined
        text = raw.decode("latin-1")
    warnings.warn(f"{file}: not UTF-8: read as Windows-1252 (Latin-1), as Windows CAM posts write; characters beyond "
                  "ASCII are read in comments only", GcodeDialectWarning, stacklevel=3)
    return text
