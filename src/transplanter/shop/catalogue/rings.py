"""Retaining rings (circlips) for shafts (DIN 471) and bores (DIN 472), with their grooves.

``retaining_rings_shafts.csv`` (shafts 3-50 mm) and ``retaining_rings_bores.csv`` (bores
8-95 mm) hold the normal-type rings: thickness ``s``, groove diameter ``d2`` with its
deviations, groove width ``m`` (tolerance H13) and ``n_min``, the least distance of the groove
from the shaft or bore end. A ring is chosen by the nominal diameter exactly -- the standards
list one ring per nominal size.

Examples
--------
>>> c = circlip_for_shaft(12)
>>> c.designation, c.s, c.groove_diameter, c.groove_width, c.n_min
('DIN 471 12x1', 1.0, 11.5, 1.1, 0.8)
>>> c.groove_note
'groove 11.5 (0/-0.11) x 1.1 H13, n >= 0.8 from the end'
>>> circlip_for_bore(28).groove_diameter
29.4
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from transplanter.core.errors import SpecError, finite_positive
from transplanter.shop.catalogue.tables import number, table

__all__ = ["Circlip", "circlip_for_bore", "circlip_for_shaft", "circlips"]

_TABLES = {"DIN 471": "retaining_rings_shafts", "DIN 472": "retaining_rings_bores"}


def _dev(x: float) -> str:
    return "0" if x == 0 else f"{x:+g}"


@dataclass(frozen=True)
class Circlip:
    """A retaining ring and its groove. Lengths in mm."""

    standard: str  #: ``DIN 471`` (shaft) or ``DIN 472`` (bore)
    nominal: float  #: d1: the shaft or bore diameter
    s: float  #: ring thickness
    groove_diameter: float  #: d2
    groove_upper: float  #: upper deviation of d2
    groove_lower: float  #: lower deviation of d2
    groove_width: float  #: m (H13)
    n_min: float  #: least distance of the groove from the end
    free_diameter: float  #: d3: the ring's bore (shaft ring) or outside diameter (bore ring) before fitting
    lug: float  #: a: lug height
    mass_kg: float
    source: str

    @property
    def designation(self) -> str:
        return f"{self.standard} {self.nominal:g}x{self.s:g}"

    @property
    def name(self) -> str:
        return "retaining ring for shaft" if self.standard == "DIN 471" else "retaining ring for bore"

    @property
    def groove_size(self) -> str:
        """The groove's diameter with its deviations and its width with its tolerance class."""
        return (
            f"{self.groove_diameter:g} ({_dev(self.groove_upper)}/{_dev(self.groove_lower)}) x "
            f"{self.groove_width:g} H13"
        )

    @property
    def groove_note(self) -> str:
        """The groove for a drawing: diameter with deviations, width with its tolerance class, n."""
        return f"groove {self.groove_size}, n >= {self.n_min:g} from the end"


@cache
def circlips(standard: str) -> tuple[Circlip, ...]:
    """Every ring of ``DIN 471`` or ``DIN 472``."""
    if standard not in _TABLES:
        raise SpecError(f"standard = {standard!r} must be one of {', '.join(_TABLES)}")
    return tuple(
        Circlip(
            standard,
            number(r, "d1_mm"),
            number(r, "s_mm"),
            number(r, "d2_mm"),
            number(r, "d2_upper_mm"),
            number(r, "d2_lower_mm"),
            number(r, "m_mm"),
            number(r, "n_min_mm"),
            number(r, "d3_mm"),
            number(r, "a_mm"),
            number(r, "mass_kg_per_1000") / 1000.0,
            r["source"],
        )
        for r in table(_TABLES[standard])
    )


def _pick(standard: str, name: str, value: float) -> Circlip:
    d = finite_positive(name, value)
    rings = circlips(standard)
    for c in rings:
        if c.nominal == d:
            return c
    near = sorted(rings, key=lambda c: abs(c.nominal - d))[:2]
    raise SpecError(
        f"{name} = {value!r} has no {standard} ring (sizes {rings[0].nominal:g}-{rings[-1].nominal:g} mm); "
        f"nearest: {', '.join(f'{c.nominal:g}' for c in sorted(near, key=lambda c: c.nominal))}"
    )


def circlip_for_shaft(d: float) -> Circlip:
    """The DIN 471 ring for a shaft of diameter ``d``; SpecError naming ``d`` and the nearest sizes."""
    return _pick("DIN 471", "d", d)


def circlip_for_bore(D: float) -> Circlip:
    """The DIN 472 ring for a bore of diameter ``D``; SpecError naming ``D`` and the nearest sizes."""
    return _pick("DIN 472", "D", D)
