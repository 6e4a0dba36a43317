"""Meshing of the generated parts themselves: penetration, transmission error, contact;
trains rebuilt from the parts; followers on the made cams.

Tolerances: overlap 1e-3 mm² (zero-backlash teeth overlap only by the outlines' chord error,
measured ~1e-4 mm² over a window); transmission error 1 µm for zero backlash (the envelope is
exact to 0.25 µm per outline); backlash band 0.09..0.12 mm for 0.05 mm thinning per gear (the
circumferential backlash varies with the pitch curve's pressure angle); needle-tip deviation
of a rebuilt train 2 µm (150 mm arm × TE/r2 ≈ 150 × 1e-4 / 15); follower on a made cam 5 µm
(``families.FOLLOWER_TOL``), a wrong cam misses by > 50 µm.
"""

import dataclasses
import math

import numpy as np
import pytest
import shapely

from transplanter.core.errors import GeometryError
from transplanter.design.planetary import ArmGeometry, DifferentialTrain
from transplanter.families import FOLLOWER_TOL, ToothedPairStudy, run_script
from transplanter.geometry.backlash import backlash_band
from transplanter.geometry.cams import FlatFacedFollower, MotionProgram, OscillatingRollerFollower, disc_cam
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pair_gate import generate_pair
from transplanter.geometry.pitch import Constant, GearPair, PitchCurve
from transplanter.geometry.teeth import generate
from transplanter.proof.validate import follower_check, mesh_check, train_check


@pytest.fixture(scope="module")
def ellipse_pair():
    return GearPair.from_driver(PitchCurve.ellipse(40.0, 0.2, 2), "external", 2).sized(module=2.0)


def test_generated_pair_meshes_without_backlash(ellipse_pair):
    pair, sizing = ellipse_pair
    g1, g2 = generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth, backlash=0.0)
    r = mesh_check(pair, g1.polygon, g2.polygon, 2.0, steps=48)
    assert r.problems() == []
    assert r.max_penetration < 1e-3
    assert r.max_transmission_error < 1e-3
    assert r.min_contacts >= 1 and r.contact_ratio > 2  # both flanks touch


def test_backlash_pair_stays_in_its_band(ellipse_pair):
    pair, sizing = ellipse_pair
    g1, g2 = generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth, backlash=0.1)
    r = mesh_check(pair, g1.polygon, g2.polygon, 2.0, steps=48)
    assert r.problems(backlash=(0.09, 0.12)) == []
    assert r.offset == pytest.approx(-0.05, abs=0.01)  # half the backlash on each side
    assert r.max_transmission_error < 0.02 and 1.5 < r.contact_ratio < 2.5


def test_broken_pairs_are_caught(ellipse_pair):
    pair, sizing = ellipse_pair
    g1, g2 = generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth, backlash=0.0)
    close = dataclasses.replace(pair, centre_distance=pair.centre_distance - 0.3)
    r = mesh_check(close, g1.polygon, g2.polygon, 2.0, steps=24)
    assert any("teeth interfere" in p for p in r.problems())
    # a driven gear with one tooth more, cut on its own curve, placed as the design pair
    bigger, s2 = pair.sized(teeth=sizing.teeth[0] + 2)  # the 2-lobe gear: one more tooth per lobe
    wrong = generate(bigger.driven.scaled(sizing.module / s2.module), ShaperCutter(20, 2.0), s2.teeth[1], phase=0.5)
    r = mesh_check(pair, g1.polygon, wrong.polygon, 2.0, steps=24)
    assert any("teeth interfere" in p for p in r.problems())


@pytest.fixture(scope="module")
def four_lobe_ring_pair():
    """A 4-lobe ring (60 teeth) driving a 15-tooth planet, m = 2."""
    return GearPair.from_driver(PitchCurve.ellipse(60.0, 0.05, 4), "internal", 1).sized(module=2.0)


