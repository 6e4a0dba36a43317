"""Standard data a shop buys by name: materials and the bought parts of the machines, each row
with the standard or maker it is taken from.

The tables are package data (``*.csv`` beside this module, read by
:func:`~transplanter.shop.catalogue.tables.table`); a row's ``source`` says where its figures
come from, so a drawing or a bill of materials can cite it, and each table's ``#`` notes say which
standard and edition, and which maker's catalogue or transcription, its figures were read from
(docs/catalogue.md lists them). The modules choose from them, pure functions that raise a
:class:`~transplanter.core.errors.SpecError` naming the parameter and the limit when nothing fits:

* :mod:`~transplanter.shop.catalogue.bearings` -- ISO 15 deep groove ball bearings by bore, speed
  and load (ISO 281 life, static safety, axial limit, limiting speed): :func:`bearing_for`;
* :mod:`~transplanter.shop.catalogue.bushes` -- ISO 3547-1 wrapped plain bushes: :func:`bush_for`;
* :mod:`~transplanter.shop.catalogue.fasteners` -- DIN 6885-1 keys (:func:`key_for`), ISO 4762
  screws (:func:`screw`), ISO 4032 nuts (:func:`nut`), ISO 7089/7090 washers (:func:`washer`);
* :mod:`~transplanter.shop.catalogue.rings` -- DIN 471/472 retaining rings and their grooves
  (:func:`circlip_for_shaft`, :func:`circlip_for_bore`);
* :mod:`~transplanter.shop.catalogue.fits` -- ISO 286-2 deviations for h6, j6, k6, H7 (:func:`fit`);
* :mod:`~transplanter.shop.catalogue.gear_materials` -- ISO 6336-5 allowable stress numbers of the
  gear materials a source at hand gives (``gear_material``).

Every chosen part has ``designation``, ``standard``, ``name`` and ``mass_kg``: what
:class:`transplanter.shop.bom.BoughtPart` takes.

Examples
--------
>>> m = material("C45")
>>> m.density_kg_m3, m.standard
(7850.0, 'EN ISO 683-1:2018')
>>> material("brass")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
transplanter.core.errors.SpecError: material = 'brass' is not in the catalogue: expected one of 42CrMo4, ...
>>> bearing_for(12, speed_rpm=100, radial_n=300).designation, fit(12, "k6").text
('61801-2Z', 'Ø12 k6 (+0.012/+0.001)')
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from transplanter.core.errors import SpecError
from transplanter.shop.catalogue.bearings import Bearing, SelectedBearing, bearing, bearing_for, bearings
from transplanter.shop.catalogue.bushes import Bush, SelectedBush, bush, bush_for
from transplanter.shop.catalogue.fasteners import Key, Nut, Screw, Washer, key_for, nut, screw, washer
from transplanter.shop.catalogue.fits import Fit, fit
from transplanter.shop.catalogue.rings import Circlip, circlip_for_bore, circlip_for_shaft
from transplanter.shop.catalogue.tables import notes, table

__all__ = [
    "Bearing",
    "Bush",
    "Circlip",
    "Fit",
    "Key",
    "Material",
    "Nut",
    "Screw",
    "SelectedBearing",
    "SelectedBush",
    "Washer",
    "bearing",
    "bearing_for",
    "bearings",
    "bush",
    "bush_for",
    "circlip_for_bore",
    "circlip_for_shaft",
    "fit",
    "key_for",
    "material",
    "materials",
    "notes",
    "nut",
    "screw",
    "table",
    "washer",
]


@dataclass(frozen=True)
class Material:
    """A material a drawing names: its short ``name`` (what part scripts give), the full
    designation and standard a shop orders it by, its density and where that figure is from."""

    name: str
    designation: str
    standard: str
    density_kg_m3: float
    source: str

    @property
    def note(self) -> str:
        """The drawing's material note, e.g. ``material C45+QT (1.0503) steel, EN ISO 683-1:2018``."""
        return f"material {self.designation}, {self.standard}"


@cache
def materials() -> dict[str, Material]:
    """Every material of the catalogue by its short name."""
    return {
        r["name"]: Material(r["name"], r["designation"], r["standard"], float(r["density_kg_m3"]), r["source"])
        for r in table("materials")
    }


def material(name: str) -> Material:
    """The catalogue's material ``name``; a :class:`~transplanter.core.errors.SpecError` naming the
    known ones otherwise."""
    known = materials()
    if not isinstance(name, str) or name not in known:
        raise SpecError(f"material = {name!r} is not in the catalogue: expected one of {', '.join(sorted(known))}")
    return known[name]
