"""What a user hands in, checked in one place: numbers, booleans, folders, files — and the limits.

Every entry point (the CLI's commands and the Python API behind them) takes its inputs through
these functions (numbers through :func:`errors.check_number` / :func:`errors.check_int`), so a bad
one ends in one :class:`~transplanter.core.errors.SpecError` naming the parameter, the value and the
limit, never in a traceback from the standard library, numpy or scipy, and never in a wait:

- a **file** is read only if it is a regular file (a FIFO, a device or a folder is refused before
  it is opened, and it is opened without blocking) and no larger than its limit;
- a **folder** must be a path (``str`` or ``os.PathLike``), not empty;
- a **boolean** is True or False (a truthy string such as ``'no'`` is refused).

The limits are this module's constants, each with its reason (the expression's length and
nesting are :mod:`transplanter.geometry.pitch.transmission`'s, a manifest's size
:mod:`transplanter.families.builder.manifest`'s).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from transplanter.core.errors import SpecError, check_number

__all__ = [
    "MAX_CSV_BYTES",
    "MAX_CSV_ROWS",
    "MAX_TEETH",
    "SCRIPT_TIMEOUT_S",
    "MAX_SCRIPT_TIMEOUT_S",
    "boolean",
    "folder",
    "read_data_file",
    "timeout",
]

#: a ratio CSV, bytes: 100 000 rows of two numbers fit in 4 MB; more is not a ratio law
MAX_CSV_BYTES = 8_000_000
#: a ratio CSV, rows: a sample every 0.0036° is already far beyond a spline's need
MAX_CSV_ROWS = 100_000
#: teeth on a gear a shop cuts from the pair command (a 1 m ring at module 0.5: 6300 teeth)
MAX_TEETH = 10_000
#: a part script (its module and ``family()``) must load within this, seconds (the seed scripts
#: take under 10 s; ``--timeout`` raises it)
SCRIPT_TIMEOUT_S = 600.0
#: the longest time limit taken for a part script, seconds (a day)
MAX_SCRIPT_TIMEOUT_S = 86_400.0


def boolean(name: str, value) -> bool:
    """``value`` if it is True or False; SpecError naming ``name`` otherwise."""
    if not isinstance(value, bool):
        raise SpecError.out_of_range(name, value, "True or False")
    return value


def folder(name: str, value) -> Path:
    """``value`` as a folder path (``str`` or ``os.PathLike``, not empty); SpecError otherwise."""
    if not isinstance(value, str | os.PathLike) or not str(os.fspath(value)).strip():
        raise SpecError.out_of_range(name, value, "a folder path (a non-empty str or os.PathLike)")
    return Path(value)


def timeout(value) -> float:
    """A part script's time limit, seconds: > 0 and <= ``MAX_SCRIPT_TIMEOUT_S``."""
    return check_number("timeout", value, 0.0, MAX_SCRIPT_TIMEOUT_S, low_open=True, unit="s")


def read_data_file(name: str, path, max_bytes: int) -> bytes:
    """The bytes of the regular file ``path`` (``name`` says what it is in the messages), at most
    ``max_bytes``; SpecError when it is missing, not a regular file (a FIFO would block, a device
    never end), unreadable or too large."""
    p = folder(name, path)
    try:
        info = os.stat(p)
    except OSError as exc:
        raise SpecError(f"the {name} {str(p)!r} cannot be read: {exc.strerror or exc}") from exc
    if not stat.S_ISREG(info.st_mode):
        kind = "a folder" if stat.S_ISDIR(info.st_mode) else "not a regular file (a pipe, a device?)"
        raise SpecError(f"the {name} {str(p)!r} is {kind}: give a file")
    if info.st_size > max_bytes:
        raise SpecError.out_of_range(f"the {name}'s size", info.st_size, f"<= {max_bytes} bytes")
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(fd, "rb") as f:
            data = f.read(max_bytes + 1)
    except OSError as exc:
        raise SpecError(f"the {name} {str(p)!r} cannot be read: {exc.strerror or exc}") from exc
    if len(data) > max_bytes:  # it grew while it was read
        raise SpecError.out_of_range(f"the {name}'s size", len(data), f"<= {max_bytes} bytes")
    return data
