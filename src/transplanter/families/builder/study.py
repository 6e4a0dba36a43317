"""What the builder asks of a study: the :class:`Study` protocol and what building or checking one gives.

A part of a family is a *study*: any object with a ``name`` and the four methods below. The
builder (:mod:`transplanter.families.builder.build`), ``transplanter check`` and ``transplanter analyse``
use nothing else, so a new kind of study is one new module (a frozen dataclass deriving from
:class:`StudyDefaults` for the methods it does not need) and the part script that uses it —
no list of kinds to extend anywhere.

Examples
--------
>>> from dataclasses import dataclass
>>> @dataclass(frozen=True)
... class Square(StudyDefaults):
...     name: str
...     side: float
...     def build(self, out):
...         return Built({"kind": "square", "results": {"area": self.side**2}}, {})
...     def tables(self):
...         return [Table(self.name, (("area", self.side**2, "mm²", None),))]
>>> isinstance(Square("s", 2.0), Study), Square("s", 2.0).build(".").record["results"]
(True, {'area': 4.0})
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, NamedTuple, Protocol, runtime_checkable

__all__ = ["Study", "StudyDefaults", "Built", "Checked", "Table"]


class Built(NamedTuple):
    """A study built: its manifest record (``kind``, ``parameters``, ``results``) and its files
    by name (the builder writes them into the family's folder and records their SHA-256)."""

    record: dict
    files: dict[str, bytes]


class Checked(NamedTuple):
    """A study's checks re-run on its files as found on disk: figures, problems, and whether
    problems are ``expected`` (a study built to show a finding, e.g. a published pair that does
    not mesh: its problems do not fail the check)."""

    results: dict
    problems: list[str]
    expected: bool = False


@dataclass(frozen=True)
class Table:
    """A table for ``transplanter analyse``: ``rows`` of (quantity, value, unit, published value
    or None)."""

    title: str
    rows: tuple[tuple[str, float, str, float | None], ...]


@runtime_checkable
class Study(Protocol):
    """A part of a family.

    ``name`` names its files; ``cost`` (relative build time, ~1 for an analysis, 10 for a gear
    pair) lets a parallel build hand out the longest parts first.

    **Parts built from other parts' files.** A study may name earlier parts of its family in
    ``uses`` (a machine posed from its gears' re-read DXFs): the builder then builds those first
    and calls ``build_using(out, files)`` with their files (name -> bytes) instead of ``build``;
    ``check`` gets their files beside its own, and the part is rebuilt whenever one of them is.
    """

    name: str
    cost: ClassVar[int]

    def build(self, out: Path) -> Built:
        """Compute, make and verify everything; files in memory (``out``: the family folder)."""
        ...

    def check(self, files: dict[str, bytes]) -> Checked | None:
        """Re-run the proofs on built ``files`` as found on disk; None: no proofs of its own
        (``check`` then compares its data files with a fresh build)."""
        ...

    def tables(self) -> list[Table]:
        """What ``transplanter analyse`` prints (may be empty)."""
        ...

    def analysis_files(self) -> dict[str, bytes]:
        """What ``transplanter analyse --plots DIR`` writes (may be empty)."""
        ...


class StudyDefaults:
    """The methods a study may leave out: no proofs of its own, nothing to analyse, cost 1."""

    cost: ClassVar[int] = 1

    def check(self, files: dict[str, bytes]) -> Checked | None:
        return None

    def tables(self) -> list[Table]:
        return []

    def analysis_files(self) -> dict[str, bytes]:
        return {}
