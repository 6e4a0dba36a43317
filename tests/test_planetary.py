"""Seed-004 differential planetary train: kinematics, reading, agronomic metrics."""

import json
import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from transplanter.core.errors import GeometryError, SpecError
from transplanter.design.agronomy import segment_distance, transplanting_metrics
from transplanter.design.planetary import ArmGeometry, DifferentialTrain
from transplanter.families import run_script
from transplanter.geometry.pitch import Constant, GearPair, PitchCurve


@pytest.fixture(scope="module")
def seed004(parts_dir):
    """The design model beside the seed-004 part script: the paper's data and our reading."""
    return run_script(parts_dir / "_seed004.py")


@pytest.fixture(scope="module")
def metrics004(seed004):
    tr = seed004["train"]()
    pair = tr.pair
    return transplanting_metrics(
        tr, seed004["SEEDLING_BOX"], seed004["PLANT_SPACING"], seed004["PLANTING_DEPTH"], pair.driver.max_radius().value
    )


def test_train_follows_seed_equations(seed004):
    """Eqs 1-10 integrated independently (solve_ivp on the ring radius) give the same tip."""
    tr = seed004["train"]()
    ring = tr.pair.driver
    a = tr.pair.centre_distance
    theta = np.linspace(0, 2 * math.pi, 181)
    gamma1 = (1 - tr.speed_ratio) * theta

    def rate(g, _y):  # dγ2/dγ1 = r1/r2 with the contact at ring body angle -γ1
        r1 = float(ring.r(-g))
        return [r1 / (r1 - a)]

    sol = integrate.solve_ivp(rate, (0, gamma1[-1]), [0.0], t_eval=gamma1, rtol=1e-12, atol=1e-12)
    gamma2 = sol.y[0]
    phi_h = tr.carrier_start - theta
    phi2 = phi_h + gamma2
    s, beta = tr.arm.tip, tr.arm.mount
    tip = a * np.c_[np.cos(phi_h), np.sin(phi_h)] + s * np.c_[np.cos(phi2 + beta), np.sin(phi2 + beta)]
    assert np.max(np.linalg.norm(tr.state(theta).tip - tip, axis=1)) < 1e-6  # solve_ivp rtol 1e-12 on 150 mm


def test_seed004_reading_closes_and_repeats(seed004):
    tr = seed004["train"]()
    assert tr.pair.lobes == (4, 1)
    assert tr.speed_ratio == 0.75
    assert tr.relative_turns == pytest.approx(1.0, abs=1e-15)
    assert tr.pair.closure_error < 1e-9
    assert tr.closure_error() < 1e-9  # the arm returns to its start every carrier turn
    assert tr.phase_error() < 1e-9  # three identical arms, 120 deg apart
    s = tr.state(np.array([0.0, 2 * math.pi]))
    assert s.planet_angle[1] - s.planet_angle[0] == pytest.approx(0.0, abs=1e-9)  # no net arm rotation
    assert tr.pair.centre_distance == pytest.approx(57.7489, abs=1e-4)


def test_seed004_metrics_beside_the_paper(metrics004):
    m = metrics004
    # Paper: picking 342, pushing 296, difference 46 deg. Our reading differs by the amounts
    # README explains (the missing r11, the paper's unstated spline); pin the measured values.
    assert m.picking_angle == pytest.approx(337.31, abs=0.05)
    assert m.pushing_angle == pytest.approx(289.37, abs=0.05)
    assert m.angle_difference == pytest.approx(47.94, abs=0.05)
    assert abs(m.picking_angle - 342) < 6 and abs(m.pushing_angle - 296) < 8 and abs(m.angle_difference - 46) < 3
    # Paper height 245 mm; ours 283 mm (the paper does not define its height; see README).
    assert m.trajectory_height == pytest.approx(283.18, abs=0.05)
    assert m.picking_box_distance < 12  # the tip reaches the seedling box opening
    assert m.hole_width < 30  # seed 004 requirement ix at 120 mm spacing
    assert m.needle_clearance > 20


