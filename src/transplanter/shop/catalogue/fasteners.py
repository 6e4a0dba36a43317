"""Keys, screws, nuts and washers from their standards, with the lengths a shop can buy.

* :func:`key_for` -- a DIN 6885-1 Form A parallel key for a shaft and hub (``parallel_keys.csv``,
  ``parallel_key_lengths.csv``): section ``b x h`` and keyway depths ``t1`` (shaft), ``t2`` (hub)
  by the shaft's diameter step; the longest standard length not longer than the hub.
* :func:`screw` -- an ISO 4762 socket head cap screw M3-M12 of a standard length within the
  size's range (``socket_head_cap_screws.csv``, ``socket_head_cap_screw_lengths.csv``).
* :func:`nut` -- an ISO 4032 hexagon nut (``hex_nuts.csv``); :func:`washer` -- an ISO 7089 or
  ISO 7090 plain washer (``plain_washers.csv``).

Masses of these parts are **estimates** from their nominal dimensions and the density of steel
(7850 kg/m3, the catalogue's C45 row): the standards tabulate no mass. Each part's ``mass_note``
says so, for the bill of materials.

Examples
--------
>>> k = key_for(12, hub_length=20)
>>> k.designation, k.t1, k.t2
('DIN 6885 A 4x4x20', 2.5, 1.8)
>>> s = screw("M4", 12)
>>> s.designation, s.head_diameter, s.thread_min
('ISO 4762 M4x12', 7.0, 12.0)
>>> nut("M4").designation, washer("M4").designation
('ISO 4032 M4', 'ISO 7089 4')
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import cache

from transplanter.core.errors import SpecError, finite_positive
from transplanter.shop.catalogue.tables import number, table

__all__ = ["Key", "Nut", "Screw", "Washer", "key_for", "key_lengths", "nut", "screw", "screw_lengths", "washer"]

MASS_NOTE = "estimated from nominal dimensions, steel 7850 kg/m3"


@cache
def _steel_kg_mm3() -> float:
    row = next(r for r in table("materials") if r["name"] == "C45")
    return number(row, "density_kg_m3") * 1e-9


def _size(M: str | float, name: str = "M") -> str:
    """``"M4"``, ``4`` or ``4.0`` as ``"M4"``."""
    if isinstance(M, str) and re.fullmatch(r"M\d+(\.\d+)?", M):
        return M
    if isinstance(M, int | float) and not isinstance(M, bool) and math.isfinite(M) and M > 0:
        return f"M{M:g}"
    raise SpecError(f"{name} = {M!r} must be a metric thread size such as 'M4' or 4")


@dataclass(frozen=True)
class Key:
    """A DIN 6885-1 Form A parallel key and its keyways. Lengths in mm."""

    b: float  #: width
    h: float  #: height
    length: float
    t1: float  #: keyway depth in the shaft
    t2: float  #: keyway depth in the hub
    depth_tol: float  #: upper deviation of t1 and t2
    shaft_over: float  #: the diameter step: over ...
    shaft_to: float  #: ... up to and including
    source: str

    standard = "DIN 6885-1"
    name = "parallel key"
    mass_note = MASS_NOTE

    @property
    def designation(self) -> str:
        return f"DIN 6885 A {self.b:g}x{self.h:g}x{self.length:g}"

    @property
    def mass_kg(self) -> float:
        """Form A: a rectangle of length ``l - b`` and two half discs of diameter ``b``, height ``h``."""
        return ((self.length - self.b) * self.b + math.pi / 4 * self.b**2) * self.h * _steel_kg_mm3()

    def shaft_note(self, shaft_d: float) -> str:
        """The shaft keyway for a drawing: ``keyway 4 N9 x 2.5 +0.1 deep (d - t1 = 9.5)``."""
        return f"keyway {self.b:g} N9 x {self.t1:g} +{self.depth_tol:g} deep (d - t1 = {shaft_d - self.t1:g})"

    def hub_note(self, shaft_d: float) -> str:
        """The hub keyway for a drawing: ``keyway 4 JS9 x 1.8 +0.1 deep (d + t2 = 13.8)``."""
        return f"keyway {self.b:g} JS9 x {self.t2:g} +{self.depth_tol:g} deep (d + t2 = {shaft_d + self.t2:g})"


@cache
def key_lengths() -> tuple[float, ...]:
    """The standard key lengths, mm, ascending."""
    return tuple(sorted(number(r, "length_mm") for r in table("parallel_key_lengths")))


def key_for(shaft_d: float, hub_length: float) -> Key:
    """The parallel key for a shaft of diameter ``shaft_d`` in a hub ``hub_length`` long: the
    section of the shaft's diameter step and the longest standard length not over the hub.

    Raises
    ------
    SpecError
        Naming ``shaft_d`` and the steps covered, or ``hub_length`` when no standard length that
        is longer than the key's width fits.
    """
    d = finite_positive("shaft_d", shaft_d)
    hub = finite_positive("hub_length", hub_length)
    rows = table("parallel_keys")
    for r in rows:
        lo, hi = number(r, "shaft_over_mm"), number(r, "shaft_to_mm")
        if lo < d <= hi:
            b = number(r, "b_mm")
            fits = [x for x in key_lengths() if b < x <= hub]
            if not fits:
                raise SpecError(
                    f"hub_length = {hub_length!r} takes no standard DIN 6885 key of {b:g} mm width: "
                    f"the shortest over {b:g} mm is {min(x for x in key_lengths() if x > b):g} mm"
                )
            return Key(
                b,
                number(r, "h_mm"),
                max(fits),
                number(r, "t1_mm"),
                number(r, "t2_mm"),
                number(r, "depth_tol_mm"),
                lo,
                hi,
                r["source"],
            )
    lo, hi = number(rows[0], "shaft_over_mm"), number(rows[-1], "shaft_to_mm")
    raise SpecError(f"shaft_d = {shaft_d!r} is out of range: the key table covers over {lo:g} up to {hi:g} mm")


@dataclass(frozen=True)
class Screw:
    """An ISO 4762 hexagon socket head cap screw. Lengths in mm."""

    size: str  #: ``M4``
    d: float  #: nominal thread diameter
    pitch: float
    length: float  #: nominal length l (under the head)
    head_diameter: float  #: dk max
    head_height: float  #: k
    socket: float  #: hexagon socket size s
    socket_depth: float  #: t min
    thread_ref: float  #: b (reference)
    source: str

    standard = "ISO 4762"
    name = "socket head cap screw"
    mass_note = MASS_NOTE

    @property
    def designation(self) -> str:
        return f"ISO 4762 {self.size}x{self.length:g}"

    @property
    def thread_min(self) -> float:
        """The least thread length: ``b``, or the whole length when shorter (ISO 4762: the plain
        shank is at most ``l - b``)."""
        return min(self.thread_ref, self.length)

    @property
    def mass_kg(self) -> float:
        """Head cylinder less the socket prism, plus a shank of the nominal diameter."""
        head = math.pi / 4 * self.head_diameter**2 * self.head_height
        socket = math.sqrt(3) / 2 * self.socket**2 * self.socket_depth
        shank = math.pi / 4 * self.d**2 * self.length
        return (head - socket + shank) * _steel_kg_mm3()


@cache
def screw_lengths() -> tuple[float, ...]:
    """The ISO 4762 nominal lengths, mm, ascending."""
    return tuple(sorted(number(r, "length_mm") for r in table("socket_head_cap_screw_lengths")))


def _row(name: str, size: str, what: str) -> dict[str, str]:
    rows = {r["size"]: r for r in table(name)}
    if size not in rows:
        raise SpecError(f"M = {size!r} has no {what} in the catalogue: expected one of {', '.join(rows)}")
    return rows[size]


def screw(M: str | float, length: float) -> Screw:
    """The ISO 4762 screw ``M`` x ``length``; SpecError naming ``length`` and the lengths of
    that size when it is not a standard length in the size's range."""
    size = _size(M)
    r = _row("socket_head_cap_screws", size, "ISO 4762 screw")
    lo, hi = number(r, "l_min_mm"), number(r, "l_max_mm")
    ok = [x for x in screw_lengths() if lo <= x <= hi]
    if not isinstance(length, int | float) or isinstance(length, bool) or float(length) not in ok:
        known = ", ".join(f"{x:g}" for x in ok)
        raise SpecError(f"length = {length!r} is not a standard ISO 4762 {size} length: expected one of {known}")
    return Screw(
        size,
        float(size[1:]),
        number(r, "pitch_mm"),
        float(length),
        number(r, "dk_max_mm"),
        number(r, "k_mm"),
        number(r, "s_mm"),
        number(r, "t_min_mm"),
        number(r, "b_ref_mm"),
        r["source"],
    )


