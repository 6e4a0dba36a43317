"""3D solids of gears, ring gears and cams by manifold3d Boolean subtraction.

A part is prismatic: a *blank* section extruded to the face width, minus the extruded *cuts*
(tooth spaces, the ring's tip region), a bore with a standard keyway (DIN 6885-1 / ISO 773
hub depth ``t2``), lightening holes or a bolt circle. The same features are also subtracted
in 2D (shapely), giving the section that goes to DXF and the reference the solid is checked
against: a valid manifold (``status() == NoError``) whose volume equals section area × face
width within 1e-6 relative.

Round features are polygons whose chords stay within ``CHORD`` (0.25 µm) of the circle, and
the identical polygons are used in 2D and 3D, so the section and the solid agree exactly.

Examples
--------
>>> import shapely
>>> from transplanter.shop.solids import Features, part_section, part_solid, key_for
>>> key_for(20.0)
Key(width=6.0, height=6.0, hub_depth=2.8)
>>> blank = shapely.Point(0, 0).buffer(40.0, 256)
>>> f = Features(bore=20.0, keyway=True)
>>> sec = part_section(blank, shapely.Polygon(), f)
>>> solid = part_solid(blank, shapely.Polygon(), f, width=10.0)
>>> abs(solid.volume() / (sec.area * 10.0) - 1) < 1e-6
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import manifold3d
import numpy as np
import shapely

from transplanter.core.errors import MAX_MAGNITUDE, GeometryError, SpecError, check_number, finite_positive

__all__ = ["Key", "key_for", "Features", "circle_polygon", "part_section", "part_solid", "check_solid"]

CHORD = 0.25e-3  # mm

#: DIN 6885-1 parallel keys: shaft diameter range (over, up to], key b x h, hub keyway depth t2 (mm)
KEYS = (
    (6, 8, 2, 2, 1.0),
    (8, 10, 3, 3, 1.4),
    (10, 12, 4, 4, 1.8),
    (12, 17, 5, 5, 2.3),
    (17, 22, 6, 6, 2.8),
    (22, 30, 8, 7, 3.3),
    (30, 38, 10, 8, 3.3),
    (38, 44, 12, 8, 3.3),
    (44, 50, 14, 9, 3.8),
    (50, 58, 16, 10, 4.3),
    (58, 65, 18, 11, 4.4),
    (65, 75, 20, 12, 4.9),
    (75, 85, 22, 14, 5.4),
    (85, 95, 25, 14, 5.4),
    (95, 110, 28, 16, 6.4),
    (110, 130, 32, 18, 7.4),
)


@dataclass(frozen=True)
class Key:
    """Parallel key: width b, height h and the hub keyway depth t2 (mm)."""

    width: float
    height: float
    hub_depth: float


def key_for(bore: float) -> Key:
    """The DIN 6885-1 key for a shaft of diameter ``bore`` (mm, 6 < d <= 130)."""
    d = finite_positive("bore", bore)
    for lo, hi, b, h, t2 in KEYS:
        if lo < d <= hi:
            return Key(float(b), float(h), float(t2))
    raise SpecError.out_of_range("bore", bore, "6 < d <= 130 mm for a DIN 6885-1 key")


def circle_polygon(cx: float, cy: float, r: float) -> shapely.Polygon:
    """Circle as a polygon whose chords are within CHORD of it (counter-clockwise)."""
    n = max(16, int(math.ceil(math.pi / math.acos(max(-1.0, 1 - CHORD / r)))))
    a = 2 * math.pi * np.arange(n) / n
    return shapely.Polygon(np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], axis=1))


@dataclass(frozen=True)
class Features:
    """Holes in a part, mm.

    Parameters
    ----------
    bore : float or None
        Shaft diameter at the rotation centre (origin).
    keyway : bool
        Cut the DIN 6885-1 hub keyway for ``bore`` (towards +y).
    holes : tuple of (x, y, diameter)
        Extra round holes (lightening holes, bolt circle).
    notches : tuple of (x, y, diameter)
        Round notches centred on the part's edge (a ring's timing mark): cut like holes, but
        meant to break out of the outline.
    """

    bore: float | None = None
    keyway: bool = True
    holes: tuple[tuple[float, float, float], ...] = ()
    notches: tuple[tuple[float, float, float], ...] = ()

    def __post_init__(self) -> None:
        if self.bore is not None:
            finite_positive("bore", self.bore)
            if self.keyway:
                key_for(self.bore)
        for x, y, dia in self.holes + self.notches:
            check_number("hole centre x", x, -MAX_MAGNITUDE, MAX_MAGNITUDE, unit="mm")
            check_number("hole centre y", y, -MAX_MAGNITUDE, MAX_MAGNITUDE, unit="mm")
            finite_positive("hole diameter", dia)

    @classmethod
    def bolt_circle(cls, n: int, radius: float, diameter: float, bore: float | None = None, keyway: bool = True):
        """``n`` holes of ``diameter`` on a circle of ``radius`` (mm), the first on +x."""
        if not isinstance(n, int) or n < 1:
            raise SpecError.out_of_range("bolt circle holes", n, "an integer >= 1")
        a = 2 * math.pi * np.arange(n) / n
        holes = tuple((float(radius * math.cos(t)), float(radius * math.sin(t)), float(diameter)) for t in a)
        return cls(bore=bore, keyway=keyway, holes=holes)

    def cuts(self) -> list[shapely.Polygon]:
        """The feature holes as polygons."""
        out = []
        if self.bore is not None:
            r = self.bore / 2
            out.append(circle_polygon(0.0, 0.0, r))
            if self.keyway:
                k = key_for(self.bore)
                # hub keyway: b wide, from the axis to t2 beyond the bore at +y; its bottom
                # corners rounded by 0.08 b (DIN 6885 allows it) so a wire can cut them
                rk = 0.08 * k.width
                box = shapely.box(-k.width / 2, 0.0, k.width / 2, r + k.hub_depth)
                out.append(box.buffer(-rk, join_style="mitre").buffer(rk, quad_segs=32))
        out.extend(circle_polygon(x, y, d / 2) for x, y, d in self.holes + self.notches)
        return out


#: thinnest wall (mm) left between a feature hole (bore, keyway, holes) and the part's edge or
#: another hole: below it a wire-cut web tears or warps
MIN_WALL = 0.5


def _check_features(blank, cuts, features: Features, holes: list[shapely.Polygon]) -> None:
    """GeometryError naming the feature that breaks out of the part or leaves a wall < MIN_WALL;
    ``holes`` are ``features.cuts()``."""
    material = shapely.difference(blank, cuts)
    edge = material.boundary
    named = []
    if features.bore is not None:
        k = 2 if features.keyway else 1
        label = f"the bore (dia {features.bore:g} mm{' with its keyway' if features.keyway else ''})"
        named.append((label, shapely.union_all(holes[:k]), True))
        holes = holes[k:]
    named += [
        (f"the hole at ({x:g}, {y:g}) mm (dia {d:g} mm)", h, False)
        for (x, y, d), h in zip(features.holes, holes[: len(features.holes)], strict=True)
    ]
    notches = [
        (f"the notch at ({x:g}, {y:g}) mm (dia {d:g} mm)", h, None)
        for (x, y, d), h in zip(features.notches, holes[len(features.holes) :], strict=True)
    ]
    for k, (name, hole, is_bore) in enumerate(named + notches):
        if is_bore is None:  # a notch breaks out by design; only its distance to the others counts
            continue
        inside = material.contains(hole)
        wall = float(shapely.distance(hole, edge)) if inside else 0.0
        if wall < MIN_WALL:
            if is_bore and not material.contains(circle_polygon(0.0, 0.0, features.bore / 2 + MIN_WALL)):
                reach = float(shapely.distance(shapely.Point(0.0, 0.0), edge))
                what = f"does not fit: the part reaches only {reach:.3g} mm from the axis"
            elif is_bore:
                what = "breaks through the hub with its keyway" if not inside else f"leaves a wall of {wall:.3g} mm"
            else:
                what = "breaks out of the part" if not inside else f"leaves a wall of {wall:.3g} mm"
            raise GeometryError(f"{name} {what} (limit: a wall of {MIN_WALL:g} mm); make it smaller or move it")
        for other_name, other, _ in (named + notches)[k + 1 :]:
            gap = float(shapely.distance(hole, other))
            if gap < MIN_WALL:
                raise GeometryError(f"{name} and {other_name} leave a wall of {gap:.3g} mm (limit {MIN_WALL:g} mm)")


def part_section(blank, cuts, features: Features) -> shapely.Polygon:
    """2D section: blank minus cuts minus the feature holes (one polygon, may have holes).

    Every feature hole must lie inside the part with a wall of at least MIN_WALL (a keyway
    breaking through a thin hub, or a bore wider than the part, is an error naming it)."""
    holes = features.cuts()
    _check_features(blank, cuts, features, holes)
    section = shapely.difference(blank, shapely.union_all([cuts, *holes]))
    if not isinstance(section, shapely.Polygon) or section.is_empty:
        raise GeometryError(
            "the bore, keyway or holes cut the part apart or leave nothing: make them smaller or move them"
        )
    return section


def _cross_section(geom) -> manifold3d.CrossSection:
    polys = []
    for g in getattr(geom, "geoms", [geom]):
        if g.is_empty:
            continue
        g = shapely.geometry.polygon.orient(g, 1.0)
        polys.append(np.asarray(g.exterior.coords)[:-1])
        polys.extend(np.asarray(r.coords)[:-1] for r in g.interiors)
    return manifold3d.CrossSection(polys, manifold3d.FillRule.EvenOdd) if polys else manifold3d.CrossSection()


def part_solid(blank, cuts, features: Features, width: float, hub: tuple[float, float] | None = None):
    """manifold3d solid: extruded blank (plus an optional hub ``(diameter, length)`` on the back face)
    minus the extruded cuts and feature holes, all by 3D Boolean subtraction."""
    w = finite_positive("face width", width)
    body = manifold3d.Manifold.extrude(_cross_section(blank), w)
    depth = w
    if hub is not None:
        dia, length = (finite_positive(n, v) for n, v in zip(("hub diameter", "hub length"), hub, strict=True))
        collar = manifold3d.Manifold.extrude(_cross_section(circle_polygon(0.0, 0.0, dia / 2)), length)
        body = body + collar.translate((0.0, 0.0, -length))
        depth = w + length
    tools = shapely.union_all([cuts, *features.cuts()])
    solid = body
    if not tools.is_empty:  # (extruding nothing is an invalid construction in manifold3d)
        tool = manifold3d.Manifold.extrude(_cross_section(tools), depth + 2.0)
        solid = body - tool.translate((0.0, 0.0, -(depth - w) - 1.0))
    check_solid(solid)
    return solid


def check_solid(solid) -> None:
    """GeometryError unless the manifold is valid and not empty."""
    status = solid.status()
    if status != manifold3d.Error.NoError:
        raise GeometryError(f"the solid is not a valid manifold: {status}")
    if solid.is_empty() or solid.volume() <= 0:
        raise GeometryError("the solid is empty")
