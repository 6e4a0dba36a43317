"""A seed-004 planting arm as two plates a shop cuts: the arm plate keyed to the planet's shaft and
the needle bolted to it, both drawn in the planet's DXF frame.

The arm of :class:`~transplanter.design.planetary.ArmGeometry` runs from the planet centre O1 to the
knee A (``H1``) and on, perpendicular to O1A, to the needle tip B (``S``), mounted at ``β`` from
the planet's body x-axis. As a designer draws it:

* the **arm plate** is the convex hull of three bosses — the hub around O1, a boss at the knee
  and one a ``tab`` further along the needle — with the planet's keyed bore (the keyway where the
  planet's is, so the key sets ``β``) and two tapped holes (M4, tap drill 3.3 mm) for the needle;
* the **needle** is a flat bar ``width`` wide from the knee to a point at B, with a bolting tab
  over the plate (two clearance holes, 4.5 mm) and the last ``point`` mm ground to the tip.

Both are drawn in the planet's frame (origin at O1, +x the planet's body x-axis), so the arm's
pose is the planet's and a judge places the plate and the needle with the planet's pose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from transplanter.core.errors import SpecError, check_number
from transplanter.design.planetary import ArmGeometry
from transplanter.shop.solids import circle_polygon

__all__ = ["ArmParts", "arm_parts", "TAP_DRILL_M4", "CLEARANCE_M4"]

#: M4 tap drill and clearance hole, mm (ISO 273 medium)
TAP_DRILL_M4 = 3.3
CLEARANCE_M4 = 4.5
#: radius of the needle's point, mm (its farthest point is the tip B)
TIP_RADIUS = 0.5
#: the needle's tab narrows to the bar over this many tab lengths
TAPER = 1.5


@dataclass(frozen=True)
class ArmParts:
    """The arm plate and the needle (sections, holes as (x, y, diameter)) in the planet's frame;
    the knee A, the tip B and the needle's direction, mm."""

    plate: shapely.Polygon
    plate_holes: tuple[tuple[float, float, float], ...]
    needle: shapely.Polygon
    needle_holes: tuple[tuple[float, float, float], ...]
    knee: tuple[float, float]
    tip: tuple[float, float]
    #: length of the plain bar from the tab's end to the tip, mm: what may enter the work
    bar: float = 0.0


def arm_parts(
    arm: ArmGeometry,
    hub: float = 16.0,
    boss: float = 9.0,
    tab: float = 20.0,
    width: float = 6.0,
    point: float = 12.0,
) -> ArmParts:
    """The plate and needle of ``arm`` (mm): hub and knee-boss radii, bolting-tab length along the
    needle, needle width and the length of its point (module docstring)."""
    check_number("hub radius", hub, 1.0, arm.knee, unit="mm")
    check_number("boss radius", boss, 1.0, arm.knee, unit="mm")
    needle_length = arm.needle_length
    check_number("needle width", width, 1.0, 2 * boss, unit="mm")
    check_number("tab", tab, 2 * CLEARANCE_M4, needle_length / 2, unit="mm")
    check_number("point", point, width / 2, needle_length - (1 + TAPER) * tab - boss, unit="mm")
    knee_dir = arm.mount + arm.knee_angle
    a = arm.knee * np.array([math.cos(knee_dir), math.sin(knee_dir)])
    b = arm.tip * np.array([math.cos(arm.mount), math.sin(arm.mount)])
    u = (b - a) / np.linalg.norm(b - a)
    n = np.array([-u[1], u[0]])
    t = a + tab * u
    plate = shapely.union_all([circle_polygon(0.0, 0.0, hub), circle_polygon(*a, boss), circle_polygon(*t, boss)])
    plate = shapely.convex_hull(plate)
    # the bolting tab tapers into the bar over TAPER tab lengths (no inside corner a wire cannot
    # cut: the bar leaves the taper at 180 deg less the taper's half angle)
    w = width / 2
    neck = t + TAPER * tab * u
    lug = shapely.convex_hull(
        shapely.union_all(
            [
                circle_polygon(*a, width),
                circle_polygon(*t, width),
                shapely.Point(neck + w * n),
                shapely.Point(neck - w * n),
            ]
        )
    )
    tip = circle_polygon(*(b - TIP_RADIUS * u), TIP_RADIUS)  # its point at B
    bar = shapely.convex_hull(
        shapely.union_all(
            [shapely.MultiPoint([neck + w * n, b - point * u + w * n, b - point * u - w * n, neck - w * n]), tip]
        )
    )
    needle = shapely.union(lug, bar).normalize()
    if not isinstance(needle, shapely.Polygon):
        raise SpecError(f"the needle of {arm} is not one piece")
    bolts = (a, t)
    return ArmParts(
        plate,
        tuple((float(p[0]), float(p[1]), TAP_DRILL_M4) for p in bolts),
        needle,
        tuple((float(p[0]), float(p[1]), CLEARANCE_M4) for p in bolts),
        (float(a[0]), float(a[1])),
        (float(b[0]), float(b[1])),
        float(np.linalg.norm(b - neck)),
    )
