"""Deep groove ball bearings (ISO 15) by bore, speed and load: ISO 281 basic rating life.

The rows are SKF's (``deep_groove_ball_bearings.csv``: series 618, 619, 60 and 62, bores 5-50 mm,
from the SKF General Catalogue); :func:`bearing_for` picks the smallest of the asked series whose
bore matches and which carries the stated load at the stated speed:

* equivalent dynamic load (ISO 281:2007 clause 5.1, table 3, radial ball bearings, normal
  clearance -- SKF General Catalogue table 5 p. 299 lists the same figures): ``P = Fr`` when
  ``Fa/Fr <= e``, else ``P = 0.56 Fr + Y Fa``, with ``e`` and ``Y`` interpolated linearly in
  ``f0 Fa/C0`` (``f0`` from the bearing's row). Below the table's first point (0.172) its first
  row is used (the largest ``Y``: on the safe side), above the last (6.89) its last;
* basic rating life ``L10 = (C/P)^3`` million revolutions, ``L10h = 10^6 L10 / (60 n)`` hours, at
  least ``life_h`` (default 3 000 h: the upper end of SKF's guideline 300-3 000 h for agricultural
  machines, General Catalogue table 8 p. 72);
* equivalent static load ``P0 = max(0.6 Fr + 0.5 Fa, Fr)`` and static safety ``s0 = C0/P0`` at
  least ``static_safety`` (default 1.5: SKF's guideline for rotating ball bearings under
  pronounced shock loads, table 10 p. 77 -- a needle striking soil);
* axial load at most ``0.5 C0``, or ``0.25 C0`` for bores up to 12 mm and the light diameter
  series 8, 9 and 0 (SKF p. 299);
* speed at most the limiting speed (of the shielded bearing, ``-2Z``, when ``shielded``).

Not checked: the requisite minimum load (it needs the lubricant's viscosity) and the SKF
life-modification factor ``a_SKF``; ``L10`` is the plain ISO 281 basic rating life at 90 %
reliability.

Examples
--------
>>> b = bearing("6001")
>>> b.d, b.D, b.B, b.C_n, b.designation_2z
(12.0, 28.0, 8.0, 5400.0, '6001-2Z')
>>> s = bearing_for(12, speed_rpm=60, radial_n=300)
>>> s.designation, s.bearing.D, round(s.life_h), round(s.static_safety, 2)
('61801-2Z', 21.0, 30084, 2.23)
>>> bearing_for(12, speed_rpm=60, radial_n=800).designation  # 618 and 619 fall short of s0 = 1.5
'6001-2Z'
>>> round(rating_life(55300, 10000), 1), round(rating_life_h(55300, 10000, 3000))  # SKF p. 78, example 1
(169.1, 940)
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from transplanter.core.errors import SpecError, check_number, finite_positive
from transplanter.shop.catalogue.tables import number, table

__all__ = [
    "SERIES",
    "Bearing",
    "SelectedBearing",
    "bearing",
    "bearing_for",
    "bearings",
    "equivalent_load",
    "rating_life",
    "rating_life_h",
]

#: the ISO 15 series the table holds, lightest section first
SERIES = ("618", "619", "60", "62")
#: ISO 281:2007 table 3, radial ball bearings, normal clearance: f0 Fa/C0, e, Y (X = 0.56 above e)
_F0FA_C0 = np.array([0.172, 0.345, 0.689, 1.03, 1.38, 2.07, 3.45, 5.17, 6.89])
_E = np.array([0.19, 0.22, 0.26, 0.28, 0.30, 0.34, 0.38, 0.42, 0.44])
_Y = np.array([2.30, 1.99, 1.71, 1.55, 1.45, 1.31, 1.15, 1.04, 1.00])
_X = 0.56
#: default required basic rating life, h (SKF General Catalogue table 8: agricultural machines 300-3 000 h)
LIFE_H = 3000.0
#: default static safety s0 (SKF General Catalogue table 10: rotating ball bearing, pronounced shock loads)
STATIC_SAFETY = 1.5


@dataclass(frozen=True)
class Bearing:
    """One catalogue row: a single-row deep groove ball bearing. Lengths in mm, loads in N."""

    designation: str  #: the open bearing's basic designation, e.g. ``6001``
    series: str  #: ``618``, ``619``, ``60`` or ``62``
    d: float  #: bore, mm
    D: float  #: outside diameter, mm
    B: float  #: width, mm
    r_min: float  #: smallest chamfer r1,2 min, mm
    C_n: float  #: basic dynamic load rating, N
    C0_n: float  #: basic static load rating, N
    Pu_n: float  #: fatigue load limit, N
    f0: float  #: ISO 281 calculation factor
    reference_speed_rpm: float
    limiting_speed_rpm: float  #: of the open bearing
    limiting_speed_2z_rpm: float | None  #: of the bearing with two shields; None: no 2Z variant listed
    mass_kg: float
    source: str

    standard = "ISO 15"

    @property
    def designation_2z(self) -> str | None:
        """The shielded bearing's designation (``6001-2Z``), or None when SKF lists none."""
        return f"{self.designation}-2Z" if self.limiting_speed_2z_rpm is not None else None

    @property
    def light(self) -> bool:
        """True for the bearings whose pure axial load SKF limits to 0.25 C0 (bore <= 12 mm or
        diameter series 8, 9, 0)."""
        return self.d <= 12 or self.series in ("618", "619", "60")