def test_published_module_needs_a_fractional_tooth_count(seed004):
    pair = seed004["gear_pair"]()
    _, sizing = pair.sized(teeth=80)
    assert sizing.module == pytest.approx(2.8411, abs=1e-4)
    teeth_at_published = pair.driver.perimeter / (math.pi * seed004["PUBLISHED_MODULE"])
    assert teeth_at_published == pytest.approx(81.76, abs=0.01)  # not a multiple of 4 lobes


def test_other_readings_are_not_physical(seed004):
    """The radii as the planet's curve need |OO1| = 260.6 mm and a trajectory over 500 mm tall."""
    planet = PitchCurve.from_polar_points(np.radians(seed004["CARRIER_ANGLES_DEG"]), seed004["RING_RADII_MM"])
    ring_pair = GearPair.from_driver(planet, "internal", 4)  # the planet's 4-lobed ring
    assert ring_pair.centre_distance == pytest.approx(260.56, abs=0.01)
    pair = GearPair.from_driver(ring_pair.driven, "internal", 1)  # the same pair, ring driving
    assert pair.centre_distance == pytest.approx(ring_pair.centre_distance, abs=1e-9)
    tr = DifferentialTrain(pair, seed004["ARM"], seed004["CARRIER_START"])
    assert np.ptp(tr.cycle(720).tip[:, 1]) > 500


def test_seed004_manufacturability_figures(seed004):
    pair = seed004["gear_pair"]()
    planet = pair.driven
    assert planet.min_radius().value == pytest.approx(3.84, abs=0.01)
    assert math.degrees(planet.max_pressure_deviation()) == pytest.approx(64.5, abs=0.1)
    assert not planet.is_convex and not pair.driver.is_convex


def test_translating_arm_with_circular_gears():
    """Circular ring (4 'lobes') and planet: the arm translates, the tip draws a circle of radius a."""
    ring = PitchCurve(Constant(80.0, period=math.pi / 2))
    pair = GearPair.from_driver(ring, "internal", 1)
    assert pair.centre_distance == pytest.approx(60.0, abs=1e-12)
    tr = DifferentialTrain(pair, ArmGeometry(150.0, 80.0, -0.5), carrier_start=0.3)
    m = transplanting_metrics(tr, (100.0, 50.0), 100.0, 20.0, 90.0)
    assert m.trajectory_height == pytest.approx(120.0, abs=1e-9)
    assert m.angle_difference == pytest.approx(0.0, abs=1e-9)
    c = tr.cycle(360)
    assert np.ptp(c.attitude) < 1e-12
    centre = np.array([150 * math.cos(0.3 - 0.5), 150 * math.sin(0.3 - 0.5)])
    assert np.allclose(np.linalg.norm(c.tip - centre, axis=1), 60.0, atol=1e-12)
    assert m.gearbox_clearance == pytest.approx(-90.0 - m.soil_level, abs=1e-12)


def test_train_rejects_bad_input():
    ext = GearPair.from_driver(PitchCurve.ellipse(40, 0.2), "external", 1)
    with pytest.raises(SpecError, match="ring as driver"):
        DifferentialTrain(ext, ArmGeometry(150, 80, 0), 0.0)
    with pytest.raises(SpecError, match="knee"):
        ArmGeometry(tip=80.0, knee=90.0, mount=0.0)
    with pytest.raises(SpecError, match="tip"):
        ArmGeometry(tip=float("nan"), knee=10.0, mount=0.0)
    ring = GearPair.from_driver(PitchCurve.ellipse(80, 0.05, 4), "internal", 1)
    with pytest.raises(SpecError, match="speed_ratio"):
        DifferentialTrain(ring, ArmGeometry(150, 80, 0), 0.0, speed_ratio=1.0)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-50, 50).map(lambda v: round(v, 6)), min_size=8, max_size=8))  # shapely NaNs on 1e-300
