"""The tooth load along a made non-circular mesh over a cycle (``transplanter.proof.mesh_cycle``):
the loaded flanks closed by the smallest turn (checked against a shapely bisection), the force at
each contact equal to the torque over the normal's lever arm there, and the pair touching, not
overlapping."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from transplanter.core.errors import SpecError
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pair_gate import generate_pair
from transplanter.geometry.pitch import GearPair, PitchCurve
from transplanter.geometry.pitch.pair import driven_axis, driven_turn
from transplanter.proof.mesh_cycle import mesh_cycle_load
from transplanter.shop.catalogue.gear_materials import gear_material

STEPS = 8


def _placed(outline, centre, angle):
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    return shapely.Polygon(outline @ rot.T + centre)


@pytest.fixture(scope="module")
def cycle():
    """A made elliptical pair (ellipse 40 mm, e = 0.2, two lobes, m = 2 mm, 40/40 teeth) at 8
    driver angles, the driven gear at its design angle, torques of both signs on it."""
    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(40.0, 0.2, 2), "external", 2).sized(module=2.0)
    drv, drn = generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth)
    phi1 = np.linspace(0.0, math.pi, STEPS, endpoint=False) + 0.05
    c2 = np.array([driven_axis(pair), 0.0])
    poses = ((np.zeros((STEPS, 2)), -phi1), (np.tile(c2, (STEPS, 1)), np.asarray(driven_turn(pair, phi1), float)))
    torque = 8000.0 * np.where(np.arange(STEPS) % 2 == 0, 1.0, -1.0) * (1 + 0.1 * np.arange(STEPS))
    outlines = (drv.toothed_contour, drn.toothed_contour)
    res = mesh_cycle_load(outlines, poses, torque, width=10.0, module=2.0, ring=False, theta=phi1)
    return outlines, poses, torque, res


def test_the_force_at_each_contact_is_the_torque_over_the_normals_lever(cycle):
    outlines, poses, torque, res = cycle
    assert len(res.places) >= STEPS and np.all(res.contacts >= 1)
    c2 = poses[1][0][0]
    for place in res.places:
        k = place.step
        line = shapely.LineString([place.point - 500 * place.normal, place.point + 500 * place.normal])
        lever = line.distance(shapely.Point(*c2))
        assert place.load.lever_arm == pytest.approx(lever, rel=1e-9)
        assert place.load.force == pytest.approx(abs(torque[k]) / lever, rel=1e-9)
        # the normal is the force on the driven flank: its moment has the torque's sign
        r = place.point - c2
        moment = float(r[0] * place.normal[1] - r[1] * place.normal[0])
        assert np.sign(moment) == np.sign(torque[k])
        assert place.gap <= 2e-3 and all(rs.sigma_f > 0 for rs in place.load.root)
        if place.load.hertz is None:  # a tip corner poking the other's fillet: an edge contact
            assert None in place.load.radii
        else:  # Hertz with both flanks' radii there (convex flanks of an external pair)
            assert all(r > 0 for r in place.load.radii)
    assert sum(p.load.hertz is not None for p in res.places) >= STEPS // 2
    for k in range(STEPS):  # per position: the largest over its flank contacts (NaN: only edge contacts)
        flank = [p.load.hertz.sigma_h for p in res.places if p.step == k and p.load.hertz is not None]
        assert (res.sigma_h[k] == max(flank)) if flank else np.isnan(res.sigma_h[k])
        assert res.contacts[k] == sum(p.step == k for p in res.places)
    assert res.max_sigma_h.value == pytest.approx(np.nanmax(res.sigma_h))
    assert res.max_sigma_f[1].value == pytest.approx(res.sigma_f[:, 1].max())


def test_the_closing_turn_finds_a_touching_not_overlapping_pair(cycle):
    outlines, poses, torque, res = cycle
    (c1, a1), (c2, a2) = poses
    for k in range(STEPS):
        sense = -np.sign(torque[k])  # the load turns the driven gear against the mesh torque
        turn = res.turn[k]
        assert np.sign(turn) == sense and abs(turn) < 0.1
        one = _placed(outlines[0], c1[k], a1[k])
        closed = _placed(outlines[1], c2[k], a2[k] + turn)
        assert one.intersection(closed).area < 1e-9
        x, y = next(p.point for p in res.places if p.step == k)  # near it (a whole-outline distance is slow)
        near = [shapely.clip_by_rect(g, x - 6, y - 6, x + 6, y + 6) for g in (one, closed)]
        assert shapely.distance(*near) < 1e-9
        design = shapely.clip_by_rect(_placed(outlines[1], c2[k], a2[k]), x - 6, y - 6, x + 6, y + 6)
        assert shapely.distance(near[0], design) > 1e-3  # the design pose has play
    # the smallest such turn: a bisection on shapely's overlap agrees
    for k in (3,):
        sense = -np.sign(torque[k])
        one = _placed(outlines[0], c1[k], a1[k])
        shapely.prepare(one)
        lo, hi = 0.0, 0.02
        assert abs(res.turn[k]) < hi
        for _ in range(16):  # to 3e-7 rad
            mid = (lo + hi) / 2
            hit = one.intersects(_placed(outlines[1], c2[k], a2[k] + sense * mid))
            lo, hi = (lo, mid) if hit else (mid, hi)
        assert abs(res.turn[k]) == pytest.approx(lo, abs=1e-6)


def test_safety_factors_need_a_material_and_refusals(cycle):
    outlines, poses, torque, res = cycle
    assert res.s_h is None and res.s_f == (None, None) and "no gear material" in res.note
    m = gear_material("18CrNiMo7-6")
    few = tuple((c[:2], a[:2]) for c, a in poses)
    rated = mesh_cycle_load(outlines, few, torque[:2], width=10.0, module=2.0, ring=False, material=m)
    assert rated.s_h == pytest.approx(m.sigma_hlim / rated.max_sigma_h.value)
    assert rated.s_f[1] == pytest.approx(m.sigma_fe / rated.max_sigma_f[1].value)
    with pytest.raises(SpecError, match="poses\\[1\\] angles must be finite numbers of shape \\(2,\\)"):
        mesh_cycle_load(outlines, (few[0], (few[1][0], [0.0])), torque[:2], width=10.0, module=2.0, ring=False)
