"""Handing the memory a build has freed back to the system, between its stages.

glibc keeps the C heap a process frees for its own later use, and each thread allocates from an
arena of its own: memory freed after the meshing proofs (run in worker threads), after the 3MF
re-read (trimesh's caches) or after OpenCASCADE's transfer stays resident, and the next stage's
allocations, from another arena or in pieces too large for the holes left, land on top of it. So a
part's stages stacked their peaks: seed 004's optimised ring pair reached 776–902 MB where no
stage needs more than ~580 MB once the one before it has given its memory back.

:func:`trim` collects Python's garbage (the re-read meshes hold reference cycles) and calls glibc's
``malloc_trim(0)``, which returns the free memory of every arena; elsewhere (not glibc) it only
collects. :func:`released` trims before and after a block. Neither changes what is computed.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import functools
import gc

__all__ = ["released", "trim"]


@functools.cache
def _malloc_trim():
    try:
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim
    except (OSError, AttributeError):  # not glibc
        return None


def trim(generation: int = 2) -> None:
    """Collect garbage up to ``generation`` (0-2) and hand the free C heap back to the system."""
    gc.collect(generation)
    give_back = _malloc_trim()
    if give_back is not None:
        give_back(0)


@contextlib.contextmanager
def released(generation: int = 0):
    """:func:`trim` before the block and after it (``generation``: how much garbage to collect)."""
    trim(generation)
    try:
        yield
    finally:
        trim(generation)
