"""Shaper-cutter envelope teeth against exact involutes and the brute-force Boolean reference.

Tolerances: FLANK = 1 µm is the issue's accuracy target. Envelope points are exact to the
pitch-frame accuracy (< 1e-9 mm), the outline's chords are within CHORD_TOLERANCE (0.25 µm)
of the envelope, and the Boolean reference with 200 positions per pitch and 200 outline
points per profile piece is itself within ~0.02 µm, so 1 µm leaves margin on every side.
"""

import math

import numpy as np
import pytest
import shapely

from reference_teeth import boolean_reference, flank_deviation
from transplanter.core.errors import GeometryError, SpecError
from transplanter.families import run_script
from transplanter.geometry.contact import distance_to_ring
from transplanter.geometry.cutter import ShaperCutter, involute
from transplanter.geometry.pitch import Constant, GearPair, PitchCurve
from transplanter.geometry.teeth import CHORD_TOLERANCE, ArcFrame, generate

FLANK = 1e-3  # mm


def _space_width(z, m, x, internal, cutter):
    """Exact tooth-space width on the pitch circle of a circular gear cut by ``cutter``."""
    big_r, rc, al = z * m / 2, cutter.pitch_radius, cutter.pressure_angle
    sc = math.pi * m / 2 + cutter.thickening
    if internal:
        a = big_r - rc
        alp = math.acos(a * math.cos(al) / (a - x * m))
        return sc + 2 * (big_r - rc) * (involute(alp) - involute(al))
    a = big_r + rc
    alp = math.acos(a * math.cos(al) / (a + x * m))
    return sc - 2 * (big_r + rc) * (involute(alp) - involute(al))


def _involute_deviation(gear, z, m, x, internal, points_of):
    """Largest normal distance (mm) of points from the exact involute flanks of the gear."""
    big_r = z * m / 2
    al = gear.cutter.pressure_angle
    rb = big_r * math.cos(al)
    e = _space_width(z, m, x, internal, gear.cutter)
    worst = 0.0
    for sp in gear.spaces:
        pts = points_of(sp)
        rho = np.linalg.norm(pts, axis=1)
        d = np.angle(np.exp(1j * (np.arctan2(pts[:, 1], pts[:, 0]) - sp.s / big_r)))
        a_rho = np.arccos(np.clip(rb / rho, -1, 1))
        sign = -1 if internal else 1
        half = e / (2 * big_r) + sign * (involute(a_rho) - involute(al))
        worst = max(worst, float(np.max(np.abs(rb * (np.abs(d) - half)))))  # involutes are parallel: r_b Δθ
    return worst


def _to_boundary(polygon):
    """Each point's distance to the polygon's boundary — ``shapely.distance(boundary, points)`` —
    as the least of its distances to each ring, each found by the nearest segment in an STRtree
    (``contact.distance_to_ring``), not by GEOS trying every segment for every point: a function
    of the points ``(n, 2)``."""
    rings = [distance_to_ring(shapely.get_coordinates(r)) for r in shapely.get_rings(polygon)]
    return lambda xy: np.min([to_ring(xy) for to_ring in rings], axis=0)


def _surviving_flank_points(gear):
    to_boundary = _to_boundary(gear.polygon)

    def pick(sp):
        pts = np.concatenate([sp.lower, sp.upper])
        return pts[to_boundary(pts) < 1e-6]

    return pick


CIRCULAR = [
    (12, 0.45, False),
    (17, 0.0, False),
    (30, 0.3, False),
    (30, -0.25, False),
    (120, 0.0, False),
    (40, 0.0, True),
    (60, 0.3, True),
    (200, 0.0, True),
]


