"""The catalogue's tables: CSV package data beside this module, each row with its ``source``.

A table ``<name>.csv`` opens with ``#`` note lines (what the columns mean, which standard and
edition, which maker's catalogue or transcription the figures were read from), then a header
row and the rows. :func:`table` gives the rows as text, :func:`notes` the note lines, and
:func:`number` one cell as a float.

Examples
--------
>>> rows = table("parallel_keys")
>>> rows[2]["b_mm"], rows[2]["t1_mm"]
('4', '2.5')
>>> notes("parallel_keys")[0][:41]
'Parallel keys, deep pattern, DIN 6885-1 ('
"""

from __future__ import annotations

import csv
import io
from functools import cache
from importlib import resources

from transplanter.core.errors import SpecError

__all__ = ["notes", "number", "table"]


@cache
def _text(name: str) -> str:
    return resources.files(__package__).joinpath(f"{name}.csv").read_text(encoding="utf-8")


@cache
def table(name: str) -> tuple[dict[str, str], ...]:
    """The rows of the catalogue table ``<name>.csv`` (lines starting with ``#`` are its notes)."""
    lines = [line for line in _text(name).splitlines() if line and not line.startswith("#")]
    return tuple(csv.DictReader(io.StringIO("\n".join(lines))))


@cache
def notes(name: str) -> tuple[str, ...]:
    """The ``#`` note lines of ``<name>.csv`` without the ``#``: its columns and sources."""
    return tuple(line[1:].strip() for line in _text(name).splitlines() if line.startswith("#"))


def number(row: dict[str, str], column: str) -> float:
    """``row[column]`` as a float; a SpecError naming the column when the cell is empty or text."""
    try:
        return float(row[column])
    except (KeyError, ValueError) as exc:
        raise SpecError(f"catalogue column {column!r} of row {row!r} is not a number") from exc