def test_segment_distance_matches_shapely(c):
    p0, p1, q0, q1 = (np.array([[c[i], c[i + 1]]]) for i in range(0, 8, 2))
    ours = float(segment_distance(p0, p1, q0, q1)[0])
    ref = shapely.distance(shapely.LineString([p0[0], p1[0]]), shapely.LineString([q0[0], q1[0]]))
    assert ours == pytest.approx(ref, abs=1e-9)


def test_seed004_family_builds(built):
    manifest = json.loads((built / "planetary_seed004" / "manifest.json").read_text())
    assert manifest["ok"], manifest
    res = manifest["parts"]["transplanting_train"]["results"]
    assert res["metrics"]["picking angle"]["published"] == 342.0
    assert set(res["variants"]) == {"r11 = 94 mm", "r11 = 96 mm", "r11 = 98 mm", "r11 = 100 mm", "quintic spline"}
    heights = [v["trajectory height"] for v in res["variants"].values()]
    assert max(heights) - min(heights) < 7  # r11 and the spline degree move the height by < 7 mm
    pitch = manifest["parts"]["ring_planet_pitch"]["results"]
    assert pitch["driver"]["teeth"] == 80 and pitch["driven"]["teeth"] == 20
    assert (built / "planetary_seed004" / "transplanting_train.trajectory.png").stat().st_size > 10_000
    teeth = manifest["parts"]["ring_planet_teeth"]["results"]
    assert teeth["driver"]["teeth"] == 560 and teeth["driven"]["teeth"] == 140
    assert teeth["driver"]["undercut_mm"] == 0.0 and teeth["driver"]["internal"]
    rejected = teeth["rejected_alternatives"]
    assert "cutter-curve interference" in rejected["paper module (80/20 teeth, 12-tooth cutter)"]
    assert "undercut" in rejected["m = 0.71 mm (320/80 teeth, 8-tooth cutter)"]


@pytest.mark.parametrize("n1, n2, planets, ok", [(4, 1, 3, True), (8, 2, 3, True), (5, 2, 3, False), (9, 3, 3, False)])
def test_arms_are_copies_only_when_the_lobe_numbers_allow(n1, n2, planets, ok):
    """(n1 - n2)/(N n2) whole: the arms are copies (phase error at round-off); otherwise the
    constructor refuses (the phase error would be hundreds of millimetres)."""
    pair = GearPair.from_driver(PitchCurve.ellipse(80.0, 0.08, lobes=n1), "internal", driven_lobes=n2)
    arm = ArmGeometry(tip=150.0, knee=80.0, mount=-0.7)
    if ok:
        assert DifferentialTrain(pair, arm, carrier_start=0.7, planets=planets).phase_error() < 1e-9
    else:
        with pytest.raises(SpecError, match=r"would not be copies of each other: .* must be a whole number"):
            DifferentialTrain(pair, arm, carrier_start=0.7, planets=planets)


def test_train_from_a_ratio_law_closes_and_follows_it():
    """i(φ) = n(1 + A cos(nφ - p)): ring radius a i/(i - 1), planet a/(i - 1), both closed."""
    n, a, amp, ph = 4, 60.0, 0.3, 0.7
    tr = DifferentialTrain.from_ratio(
        n, ((amp * math.cos(ph), amp * math.sin(ph)),), a, ArmGeometry(150, 80, -0.7), 0.7
    )
    phi = np.linspace(0, 2 * math.pi, 97)
    i = n * (1 + amp * np.cos(n * phi - ph))
    assert np.allclose(tr.pair.driver.r(phi), a * i / (i - 1), rtol=1e-12)
    assert np.allclose(tr.pair.ratio(phi), i, rtol=1e-9)
    assert tr.pair.closure_error < 1e-9 and tr.closure_error() < 1e-6 and tr.phase_error() < 1e-9
    with pytest.raises(GeometryError, match="ratio"):  # i must stay above 1
        DifferentialTrain.from_ratio(4, ((0.8, 0.0),), a, ArmGeometry(150, 80, -0.7), 0.7)