@dataclass(frozen=True)
class SelectedBearing:
    """A bearing chosen for a load case, with the figures that made it pass."""

    bearing: Bearing
    shielded: bool  #: the ``-2Z`` bearing (greased for life, shields both sides)
    speed_rpm: float
    radial_n: float
    axial_n: float
    X: float
    Y: float
    e: float
    equivalent_load_n: float  #: P, N
    static_load_n: float  #: P0, N
    static_safety: float  #: s0 = C0/P0
    life_mrev: float  #: L10, million revolutions
    life_h: float  #: L10h, hours (inf at speed 0)

    @property
    def designation(self) -> str:
        """What a shop orders: ``6001-2Z`` or ``6001``."""
        b = self.bearing
        return b.designation_2z if self.shielded else b.designation

    @property
    def limiting_speed_rpm(self) -> float:
        b = self.bearing
        return b.limiting_speed_2z_rpm if self.shielded else b.limiting_speed_rpm

    @property
    def standard(self) -> str:
        return self.bearing.standard

    @property
    def mass_kg(self) -> float:
        return self.bearing.mass_kg

    @property
    def name(self) -> str:
        return "deep groove ball bearing"

    @property
    def d(self) -> float:
        return self.bearing.d

    @property
    def D(self) -> float:
        return self.bearing.D

    @property
    def B(self) -> float:
        return self.bearing.B


@cache
def bearings() -> tuple[Bearing, ...]:
    """Every row of ``deep_groove_ball_bearings.csv``."""
    out = []
    for r in table("deep_groove_ball_bearings"):
        lim2z = r["limiting_speed_2z_rpm"]
        out.append(
            Bearing(
                r["designation"],
                r["series"],
                number(r, "d_mm"),
                number(r, "D_mm"),
                number(r, "B_mm"),
                number(r, "r_min_mm"),
                1000.0 * number(r, "C_kN"),
                1000.0 * number(r, "C0_kN"),
                1000.0 * number(r, "Pu_kN"),
                number(r, "f0"),
                number(r, "reference_speed_rpm"),
                number(r, "limiting_speed_rpm"),
                float(lim2z) if lim2z else None,
                number(r, "mass_kg"),
                r["source"],
            )
        )
    return tuple(out)


def bearing(designation: str) -> Bearing:
    """The row of ``designation`` (``6001`` or ``6001-2Z``); SpecError naming it otherwise."""
    base = designation.removesuffix("-2Z") if isinstance(designation, str) else designation
    for b in bearings():
        if b.designation == base and (base == designation or b.designation_2z == designation):
            return b
    raise SpecError(f"bearing = {designation!r} is not in the deep groove ball bearing table")


def rating_life(C_n: float, P_n: float) -> float:
    """ISO 281 basic rating life of a ball bearing, ``L10 = (C/P)^3``, million revolutions."""
    C = finite_positive("C_n", C_n)
    P = check_number("P_n", P_n, 0.0, unit="N")
    return float("inf") if P == 0 else (C / P) ** 3


def rating_life_h(C_n: float, P_n: float, speed_rpm: float) -> float:
    """The basic rating life in hours at ``speed_rpm``: ``L10h = 10^6 L10 / (60 n)`` (inf at rest)."""
    n = check_number("speed_rpm", speed_rpm, 0.0, unit="r/min")
    l10 = rating_life(C_n, P_n)
    return float("inf") if n == 0 or l10 == float("inf") else 1e6 * l10 / (60.0 * n)


def equivalent_load(b: Bearing, radial_n: float, axial_n: float = 0.0) -> tuple[float, float, float, float]:
    """ISO 281 equivalent dynamic load of ``b``: ``(P, X, Y, e)`` in N (see the module text)."""
    Fr = check_number("radial_n", radial_n, 0.0, unit="N")
    Fa = check_number("axial_n", axial_n, 0.0, unit="N")
    rel = b.f0 * Fa / b.C0_n
    e = float(np.interp(rel, _F0FA_C0, _E))
    Y = float(np.interp(rel, _F0FA_C0, _Y))
    if Fa == 0 or (Fr > 0 and Fa / Fr <= e):
        return Fr, 1.0, 0.0, e
    return _X * Fr + Y * Fa, _X, Y, e


