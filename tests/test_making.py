"""Solids, DXF and STL: every export re-reads within 1 µm, is watertight and has the right volume.

Tolerances: DXF read-back 1 µm (the issue's limit; arcs are fitted within 0.5 µm of contour
points that are themselves within 0.25 µm of the envelope); STL volume 1e-6 relative (the mesh
is the exact polygon section extruded: only float round-off, ~1e-9, separates them).
"""

import math

import numpy as np
import pytest
import shapely

from transplanter.app.testing import admesh_available, assert_admesh_clean
from transplanter.core.errors import GeometryError, SpecError
from transplanter.families import Making
from transplanter.families.builder.making import manufacture
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pair_gate import generate_pair
from transplanter.geometry.pitch import GearPair, PitchCurve
from transplanter.geometry.teeth import generate
from transplanter.shop import arcs, dxf, machining, solids, stl


@pytest.fixture(scope="module")
def ellipse_gears():
    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(40.0, 0.2, 2), "external", 2).sized(module=2.0)
    return generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth, backlash=0.0)


def test_arc_fit_beats_segments_like_the_anchor():
    # ANCHORS: an ellipse-like pitch curve (r ~ 30 mm) needs 472 segments at 1 µm
    t = np.linspace(0, 2 * np.pi, 20000, endpoint=False)
    ell = np.stack([34 * np.cos(t), 26 * np.sin(t)], axis=1)
    verts = arcs.fit_arcs(ell, tolerance=1e-3)
    assert len(verts) < 472 // 3
    assert dxf.contour_deviation(ell, dxf.arcs_to_points(verts)) < 1.05e-3
    # tangent continuity: each arc ends in the direction the next one starts
    pts = dxf.arcs_to_points(verts, 1e-6)
    seg = np.diff(np.vstack([pts, pts[:1]]), axis=0)
    turn = np.abs(np.angle(np.exp(1j * np.diff(np.arctan2(seg[:, 1], seg[:, 0])))))
    assert turn.max() < 0.01


def _bulge_points_per_vertex(verts, sagitta):
    """arcs.bulge_points as it was written first: numpy at every vertex (the reference it keeps to the bit)."""
    out = []
    for k in range(len(verts)):
        p0, p1, b = verts[k, :2], verts[(k + 1) % len(verts), :2], verts[k, 2]
        out.append(p0[None])
        if b == 0.0:
            continue
        theta = 4.0 * math.atan(b)
        chord = p1 - p0
        c = math.hypot(*chord)
        r = c / (2.0 * math.sin(theta / 2))
        centre = (p0 + p1) / 2 + np.array([-chord[1], chord[0]]) / c * r * math.cos(theta / 2)
        steps = max(1, math.ceil(abs(theta) / (2 * math.acos(max(-1.0, 1 - sagitta / abs(r))))))
        a = math.atan2(p0[1] - centre[1], p0[0] - centre[0]) + theta * np.arange(1, steps) / steps
        out.append(np.stack([centre[0] + abs(r) * np.cos(a), centre[1] + abs(r) * np.sin(a)], axis=1))
    return np.concatenate(out)


def test_bulge_points_are_the_per_vertex_formula_to_the_bit_and_within_the_sagitta():
    rng = np.random.default_rng(7)
    t = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    verts = arcs.fit_arcs(np.stack([34 * np.cos(t), 26 * np.sin(t)], axis=1), tolerance=1e-3)
    bulges = np.where(rng.random(60) < 0.3, 0.0, rng.uniform(-1, 1, 60))  # lines and arcs up to half circles
    mixed = np.column_stack((rng.uniform(-50, 50, (60, 2)), bulges))
    for v, sagitta in ((verts, 1e-3), (verts, 1e-4), (mixed, 1e-3), (np.array([[1.0, 2.0, 0.0]]), 1e-3)):
        got = arcs.bulge_points(v, sagitta)
        assert got.shape == _bulge_points_per_vertex(v, sagitta).shape
        assert got.tobytes() == _bulge_points_per_vertex(v, sagitta).tobytes()
    # every chord of the ellipse's arcs within the sagitta of the fitted curve it samples
    assert dxf.contour_deviation(dxf.arcs_to_points(verts, 1e-6), arcs.bulge_points(verts, 1e-4)) < 1.01e-4