@pytest.mark.parametrize(("z", "x", "internal"), CIRCULAR)
def test_circular_gears_are_exact_involutes(z, x, internal):
    m = 2.0
    cutter = ShaperCutter(20, m, dedendum=1.6, thickening=0.05)
    gear = generate(PitchCurve.circle(z * m / 2), cutter, z, internal=internal, shift=x, allow_undercut=True)
    assert gear.polygon.is_valid and gear.teeth == z
    # the exact envelope points
    dev = _involute_deviation(gear, z, m, x, internal, _surviving_flank_points(gear))
    assert dev < 1e-9
    # the outline itself: exact involute points sampled densely, distance to the polygon boundary
    rb = z * m / 2 * math.cos(cutter.pressure_angle)
    to_boundary = _to_boundary(gear.polygon)
    sp = gear.spaces[z // 3]
    for flank in (sp.lower, sp.upper):
        on = flank[to_boundary(flank) < 1e-6]
        rho = np.linspace(np.linalg.norm(on, axis=1).min(), np.linalg.norm(on, axis=1).max(), 400)
        sgn = math.copysign(
            1.0, float(np.mean(np.angle(np.exp(1j * (np.arctan2(on[:, 1], on[:, 0]) - sp.s * 2 / (z * m))))))
        )
        e = _space_width(z, m, x, internal, cutter)
        a_rho = np.arccos(np.clip(rb / rho, -1, 1))
        half = e / (z * m) + (-1 if internal else 1) * (involute(a_rho) - involute(cutter.pressure_angle))
        ang = sp.s * 2 / (z * m) + sgn * half
        exact = np.stack([rho * np.cos(ang), rho * np.sin(ang)], axis=1)
        assert float(to_boundary(exact).max()) < CHORD_TOLERANCE + 1e-9


def test_cutter_profile_is_an_exact_involute():
    c = ShaperCutter(24, 1.5, thickening=0.02)
    tau = np.concatenate([np.linspace(1, 2, 101), np.linspace(5, 6, 101)])
    q, n, k = c.profile(tau)
    assert np.max(np.abs(np.abs(k) - c.base_radius)) < 1e-12  # normals tangent to the base circle
    rho = np.linalg.norm(q, axis=1)
    ang = np.abs(np.arctan2(q[:, 1], q[:, 0]))
    assert np.max(np.abs(ang - c.half_thickness_angle(rho))) < 1e-12
    # normals are unit and perpendicular to the profile everywhere, and the profile is continuous
    tau = np.linspace(0, 7, 7001)[1:-1]
    q, n, _ = c.profile(tau)
    h = 1e-7
    dq = (c.profile(np.clip(tau + h, 0, 7))[0] - c.profile(np.clip(tau - h, 0, 7))[0]) / (2 * h)
    dq /= np.linalg.norm(dq, axis=1)[:, None]
    assert np.max(np.abs(np.einsum("ij,ij->i", dq, n))) < 1e-5
    assert np.max(np.abs(np.linalg.norm(n, axis=1) - 1)) < 1e-15
    joints = np.arange(1, 7, dtype=float)
    left, right = c.profile(joints - 1e-13)[0], c.profile(joints + 1e-13)[0]
    assert np.max(np.linalg.norm(left - right, axis=1)) < 1e-9


def test_arc_frame_matches_the_exact_curve():
    curve = PitchCurve.ellipse(40.0, 0.4, 2)
    frame = ArcFrame.from_curve(curve)
    s = np.random.default_rng(1).uniform(0, frame.length, 500)
    p, t, nrm, kap = frame.at(s)
    phi = curve.angle_at_arc_length(s)
    assert np.max(np.linalg.norm(p - curve.points(phi), axis=1)) < 1e-10
    assert np.max(np.linalg.norm(t - curve.tangent(phi), axis=1)) < 1e-8
    assert np.max(np.linalg.norm(nrm - curve.normal(phi), axis=1)) < 1e-8
    assert np.max(np.abs(kap - curve.curvature(phi))) < 1e-6


@pytest.fixture(scope="module")
def ellipse_pair():
    pair = GearPair.from_driver(PitchCurve.ellipse(40.0, 0.2, 2), "external", 2)
    return pair.sized(module=2.0)


def test_ellipse_pair_against_boolean_reference(ellipse_pair):
    pair, sizing = ellipse_pair
    cutter = ShaperCutter(20, 2.0)
    for curve, z in ((pair.driver, sizing.teeth[0]), (pair.driven, sizing.teeth[1])):
        gear = generate(curve, cutter, z)
        spaces = [0, z // 4 + 1, z // 2 - 1]  # across the lobe: flat and pointed ends
        ref = boolean_reference(curve, cutter, z, 200, spaces=spaces, per_piece=200)
        assert flank_deviation(gear, ref, spaces) < FLANK
        assert gear.undercut == 0.0 and gear.tip_lands.min() > 0.2 * 2.0


def test_internal_non_circular_pair_against_boolean_reference():
    pair = GearPair.from_driver(PitchCurve.ellipse(60.0, 0.05, 4), "internal", 1)
    pair, sizing = pair.sized(module=2.0)
    cutter = ShaperCutter(16, 2.0)
    ring = generate(pair.driver, cutter, sizing.teeth[0], internal=True)
    assert isinstance(ring.polygon, shapely.Polygon) and len(ring.polygon.interiors) == 1
    ref = boolean_reference(pair.driver, cutter, sizing.teeth[0], 200, internal=True, spaces=[0, 7], per_piece=200)
    assert flank_deviation(ring, ref, [0, 7]) < FLANK
    planet = generate(pair.driven, cutter, sizing.teeth[1])
    ref = boolean_reference(pair.driven, cutter, sizing.teeth[1], 200, spaces=[0, 4], per_piece=200)
    assert flank_deviation(planet, ref, [0, 4]) < FLANK


@pytest.fixture(scope="module")
def seed004_pair(parts_dir):
    return run_script(parts_dir / "_seed004.py")["gear_pair"]()


def test_seed004_pair_at_the_published_module_cannot_be_cut(seed004_pair):
    pair, sizing = seed004_pair.sized(teeth=80)
    with pytest.raises(GeometryError, match=r"rolling radius 17.05 mm .* smallest convex radius of curvature 3.003 mm"):
        generate(pair.driver, ShaperCutter(12, sizing.module), sizing.teeth[0], internal=True)


def test_seed004_pair_at_a_fine_module(seed004_pair):
    """m = 0.406 mm (560/140 teeth): an 8-tooth cutter fits the 3 mm corners without secondary cutting."""
    pair, sizing = seed004_pair.sized(teeth=560)
    cutter = ShaperCutter(8, sizing.module, tip_fillet=0.1)
    ring = generate(pair.driver, cutter, sizing.teeth[0], internal=True)
    planet = generate(pair.driven, cutter, sizing.teeth[1])
    assert ring.undercut == 0.0 and planet.undercut == 0.0
    coarse, s2 = seed004_pair.sized(teeth=320)  # m = 0.71 mm: the same cutter cuts the ring twice
    with pytest.raises(GeometryError, match="secondary cutting"):
        generate(
            coarse.driver, ShaperCutter(8, s2.module, tip_fillet=0.1), s2.teeth[0], internal=True, allow_undercut=True
        )
    for gear, curve in ((ring, pair.driver), (planet, pair.driven)):
        corner = curve.max_curvature().angle  # the sharpest corner, where errors would show
        worst = int(
            np.argmin(
                np.abs(
                    np.angle(
                        np.exp(1j * (np.array([np.arctan2(*sp.pitch_point[::-1]) for sp in gear.spaces]) - corner))
                    )
                )
            )
        )
        spaces = [worst, (worst + gear.teeth // 2) % gear.teeth]
        ref = boolean_reference(curve, cutter, gear.teeth, 200, internal=gear.internal, spaces=spaces, per_piece=120)
        assert flank_deviation(gear, ref, spaces) < FLANK


def test_generation_errors_name_the_limit():
    m = 2.0
    with pytest.raises(GeometryError, match=r"perimeter .* != teeth \* π \* m"):
        generate(PitchCurve.circle(30.0), ShaperCutter(20, m), 31)
    with pytest.raises(GeometryError, match=r"undercut at tooth space \d+: 4\d\.\d µm"):
        generate(PitchCurve.circle(10.0), ShaperCutter(20, m), 10)
    with pytest.raises(GeometryError, match="pointed tooth"):
        generate(PitchCurve.circle(12.0), ShaperCutter(20, m, dedendum=2.0), 12, shift=0.9)
    with pytest.raises(GeometryError, match="secondary cutting"):
        generate(PitchCurve.circle(26.0), ShaperCutter(20, m), 26, internal=True)
    with pytest.raises(GeometryError, match="concave radius of curvature"):
        wavy = PitchCurve.from_fourier(40.0, (0.0, 0.0, 0.0, 3.5), (2.0,))
        pair, s = GearPair.from_driver(wavy, "external", 1).sized(module=2.0)
        generate(pair.driver, ShaperCutter(76, m), s.teeth[0])  # r_c = 76 mm > its 6x mm concave radius
    with pytest.raises(SpecError, match="teeth"):
        generate(PitchCurve.circle(5.0), ShaperCutter(20, m), 5)
    with pytest.raises(SpecError, match="cutter teeth"):
        ShaperCutter(4, m)
    with pytest.raises(GeometryError, match="pointed"):
        ShaperCutter(8, m, addendum=1.6)


# -- rack cutter (hob) ----------------------------------------------------------------------


@pytest.mark.parametrize(("z", "x"), [(12, 0.5), (17, 0.3), (30, 0.0), (60, -0.2)])
def test_rack_cut_circular_gears_are_exact_involutes(z, x):
    """A rack generates the exact involute of the gear's base circle; its space on the pitch
    circle is ``π m / 2 + thickening - 2 x m tan α``. Envelope points within 1e-9 mm, the
    outline within the chord tolerance (0.25 µm) of exact involute points."""
    from transplanter.geometry.cutter import RackCutter

    m = 2.0
    cutter = RackCutter(m, dedendum=1.6, thickening=0.05)
    gear = generate(PitchCurve.circle(z * m / 2), cutter, z, shift=x)
    assert gear.polygon.is_valid and gear.teeth == z and gear.undercut == 0.0
    big_r, al = z * m / 2, cutter.pressure_angle
    rb = big_r * math.cos(al)
    e = math.pi * m / 2 + cutter.thickening - 2 * x * m * math.tan(al)
    to_boundary, pick = _to_boundary(gear.polygon), _surviving_flank_points(gear)
    worst = 0.0
    for sp in gear.spaces:
        pts = pick(sp)
        rho = np.linalg.norm(pts, axis=1)
        d = np.angle(np.exp(1j * (np.arctan2(pts[:, 1], pts[:, 0]) - sp.s / big_r)))
        half = e / (2 * big_r) + involute(np.arccos(np.clip(rb / rho, -1, 1))) - involute(al)
        worst = max(worst, float(np.max(np.abs(rb * (np.abs(d) - half)))))
    assert worst < 1e-9
    sp = gear.spaces[z // 3]
    for flank in (sp.lower, sp.upper):
        on = flank[to_boundary(flank) < 1e-6]
        rho = np.linspace(np.linalg.norm(on, axis=1).min(), np.linalg.norm(on, axis=1).max(), 400)
        half = e / (2 * big_r) + involute(np.arccos(np.clip(rb / rho, -1, 1))) - involute(al)
        off = np.angle(np.exp(1j * (np.arctan2(on[:, 1], on[:, 0]) - sp.s / big_r)))
        ang = sp.s / big_r + math.copysign(1.0, float(np.mean(off))) * half
        exact = np.stack([rho * np.cos(ang), rho * np.sin(ang)], axis=1)
        assert float(to_boundary(exact).max()) < CHORD_TOLERANCE + 1e-9


def test_a_rack_cut_non_circular_pair_meshes_with_its_backlash():
    from transplanter.geometry.backlash import backlash_band
    from transplanter.geometry.cutter import RackCutter
    from transplanter.geometry.pair_gate import generate_pair
    from transplanter.proof import validate

    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(30.0, 0.1, 2), "external", 2).sized(module=2.0)
    driver, driven = generate_pair(pair, RackCutter(2.0), sizing.teeth, backlash=0.1)
    report = validate.mesh_check(pair, driver.polygon, driven.polygon, 2.0, steps=180, teeth=sizing.teeth[0])
    assert report.problems() == [] and report.max_penetration == 0.0
    low, high = backlash_band(pair, 0.1)
    assert low <= report.backlash.min() and report.backlash.max() <= high
    assert report.contact_ratio > 1.2


def test_a_rack_refuses_rings_and_concave_pitch_curves():
    from transplanter.geometry.cutter import RackCutter
    from transplanter.geometry.pair_gate import generate_pair

    ring_pair, ring = GearPair.from_driver(PitchCurve.ellipse(30.0, 0.05, 2), "internal", 3).sized(module=2.0)
    with pytest.raises(GeometryError, match="cannot cut a ring gear"):
        generate_pair(ring_pair, RackCutter(2.0), ring.teeth)
    concave = PitchCurve.from_fourier(30.0, (0.0, 0.0, 4.0), lobes=1)  # a 3-lobed, dented curve
    assert not concave.is_convex
    pair, sizing = GearPair.from_driver(concave, "external", 1).sized(module=1.0)
    with pytest.raises(GeometryError, match="cannot cut the concave part of the pitch curve at arc length"):
        generate_pair(pair, RackCutter(1.0), sizing.teeth)


def test_a_cutter_without_a_module_takes_its_studys():
    """Sizing stated once: a cutter given without a module is sized by the study; on its own
    it cannot cut, and its thickening (mm) waits for the module too."""
    from transplanter.families import ToothedPairStudy
    from transplanter.geometry.cutter import RackCutter

    pair = GearPair.from_driver(PitchCurve.ellipse(30.0, 0.1, 2), "external", 2)
    with pytest.raises(SpecError, match="the cutter has no module"):
        generate(pair.sized(teeth=30)[0].driver, ShaperCutter(12), 30)
    with pytest.raises(SpecError, match="thickening \\(mm\\) needs its module"):
        ShaperCutter(12, thickening=0.05)
    for unsized in (ShaperCutter(12), RackCutter()):
        study = ToothedPairStudy("p", pair, unsized, teeth=30)
        module = pair.sized(teeth=30)[1].module
        assert study.tool == unsized.sized(module) and study.tool.module == module
    with pytest.raises(SpecError, match="cutter module = 3.0 is out of range"):
        assert ToothedPairStudy("p", pair, ShaperCutter(12, 3.0), teeth=30).design_backlash > 0


def test_pair_studies_size_one_way():
    """Both pair studies take ``teeth`` (the driver's) or ``module`` (mm), exactly one, and size
    the pair as ``GearPair.sized`` does: a module scales the curves to a whole number of teeth."""
    from transplanter.families import PitchPairStudy, ToothedPairStudy

    pair = GearPair.from_driver(PitchCurve.ellipse(30.0, 0.1, 2), "external", 2)
    by_module = ToothedPairStudy("p", pair, ShaperCutter(12), module=2.0).sized
    scaled, sizing = pair.sized(module=2.0)
    assert by_module.sizing == sizing and by_module.pair.centre_distance == scaled.centre_distance
    assert (
        by_module.tool.module == 2.0
        and ToothedPairStudy("p", pair, ShaperCutter(12), teeth=30).sized.sizing.teeth[0] == 30
    )
    for kwargs in ({}, {"teeth": 30, "module": 2.0}):
        with pytest.raises(SpecError, match="give exactly one of teeth"):
            ToothedPairStudy("p", pair, ShaperCutter(12), **kwargs)
    assert {f for f in PitchPairStudy.__dataclass_fields__} >= {"teeth", "module"}


def _lobed_pair():
    """A 2-lobed planet (60 teeth) in its 3-lobed ring (90), m = 2 (the teeth benchmark's)."""
    pair = GearPair.from_driver(PitchCurve.ellipse(60.0, 0.12, lobes=2), "internal", driven_lobes=3)
    return pair.sized(module=2.0)[0]


ASSEMBLY_CASES = [
    ("circular external", lambda: PitchCurve.circle(60.0), 60, False, 0.0, 0.0),
    ("circular ring, shifted", lambda: PitchCurve.circle(60.0), 60, True, 0.3, 0.5),
    ("2-lobed planet", lambda: _lobed_pair().driver, 60, False, 0.0, 0.0),
    ("3-lobed ring", lambda: _lobed_pair().driven, 90, True, 0.0, 0.5),
]


def _hausdorff(a, b) -> float:
    """GEOS's discrete Hausdorff distance of two polygons (``shapely.hausdorff_distance``: every
    vertex of each boundary to the other boundary, the largest), by :func:`_to_boundary`, not by
    trying every pair (~15 000 × 15 000 here)."""

    def one_way(p, q) -> float:
        return float(_to_boundary(q)(shapely.get_coordinates(shapely.get_rings(p))).max())

    return max(one_way(a, b), one_way(b, a))


def test_the_distances_by_nearest_segment_are_geos_own():
    ring = shapely.Point(0, 0).buffer(10.0, quad_segs=64).difference(shapely.box(-1, -1, 1, 1))
    moved = shapely.affinity.rotate(ring, 0.3, origin=(0.2, 0.0)).simplify(0.01)
    # (GEOS measures a vertex to a segment by another routine: the last digits differ, ~1e-15 mm)
    assert _hausdorff(ring, moved) == pytest.approx(shapely.hausdorff_distance(ring, moved), rel=0, abs=1e-12)
    assert _hausdorff(ring, ring) == 0.0
    xy = np.random.default_rng(3).uniform(-12.0, 12.0, (500, 2))
    assert np.allclose(_to_boundary(ring)(xy), shapely.distance(ring.boundary, shapely.points(xy)), rtol=0, atol=1e-12)


@pytest.mark.parametrize(("label", "curve", "z", "internal", "x", "phase"), ASSEMBLY_CASES)
def test_the_fast_assembly_and_the_symmetry_give_the_boolean_outline(monkeypatch, label, curve, z, internal, x, phase):
    """The outline assembled without a union (spaces that neither fold nor touch) from one
    symmetric sector turned onto the others is the outline of the general path — every space
    computed and the spaces unioned: the same region but for where the tip polyline's vertices
    fall (within a tenth of the chord tolerance), the same tip lands and undercut (the general
    path's lands follow the tip polyline, within its chord error)."""
    from transplanter.geometry import teeth

    curve = curve()
    cutter = ShaperCutter(16, 2.0)
    fast = generate(curve, cutter, z, internal=internal, shift=x, phase=phase)
    assert teeth._symmetry(curve, z) == (z if curve.lobes == 1 else curve.lobes)
    assert isinstance(fast.removed[-1], shapely.MultiPolygon)  # the union was not needed
    monkeypatch.setattr(teeth, "apart_spaces", lambda *a: None)
    monkeypatch.setattr(teeth, "_symmetry", lambda curve, teeth: 1)
    general = generate(curve, cutter, z, internal=internal, shift=x, phase=phase)
    assert not isinstance(general.removed[-1], shapely.MultiPolygon) or len(general.removed[-1].geoms) == 1
    # the same region, but for the tip polyline: sampled on a sector, its vertices differ
    assert _hausdorff(fast.polygon, general.polygon) < CHORD_TOLERANCE / 10
    assert abs(fast.polygon.area - general.polygon.area) < 1e-7 * general.polygon.area
    assert np.abs(fast.tip_lands - general.tip_lands).max() < CHORD_TOLERANCE
    assert fast.undercut == general.undercut == 0.0
    for a, b in zip(fast.spaces, general.spaces, strict=True):
        assert np.abs(a.upper - b.upper).max() < 1e-9 and a.s == pytest.approx(b.s, abs=1e-12)


def test_nearly_pointed_teeth_take_the_general_path():
    """Spaces whose caps meet above a nearly pointed tooth are not apart: the union path cuts
    the gear, and reports the pointed tooth."""
    cutter = ShaperCutter(20, 2.0, dedendum=2.2)
    gear = generate(PitchCurve.circle(12.0), cutter, 12, shift=0.9, allow_undercut=True, min_land=0.0)
    assert isinstance(gear.removed[-1], shapely.Polygon)  # unioned
    assert gear.tip_lands.min() == pytest.approx(0.152, abs=1e-3)
    with pytest.raises(GeometryError, match=r"pointed tooth 0: its tip land is 0.1521 mm, below min_land"):
        generate(PitchCurve.circle(12.0), cutter, 12, shift=0.9, allow_undercut=True)


@pytest.mark.parametrize("z", [22, 27])  # 22: deeper than half a module, measured on the whole ring
def test_secondary_cutting_is_measured_alike_on_a_sector_and_on_the_whole_ring(monkeypatch, z):
    """A circular ring is checked for secondary cutting on one sector, the ring clipped around
    the cutter: the depth found is the one the whole ring gives."""
    import re

    from transplanter.geometry import teeth

    def depth():
        with pytest.raises(GeometryError, match="secondary cutting") as err:
            generate(PitchCurve.circle(z * 1.0), ShaperCutter(20, 2.0), z, internal=True)
        return float(re.search(r"reach ([\d.]+) µm", str(err.value)).group(1))

    sector = depth()
    monkeypatch.setattr(teeth, "_symmetry", lambda curve, teeth: 1)
    assert sector == depth() > 1.0


def test_an_undercut_fold_is_no_needle_in_the_outline():
    """A 12-tooth circular gear cut by an 18-tooth shaper is undercut: the fold's two envelope
    pieces met in a 17 µm needle that hid the undercut and that the DXF's arcs missed by 1.2 µm
    (``transplanter pair "2*phi" --teeth 24 --module 1.5`` failed at the DXF re-read). The needle
    is an envelope artefact (``SPIKE_LENGTH``): the undercut is said, with its depth."""
    pair, _ = GearPair.from_ratio(Constant(2.0, period=math.pi), 27.0).sized(teeth=24)
    with pytest.raises(GeometryError, match=r"undercut at tooth space \d+: [\d.]+ µm of involute flank"):
        generate(pair.driven, ShaperCutter(18, 1.5), 12, phase=0.5)
