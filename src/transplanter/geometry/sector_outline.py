"""The made outline of an incomplete gear: the wire's closing, specks dropped, and the contour on a
grid its files hold exactly — one valid polygon from the cut to the files the proof re-reads.

A sector gear is its blank less what the cutter and the driver's sweep remove
(:mod:`transplanter.geometry.incomplete`); a shop gets that body as the wire cuts it, written to
files (the outline CSV at nine decimals, DXF arcs, STL) that the proof reads back. Two rules keep
it one valid polygon all the way:

* the wire's **closing** (the body grown by the wire's radius and shrunk back) must hold the body,
  but GEOS's offsets fail on some outlines: the erosion comes back empty (``examples/dwells.csv``
  at module 4, 120 mm), or beside a speck (1.2e-8 mm², an invalid MultiPolygon:
  ``tests/data/dwells_speck.csv`` at module 4, 80 mm), or with a thin part shaved off. The body
  was then passed on as it was — off the grid, its corners not closed — and the files' rounding
  folded it (``driver_polygon must be a valid ... polygon`` from the proof on the outline; uniting
  the pieces back raises a GEOS TopologyException). A closing is taken only if it is one valid
  polygon (specks under ``SPECK_MM2`` dropped) that leaves out of the body no more than the
  chords' error (``CLOSING_SLACK_MM``); else it is offset again with fewer chords, then from the
  body snapped to the grid, and refused if none holds;
* the contour is **snapped to** ``GRID_MM`` (GEOS snap-rounding, valid by construction) after the
  vertices within ``SLIVER_MM`` of their neighbours' line are dropped; specks under ``SPECK_MM2``
  the grid splits off are dropped, and an outline that is still not one valid polygon on the grid
  is refused (:class:`~transplanter.core.errors.GeometryError`), never written off it.
"""

from __future__ import annotations

import shapely

from transplanter.core.errors import GeometryError

__all__ = [
    "CLOSING_SLACK_MM",
    "CORNER_RADIUS_MM",
    "GRID_MM",
    "SLIVER_MM",
    "SPECK_MM2",
    "largest",
    "made_of",
    "one_piece",
    "wire_cut",
]

#: the inside-corner radius the gears are given where sectors meet locking arcs and where the
#: sweep leaves corners: a 0.25 mm wire with its 0.02 mm spark gap, and a margin (mm)
CORNER_RADIUS_MM = 0.16
#: vertices closer than this to the outline through their neighbours are dropped after the wire's
#: closing (mm): far below the chord tolerance, far above float round-off
SLIVER_MM = 1e-6
#: the grid the made outlines are snapped to, mm: the outline CSV's nine decimals hold it exactly
GRID_MM = 1e-7
#: a piece the offsets or the grid leave beside an outline smaller than this is a speck, mm² (a 1 µm
#: square)
SPECK_MM2 = 1e-6
#: how much of the body a closing may leave out, mm² per mm of its outline: the offsets' chords
#: (64 a quarter turn) miss a 0.16 mm arc by 3e-6 mm
CLOSING_SLACK_MM = 1e-5


def made_of(body: shapely.Polygon) -> tuple[shapely.Polygon, shapely.Geometry]:
    """(blank, cut) whose 3D difference is ``body``: its outer contour extruded, less its holes —
    a ring's toothed hole cut from its rim disc. (A cut made as the blank less the body would
    share the tip lands with the blank to a nanometre: slivers in the mesh.)"""
    holes = [shapely.Polygon(r) for r in body.interiors]
    return shapely.Polygon(body.exterior), (shapely.union_all(holes) if holes else shapely.Polygon())


def wire_cut(body, radius: float):
    """``body`` as a wire of ``radius`` cuts it: inside corners tighter than the wire filled (the
    morphological closing ``machining.wire_violations`` measures), on the grid (module docstring);
    GeometryError when no closing holds the body."""
    if radius <= 0 or not isinstance(body, shapely.Polygon):
        return body
    closed = None
    # GEOS's offsets fail on some outlines (an empty erosion, a speck, a part shaved off): offset
    # again with fewer chords, then the body snapped to the grid, before giving up
    for attempt, quad_segs in ((body, 64), (body, 48), (shapely.set_precision(body, GRID_MM), 64)):
        closed = _closing(attempt, radius, quad_segs)
        if closed is not None:
            break
    if closed is None:
        raise GeometryError(
            f"the wire's closing ({radius:g} mm) of a gear's outline ({len(body.exterior.coords)} points) fails in "
            "GEOS: its offsets do not hold the outline"
        )
    # the offsets leave vertices nanometres apart, which a mesh writer would weld into slivers and
    # a file's rounding could fold: dropped, and the rest snapped to a grid far below the chord
    # tolerance (valid by construction; the CSV's nine decimals then hold it exactly)
    snapped = _without_specks(shapely.set_precision(shapely.simplify(closed, SLIVER_MM), GRID_MM))
    if not isinstance(snapped, shapely.Polygon) or snapped.is_empty or not snapped.is_valid:
        raise GeometryError(
            f"the gear's outline as the wire cuts it is not one polygon on the {GRID_MM:g} mm grid its files are "
            f"written to ({snapped.geom_type})"
        )
    return snapped


def _without_specks(geom):
    """``geom`` without the pieces under ``SPECK_MM2`` beside its one real piece."""
    if isinstance(geom, shapely.MultiPolygon):
        kept = [g for g in geom.geoms if g.area >= SPECK_MM2]
        return kept[0] if len(kept) == 1 else geom
    return geom


def _closing(body: shapely.Polygon, radius: float, quad_segs: int) -> shapely.Polygon | None:
    """The closing of ``body`` by ``radius`` if GEOS gives one that holds it: one valid polygon
    (specks aside) that leaves out of the body no more than ``CLOSING_SLACK_MM`` along its length
    (the chords' error); None otherwise."""
    try:
        closed = _without_specks(body.buffer(radius, quad_segs=quad_segs).buffer(-radius, quad_segs=quad_segs))
        if not isinstance(closed, shapely.Polygon) or closed.is_empty or not closed.is_valid:
            return None
        return closed if shapely.difference(body, closed).area <= CLOSING_SLACK_MM * body.length else None
    except shapely.errors.GEOSException:  # a TopologyException on what the offsets made
        return None


def one_piece(pre, sweep, module: float) -> bool:
    """Whether ``pre`` less one dwell's ``sweep`` is still one piece (specks aside)."""
    return isinstance(largest(shapely.difference(pre, sweep), module), shapely.Polygon)


def largest(body, module: float):
    """The body without specks the sweep left (pieces below 1e-3 m²)."""
    if isinstance(body, shapely.MultiPolygon):
        keep = [g for g in body.geoms if g.area >= 1e-3 * module**2]
        return keep[0] if len(keep) == 1 else shapely.MultiPolygon(keep)
    return body
