"""A machine's bill of materials: the parts it makes (its files) and the parts it buys, one table.

A **made part** (:class:`MadePart`) is named by its files' stem (``carrier.dxf``, ``carrier.stl``
-> ``carrier``) and carries its quantity, its material (a name of
``transplanter.shop.catalogue.material``) and the volume of its solid: its mass is the
material's density times that volume (:meth:`MadePart.from_solid` reads the volume from the
manifold3d solid). A **bought part** (:class:`BoughtPart`) carries its standard designation, its
standard, its quantity and its mass each -- :meth:`BoughtPart.of` takes them from any part the
catalogue chooses (a bearing, a key, a screw, a circlip, ...).

**Item numbers** are stable across rebuilds, so a balloon on an assembly drawing keeps pointing at
the same part:

* with no earlier list, made parts come first, ordered by name (case-folded, then as written), then
  bought parts ordered by standard, then designation; they are numbered 1, 2, 3, ...;
* given the earlier list's numbers (``previous``: :meth:`Bom.numbers` of the last build, or
  :func:`numbers_from_csv` of its ``bom.csv``), every item that is still there keeps its number;
  new items are numbered on from the largest number of the earlier list (:attr:`Bom.last` when it is
  a :class:`Bom`), in the order above; the number of a dropped item is not given again.

:meth:`Bom.problems` checks the list against the files of the build, one to one: every made file
is in exactly one made item (by its stem) and listed there, every made item's files exist, and
every other item is a bought part with a designation and a standard. :meth:`Bom.csv` writes the
CSV (through :func:`transplanter.shop.export.csv_bytes`), :meth:`Bom.rows` the report's table.

Examples
--------
>>> from transplanter.shop.catalogue import bearing_for, circlip_for_shaft
>>> made = [MadePart("carrier", ("carrier.dxf", "carrier.stl"), 1, "6061-T6", 20000.0),
...         MadePart("arm", ("arm.dxf",), 4, "C45", 5000.0)]
>>> bought = [BoughtPart.of(bearing_for(12, 100, 300), 8), BoughtPart.of(circlip_for_shaft(12), 8)]
>>> bom = build_bom(made, bought)
>>> [(i.item, i.name, i.designation) for i in bom.items]  # doctest: +NORMALIZE_WHITESPACE
[(1, 'arm', ''), (2, 'carrier', ''), (3, 'retaining ring for shaft', 'DIN 471 12x1'),
 (4, 'deep groove ball bearing', '61801-2Z')]
>>> round(bom.items[0].mass_kg, 4), bom.problems(["arm.dxf", "carrier.dxf", "carrier.stl"])
(0.0393, ())
>>> bom.problems(["arm.dxf", "carrier.dxf"])
('item 2 (carrier): file carrier.stl is missing',)
"""

from __future__ import annotations

import csv
import io
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import PurePosixPath

from transplanter.core.errors import SpecError, check_int, check_number
from transplanter.shop.catalogue import material
from transplanter.shop.export import csv_bytes

__all__ = ["HEADER", "Bom", "BoughtPart", "Item", "MadePart", "build_bom", "numbers_from_csv"]

#: the columns of the CSV and of the report's table
HEADER = [
    "item",
    "name",
    "quantity",
    "made",
    "material",
    "density_kg_m3",
    "designation",
    "standard",
    "mass_kg",
    "file",
]


@dataclass(frozen=True)
class MadePart:
    """A part the machine makes: ``name`` is its files' stem; ``volume_mm3`` its solid's volume."""

    name: str
    files: tuple[str, ...]
    quantity: int
    material: str
    volume_mm3: float

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise SpecError(f"made part name = {self.name!r} must be a file stem")
        check_int(f"quantity of {self.name}", self.quantity, 1, 10**6)
        check_number(f"volume_mm3 of {self.name}", self.volume_mm3, 0.0, None, low_open=True, unit="mm3")
        material(self.material)  # a SpecError naming the known materials
        object.__setattr__(self, "files", tuple(sorted(self.files)))
        bad = [f for f in self.files if PurePosixPath(f).stem != self.name or "/" in f]
        if bad:
            raise SpecError(f"files of made part {self.name!r} must be plain names with stem {self.name!r}: {bad}")

    @classmethod
    def from_solid(cls, name: str, files: Iterable[str], quantity: int, material_name: str, solid) -> MadePart:
        """The part with the volume of its manifold3d ``solid`` (mm3)."""
        return cls(name, tuple(files), quantity, material_name, float(solid.volume()))

    @property
    def mass_kg(self) -> float:
        """Density times volume, kg (one part)."""
        return material(self.material).density_kg_m3 * self.volume_mm3 * 1e-9