def test_ring_tips_in_a_small_planet_are_caught_and_a_shorter_addendum_cures_them(four_lobe_ring_pair):
    """Involute interference of internal gears: with a full-depth ring addendum the 15-tooth planet's
    flanks below its base curve are hit by the ring's tips (circular 60/15 gears at 20 deg need a
    ring tip radius >= 58.44 mm, i.e. an addendum <= 0.78 m)."""
    pair, sizing = four_lobe_ring_pair
    cutter = ShaperCutter(16, 2.0)
    planet = generate(pair.driven, cutter, sizing.teeth[1], phase=0.5)
    full = generate(pair.driver, cutter, sizing.teeth[0], internal=True)
    r = mesh_check(pair, full.polygon, planet.polygon, 2.0, steps=40, teeth=sizing.teeth[0])
    (problem,) = r.problems(names=("ring", "planet"))
    assert "at the pitch point" in problem and "the ring's tooth tips in the planet's flanks" in problem
    assert r.max_penetration > 0.02 and r.max_fouling < 1e-9
    short = generate(pair.driver, cutter, sizing.teeth[0], internal=True, addendum=0.7)
    r = mesh_check(pair, short.polygon, planet.polygon, 2.0, steps=40, teeth=sizing.teeth[0])
    assert r.problems(names=("ring", "planet")) == [] and r.min_contacts >= 2


def test_steps_are_coprime_with_the_tooth_count(ellipse_pair):
    pair, sizing = ellipse_pair
    g1, g2 = generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth, backlash=0.0)
    r = mesh_check(pair, g1.polygon, g2.polygon, 2.0, steps=sizing.teeth[0], teeth=sizing.teeth[0])
    assert math.gcd(len(r.driver_angle), sizing.teeth[0]) == 1 and len(r.driver_angle) > sizing.teeth[0]


def test_seed004_teeth_foul_away_from_the_pitch_point(parts_dir):
    """The finding behind seed 004's withheld shop files: exact at the pitch point, fouling 5-15 mm away."""
    ns = run_script(parts_dir / "planetary_seed004.py")  # the script's constants, not its family
    pair, sizing = ns["train"]().pair.sized(teeth=ns["FINE_RING_TEETH"])
    ring, planet = generate_pair(
        pair, ShaperCutter(8, sizing.module, tip_fillet=0.1), sizing.teeth, backlash=0.0, check_interference=False
    )
    r = mesh_check(pair, ring.polygon, planet.polygon, sizing.module, steps=48, teeth=sizing.teeth[0])
    near = r.penetration - r.fouling
    assert near.max() < 1e-3 and r.max_transmission_error < 1e-3  # conjugate at the pitch point
    assert r.max_fouling > 0.1
    k = int(np.argmax(r.fouling))
    assert 5.0 < r.overlap_distance[k] < 15.0
    assert any(p.startswith("the teeth foul") for p in r.problems(names=("ring", "planet")))


def test_train_rebuilt_from_its_parts_follows_the_design(four_lobe_ring_pair):
    """A seed-004-like train (4-lobe ring, planet, 150 mm arm) built from generated teeth: the needle
    tip stays within 2 µm of the designed path, and the deviation is exactly the arm swung by the
    planet's measured angle error (2 S sin(δ/2)) — the rebuild uses nothing but the parts' meshing."""
    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(80.0, 0.05, 4), "internal", 1).sized(module=1.0)
    arm = ArmGeometry(tip=150.0, knee=80.0, mount=-0.7)
    train = DifferentialTrain(pair, arm, carrier_start=0.7)
    for thick, limit in ((0.0, 2e-3), (0.05, 1.0)):
        cutter = ShaperCutter(16, sizing.module)
        ring, planet = generate_pair(pair, cutter, sizing.teeth, backlash=2 * thick, addendum=0.8, trim_ring_tips=True)
        r = mesh_check(pair, ring.polygon, planet.polygon, sizing.module, steps=60, teeth=sizing.teeth[0])
        assert r.problems(backlash=backlash_band(pair, 2 * thick)) == []
        t = train_check(train, r)
        assert t.max_deviation < limit
        np.testing.assert_allclose(t.deviation, 2 * arm.tip * np.abs(np.sin(r.driven_error / 2)), atol=1e-9)
    assert t.max_deviation > 0.1  # 0.05 mm thinning: the planet lags by half the backlash


