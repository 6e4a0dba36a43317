"""Seed 002's carrier parts as a designer draws them: plates as the hull of bosses around their
shafts, the follower lever, sector gears trimmed from cut gears, the arm and its claw.

Every shape here is a plane section in the part's own frame (mm), the frame its DXF is drawn in
and its pose in the machine is given for (:mod:`transplanter.machine.carriers`):

* a **plate** (:func:`plate`): the convex hull of round bosses, one around each shaft, with the
  shafts' holes — carrier 1 (origin A0, +x to A_c), carrier 2 (origin A_c, +x to Q);
* the **follower lever** (:func:`lever`): origin at its pivot, +x to the roller's pin, a boss at
  each end and the pin's hole (the roller is a bought ball bearing);
* a **sector gear** (:func:`sector`): a cut gear's section kept over the angles its mesh uses plus
  ``margin`` pitches each side, each end in a tooth space (the radius' least near the end), the
  rest cut away down to a hub; the cut's inside corners rounded for the wire;
* the **arm** (:func:`arm`): link 3, origin Q, +x to the claw tip at ``length``: a plate from the
  hub to a boss where the claw is bolted, and the **claw** (the clamping tines' section, tapering
  to a rounded point at the tip).
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from transplanter.core.errors import GeometryError, check_number
from transplanter.shop.solids import circle_polygon

__all__ = ["plate", "lever", "sector", "arm", "claw", "ROUND_MM", "TIP_RADIUS_MM"]

#: inside corners of trimmed parts are rounded to this radius (> the wire's 0.145 mm), mm
ROUND_MM = 1.0
#: radius of the claw's point, mm
TIP_RADIUS_MM = 1.0


def plate(bosses: list[tuple[float, float, float]]) -> shapely.Polygon:
    """The convex hull of round bosses ``(x, y, radius)`` (mm)."""
    for boss in bosses:
        check_number("boss radius", boss[2], 1.0, 1000.0, unit="mm")
    return shapely.convex_hull(shapely.union_all([circle_polygon(x, y, r) for x, y, r in bosses])).normalize()


def lever(length: float, pivot_boss: float, pin_boss: float) -> shapely.Polygon:
    """The follower lever: pivot at the origin, the roller's pin ``length`` along +x (mm)."""
    check_number("lever length", length, pivot_boss + pin_boss, 10_000.0, unit="mm")
    return plate([(0.0, 0.0, pivot_boss), (length, 0.0, pin_boss)])


def sector(
    gear: shapely.Polygon, start: float, end: float, pitch: float, hub: float, margin: int = 3
) -> shapely.Polygon:
    """``gear`` (its section, origin at its axis) kept from body angle ``start`` to ``end`` (rad,
    the angles of the contacts its mesh uses) and ``margin`` pitches (``pitch``, rad) beyond each,
    each end moved into the nearest tooth space; cut away to a ``hub`` radius elsewhere."""
    if not end > start:
        raise GeometryError(f"a sector needs end > start, got {start:.4g}..{end:.4g} rad")
    xy = shapely.get_coordinates(gear.exterior)
    ang = np.arctan2(xy[:, 1], xy[:, 0])
    rad = np.hypot(xy[:, 0], xy[:, 1])

    def in_space(a: float) -> float:
        near = np.abs(np.angle(np.exp(1j * (ang - a)))) <= 0.5 * pitch
        k = np.flatnonzero(near)[np.argmin(rad[near])]
        return a + float(np.angle(np.exp(1j * (ang[k] - a))))

    lo, hi = in_space(start - margin * pitch), in_space(end + margin * pitch)
    if hi - lo >= 2 * math.pi - pitch:
        return gear
    far = 2.0 * float(rad.max())
    a = np.linspace(lo, hi, max(8, int(math.degrees(hi - lo))))
    wedge = shapely.Polygon([(0.0, 0.0), *zip(far * np.cos(a), far * np.sin(a), strict=True)])
    mask = shapely.union(wedge, circle_polygon(0.0, 0.0, hub)).buffer(ROUND_MM).buffer(-ROUND_MM)
    out = shapely.intersection(gear, mask)
    if not isinstance(out, shapely.Polygon):
        raise GeometryError("the sector falls apart: raise its hub radius")
    return out.normalize()


def arm(length: float, hub: float, boss: float, claw_at: float) -> shapely.Polygon:
    """Link 3's plate: origin Q, the claw's tip ``length`` along +x; a ``hub`` boss at Q and a
    ``boss`` at ``claw_at`` where the claw is bolted (mm)."""
    check_number("claw position", claw_at, hub + boss, length - boss, unit="mm")
    return plate([(0.0, 0.0, hub), (claw_at, 0.0, boss)])


def claw(length: float, start: float, width: float, tab: float) -> shapely.Polygon:
    """The claw's tines in the arm's frame: a bolting tab ``tab`` long and ``width`` wide from
    ``start`` along +x, tapering to a point of radius :data:`TIP_RADIUS_MM` at ``length`` (mm)."""
    check_number("claw width", width, 2 * TIP_RADIUS_MM, 100.0, unit="mm")
    check_number("claw tab", tab, width, length - start - width, unit="mm")
    w = width / 2
    body = shapely.box(start, -w, start + tab, w)
    tip = circle_polygon(length - TIP_RADIUS_MM, 0.0, TIP_RADIUS_MM)
    taper = shapely.convex_hull(shapely.union_all([shapely.box(start + tab - 1.0, -w, start + tab, w), tip]))
    out = shapely.union(body, taper).buffer(ROUND_MM).buffer(-ROUND_MM)
    return out.normalize()
