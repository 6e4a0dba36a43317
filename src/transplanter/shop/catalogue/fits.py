"""ISO 286-2 limit deviations for the fits a bearing seat needs: shafts h6, j6, k6, holes H7.

``shaft_and_hole_tolerances.csv`` holds the deviations (micrometres) by nominal size step, read
from the SKF General Catalogue's tables of shaft and housing tolerances (which list ISO
286-2:2010). :func:`fit` gives a :class:`Fit` whose :attr:`Fit.text` is what a drawing states.
A nominal size equal to a step's upper end belongs to that step (ISO 286: "over ... up to and
including").

Examples
--------
>>> fit(12, "k6").text
'Ø12 k6 (+0.012/+0.001)'
>>> fit(12, "h6").limits
(12.0, 11.989)
>>> fit(28, "H7").text
'Ø28 H7 (+0.021/0)'
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from transplanter.core.errors import SpecError, finite_positive
from transplanter.shop.catalogue.tables import number, table

__all__ = ["Fit", "fit", "tolerance_classes"]


def _mm(um: float) -> str:
    return "0" if um == 0 else f"{um / 1000:+.3f}"


@dataclass(frozen=True)
class Fit:
    """A nominal size with a tolerance class and its limit deviations (mm)."""

    nominal: float  #: mm
    tolerance_class: str  #: e.g. ``k6``
    upper: float  #: upper deviation, mm
    lower: float  #: lower deviation, mm
    source: str

    standard = "ISO 286-2"

    @property
    def limits(self) -> tuple[float, float]:
        """The largest and smallest permitted size, mm."""
        return round(self.nominal + self.upper, 6), round(self.nominal + self.lower, 6)

    @property
    def text(self) -> str:
        """``Ø12 k6 (+0.012/+0.001)``: nominal, class and deviations in mm."""
        return (
            f"Ø{self.nominal:g} {self.tolerance_class} "
            f"({_mm(round(self.upper * 1000, 3))}/{_mm(round(self.lower * 1000, 3))})"
        )


@cache
def tolerance_classes() -> tuple[str, ...]:
    """The classes the table holds."""
    return tuple(dict.fromkeys(r["tolerance_class"] for r in table("shaft_and_hole_tolerances")))


def fit(nominal: float, tolerance_class: str) -> Fit:
    """The limit deviations of ``tolerance_class`` at ``nominal`` (mm).

    Raises
    ------
    SpecError
        Naming ``tolerance_class`` and the classes known, or ``nominal`` and the sizes the class
        covers.
    """
    d = finite_positive("nominal", nominal)
    if tolerance_class not in tolerance_classes():
        raise SpecError(
            f"tolerance_class = {tolerance_class!r} is not in the catalogue: expected one of "
            f"{', '.join(tolerance_classes())}"
        )
    rows = [r for r in table("shaft_and_hole_tolerances") if r["tolerance_class"] == tolerance_class]
    for r in rows:
        if number(r, "over_mm") < d <= number(r, "to_mm"):
            return Fit(d, tolerance_class, number(r, "upper_um") / 1000, number(r, "lower_um") / 1000, r["source"])
    lo, hi = number(rows[0], "over_mm"), number(rows[-1], "to_mm")
    raise SpecError(f"nominal = {nominal!r} is out of range for {tolerance_class}: must be > {lo:g} and <= {hi:g} mm")