def test_follower_on_the_made_cam_follows_the_law():
    swing = MotionProgram.rise_return(
        lift=math.radians(20), rise=math.radians(120), dwell=math.radians(60), ret=math.radians(120)
    )
    follower = OscillatingRollerFollower(pivot_distance=80, arm_length=50, roller_radius=8, base_radius=35)
    cam = disc_cam(swing, follower)
    r = follower_check(shapely.Polygon(cam.profile), swing, follower, n=180)
    assert r.max_error < FOLLOWER_TOL / 100 and r.unit == "rad"
    other = disc_cam(swing, dataclasses.replace(follower, base_radius=35.2))  # a cam for another follower
    r = follower_check(shapely.Polygon(other.profile), swing, follower, n=180)
    assert r.max_error > 10 * FOLLOWER_TOL
    lift = MotionProgram.rise_return(lift=12.0, rise=math.radians(150), dwell=math.radians(30), ret=math.radians(150))
    flat = FlatFacedFollower(base_radius=40.0)
    r = follower_check(shapely.Polygon(disc_cam(lift, flat).profile), lift, flat, n=180)
    assert r.max_error < 1e-3 and r.unit == "mm"


def test_a_pair_that_does_not_mesh_fails_its_part(four_lobe_ring_pair, tmp_path):
    pair, sizing = four_lobe_ring_pair
    # the closed-form check refuses the untrimmed ring before cutting; a finding cuts it anyway
    # and the meshing check finds the same interference on the teeth
    study = ToothedPairStudy("ring_planet", pair, ShaperCutter(16, 2.0), sizing.teeth[0], trim_ring_tips=False)
    with pytest.raises(GeometryError, match="interferes before cutting: fillet interference"):
        study.build(tmp_path)
    too_big = ToothedPairStudy("ring_planet", pair, ShaperCutter(40, 2.0), sizing.teeth[0])
    with pytest.raises(GeometryError, match=r"rolling radius 40 mm .* exceeds"):
        too_big.build(tmp_path)
    finding = dataclasses.replace(study, must_mesh=False)
    record, files = finding.build(tmp_path)
    assert record["results"]["shop_files"].startswith("withheld")
    assert record["results"]["meshing"]["outline"]["problems"][0].startswith("the teeth interfere at the pitch point")
    assert record["results"]["interference"]["screen_findings"][0].startswith("fillet interference")
    assert record["results"]["interference"]["verdict"].startswith("confirmed by the meshing proof")
    assert not any(f.endswith((".dxf", ".stl")) for f in files) and "ring_planet.meshing.png" in files


def test_planet_driven_ring_agrees_with_the_circular_interference_limit():
    """A 30-tooth pinion driving a 60-tooth ring (m = 2, 20 deg), both cut by a 16-tooth cutter.

    Closed form: the cutter's tip (1.25 m) ends the pinion's involute at its form radius; the
    ring's tip circle meets the line of action at a pinion radius that must not be below it.
    The check must flag the full ring addendum and pass one below the limit (0.80 m here).
    """
    m, alpha = 2.0, math.radians(20.0)
    rb1, rb2, rbc = 30 * math.cos(alpha), 60 * math.cos(alpha), 16 * math.cos(alpha)
    t1t2 = (30 + 16) * math.sin(alpha)  # pinion-cutter: tangency points apart on the line of action
    form = math.hypot(rb1, t1t2 - math.sqrt((16 + 1.25 * m) ** 2 - rbc**2))
    # ring tip radius r_a reaches the pinion at radius hypot(rb1, sqrt(r_a² - rb2²) - 30 sin α)
    limit = (60 - math.hypot(rb2, 30 * math.sin(alpha) + math.sqrt(form**2 - rb1**2))) / m
    assert 0.75 < limit < 1.0
    pair, _ = GearPair.from_ratio(Constant(0.5), 30.0, "internal", ring="driven").sized(module=m)
    cutter = ShaperCutter(16, m)
    pinion = generate(pair.driver, cutter, 30)
    for addendum, fails in ((1.0, True), (0.75, False)):
        ring = generate(pair.driven, cutter, 60, internal=True, phase=0.5, addendum=addendum)
        r = mesh_check(pair, pinion.polygon, ring.polygon, m, steps=20, teeth=30)
        assert bool(r.problems()) is fails, (addendum, r.summary())
    assert r.min_contacts >= 2