@dataclass(frozen=True)
class BoughtPart:
    """A part the machine buys: its standard designation (``6001-2Z``, ``DIN 6885 A 4x4x16``,
    ``ISO 4762 M4x12``), standard, quantity, mass of one, what it is and (optionally) of what."""

    designation: str
    standard: str
    quantity: int
    mass_kg: float
    name: str = ""
    material: str = ""

    def __post_init__(self):
        for field in ("designation", "standard"):
            if not isinstance(getattr(self, field), str) or not getattr(self, field):
                raise SpecError(f"bought part {field} = {getattr(self, field)!r} must be named")
        check_int(f"quantity of {self.designation}", self.quantity, 1, 10**6)
        check_number(f"mass_kg of {self.designation}", self.mass_kg, 0.0, None, low_open=True, unit="kg")

    @classmethod
    def of(cls, part, quantity: int, material_name: str = "") -> BoughtPart:
        """``quantity`` of a part the catalogue chose (it has ``designation``, ``standard``,
        ``mass_kg`` and ``name``)."""
        return cls(part.designation, part.standard, quantity, float(part.mass_kg), part.name, material_name)


@dataclass(frozen=True)
class Item:
    """One row of the bill of materials (``mass_kg`` is one part's; ``file`` the made files,
    comma-separated; a bought item has no file)."""

    item: int
    name: str
    quantity: int
    material: str
    made: bool
    designation: str
    standard: str
    mass_kg: float
    file: str

    @property
    def key(self) -> str:
        """What identifies the item across rebuilds: ``made:<name>`` or ``bought:<standard>:<designation>``."""
        return f"made:{self.name}" if self.made else f"bought:{self.standard}:{self.designation}"

    @property
    def files(self) -> tuple[str, ...]:
        return tuple(f for f in self.file.split(", ") if f)


def _key_made(p: MadePart) -> str:
    return f"made:{p.name}"


def _key_bought(p: BoughtPart) -> str:
    return f"bought:{p.standard}:{p.designation}"


@dataclass(frozen=True)
class Bom:
    """The bill of materials: items in item-number order."""

    items: tuple[Item, ...]
    #: the largest number ever given (a dropped item's number is not given again)
    last: int = 0

    def numbers(self) -> dict[str, int]:
        """Item key -> number, to pass as ``previous`` to the next :func:`build_bom`."""
        return {i.key: i.item for i in self.items}

    @property
    def total_mass_kg(self) -> float:
        return sum(i.mass_kg * i.quantity for i in self.items)

    def problems(self, files: Iterable[str]) -> tuple[str, ...]:
        """What keeps the list and the made ``files`` from matching one to one (empty: they do)."""
        files = sorted(set(files))
        made = {i.name: i for i in self.items if i.made}
        out = []
        for f in files:
            owner = made.get(PurePosixPath(f).stem)
            if owner is None:
                out.append(f"file {f} is in no item")
            elif f not in owner.files:
                out.append(f"file {f} is not listed in item {owner.item} ({owner.name})")
        have = set(files)
        for i in self.items:
            if i.made:
                if not i.files:
                    out.append(f"item {i.item} ({i.name}) is made but has no file")
                out += [f"item {i.item} ({i.name}): file {f} is missing" for f in i.files if f not in have]
            elif not (i.designation and i.standard) or i.file:
                out.append(f"item {i.item} ({i.name}) is neither a file nor a bought part with a designation")
        return tuple(out)

    def check(self, files: Iterable[str]) -> None:
        """:meth:`problems`, raised as a SpecError naming each."""
        found = self.problems(files)
        if found:
            raise SpecError("the bill of materials does not match the files: " + "; ".join(found))

    def _cells(self, i: Item) -> list[object]:
        density = material(i.material).density_kg_m3 if i.made else ""
        return [
            i.item,
            i.name,
            i.quantity,
            "made" if i.made else "bought",
            i.material,
            density,
            i.designation,
            i.standard,
            round(i.mass_kg, 6),
            i.file,
        ]

    def csv(self) -> bytes:
        """The list as CSV bytes (``HEADER``; floats as ``repr``, ``\\n`` line ends)."""
        return csv_bytes(list(HEADER), [self._cells(i) for i in self.items])

    def rows(self) -> list[list[str]]:
        """The report's table: ``HEADER`` then one row of text per item (masses to 4 digits, densities
        as ``:g``)."""
        out = [list(HEADER)]
        for i in self.items:
            cells = self._cells(i)
            cells[8] = f"{i.mass_kg:.4g}"
            cells[5] = f"{cells[5]:g}" if i.made else ""
            out.append(["" if c == "" else str(c) for c in cells])
        return out


    def markdown(self) -> str:
        """The list as a Markdown table (the README's): item, part, quantity, made or bought, the
        material or the bought part's designation, mass each in g; and a line that sums it up
        (:meth:`summary`)."""
        lines = ["| item | part | qty | | material or designation | g each |", "|---:|---|---:|---|---|---:|"]
        for i in self.items:
            what = (i.material, "made") if i.made else (i.designation, "bought")
            lines.append(f"| {i.item} | {i.name} | {i.quantity} | {what[1]} | {what[0]} | {1000 * i.mass_kg:.4g} |")
        return "\n".join(lines)

    def summary(self) -> str:
        """``N items: M made, K bought, X kg`` — the list in one line."""
        made = sum(i.made for i in self.items)
        return (
            f"{len(self.items)} items: {made} made, {len(self.items) - made} bought, {self.total_mass_kg:.3g} kg"
        )


