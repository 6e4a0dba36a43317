"""Wire start holes are in the scrap: every START_HOLES circle of every shipped DXF lies inside a
hole of the part, at least START_HOLE_MARGIN_MM from every cut contour measured on the exact
arcs — regression for start holes placed from the arc-fit vertices without their bulges (58 of
72 sat 0.02-0.07 mm inside the hole contour: the wire cut ~0.45 mm into the part at every pin)."""

import io

import ezdxf
import numpy as np
import shapely

from transplanter.shop import dxf
from transplanter.shop.dxf import START_HOLE_MARGIN_MM


def _contours_and_start_holes(data: bytes):
    """The outline's contours as exact arcs (bulges flattened to 0.01 µm) and the START_HOLES
    circles, from one reading of the file."""
    msp = ezdxf.read(io.StringIO(data.decode())).modelspace()
    verts = [
        list(e.get_points("xyb"))
        if e.dxftype() == "LWPOLYLINE"
        else [(v.dxf.location.x, v.dxf.location.y, v.dxf.bulge) for v in e.vertices]
        for e in msp.query("LWPOLYLINE POLYLINE")
        if e.dxf.layer in dxf.OUTLINES
    ]
    rings = [shapely.LinearRing(dxf.arcs_to_points(v, 1e-5)) for v in verts]
    holes = msp.query("CIRCLE[layer=='START_HOLES']")
    return rings, [(c.dxf.center.x, c.dxf.center.y, c.dxf.radius) for c in holes]


def test_every_start_hole_is_in_the_scrap(built):
    checked = 0
    for path in sorted(built.rglob("*.dxf")):
        if path.name.endswith("assembly.dxf") or b"\nTURN\n" in path.read_bytes():  # a lathe's part: no wire
            continue
        rings, circles = _contours_and_start_holes(path.read_bytes())
        outer = max(rings, key=lambda r: shapely.Polygon(r).area)
        for x, y, r in circles:
            p = shapely.Point(x, y)
            inside = [ring for ring in rings if ring is not outer and shapely.Polygon(ring).contains(p)]
            assert len(inside) == 1, f"{path.name}: start hole at ({x:.3f}, {y:.3f}) is not in one hole"
            room = min(float(shapely.distance(p, ring)) for ring in rings)
            assert room >= r + START_HOLE_MARGIN_MM - 1e-6, f"{path.name}: start hole at ({x:.3f}, {y:.3f}): {room:.4f}"
            checked += 1
    assert checked > 50


def test_a_round_hole_of_few_arcs_gets_its_start_hole_at_its_centre():
    # a 4.025 mm hole drawn as two half-circle bulges (the vertices alone are a sliver)
    verts = np.array([[4.025, 0.0, 1.0], [-4.025, 0.0, 1.0]])
    x, y = dxf.start_hole(verts, 1.0)
    assert abs(x) < 1e-3 and abs(y) < 1e-3


def test_no_start_hole_where_none_fits_says_so():
    verts = np.array([[0.5, 0.0, 1.0], [-0.5, 0.0, 1.0]])  # a 1 mm hole: no 1 mm start hole fits
    note = dxf.start_hole(verts, 1.0)
    assert isinstance(note, str) and note.startswith("NO START HOLE") and "1.000 mm" in note