def _dxf_points_per_arc(verts, flatten):
    """dxf.read_contours' points as they were written first: numpy per arc, each a clockwise
    arc's points walked back (the reference ``dxf._bulge_points`` keeps to the bit)."""
    from ezdxf.math import bulge_to_arc

    out = []
    for k in range(len(verts)):
        x0, y0, b = verts[k]
        x1, y1, _ = verts[(k + 1) % len(verts)]
        out.append((x0, y0))
        if b == 0:
            continue
        centre, a0, a1, r = bulge_to_arc((x0, y0), (x1, y1), b)
        sweep = (a1 - a0) % (2 * math.pi)
        steps = max(1, int(math.ceil(sweep / (2 * math.acos(max(-1.0, 1 - flatten / r))))))
        ang = a0 + sweep * np.arange(1, steps) / steps
        pts = np.stack([centre.x + r * np.cos(ang), centre.y + r * np.sin(ang)], axis=1)
        out.extend(pts[::-1] if b < 0 else pts)
    return np.array(out)


def test_a_dxfs_arcs_are_read_as_the_per_arc_formula_to_the_bit():
    """Every arc of a contour sampled at once (``arcs.with_arcs``) gives the points a loop over the
    arcs gave, to the bit — clockwise arcs (negative bulges) walked back, lines, half circles — and a
    bulge on a segment of no length (a damaged drawing) is no arc, not a division by zero."""
    rng = np.random.default_rng(11)
    t = np.linspace(0, 2 * np.pi, 3000, endpoint=False)
    fitted = arcs.fit_arcs(np.stack([30 * np.cos(t), 22 * np.sin(t)], axis=1), tolerance=1e-3)
    bulges = np.where(rng.random(80) < 0.3, 0.0, rng.uniform(-1, 1, 80))
    mixed = np.column_stack((rng.uniform(-50, 50, (80, 2)), bulges))
    for verts in (fitted, fitted * [1, 1, -1], mixed):
        for flatten in (1e-5, 5e-5, 1e-3):
            got, want = dxf._bulge_points(verts, flatten), _dxf_points_per_arc(verts, flatten)
            assert got.shape == want.shape and got.tobytes() == want.tobytes()
    flat = np.array([[0.0, 0.0, 0.5], [0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]])
    assert dxf._bulge_points(flat, 1e-5).tolist() == flat[:, :2].tolist()


@pytest.mark.parametrize("version", ["R2000", "R12"])
def test_gear_dxf_reads_back_within_1um(ellipse_gears, version):
    gear = ellipse_gears[0]
    section = solids.part_section(gear.blank, gear.cut, solids.Features(bore=16.0))
    data = dxf.dxf_bytes(dxf.DxfPart("g", section, ("40 teeth",)), version)
    assert data == dxf.dxf_bytes(dxf.DxfPart("g", section, ("40 teeth",)), version)  # byte-identical
    text = data.decode()
    assert ("$INSUNITS\n 70\n4" in text) == (version == "R2000")
    back = dxf.read_contours(data)
    assert len(back) == 2  # toothed outline and the bore with its keyway
    for src in (np.asarray(section.exterior.coords), np.asarray(section.interiors[0].coords)):
        assert min(dxf.contour_deviation(src, b) for b in back) < 1e-3
    for b in back:
        assert shapely.LinearRing(b).is_simple  # no self-intersections
    verts = arcs.fit_arcs(np.asarray(section.exterior.coords), 0.5e-3)
    spacing = np.linalg.norm(np.roll(verts[:, :2], -1, axis=0) - verts[:, :2], axis=1)
    assert spacing.min() >= 1e-3  # no segment shorter than 1 µm
    assert "START_HOLES" in text and "ANNOTATION" in text


def test_wire_compensated_dxf(ellipse_gears):
    gear = ellipse_gears[0]
    section = solids.part_section(gear.blank, gear.cut, solids.Features(bore=16.0))
    data = dxf.dxf_bytes(dxf.DxfPart("g", section, wire_offset=0.145))
    back = sorted(dxf.read_contours(data), key=len)
    outer, hole = shapely.Polygon(back[-1]), shapely.Polygon(back[0])
    assert outer.area > shapely.Polygon(section.exterior).area  # outer contour moved out
    assert hole.area < shapely.Polygon(section.interiors[0]).area  # the bore's path moved in


def test_hub_adds_its_collar():
    blank = shapely.Point(0, 0).buffer(40.0, 256)
    f = solids.Features(bore=20.0)
    plain = solids.part_solid(blank, shapely.Polygon(), f, 10.0)
    hub = solids.part_solid(blank, shapely.Polygon(), f, 10.0, hub=(36.0, 8.0))
    collar = solids.part_section(solids.circle_polygon(0, 0, 18.0), shapely.Polygon(), f).area * 8.0
    assert hub.volume() - plain.volume() == pytest.approx(collar, rel=1e-6)


