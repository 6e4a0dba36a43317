"""Gear materials and their ISO 6336-5 allowable stress numbers, read from ``gear_materials.csv``.

Each row cites the figure, grade and hardness it was read from; the table's notes say which lines
are missing and why (no figure is estimated).

Examples
--------
>>> m = gear_material("18CrNiMo7-6")
>>> m.sigma_hlim, m.sigma_fe, m.grade
(1500.0, 860.0, 'MQ')
>>> gear_material("C45")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
transplanter.core.errors.SpecError: gear material = 'C45' has no ISO 6336-5 allowables in the catalogue: ...
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from transplanter.core.errors import SpecError
from transplanter.shop.catalogue.tables import number, table

__all__ = ["GearMaterial", "gear_material", "gear_materials"]

#: ISO 6336-3's stress correction factor of the reference test gear: σ_FE = Y_ST σ_Flim
Y_ST = 2.0


@dataclass(frozen=True)
class GearMaterial:
    """A gear material's ISO 6336-5 allowables (MPa), elastic constants and their ``source``."""

    name: str
    designation: str
    treatment: str
    grade: str
    hardness: str
    sigma_hlim: float
    sigma_flim: float
    e: float
    nu: float
    source: str

    @property
    def sigma_fe(self) -> float:
        """Allowable stress number for bending σ_FE = Y_ST σ_Flim, MPa."""
        return Y_ST * self.sigma_flim


@cache
def gear_materials() -> dict[str, GearMaterial]:
    """Every gear material of the catalogue by its short name."""
    return {
        r["name"]: GearMaterial(
            r["name"],
            r["designation"],
            r["treatment"],
            r["grade"],
            r["hardness"],
            number(r, "sigma_hlim_mpa"),
            number(r, "sigma_flim_mpa"),
            number(r, "e_mpa"),
            number(r, "nu"),
            r["source"],
        )
        for r in table("gear_materials")
    }


def gear_material(name: str) -> GearMaterial:
    """The catalogue's gear material ``name``; a SpecError naming the known ones otherwise."""
    known = gear_materials()
    if not isinstance(name, str) or name not in known:
        raise SpecError(
            f"gear material = {name!r} has no ISO 6336-5 allowables in the catalogue: expected one of "
            f"{', '.join(sorted(known))}"
        )
    return known[name]