def _check(b: Bearing, shielded: bool, n: float, Fr: float, Fa: float, life_h: float, s0_min: float):
    """The load case on ``b``: (SelectedBearing, None) when it passes, (None, why) otherwise."""
    if shielded and b.limiting_speed_2z_rpm is None:
        return None, f"{b.designation} has no -2Z variant"
    P, X, Y, e = equivalent_load(b, Fr, Fa)
    P0 = max(0.6 * Fr + 0.5 * Fa, Fr)
    s0 = float("inf") if P0 == 0 else b.C0_n / P0
    l10 = rating_life(b.C_n, P)
    l10h = rating_life_h(b.C_n, P, n)
    pick = SelectedBearing(b, shielded, n, Fr, Fa, X, Y, e, P, P0, s0, l10, l10h)
    name = pick.designation
    fa_max = (0.25 if b.light else 0.5) * b.C0_n
    if n > pick.limiting_speed_rpm:
        return None, f"{name}: speed_rpm = {n:g} > limiting speed {pick.limiting_speed_rpm:g} r/min"
    if Fa > fa_max:
        return None, f"{name}: axial_n = {Fa:g} N > {fa_max:g} N ({0.25 if b.light else 0.5:g} C0)"
    if s0 < s0_min:
        return None, f"{name}: static safety C0/P0 = {s0:.3g} < static_safety = {s0_min:g}"
    if l10h < life_h:
        return None, f"{name}: L10h = {l10h:.4g} h < life_h = {life_h:g} h"
    return pick, None


def bearing_for(
    bore_mm: float,
    speed_rpm: float,
    radial_n: float,
    axial_n: float = 0.0,
    life_h: float = LIFE_H,
    *,
    series: tuple[str, ...] = SERIES,
    shielded: bool = True,
    static_safety: float = STATIC_SAFETY,
) -> SelectedBearing:
    """The smallest bearing of ``series`` with bore ``bore_mm`` that carries the load case.

    Parameters
    ----------
    bore_mm : float
        The shaft seat diameter, mm; a bearing's bore must equal it.
    speed_rpm : float
        Speed of the inner ring relative to the outer, r/min (>= 0; at 0 only the static check
        and the axial limit bind).
    radial_n, axial_n : float
        Constant radial and axial load, N.
    life_h : float
        Required ISO 281 basic rating life L10h, hours.
    series : tuple of str
        The ISO 15 series to choose from (``SERIES``).
    shielded : bool
        Choose the ``-2Z`` bearing (shields both sides, greased for life) and hold the speed to
        its limiting speed; False: the open bearing.
    static_safety : float
        Least ``s0 = C0/P0``.

    Returns
    -------
    SelectedBearing
        The first that passes in order of outside diameter, then width, then mass.

    Raises
    ------
    SpecError
        Naming ``bore_mm`` and the bores there are when no row has that bore, or the load case
        and why the largest candidate fails when none passes.
    """
    d = finite_positive("bore_mm", bore_mm)
    n = check_number("speed_rpm", speed_rpm, 0.0, unit="r/min")
    Fr = check_number("radial_n", radial_n, 0.0, unit="N")
    Fa = check_number("axial_n", axial_n, 0.0, unit="N")
    life = check_number("life_h", life_h, 0.0, unit="h")
    s0 = check_number("static_safety", static_safety, 0.0)
    if isinstance(series, str) or not series or not set(series) <= set(SERIES):
        raise SpecError(f"series = {series!r} must be a non-empty tuple of {', '.join(SERIES)}")
    rows = sorted(
        (b for b in bearings() if b.series in series and b.d == d),
        key=lambda b: (b.D, b.B, b.mass_kg, b.designation),
    )
    if not rows:
        bores = sorted({b.d for b in bearings() if b.series in series})
        raise SpecError(
            f"bore_mm = {bore_mm!r} has no deep groove ball bearing of series {', '.join(series)}: "
            f"expected one of {', '.join(f'{x:g}' for x in bores)} mm"
        )
    why = ""
    for b in rows:
        pick, why = _check(b, shielded, n, Fr, Fa, life, s0)
        if pick is not None:
            return pick
    raise SpecError(
        f"no deep groove ball bearing of bore {d:g} mm (series {', '.join(series)}) carries radial_n = {Fr:g} N, "
        f"axial_n = {Fa:g} N at speed_rpm = {n:g} for life_h = {life:g}: the largest, {why}"
    )