@dataclass(frozen=True)
class Nut:
    """An ISO 4032 hexagon nut, style 1. Lengths in mm."""

    size: str
    d: float
    pitch: float
    height: float  #: m
    across_flats: float  #: s
    source: str

    standard = "ISO 4032"
    name = "hexagon nut"
    mass_note = MASS_NOTE

    @property
    def designation(self) -> str:
        return f"ISO 4032 {self.size}"

    @property
    def mass_kg(self) -> float:
        """Hexagon prism less a hole of the nominal diameter."""
        return (math.sqrt(3) / 2 * self.across_flats**2 - math.pi / 4 * self.d**2) * self.height * _steel_kg_mm3()


def nut(M: str | float) -> Nut:
    """The ISO 4032 nut of size ``M``."""
    size = _size(M)
    r = _row("hex_nuts", size, "ISO 4032 nut")
    return Nut(size, float(size[1:]), number(r, "pitch_mm"), number(r, "m_mm"), number(r, "s_mm"), r["source"])


@dataclass(frozen=True)
class Washer:
    """An ISO 7089 / ISO 7090 plain washer. Lengths in mm."""

    standard: str
    size: str
    inner: float  #: d1 (min)
    outer: float  #: d2 (max)
    thickness: float  #: h (nominal)
    source: str

    name = "plain washer"
    mass_note = MASS_NOTE

    @property
    def designation(self) -> str:
        return f"{self.standard} {self.size[1:]}"

    @property
    def mass_kg(self) -> float:
        return math.pi / 4 * (self.outer**2 - self.inner**2) * self.thickness * _steel_kg_mm3()


def washer(M: str | float, standard: str = "ISO 7089") -> Washer:
    """The plain washer for a screw of size ``M`` (``ISO 7089`` or the chamfered ``ISO 7090``)."""
    size = _size(M)
    rows = {(r["standard"], r["size"]): r for r in table("plain_washers")}
    if (standard, size) not in rows:
        known = ", ".join(f"{s} {m}" for s, m in rows)
        raise SpecError(f"washer {standard!r} {size!r} is not in the catalogue: expected one of {known}")
    r = rows[(standard, size)]
    return Washer(standard, size, number(r, "d1_mm"), number(r, "d2_mm"), number(r, "h_mm"), r["source"])
