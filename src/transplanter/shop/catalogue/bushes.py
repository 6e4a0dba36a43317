"""Wrapped plain bushes (ISO 3547-1) for small, slow joints: SKF PCM composite bushings.

``wrapped_bushes.csv`` holds SKF's metric straight bushings of bore 5-50 mm in two materials:
``E`` (PTFE composite, runs dry) and ``M`` (POM composite, greased once). :func:`bush_for` picks
the shortest bush of a bore that fits the seat length and carries the load at the speed, by the
maker's two limits (SKF composite plain bearings, PUB BU/P2 11004 EN, pp. 11 and 13):

* specific bearing load ``p = K F / C`` (``K`` = 80 N/mm2 for E, 120 N/mm2 for M) at most ``K``,
  i.e. ``F <= C``, and the static load at most ``C0`` (250 N/mm2 on ``d B``);
* sliding velocity ``v = 5.82e-7 d beta f`` m/s (rotation: ``beta = 90 deg``, so
  ``v = pi d n / 60000``) at most 2 m/s (E) or 2.5 m/s (M).

The maker's ``pv`` diagram and its life formula are not applied: a bush chosen here is within
the material's load and speed limits, and its wear life is not stated.

Examples
--------
>>> b = bush_for(12, length_mm=12, radial_n=2000, speed_rpm=30)
>>> b.designation, b.bush.D, b.bush.B, round(b.pressure_n_mm2, 2)
('PCM 121408 E', 14.0, 8.0, 20.92)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

from transplanter.core.errors import SpecError, check_number, finite_positive
from transplanter.shop.catalogue.tables import number, table

__all__ = ["Bush", "SelectedBush", "bush", "bush_for", "bushes"]

#: specific load factor K, N/mm2, and greatest sliding velocity, m/s, by material variant (SKF p. 11)
LIMITS = {"E": (80.0, 2.0), "M": (120.0, 2.5)}


@dataclass(frozen=True)
class Bush:
    """One catalogue row. Lengths in mm, loads in N."""

    designation: str  #: e.g. ``PCM 121410 E``
    variant: str  #: ``E`` (PTFE composite) or ``M`` (POM composite)
    d: float  #: bore, mm
    D: float  #: outside diameter, mm
    B: float  #: width, mm
    C_n: float  #: basic dynamic load rating, N
    C0_n: float  #: basic static load rating, N
    mass_kg: float
    source: str

    standard = "ISO 3547-1"
    name = "wrapped plain bush"


@dataclass(frozen=True)
class SelectedBush:
    """A bush chosen for a load case."""

    bush: Bush
    radial_n: float
    speed_rpm: float
    pressure_n_mm2: float  #: p = K F / C
    sliding_m_s: float  #: v

    @property
    def designation(self) -> str:
        return self.bush.designation

    @property
    def standard(self) -> str:
        return self.bush.standard

    @property
    def mass_kg(self) -> float:
        return self.bush.mass_kg

    @property
    def name(self) -> str:
        return self.bush.name


@cache
def bushes() -> tuple[Bush, ...]:
    """Every row of ``wrapped_bushes.csv``."""
    return tuple(
        Bush(
            r["designation"],
            r["variant"],
            number(r, "d_mm"),
            number(r, "D_mm"),
            number(r, "B_mm"),
            1000.0 * number(r, "C_kN"),
            1000.0 * number(r, "C0_kN"),
            number(r, "mass_g") / 1000.0,
            r["source"],
        )
        for r in table("wrapped_bushes")
    )


def bush(designation: str) -> Bush:
    """The row of ``designation`` (``PCM 121410 E``); SpecError naming it otherwise."""
    for b in bushes():
        if b.designation == designation:
            return b
    raise SpecError(f"bush = {designation!r} is not in the wrapped bush table")


def bush_for(
    bore_mm: float, length_mm: float, radial_n: float, speed_rpm: float = 0.0, *, variant: str = "E"
) -> SelectedBush:
    """The shortest bush of bore ``bore_mm`` no longer than ``length_mm`` that carries the load.

    Parameters
    ----------
    bore_mm : float
        Shaft diameter, mm; the bush's bore must equal it.
    length_mm : float
        Length of the seat in the housing, mm; the bush must not be longer.
    radial_n : float
        Radial load, N (taken as both the dynamic and the static load).
    speed_rpm : float
        Relative rotational speed, r/min (an oscillating joint: its equivalent, see the module text).
    variant : str
        ``E`` (PTFE composite, dry) or ``M`` (POM composite, greased once).

    Raises
    ------
    SpecError
        Naming the bore when there is no bush of it, or the limit the longest fitting bush breaks.
    """
    d = finite_positive("bore_mm", bore_mm)
    length = finite_positive("length_mm", length_mm)
    F = check_number("radial_n", radial_n, 0.0, unit="N")
    n = check_number("speed_rpm", speed_rpm, 0.0, unit="r/min")
    if variant not in LIMITS:
        raise SpecError(f"variant = {variant!r} must be one of {', '.join(LIMITS)}")
    K, v_max = LIMITS[variant]
    rows = sorted((b for b in bushes() if b.variant == variant and b.d == d), key=lambda b: (b.B, b.D))
    if not rows:
        bores = sorted({b.d for b in bushes() if b.variant == variant})
        known = ", ".join(f"{x:g}" for x in bores)
        raise SpecError(f"bore_mm = {bore_mm!r} has no {variant} bush: expected one of {known}")
    fitting = [b for b in rows if b.B <= length]
    if not fitting:
        raise SpecError(
            f"length_mm = {length_mm!r} is shorter than every {variant} bush of bore {d:g} mm (>= {rows[0].B:g})"
        )
    v = math.pi * d * n / 60000.0
    if v > v_max:
        raise SpecError(f"speed_rpm = {n:g} slides a {d:g} mm bore at {v:.3g} m/s > {v_max:g} m/s ({variant} bushes)")
    for b in fitting:
        if F <= b.C_n and F <= b.C0_n:
            return SelectedBush(b, F, n, K * F / b.C_n, v)
    big = fitting[-1]
    raise SpecError(
        f"radial_n = {F:g} N is more than {big.designation} carries (C = {big.C_n:g} N): "
        f"a longer seat (length_mm) or another bore"
    )