def test_objectives_of_the_published_reading(seed004):
    """Seed 004's objectives i-xii measured on the published reading, with the readings of the
    objectives module: the angles, the box and the hole pass; the gearbox misses x at the
    paper's 2.78 mm module (the ring alone reaches 102.5 mm)."""
    from transplanter.design.objectives import Site, gearbox_radius, seed004_objectives

    site = Site((165.0, 70.0), math.radians(52.0), 120.0, 30.0)
    found = {(o.number, o.name): o for o in seed004_objectives(seed004["train"](), site, 2.78)}
    assert len(found) == 13 and [k[0] for k in found][:3] == ["i", "ii", "iii"]
    by_name = {k[1]: o for k, o in found.items()}
    assert by_name["needle-needle clearance"].value == pytest.approx(21.6, abs=0.1)
    assert by_name["picking angle"].ok and by_name["pushing angle"].ok and by_name["angle difference"].ok
    assert by_name["picking depth into the box"].value == pytest.approx(16.6, abs=0.1)
    assert by_name["hole width"].ok and by_name["module"].ok
    gb = by_name["gearbox clearance above the ground"]
    assert not gb.ok and gb.shortfall == pytest.approx(20 - gb.value)
    assert gearbox_radius(100.0, 2.0) == pytest.approx(100 + 4.25 * 2 + 5)
    with pytest.raises(SpecError, match="plant_spacing"):
        Site((165.0, 70.0), 0.9, -1.0, 30.0)


def test_screen_of_a_circular_pair_is_circular_theory_then_the_cut_decides():
    """A circular ring/planet (a = 57.7, i = 4). Along a circle the windowed screen is the closed
    form of circular theory exactly; it passes 36/9 teeth (ring tips trimmed, contact ratio
    >= 1.1), the cut refuses a 9-tooth planet (undercut), and ``coarsest_cut`` settles on 52/13,
    between the 48/12 and 56/14 that the full meshing check passes in ``screen_cases``."""
    from transplanter.geometry.cutter import ShaperCutter
    from transplanter.geometry.cutter_choice import coarsest_cut
    from transplanter.geometry.interference import circular_internal, fouling_screen, screen_module
    from transplanter.geometry.pair_gate import generate_pair

    tr = DifferentialTrain.from_ratio(4, (), 57.7, ArmGeometry(150, 80, -0.7), 0.7)
    s = screen_module(tr.pair)
    assert s.teeth == (36, 9) and s.cutter_teeth == 12
    sized, sizing = tr.pair.sized(teeth=36)
    lim = fouling_screen(sized, ShaperCutter(12, sizing.module), ring_addendum=s.ring_addendum)
    exact = circular_internal(36, 9, sizing.module, cutter_teeth=12, ring_addendum=s.ring_addendum)
    assert np.nanmin(lim.fillet) == pytest.approx(float(exact.fillet[0]), abs=1e-9)
    assert lim.min_contact_ratio == pytest.approx(exact.min_contact_ratio, abs=1e-9)
    with pytest.raises(GeometryError, match="undercut"):
        generate_pair(sized, ShaperCutter(12, sizing.module), (36, 9), addendum=(s.ring_addendum, 1.0))
    assert coarsest_cut(tr.pair).teeth == (52, 13)


