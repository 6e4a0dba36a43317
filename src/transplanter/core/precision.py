"""The precision a figure is written with into a manifest or a report.

Manifests are compared byte for byte between builds and read by people: a figure computed to
float round-off is written either to fixed decimals (:func:`rounded`: coordinates, lengths,
angles — 1e-9 mm is far below anything made) or to significant figures (:func:`significant`:
errors and deviations, whose size matters, not their last digits). Every layer that reports a
figure (``validate``, ``formats``, ``families``) uses these two, and nothing else.

Examples
--------
>>> rounded(1 / 3), rounded(float("inf")), significant(0.000123456), significant(98765.4321, 2)
(0.333333333, None, 0.0001235, 99000.0)
"""

from __future__ import annotations

import math

__all__ = ["rounded", "significant"]


def rounded(value: float, digits: int = 9) -> float | None:
    """Rounded for a manifest; None for inf (JSON has no infinity: "no limit")."""
    v = float(value)
    return round(v, digits) if math.isfinite(v) else None


def significant(value: float, digits: int = 4) -> float:
    """``value`` to ``digits`` significant figures, for error figures in a manifest."""
    return float(f"{float(value):.{digits - 1}e}")
