"""Freed memory kept for the next batch (glibc's ``mallopt``).

A batch of the exact chain allocates arrays of a few megabytes and frees them. glibc's ``malloc`` gives memory of
that size back to the system as soon as it is freed (a block above its mapping threshold, and the heap's top once
it exceeds the trimming threshold), and the next batch faults it in again, a page at a time: on a virtual machine,
about half of a 64-placement batch's closed-form kinematics. :func:`keep_freed_memory` raises both thresholds, so
that the process keeps up to TRIM_BYTES of freed memory for its next arrays. Under another C library (macOS, musl)
it does nothing.
"""

from __future__ import annotations

import ctypes
import functools

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc's malloc.h
MMAP_BYTES = 32 << 20  # glibc's largest mapping threshold: larger blocks are still mapped, and returned when freed
TRIM_BYTES = 256 << 20  # free memory the heap keeps at its top


@functools.cache
def keep_freed_memory() -> bool:
    """Have this process's ``malloc`` keep freed memory (module docstring), once; whether it could."""
    try:
        mallopt = ctypes.CDLL(None).mallopt  # the C library this process runs on
    except (OSError, AttributeError):
        return False
    return bool(mallopt(M_MMAP_THRESHOLD, MMAP_BYTES)) and bool(mallopt(M_TRIM_THRESHOLD, TRIM_BYTES))