def test_optimised_seed004_train_is_made_meshes_and_meets_every_objective(built, seed004):
    """The optimised design (``OPTIMUM``): every objective i-xii met and reported beside the
    published reading; ring and planet cut, re-read from DXF and STL, mesh over the whole
    relative cycle with no overlap and backlash above the tolerance budget; the three-arm train
    rebuilt from each made source stays within the bound its backlash predicts and still meets
    the objectives; the carrier plate's planet holes re-read on the carrier radius at 120 deg."""
    folder = built / "planetary_seed004"
    manifest = json.loads((folder / "manifest.json").read_text())
    train = manifest["parts"]["optimised_train"]
    res = train["results"]
    table = res["objectives"]
    assert table["all_met"] and table["columns"][2:4] == ["this design", "published reading"]
    assert table["columns"][-1] == "paper" and "0.6 m ring tips" in table["columns"][4]
    assert len(table["rows"]) == 13 and all(row[2].endswith("pass") for row in table["rows"])
    assert any(row[3].endswith("FAIL") for row in table["rows"])  # the published reading misses some
    module = train["parameters"]["module_mm"]
    assert module >= 2.5
    pair = manifest["parts"]["optimised_ring_planet"]["results"]
    assert pair["assembly"]["kind"] == "internal" and pair["assembly"]["planets"] == 3
    for source in ("outline", "dxf", "stl"):
        mesh = pair["meshing"][source]
        assert mesh["max_penetration_mm2"] == 0.0 and not mesh["problems"], source
        assert mesh["backlash_mm"][0] > pair["assembly"]["tolerance_budget_mm"], source
        # issue 27's hard rule: the ISO/TR 10064-2 minimum at every position, the dips included
        assert mesh["backlash_mm"][0] >= pair["meshing"]["min_backlash_mm"] > 0.14, source
        assert mesh["train"]["max_tip_deviation_mm"] <= mesh["train"]["predicted_bound_mm"], source
        assert all("pass" in v for v in mesh["train"]["objectives"].values()), source
    assert res["carrier_plate"]["planet_holes_readback_mm"] < 1e-3
    for name in ("optimised_ring_planet.driver", "optimised_ring_planet.driven"):
        assert (folder / f"{name}.dxf").stat().st_size > 0 and (folder / f"{name}.stl").stat().st_size > 0
    # the carrier plate's layout is a drawing not to cut (the machine cuts its plates to it): DXF only
    assert (folder / "optimised_train.carrier.dxf").stat().st_size > 0
    assert (
        not (folder / "optimised_train.carrier.stl").exists() and not (folder / "optimised_train.carrier.step").exists()
    )
    front = res["pareto_front"]
    assert "binding at" in front["binding_constraint"] and "0.6 m required" in front["binding_constraint"]
    rows = [dict(zip(front["columns"], r, strict=True)) for r in front["rows"]]
    assert sum(r["chosen"] for r in rows) == 1 and len(rows) == 5 and any(r["pareto"] for r in rows)
    assert (folder / "optimised_train.front.png").stat().st_size > 10_000
    page = (folder / "report.html").read_text()
    assert "published reading" in page and "needle-needle clearance" in page


def test_objective_viii_is_the_same_wherever_the_sampled_cycle_starts():
    """Regression: objective viii counted time from the cycle's first sample, so a push late in
    the cycle saw the ground track set back by a period after the wrap and failed falsely."""
    import numpy as np

    from transplanter.design.objectives import back_over_plant

    s = np.linspace(0.0, 1.0, 100, endpoint=False)
    down = np.column_stack((-20.0 + 20.0 * s, 300.0 - 400.0 * s))  # to the push at (0, -100)
    up = np.column_stack((30.0 * np.sin(np.pi * s) - 45.0 * s, -100.0 + 300.0 * s))  # out on +x, then back
    back = np.column_stack((-45.0 + 25.0 * s, 200.0 + 100.0 * s))
    tip = np.vstack((down, up, back))
    values = [back_over_plant(np.roll(tip, k, axis=0), 0.0, -20.0, 1.0) for k in (0, 50, 99, 150, 299)]
    assert max(values) - min(values) < 1e-9
    assert values[0] > 1.0  # it does go back over the plant: the figure is not a blanket zero


