"""Backlash by design: the target a pair is cut for, the tolerance it must survive, the band it is checked against.

A gear pair made for a shop needs play: its teeth are cut within a manufacturing tolerance
and mounted on bores that are too. Three numbers, all circumferential at the pitch point (mm):

- the **target** ``j`` — what the teeth are thinned for: each gear's teeth lose ``j/2`` of
  thickness along the pitch curve (the shaper cutter is ``j/2`` thicker,
  ``ShaperCutter.thickening``). The default is the minimum backlash of ISO/TR 10064-2 (also
  AGMA 2002 / KHK), ``j_bn = 2/3 (0.06 + 0.0005 a + 0.03 m)`` mm normal to the flank, as
  circumferential ``j = j_bn / cos α`` — from the module and the centre distance, as gear
  standards do;
- the **tolerance** ``t`` — how far a made surface may lie from its drawing (± mm, normal to
  it); the default :data:`~transplanter.core.tolerances.WIRE_EDM_TOLERANCE` is a wire-EDM shop's;
- the **budget** — the play the tolerance can eat in the worst case: the four flanks of a
  driving and a coasting tooth pair each grown by ``t`` (``4t/cos α`` circumferential) and
  the centre distance shortened by both bores being off by ``t`` (``2 · 2t · tan α``).

The made pair (the *re-read* DXF) must keep its smallest backlash over the cycle above the
budget and its largest below the target's band (:func:`backlash_band`): on a non-circular
pair the circumferential backlash grows by ``1/cos ν`` where the pitch curve leans by ν.

Examples
--------
>>> from transplanter.geometry.backlash import design_backlash, tolerance_budget
>>> round(design_backlash(module=1.5, centre_distance=45.0), 4)   # mm, circumferential
0.0905
>>> round(tolerance_budget(0.005), 4)                             # ±5 µm wire EDM
0.0286
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.errors import SpecError, check_number, finite_positive
from transplanter.core.tolerances import WIRE_EDM_TOLERANCE

__all__ = ["design_backlash", "tolerance_budget", "backlash_band", "band_of", "resolve_backlash"]

_ALPHA = math.radians(20.0)

#: the band's upper end allows this much more than the target (/cos ν) for the outlines'
#: chord error and the flank curvature across the play, plus BAND_SLACK_MM
BAND_FACTOR = 1.1
#: absolute slack of the band's upper end, mm: four flanks, each up to 0.55 µm inside the outline
#: (the DXF's one-sided fit) and 0.05 µm of outline chord, 2.4 µm in all; the refined meshing proof
#: finds a zero-backlash DXF pair's play at 2.11 µm, which the 2 µm slack of the sampled check missed
BAND_SLACK_MM = 2.5e-3


def design_backlash(module: float, centre_distance: float, pressure_angle: float = _ALPHA) -> float:
    """ISO/TR 10064-2 minimum backlash as circumferential play at the pitch point, mm."""
    m = finite_positive("module", module)
    a = finite_positive("centre distance", centre_distance)
    return 2.0 / 3.0 * (0.06 + 0.0005 * a + 0.03 * m) / math.cos(pressure_angle)


def tolerance_budget(tolerance: float = WIRE_EDM_TOLERANCE, pressure_angle: float = _ALPHA) -> float:
    """Circumferential play (mm) a ±``tolerance`` shop can take away in the worst case."""
    t = check_number("tolerance", tolerance, 0.0, 1.0, unit="mm")
    return 4 * t / math.cos(pressure_angle) + 4 * t * math.tan(pressure_angle)


def resolve_backlash(backlash, thickening: float, module: float, centre_distance: float, pressure_angle: float):
    """The backlash a pair is cut for: ``backlash`` if given (mm, >= 0), else twice a cutter's own
    ``thickening`` if it has one, else :func:`design_backlash`. Stating it both ways is an error."""
    if backlash is None:
        if thickening != 0:
            return 2 * float(thickening)
        return design_backlash(module, centre_distance, pressure_angle)
    j = check_number("backlash", backlash, 0.0, float(module), high_open=True, unit="mm")
    if thickening != 0 and abs(2 * thickening - j) > 1e-12:
        raise SpecError(
            f"backlash = {j!r} mm and cutter thickening = {thickening!r} mm state the play twice; give the backlash "
            "and leave the cutter's thickening 0"
        )
    return j


def backlash_band(pair, backlash: float, tolerance: float = WIRE_EDM_TOLERANCE, n: int = 2048) -> tuple[float, float]:
    """Band (mm at the driven pitch point) the measured backlash must stay in over the cycle.

    Lower end: the :func:`tolerance_budget` (0 for a zero-backlash pair); upper end: the target
    grown by the driven pitch curve's largest pressure deviation ν,
    ``j / cos ν_max · BAND_FACTOR + BAND_SLACK_MM``.
    """
    psi = 2 * math.pi * np.arange(n) / n
    return band_of(backlash, float(np.max(np.abs(pair.driven.pressure_deviation(psi)))), tolerance)


def band_of(backlash: float, nu: float, tolerance: float = WIRE_EDM_TOLERANCE) -> tuple[float, float]:
    """The band of :func:`backlash_band` for a driven pitch curve whose largest pressure deviation
    is ``nu`` (rad): what an incomplete pair's sectors are held to as well."""
    j = float(backlash)
    low = tolerance_budget(tolerance) if j > 0 else 0.0
    return low, j / math.cos(nu) * BAND_FACTOR + BAND_SLACK_MM
