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

import math
import os
import re
import stat
from pathlib import Path

import numpy as np

from transplanter.core.errors import SpecError, check_number

__all__ = [
    "CSV_LARGEST_GAP_DEG",
    "MAX_CSV_BYTES",
    "MAX_CSV_ROWS",
    "MIN_CSV_ROWS",
    "MAX_TEETH",
    "SCRIPT_TIMEOUT_S",
    "MAX_SCRIPT_TIMEOUT_S",
    "boolean",
    "folder",
    "is_csv_path",
    "ratio_samples",
    "read_data_file",
    "timeout",
]

#: a ratio CSV, bytes: 100 000 rows of two numbers fit in 4 MB; more is not a ratio law
MAX_CSV_BYTES = 8_000_000
#: a ratio CSV, rows: a sample every 0.0036° is already far beyond a spline's need
MAX_CSV_ROWS = 100_000
#: a ratio CSV, the fewest rows: fewer samples of a turn are not a law
MIN_CSV_ROWS = 8
#: the widest stretch of a driver turn a ratio CSV may leave without a sample (deg, the wrap
#: included), for full pairs and for laws with dwells alike: samples that span less are not a
#: turn (typically angles given in radians), and a spline over a wider stretch is a guess
CSV_LARGEST_GAP_DEG = 90.0
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
    given = os.fspath(path)  # named as given (the repr escapes what a terminal would obey)
    try:
        info = os.stat(p)
    except OSError as exc:
        raise SpecError(f"the {name} {given!r} cannot be read: {exc.strerror or exc}") from exc
    if not stat.S_ISREG(info.st_mode):
        kind = "a folder" if stat.S_ISDIR(info.st_mode) else "not a regular file (a pipe, a device?)"
        raise SpecError(f"the {name} {given!r} is {kind}: give a file")
    if info.st_size > max_bytes:
        raise SpecError.out_of_range(f"the {name}'s size", info.st_size, f"<= {max_bytes} bytes")
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(fd, "rb") as f:
            data = f.read(max_bytes + 1)
    except OSError as exc:
        raise SpecError(f"the {name} {given!r} cannot be read: {exc.strerror or exc}") from exc
    if len(data) > max_bytes:  # it grew while it was read
        raise SpecError.out_of_range(f"the {name}'s size", len(data), f"<= {max_bytes} bytes")
    return data


def is_csv_path(spec) -> bool:
    """Whether the transmission ``spec`` names a ratio CSV (it ends in ``.csv``, blanks aside): the
    file is then read at ``spec`` exactly as given — ``"r.csv "`` is not ``r.csv``."""
    return isinstance(spec, str) and spec.rstrip().lower().endswith(".csv")


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:nan|inf|infinity)", re.IGNORECASE)


def _number(field: str) -> float | None:
    """The number ``field`` states (blanks around it aside), or None: no underscores, hex or words."""
    text = field.strip()
    return float(text) if _NUMBER.fullmatch(text) else None


def ratio_samples(data, name: str = "ratio CSV") -> tuple[np.ndarray, np.ndarray]:
    """(driver angle in deg, ratio) of a ratio CSV — the one reader of full pairs' and of laws with
    dwells' samples (a ratio of 0 marks a dwell; the ratios are the caller's to judge).

    The rules, each refusal naming the row or the rule: UTF-8 text (a byte-order mark is dropped
    before anything else); blank lines and ``#`` comments skipped; an optional header — the first
    row is one only if no field of it is a number (a first row of numbers is a sample, kept or refused);
    then two numbers per row, ``phi_deg, ratio``; ``MIN_CSV_ROWS`` to ``MAX_CSV_ROWS`` rows, finite,
    the angles increasing within [0, 360); no stretch of the turn wider than
    ``CSV_LARGEST_GAP_DEG`` without a sample, the wrap included."""
    if isinstance(data, str):
        data = data.encode()
    if not isinstance(data, bytes | bytearray):
        raise SpecError(f"the {name} must be bytes or text, got {type(data).__name__}")
    data = bytes(data)
    count = data.count(b"\n") + (not data.endswith(b"\n"))
    if count > MAX_CSV_ROWS + 1:
        raise SpecError.out_of_range(f"the {name}'s rows", count, f"<= {MAX_CSV_ROWS} samples (and a header)")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SpecError(
            f"the {name} cannot be read as numbers: it is not UTF-8 text (byte {data[exc.start]:#04x} at offset "
            f"{exc.start})"
        ) from exc
    text = text.removeprefix("\ufeff")
    lines = [(k, line.split("#", 1)[0].strip()) for k, line in enumerate(text.splitlines(), 1)]
    lines = [(k, line) for k, line in lines if line]
    if lines and all(_number(f) is None for f in lines[0][1].split(",")):
        lines = lines[1:]  # a header: no field of it is a number
    rows = []
    for k, line in lines:
        fields = line.split(",")
        if len(fields) != 2:
            raise SpecError(
                f"the {name}'s row {k} {line[:60]!r} has {len(fields)} columns: it needs 2 columns (driver angle in "
                "deg, ratio)"
            )
        values = [_number(f) for f in fields]
        if None in values:
            raise SpecError(
                f"the {name} cannot be read as numbers: row {k} {line[:60]!r} is not two numbers 'phi_deg, ratio'"
            )
        rows.append(values)
    if len(rows) < MIN_CSV_ROWS:
        raise SpecError(
            f"the {name} has 2 columns and {len(rows)} rows: it needs 2 columns (driver angle in deg, ratio) and at "
            f"least {MIN_CSV_ROWS} rows over one driver turn"
        )
    table = np.array(rows, dtype=float)
    deg, ratio = table[:, 0], table[:, 1]
    if not np.all(np.isfinite(table)):
        k = lines[int(np.flatnonzero(~np.isfinite(table).all(axis=1))[0])][0]
        raise SpecError(f"the {name}'s values must be finite: row {k} is not")
    if not (np.all(np.diff(deg) > 0) and deg[0] >= 0 and deg[-1] < 360):
        raise SpecError(f"the {name}'s driver angles must be finite and increase within [0, 360) deg")
    steps = np.append(np.diff(deg), 360.0 - deg[-1] + deg[0])
    k = int(np.argmax(steps))
    if steps[k] > CSV_LARGEST_GAP_DEG:
        radians = (
            f" — they look like radians (the largest is {deg[-1]:.4g}); give degrees" if deg[-1] <= 2 * math.pi else ""
        )
        raise SpecError(
            f"the {name}'s driver angles leave {steps[k]:.4g} deg of the turn without a sample, from {deg[k]:g} to "
            f"{(deg[(k + 1) % len(deg)]):g} deg (limit {CSV_LARGEST_GAP_DEG:g} deg){radians}"
        )
    return deg, ratio