def test_objective_viii_does_not_jump_with_the_side_the_tip_first_leaves_the_soil():
    """Regression: the side the tip retreats to was taken from its first sample out of the soil —
    right above the hole — so a tip leaving 0.2 mm to one side and then retreating to the other
    counted its whole retreat (45 mm) as going back over the plant, and 0.2 mm the other way
    counted nothing: viii jumped 0 → 44.7 mm for a 0.3 mm change of seed 004's carrier radius.
    The side is where the tip is when it reaches the seedling's height."""
    import numpy as np

    from transplanter.design.objectives import back_over_plant

    s = np.linspace(0.0, 1.0, 100, endpoint=False)
    down = np.column_stack((20.0 - 20.0 * s, 300.0 - 400.0 * s))

    def track(first_out: float):
        bump = first_out * np.sin(np.pi * np.clip((s - 0.3) * 5, 0, 1))  # out of the soil on one side
        away = 45.0 * np.clip((s - 0.5) / 0.5, 0, 1) ** 2  # then away along -x as it rises
        up = np.column_stack((bump - away, -100.0 + 300.0 * s))
        back = np.column_stack((-45.0 + 65.0 * s, 200.0 + 100.0 * s))
        return np.vstack((down, up, back))

    plus, minus = (back_over_plant(track(d), 0.0, 0.0, 1.0) for d in (0.2, -0.2))
    assert plus == pytest.approx(0.2, abs=0.02) and minus == 0.0  # 0.2 mm over the plant at most
    wide = back_over_plant(track(15.0), 0.0, 0.0, 1.0)
    assert wide == pytest.approx(15.0, abs=0.5)  # a tip that does swing 15 mm over it still fails


def test_the_objectives_are_judged_where_the_play_lets_the_arm_sit(built):
    """Issue 27: margins that survive the pair's own play. On the train rebuilt from the ring and
    planet DXFs, each planet turned to either end of its play (the proof's bound over the arm's
    length), every objective is measured again and its worst margin recorded beside the nominal
    ones — still met, and thinner than at the mid play (v, vi, i are what a re-design must widen)."""
    manifest = json.loads((built / "planetary_seed004" / "manifest.json").read_text())
    train = manifest["parts"]["optimised_ring_planet"]["results"]["meshing"]["dxf"]["train"]
    under = train["objectives_under_play"]
    assert 0.1 < under["turn_deg"] < 1.0
    # the needle tip's envelope under that play: about S x turn (150-170 mm x 0.4 deg ~ 1.1 mm) plus
    # what the turned planet's motion adds
    assert 0.5 < under["tip_envelope_mm"]["max"] < 5.0 and 0 <= under["tip_envelope_mm"]["at_carrier_deg"] < 360
    keys = ("turn_deg", "tip_envelope_mm", "margins_to_keep", "margins_short_mm_or_deg")
    figures = {k: v for k, v in under.items() if k not in keys}
    margins = {k: float(v.split("margin ")[1].split(",")[0].rstrip(")")) for k, v in figures.items()}
    assert len(margins) == 13
    # what issue 27 asks them to keep, judged: every short one said, with how much it is short by
    assert under["margins_to_keep"] == {"i": 3.0, "v": 2.0, "vi": 2.0}
    keep = under["margins_to_keep"]
    short = {k: round(keep[k.split()[0]] - m, 3) for k, m in margins.items() if k.split()[0] in keep}
    short = {k: v for k, v in short.items() if v > 0}
    assert short == {k: round(v, 3) for k, v in under["margins_short_mm_or_deg"].items()}
    for key in short:
        assert "short by" in figures[key]


def test_the_pareto_front_keeps_the_feasible_designs_no_other_beats():
    """``non_dominated``: a design is on the front when it is feasible and no feasible design has
    both a coarser (or equal) module and a larger (or equal) margin, one of them strictly."""
    from transplanter.families import FrontPoint
    from transplanter.families.mechanisms.trains import non_dominated

    points = [
        FrontPoint("a", 2.5, 1.0, "v"),
        FrontPoint("b", 3.0, -0.5, "i"),
        FrontPoint("c", 2.4, 0.5, "v"),  # beaten by a on both
        FrontPoint("d", 3.5, 2.0, "v", feasible=False),  # would beat all, but misses an objective
        FrontPoint("e", 3.0, -0.5, "i", chosen=True),  # equal to b: neither beats the other
    ]
    assert non_dominated(points) == [True, True, False, False, True]
