"""A machine's bill of materials, from the files of its family and the parts it buys.

**Made parts** are read from the records the build already has: every part made by
:func:`~transplanter.families.builder.making.manufacture` records its files' ``stem``, its
``material``, its ``quantity`` and its ``solid_volume_mm3`` in its results, and those results are
in its study's JSON record among the files the machine is built from (``<pair>.teeth.json``,
``<train>.metrics.json``, ``<cam>.cam.json``, ``<parts>.parts.json``, ...:
:func:`made_records`) — or, for the parts the machine study makes itself, handed in (``own``). A
record of quantity 0 is a drawing not to cut (its outline on REFERENCE): not an item, and its files
are not made files.

A made item's files are those its record says were written (its ``dxf_R2000``, ``stl`` and
``step`` checks). **Made files** (:func:`made_files`) are every ``.dxf``, ``.stl`` and ``.step``
of the family's files that is not an assembly's (``.assembly.dxf``, ``.assembly.step``), an
obstacle's (``.obstacle.dxf``), a bought part's drawing (``.bought.dxf``) or an R12 copy of a
drawing, less those of drawings not to cut. The bill and the made files must be one to one
(:meth:`transplanter.shop.bom.Bom.check`: every made file in exactly one made item, every item's
files there, everything else a bought part with its designation): a file no record accounts for
fails the part.

**Bought parts** are what the machine study places (:class:`~transplanter.families.machines.assembly.BoughtBody`),
counted by designation.

**Item numbers** are those of :func:`transplanter.shop.bom.build_bom`: made parts by name, then
bought parts by standard and designation — the same on every rebuild of the same machine. The
last export's ``<machine>.bom.csv`` is not read back: the builder hands a study only the files of
the parts it uses (verified), and a build must equal a full rebuild byte for byte; a caller that
has an earlier list may pass its numbers (``previous``).
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Iterable, Mapping
from pathlib import PurePosixPath

from transplanter.core.errors import SpecError
from transplanter.families.machines.record import BOUGHT, OBSTACLE
from transplanter.shop.bom import HEADER, Bom, BoughtPart, Item, MadePart, build_bom

__all__ = [
    "PART_SUFFIXES",
    "NOT_PARTS",
    "made_records",
    "made_files",
    "made_parts",
    "machine_bom",
    "bom_record",
    "bom_from_csv",
]

#: the suffixes of a made part's files
PART_SUFFIXES = (".dxf", ".stl", ".step")
#: files with those suffixes that are not a part's (an R12 DXF is the R2000 drawing again, for an
#: older CAM: the bill lists the R2000 one)
NOT_PARTS = (".assembly.dxf", ".assembly.step", ".R12.dxf", OBSTACLE, BOUGHT)
#: what a made part's record holds (:func:`~transplanter.families.builder.making.manufacture`)
RECORD_KEYS = ("stem", "material", "quantity", "solid_volume_mm3")


def _records_in(value, out: list[dict]) -> None:
    if isinstance(value, dict):
        if all(k in value for k in RECORD_KEYS):
            out.append(value)
        for v in value.values():
            _records_in(v, out)
    elif isinstance(value, list):
        for v in value:
            _records_in(v, out)


def made_records(files: Mapping[str, bytes], own: Iterable[dict] = ()) -> dict[str, dict]:
    """Every made part's record — stem -> its results — found in the JSON ``files`` (any dict
    with ``stem``, ``material``, ``quantity`` and ``solid_volume_mm3``) and in ``own``; a stem
    recorded twice must be recorded alike (SpecError otherwise)."""
    found: list[dict] = list(own)
    for name in sorted(files):
        if name.endswith(".json"):
            try:
                _records_in(json.loads(files[name]), found)
            except (ValueError, UnicodeDecodeError) as exc:
                raise SpecError(f"{name} is not a JSON record: {exc}") from exc
    out: dict[str, dict] = {}
    for r in found:
        was = out.setdefault(r["stem"], r)
        if any(was[k] != r[k] for k in RECORD_KEYS):
            raise SpecError(f"made part {r['stem']} is recorded twice, differently: {was} and {r}")
    return out


def _part_file(name: str) -> bool:
    return name.endswith(PART_SUFFIXES) and not name.endswith(NOT_PARTS)


def _stem(name: str) -> str:
    return PurePosixPath(name).stem


def made_files(files: Iterable[str], records: Mapping[str, dict]) -> list[str]:
    """The made files among ``files`` (module docstring): a part's DXF, STL and STEP, less those of
    drawings not to cut (a record of quantity 0)."""
    return sorted(
        f for f in files if _part_file(f) and not (_stem(f) in records and records[_stem(f)]["quantity"] == 0)
    )


#: the file a made part's record says was written, by the key of its check in the record
WRITTEN = {"dxf_R2000": ".dxf", "stl": ".stl", "step": ".step"}


def made_parts(records: Mapping[str, dict]) -> list[MadePart]:
    """One :class:`~transplanter.shop.bom.MadePart` per record of quantity >= 1: its stem, the
    files its record says were written (the DXF, STL and STEP whose checks it holds, ``WRITTEN``),
    quantity, material and solid volume."""
    return [
        MadePart(
            stem,
            tuple(stem + suffix for key, suffix in WRITTEN.items() if key in r),
            r["quantity"],
            r["material"],
            float(r["solid_volume_mm3"]),
        )
        for stem, r in sorted(records.items())
        if r["quantity"] >= 1
    ]


def machine_bom(
    name: str,
    files: Iterable[str],
    records: Mapping[str, dict],
    bought: Iterable[BoughtPart],
    previous: Mapping[str, int] | Bom | None = None,
) -> Bom:
    """The bill of materials of the machine ``name``: the made parts of the family's ``files``
    (names) by their ``records`` (:func:`made_records`) and the ``bought`` parts, checked one to
    one against the made files (SpecError naming every mismatch)."""
    files = list(files)
    bom = build_bom(made_parts(records), bought, previous)
    try:
        bom.check(made_files(files, records))
    except SpecError as exc:
        raise SpecError(f"{name}: {exc}") from exc
    return bom


def bom_record(name: str, bom: Bom) -> tuple[dict, dict[str, bytes]]:
    """``<name>.bom.csv`` and the machine record's ``bill_of_materials``: the table (drawn on the
    report page as one table), how many items are made and bought, the bodies counted and the
    total mass."""
    rows = bom.rows()
    made = [i for i in bom.items if i.made]
    record = {
        "file": f"{name}.bom.csv",
        "items": len(bom.items),
        "made_items": len(made),
        "bought_items": len(bom.items) - len(made),
        "made_parts": sum(i.quantity for i in made),
        "bought_parts": sum(i.quantity for i in bom.items if not i.made),
        "total_mass_kg": round(bom.total_mass_kg, 6),
        "table": {"columns": rows[0], "rows": rows[1:]},
    }
    return record, {f"{name}.bom.csv": bom.csv()}


def bom_from_csv(data: bytes) -> Bom:
    """The bill of materials a ``<machine>.bom.csv`` holds (its columns :data:`~transplanter.shop.bom.HEADER`),
    to check as found; SpecError when a row is not a bill of materials row."""
    items = []
    rows = list(csv.DictReader(io.StringIO(data.decode("utf-8"))))
    for r in rows:
        try:
            if list(r) != HEADER:
                raise KeyError("columns")
            items.append(
                Item(
                    int(r["item"]),
                    r["name"],
                    int(r["quantity"]),
                    r["material"],
                    r["made"] == "made",
                    r["designation"],
                    r["standard"],
                    float(r["mass_kg"]),
                    r["file"],
                )
            )
        except (KeyError, ValueError) as exc:
            raise SpecError(f"bom.csv row {r!r} is not a bill of materials row") from exc
    return Bom(tuple(items), max((i.item for i in items), default=0))