def test_stl_is_watertight_with_the_section_volume(ellipse_gears, tmp_path):
    gear = ellipse_gears[1]
    f = solids.Features(bore=16.0)
    section = solids.part_section(gear.blank, gear.cut, f)
    solid = solids.part_solid(gear.blank, gear.cut, f, width=8.0)
    data = stl.stl_bytes(solid)
    assert data == stl.stl_bytes(solids.part_solid(gear.blank, gear.cut, f, width=8.0))
    rep = stl.mesh_report(data)
    assert rep.watertight and rep.winding_consistent and rep.outward
    assert rep.volume == pytest.approx(section.area * 8.0, rel=1e-6)
    if admesh_available():
        path = tmp_path / "gear.stl"
        path.write_bytes(data)
        assert_admesh_clean(path)


def test_ring_solid_and_bolt_circle():
    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(60.0, 0.05, 4), "internal", 1).sized(module=2.0)
    ring = generate(pair.driver, ShaperCutter(16, 2.0), sizing.teeth[0], internal=True, rim=14.0)
    r_root = float(np.max(np.linalg.norm(ring.toothed_contour, axis=1)))
    f = solids.Features.bolt_circle(6, r_root + 7.0, 5.0)
    section = solids.part_section(ring.blank, ring.cut, f)
    assert len(section.interiors) == 7
    solid = solids.part_solid(ring.blank, ring.cut, f, 10.0)
    assert solid.volume() == pytest.approx(section.area * 10.0, rel=1e-6)


def test_wire_violation_names_the_tooth(ellipse_gears):
    gear = ellipse_gears[0]
    # the 0.4 mm cutter tip rolls out root fillets of 0.6-0.7 mm radius (a trochoid is flatter
    # than the tip that makes it): a 1 mm wire reaches them, a 1.4 mm wire does not
    making = Making(width=5.0, wire=(1.4, 0.05), material="C45")
    with pytest.raises(GeometryError, match=r"g: an inside corner at tooth space \d+ is tighter than the wire radius"):
        manufacture("g", gear.blank, gear.cut, making, (), lambda pt: f"tooth space {gear.nearest_space(pt)}")
    manufacture("g", gear.blank, gear.cut, Making(width=5.0, wire=(1.0, 0.05), material="C45"), (), lambda pt: "?")
    res, files, _ = manufacture(
        "g", gear.blank, gear.cut, Making(width=5.0, step=False, material="C45"), (), lambda pt: "?"
    )
    assert set(files) == {"g.stl", "g.dxf"} and res["stl"]["watertight"] and "step" not in res


def test_wire_path_offsets_outwards_and_into_holes():
    sec = shapely.Polygon([(0, 0), (10, 0), (10, 10), (0, 10)], [[(4, 4), (6, 4), (6, 6), (4, 6)]])
    path = machining.wire_path(sec, 0.2)
    assert path.area > sec.area
    assert path.interiors[0].length < sec.interiors[0].length  # the hole shrinks


def test_keys_and_feature_errors():
    assert solids.key_for(12.0) == solids.Key(4.0, 4.0, 1.8)
    assert solids.key_for(30.0) == solids.Key(8.0, 7.0, 3.3)
    with pytest.raises(SpecError, match="DIN 6885"):
        solids.key_for(4.0)
    with pytest.raises(GeometryError, match=r"the bore \(dia 25 mm with its keyway\) does not fit"):
        solids.part_section(shapely.Point(0, 0).buffer(10), shapely.Polygon(), solids.Features(bore=25.0))


def test_dxf_and_stl_read_back_as_the_part_section(ellipse_gears):
    """The meshing check reads parts back from their files: a DXF's CUT contours nest into the
    section (holes stay holes) within the arc fit, an STL's mid-plane section within float32
    resolution (~1e-5 mm on a 50 mm part: symmetric difference ≲ perimeter × 1e-5 mm²)."""
    gear = ellipse_gears[0]
    f = solids.Features(bore=16.0)
    section = solids.part_section(gear.blank, gear.cut, f)
    back = dxf.read_section(dxf.dxf_bytes(dxf.DxfPart("g", section)))
    assert len(back.interiors) == len(section.interiors) == 1
    assert shapely.symmetric_difference(back, section).area < section.length * 1e-3
    cut = stl.section(stl.stl_bytes(solids.part_solid(gear.blank, gear.cut, f, width=8.0)))
    assert len(cut.interiors) == 1
    assert shapely.symmetric_difference(cut, section).area < section.length * 1e-5
    with pytest.raises(GeometryError, match="outside the solid"):
        stl.section(stl.stl_bytes(solids.part_solid(gear.blank, gear.cut, f, width=8.0)), z=9.0)