def _order_made(p: MadePart):
    return (p.name.casefold(), p.name)


def _order_bought(p: BoughtPart):
    return (p.standard, p.designation)


def _merged(bought: Iterable[BoughtPart]) -> list[BoughtPart]:
    """Bought parts of one designation added up (their masses must agree)."""
    out: dict[str, BoughtPart] = {}
    for p in bought:
        k = _key_bought(p)
        if k in out:
            q = out[k]
            if abs(q.mass_kg - p.mass_kg) > 1e-9 * max(q.mass_kg, p.mass_kg):
                raise SpecError(
                    f"bought part {p.designation!r} is listed with two masses: {q.mass_kg} and {p.mass_kg} kg"
                )
            out[k] = BoughtPart(
                q.designation, q.standard, q.quantity + p.quantity, q.mass_kg, q.name or p.name, q.material
            )
        else:
            out[k] = p
    return list(out.values())


def build_bom(
    made: Iterable[MadePart], bought: Iterable[BoughtPart], previous: Mapping[str, int] | Bom | None = None
) -> Bom:
    """The bill of materials of ``made`` and ``bought`` parts, numbered as the module text says.

    Parameters
    ----------
    made, bought : iterables of MadePart, BoughtPart
        Bought parts of one standard and designation are added up into one item.
    previous : mapping or Bom, optional
        The earlier list's numbers (:meth:`Bom.numbers`, :func:`numbers_from_csv`) or the list.

    Raises
    ------
    SpecError
        When two made parts share a name, one bought designation has two masses, or ``previous``
        gives one number to two items.
    """
    made = sorted(made, key=_order_made)
    names = [p.name for p in made]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise SpecError(f"made parts {twice} are listed twice")
    bought = sorted(_merged(bought), key=_order_bought)
    if isinstance(previous, Bom):
        last, previous = previous.last, previous.numbers()
    else:
        previous = dict(previous or {})
        last = max(previous.values(), default=0)
    if len(set(previous.values())) != len(previous):
        raise SpecError("previous item numbers give one number to two items")
    entries = [(_key_made(p), p) for p in made] + [(_key_bought(p), p) for p in bought]
    items = []
    for k, p in entries:
        if k in previous:
            n = previous[k]
        else:
            last += 1
            n = last
        if isinstance(p, MadePart):
            items.append(Item(n, p.name, p.quantity, p.material, True, "", "", p.mass_kg, ", ".join(p.files)))
        else:
            items.append(Item(n, p.name, p.quantity, p.material, False, p.designation, p.standard, p.mass_kg, ""))
    return Bom(tuple(sorted(items, key=lambda i: i.item)), max([last, *(i.item for i in items)]))


def numbers_from_csv(data: bytes) -> dict[str, int]:
    """The item numbers of a ``bom.csv`` this module wrote: key -> number (see :attr:`Item.key`)."""
    out = {}
    for r in csv.DictReader(io.StringIO(data.decode("utf-8"))):
        try:
            n = int(r["item"])
            made = r["made"] == "made"
            key = f"made:{r['name']}" if made else f"bought:{r['standard']}:{r['designation']}"
        except (KeyError, ValueError) as exc:
            raise SpecError(f"bom.csv row {r!r} is not a bill of materials row") from exc
        out[key] = n
    return out
