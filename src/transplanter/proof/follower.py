"""The cam follower run on the made contour: the follower is pressed onto the made cam contour at
each cam angle (roller followers: the roller position where it just touches the contour, by
``brentq``; flat-faced: the contour's support point) and its motion is compared with the
prescribed law.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely

from transplanter.core.errors import GeometryError, SpecError
from transplanter.core.precision import significant
from transplanter.geometry import cams, contact
from transplanter.proof.meshing import _polygon

__all__ = ["FollowerReport", "follower_check"]


@dataclass(frozen=True)
class FollowerReport:
    """Follower motion on the made cam contour against the prescribed law."""

    theta: np.ndarray = field(repr=False)
    prescribed: np.ndarray = field(repr=False)
    actual: np.ndarray = field(repr=False)
    #: error as displacement at the roller centre (or face), mm
    error: np.ndarray = field(repr=False)
    unit: str = "mm"

    @property
    def max_error(self) -> float:
        return float(np.max(np.abs(self.error)))

    def summary(self) -> dict:
        return {
            "samples": len(self.theta),
            "max_error_mm": significant(self.max_error),
            "rms_error_mm": significant(np.sqrt(np.mean(self.error**2))),
            "stroke": significant(np.ptp(self.prescribed), 6),
            "stroke_unit": self.unit,
        }


def _bracketed_roots(f, lo, hi, f_lo, f_hi, xtol: float, maxiter: int = 200) -> np.ndarray:
    """Roots of the vectorised ``f`` in the brackets [lo, hi] (f_lo <= 0 <= f_hi elementwise),
    to ``xtol``: the Illinois variant of regula falsi (superlinear like brentq's secant steps,
    and never leaving the bracket), every bracket at once."""
    lo, hi, f_lo, f_hi = (np.array(v, dtype=float) for v in (lo, hi, f_lo, f_hi))
    x = 0.5 * (lo + hi)
    side = np.zeros(lo.shape, dtype=np.int8)  # which end was kept last time: -1 lo, +1 hi
    for _ in range(maxiter):
        width = hi - lo
        if np.all(width <= xtol):
            break
        denom = f_hi - f_lo
        x = np.where(denom > 0, hi - f_hi * width / np.where(denom > 0, denom, 1.0), 0.5 * (lo + hi))
        x = np.where((x > lo) & (x < hi), x, 0.5 * (lo + hi))
        fx = f(x)
        up = fx > 0  # the root is below x: x becomes hi
        zero = fx == 0
        lo = np.where(zero, x, np.where(up, lo, x))
        hi = np.where(zero, x, np.where(up, x, hi))
        # Illinois: an end kept twice in a row has its value halved, so the next secant moves it
        f_lo = np.where(up & (side == -1), 0.5 * f_lo, np.where(up, f_lo, fx))
        f_hi = np.where(~up & (side == 1), 0.5 * f_hi, np.where(up, fx, f_hi))
        side = np.where(up, -1, 1).astype(np.int8)
    return np.where(hi - lo <= xtol, 0.5 * (lo + hi), x)


def follower_check(contour, motion, follower, n: int = 720) -> FollowerReport:
    """Press ``follower`` onto the made cam ``contour`` (shapely polygon, cam frame) at ``n``
    cam angles and compare its position with ``motion`` (the law the cam was designed for).

    Roller followers: the follower coordinate s at which the roller just touches the contour
    (signed roller-centre distance minus roller radius = 0, within ±10 % of the stroke plus
    1 mm of the law, to 1e-12; every cam angle at once, distances from an STRtree of the
    contour's segments). Flat-faced: the contour's support height minus the base
    radius. The cam turns counter-clockwise by θ (``cams`` conventions).
    """
    contour = _polygon("contour", contour)
    if not isinstance(n, int) or n < 8:
        raise SpecError.out_of_range("n", n, "an integer >= 8")
    theta = 2 * math.pi * np.arange(n) / n
    law = np.asarray(motion(theta), dtype=float)
    pts = shapely.get_coordinates(contour.exterior)
    if isinstance(follower, cams.FlatFacedFollower):
        # support height along the follower's +y, which is (sin θ, cos θ) in the cam frame
        actual = np.max(pts @ np.stack([np.sin(theta), np.cos(theta)]), axis=0) - follower.base_radius
        return FollowerReport(theta, law, actual, actual - law)
    if not isinstance(follower, cams.OscillatingRollerFollower | cams.TranslatingRollerFollower):
        raise SpecError(f"unknown follower type {type(follower).__name__}")
    rr = follower.roller_radius
    span = 0.1 * float(np.ptp(law)) + (1.0 / follower.arm_length if hasattr(follower, "arm_length") else 1.0)
    distance = contact.distance_to_ring(pts)
    shapely.prepare(contour)

    def gap(s):  # signed distance of the roller centres from the contour, minus the roller radius
        c = cams.roller_centre(follower, s, theta)
        d = distance(c)
        return np.where(shapely.contains_xy(contour, c[:, 0], c[:, 1]), -d, d) - rr

    lo, hi = law - span, law + span
    g_lo, g_hi = gap(lo), gap(hi)
    bad = (g_lo > 0) | (g_hi < 0)
    if bad.any():
        t = theta[int(np.argmax(bad))]
        raise GeometryError(
            f"the follower does not reach the cam contour near θ = {math.degrees(t):.1f} deg within ±{span:.3g} "
            "of the law — the contour is not this cam's"
        )
    actual = _bracketed_roots(gap, lo, hi, g_lo, g_hi, xtol=1e-12)
    err = actual - law
    unit = "mm"
    if isinstance(follower, cams.OscillatingRollerFollower):
        err = err * follower.arm_length  # swing error as displacement at the roller
        unit = "rad"
    return FollowerReport(theta, law, actual, err, unit)
