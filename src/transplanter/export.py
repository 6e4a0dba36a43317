"""Writing files atomically and reproducibly.

Every export goes through :func:`atomic_write`: the bytes are written to a temporary file
in the target folder, flushed, then renamed over the target, so a reader never sees a
half-written file and a failed build leaves the previous file intact. Text and JSON are
serialised deterministically (sorted keys, fixed float formatting, ``\\n`` line ends), so
a rebuild from the same input is byte-identical.

Examples
--------
>>> import tempfile, pathlib
>>> from transplanter.export import atomic_write, json_bytes
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> p = atomic_write(d / "a.json", json_bytes({"b": 1.0, "a": [1, 2]}))
>>> p.read_text()
'{\\n  "a": [\\n    1,\\n    2\\n  ],\\n  "b": 1.0\\n}\\n'
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np

from transplanter.errors import ExportError

__all__ = ["atomic_write", "json_bytes", "csv_bytes", "csv_array", "rounded", "significant"]


def atomic_write(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temp file + rename); returns the path."""
    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except OSError as exc:
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; exports are meant to be shared
        os.replace(tmp, target)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


def json_bytes(obj: object) -> bytes:
    """Deterministic JSON (sorted keys, 2-space indent, trailing newline), UTF-8."""
    return (json.dumps(obj, indent=2, sort_keys=True, allow_nan=False) + "\n").encode()


def csv_bytes(header: list[str], rows: list[list[object]]) -> bytes:
    """CSV with ``\\n`` line ends; floats written with ``repr`` (round-trip exact)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for row in rows:
        w.writerow([repr(x) if isinstance(x, float) else x for x in row])
    return buf.getvalue().encode()


def csv_array(data: bytes) -> np.ndarray:
    """The numbers of a CSV written by :func:`csv_bytes` (header skipped), as an (n, k) array."""
    return np.loadtxt(io.BytesIO(data), delimiter=",", skiprows=1, ndmin=2)


def rounded(value: float, digits: int = 9) -> float | None:
    """Rounded for a manifest; None for inf (JSON has no infinity: "no limit")."""
    v = float(value)
    return round(v, digits) if math.isfinite(v) else None


def significant(value: float, digits: int = 4) -> float:
    """``value`` to ``digits`` significant figures, for error figures in a manifest."""
    return float(f"{float(value):.{digits - 1}e}")