def _reference_cases(ellipse_pair, four_lobe_ring_pair):
    pair, sizing = ellipse_pair
    cutter = ShaperCutter(20, 2.0)
    zero = generate_pair(pair, cutter, sizing.teeth, backlash=0.0)
    close = dataclasses.replace(pair, centre_distance=pair.centre_distance - 0.3)
    yield "zero backlash", pair, *(g.polygon for g in zero), None
    yield "0.1 mm backlash", pair, *(g.polygon for g in generate_pair(pair, cutter, sizing.teeth, backlash=0.1)), None
    yield "centre 0.3 mm close", close, *(g.polygon for g in zero), None
    ring_pair, s4 = four_lobe_ring_pair
    cutter = ShaperCutter(16, 2.0)
    planet = generate(ring_pair.driven, cutter, s4.teeth[1], phase=0.5).polygon
    for addendum in (1.0, 0.7):
        ring = generate(ring_pair.driver, cutter, s4.teeth[0], internal=True, addendum=addendum).polygon
        yield f"ring drives, addendum {addendum}", ring_pair, ring, planet, s4.teeth[0]
    pc, _ = GearPair.from_ratio(Constant(0.5), 30.0, "internal", ring="driven").sized(module=2.0)
    ring = generate(pc.driven, cutter, 60, internal=True, phase=0.5, addendum=0.75).polygon
    yield "pinion drives ring", pc, generate(pc.driver, cutter, 30).polygon, ring, 30


def test_closed_form_check_gives_the_reference_answers(ellipse_pair, four_lobe_ring_pair):
    """The vectorised check against the root-finding implementation it replaced, kept in
    ``tests/reference_meshing.py`` (which searches the contact in a window of 3 modules around the
    pitch point, so the check is run with that window and no refinement here): meshing, backlash,
    interfering and internal pairs (either
    gear driving). Contact arcs and backlash agree within MESH_REFERENCE_MM, overlap areas to
    round-off, contact counts exactly where the teeth do not overlap (where they do, the
    counted places of an overlap can differ by one)."""
    from reference_meshing import mesh_check_reference
    from transplanter.core.tolerances import MESH_REFERENCE_MM

    for name, pair, driver, driven, teeth in _reference_cases(ellipse_pair, four_lobe_ring_pair):
        new = mesh_check(pair, driver, driven, 2.0, steps=24, teeth=teeth, window=3.0, refine=False)
        ref = mesh_check_reference(pair, driver, driven, 2.0, steps=24, teeth=teeth)
        r2 = np.abs(pair.driver.r(ref.driver_angle) - (-1 if pair.ring == "driven" else 1) * pair.centre_distance)
        np.testing.assert_allclose(new.driven_error * r2, ref.driven_error * r2, atol=MESH_REFERENCE_MM, err_msg=name)
        np.testing.assert_allclose(new.backlash, ref.backlash, atol=MESH_REFERENCE_MM, err_msg=name)
        np.testing.assert_allclose(new.penetration, ref.penetration, rtol=1e-9, atol=1e-12, err_msg=name)
        np.testing.assert_allclose(new.fouling, ref.fouling, rtol=1e-9, atol=1e-12, err_msg=name)
        np.testing.assert_array_equal(new.overlap_side, ref.overlap_side, err_msg=name)
        clear = ref.penetration == 0
        np.testing.assert_array_equal(new.contacts[clear], ref.contacts[clear], err_msg=name)
        assert np.all(np.abs(new.contacts - ref.contacts) <= 1), name
        assert new.problems() == ref.problems(), name
