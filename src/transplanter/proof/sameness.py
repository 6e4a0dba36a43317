"""Two files of one part, the same section within a certified distance: a proof carried from one to the other.

A gear pair ships its teeth three times: the outline the design drew (CSV), the DXF a wire shop
cuts and the STL a printer makes. They describe one section up to the DXF's arc fit (within
``DXF_READBACK_MM`` of the outline) and the STL's float32. Meshing each of them anew repeats the
same proof on the same curve (issue 46); instead, the pair is meshed once, on the DXF as re-read,
and :func:`within` certifies how far each other file's teeth lie from the DXF's:

- ``r`` such that each file's *material near the teeth* lies inside the other's grown by ``r``
  (both ways). The material near the teeth is the gear's outer contour filled for an external
  gear, and everything outside the toothed hole for a ring (the bores and bolt holes, far from
  the teeth, are not compared: the outline CSV has none).
- Growing is GEOS's offset (``buffer``); its round joins are chords *inside* the true offset's
  arcs, so a region inside the grown one is inside the true ``r``-neighbourhood: the figure is an
  upper bound, never a sample's.
- ``r`` is the smallest rung of a doubling ladder (0.125 µm up) that holds, found by bisection
  (containment only gets easier as ``r`` grows).

What it carries (:class:`~transplanter.families.pairs.pair_proof.PairProof`): placed as the proved
pair is at every position of its proof, the other files' gears are no closer than the proved
clearance less the two gears' ``r``; so a positive remainder proves they never overlap there.

>>> import shapely
>>> a = shapely.Polygon([(0, 0), (10, 0), (10, 10), (0, 10)])
>>> b = shapely.Polygon([(0, 0), (10.0003, 0), (10.0003, 10), (0, 10)])
>>> within(a, b, False) * 1000  # 0.3 µm apart: the 0.5 µm rung
0.5
>>> within(a, shapely.Polygon([(0, 0), (11, 0), (11, 10), (0, 10)]), False) is None  # 1 mm: beyond the ladder
True
"""

from __future__ import annotations

import shapely

__all__ = ["LADDER_MM", "teeth_region", "within"]

#: the distances certified, mm: 0.125 µm doubling to 16 µm (the DXF's arc fit keeps within 1 µm)
LADDER_MM = tuple(0.125e-3 * 2**k for k in range(8))


def teeth_region(section: shapely.Polygon, internal: bool) -> shapely.Polygon:
    """A gear's material near its teeth: its outer contour filled (external), or the band from its
    toothed hole (the longest of its holes) out to a rim 5 mm beyond it (a ring)."""
    if not internal:
        return shapely.Polygon(section.exterior)
    if not section.interiors:
        raise ValueError("a ring's section has no toothed hole")
    hole = max(section.interiors, key=lambda r: r.length)
    xmin, ymin, xmax, ymax = shapely.bounds(hole)
    rim = shapely.box(xmin - 5.0, ymin - 5.0, xmax + 5.0, ymax + 5.0)
    return shapely.Polygon(rim.exterior.coords, [hole.coords])


def within(a: shapely.Polygon, b: shapely.Polygon, internal: bool, ladder=LADDER_MM) -> float | None:
    """The smallest rung ``r`` of ``ladder`` (mm) at which each section's material near the teeth
    (:func:`teeth_region`) lies inside the other's grown by ``r``; None if none does."""
    ta, tb = teeth_region(a, internal), teeth_region(b, internal)

    def holds(r: float) -> bool:
        return bool(shapely.covers(shapely.buffer(tb, r), ta) and shapely.covers(shapely.buffer(ta, r), tb))

    lo, hi = 0, len(ladder) - 1
    if not holds(ladder[hi]):
        return None
    while lo < hi:
        mid = (lo + hi) // 2
        if holds(ladder[mid]):
            hi = mid
        else:
            lo = mid + 1
    return ladder[lo]
