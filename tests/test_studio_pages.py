"""The design studio's pages of seed 000's arm B and of the picking arm's incomplete pair: each
opens on the design the family makes, and shows what the library computes of it — the rows here
are computed again by the library's own calls, not by the page's code."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from transplanter.app.optimise import script_problem
from transplanter.app.studio import named_designs
from transplanter.core.errors import TransplanterError
from transplanter.design.linkage.dh import DHFourBar
from transplanter.design.linkage.planting import PlantingArm
from transplanter.design.views import DesignView
from transplanter.families.builder.scripts import run_script
from transplanter.geometry.pitch.intermittent import (
    CLOSURE_ROUND_OFF,
    MIN_RATIO,
    IncompletePair,
    IntermittentLaw,
)

PARTS = Path(__file__).resolve().parents[1] / "parts"
TOL = 1e-9


def _rows(view: DesignView) -> dict:
    return {r.name: r for r in view.rows}


# -- seed 000's arm B --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def arm_b_page():
    problem, names = script_problem(PARTS / "fourbar_seed000.py", {}, None)
    return problem, names


def test_arm_b_page_opens_on_the_published_arm_b(arm_b_page):
    problem, names = arm_b_page
    assert problem.view is not None and problem.x0 == (125.0, 40.0, 100.0, 85.0, -273.8, 63.3, 322.0)
    assert named_designs(problem, names) == {"PUBLISHED_B": problem.x0, "MADE_B": problem.x0}
    assert problem.design == problem.x0 and problem.optimum == "MADE_B"
    # the family's arm B is the page's at x0: the part script builds what it built
    family_arm = next(p.arm for p in names["family"]().parts if getattr(p, "name", "") == "mechanism_B")
    assert family_arm == names["arm_b"](problem.x0)


def test_arm_b_rows_are_the_library_s_table_2_figures(arm_b_page):
    problem, _ = arm_b_page
    view = problem.view(np.array(problem.x0))
    assert isinstance(view, DesignView)
    arm = PlantingArm.from_dh(
        DHFourBar(a1=125.0, a2=40.0, a3=100.0, a4=85.0, phi=math.radians(322.0), branch=1),
        -273.8,
        63.3,
        -8 * math.pi,
        600.0,
        name="mechanism_B",
    )
    table = {label: value for label, value, _ in arm.metrics(planting_depth=40.0).table()}
    fb = arm.linkage
    mu = np.degrees(fb.transmission_angle(fb.solve(np.linspace(0, 2 * math.pi, 721))))
    in_soil = max(table[f"{k} acceleration"] for k in ("entry", "lowest", "exit"))
    rows = _rows(view)
    want = {  # (value, margin): the published arm against itself, the hole and the transmission angle
        "path length in soil (ground)": (table["path length in soil (ground)"], 0.0),
        "entry-exit distance (ground)": (table["entry-exit distance (ground)"], 0.0),
        "hole width (ground)": (table["hole width (ground)"], 3.0 - table["hole width (ground)"]),
        "loop height (reaches the seedling board)": (table["loop height"], 0.0),
        "speed entering the soil": (table["entry speed"], 0.0),
        "acceleration at entry, lowest, exit": (in_soil, 0.0),
        "transmission angle min": (float(mu.min()), float(mu.min()) - 40.0),
        "transmission angle max": (float(mu.max()), 140.0 - float(mu.max())),
    }
    assert set(rows) == set(want)
    for name, (value, margin) in want.items():
        assert rows[name].value == pytest.approx(value, abs=TOL), name
        assert rows[name].margin == pytest.approx(margin, abs=TOL), name
        assert rows[name].ok
    assert problem(np.array(problem.x0)) == pytest.approx(table["path length in soil (ground)"], abs=TOL)
    # the pose: the four-bar at 360 crank angles from the reference, its tip on the drawn path
    pose = view.pose
    assert pose.lines.shape == (360, 13, 2) and pose.label == "crank angle (deg)"
    theta = arm.angle_reference + np.radians(pose.angles)
    tip = arm.tip_motion(theta).position
    assert np.allclose(pose.lines[:, 8], tip, rtol=0, atol=TOL)
    assert np.allclose(pose.lines[:, 0], 0.0) and np.isnan(pose.lines[:, 2]).all()
    frame_tip = next(c for c in view.panels[0].curves if c.name == "tip").xy
    assert np.allclose(frame_tip, tip, rtol=0, atol=TOL)
    assert not view.panels[2].equal and view.panels[0].curves[0].kind == "obstacle"


def test_an_arm_b_whose_crank_cannot_turn_is_refused(arm_b_page):
    problem, _ = arm_b_page
    with pytest.raises(TransplanterError):  # s + l > p + q: no link turns fully
        problem.view(np.array([87.5, 52.0, 70.0, 59.5, -273.8, 63.3, 322.0]))
    assert problem(np.array([87.5, 52.0, 70.0, 59.5, -273.8, 63.3, 322.0])) == problem.infeasible


# -- the picking arm's incomplete pair ------------------------------------------------------------


@pytest.fixture(scope="module")
def picker_page():
    problem, names = script_problem(PARTS / "picking_dwell.py", {}, None)
    return problem, names


def test_picker_page_shows_the_pair_the_family_makes(picker_page):
    problem, names = picker_page
    assert problem.x0 == (60.0, 0.35, 30.0) and problem.choices == ("sector_teeth",)
    view = problem.view(np.array(problem.x0))
    assert isinstance(view, DesignView)
    study = names["family"]().parts[0]  # the family's own study, sized by its own call
    pair = study.pair
    law = IntermittentLaw.parse(names["LAW"])
    rows = _rows(view)
    motion = pair.law.motions[0]
    phi = np.linspace(math.radians(motion.start), math.radians(motion.end), 2001)
    ratio = motion.ratio(phi)
    # the pressure deviation as the proof's backlash band takes it (IncompleteProof.band)
    nu = math.degrees(float(np.max(np.abs(np.arctan2(pair.r1(phi, 1, motion=motion) / ratio, pair.r2(phi, motion))))))
    closure = abs(law.total_rise - 2 * math.pi)
    k1 = float(pair.curvature(phi, "driver", motion).min())
    k2 = float(pair.curvature(phi, "driven", motion).min())
    jump = law.transitions()[0].speed_jump
    want = {
        "closure error (the driven turns 1/1 per driver turn)": (closure, CLOSURE_ROUND_OFF * 2 * math.pi - closure),
        "smallest ratio w2/w1": (float(ratio.min()), float(ratio.min()) - MIN_RATIO),
        "pitch-curve pressure deviation": (nu, 30.0 - nu),
        "driver sectors: least curvature (convex > 0)": (k1, k1 + 1 / 16.0),
        "driven sectors: least curvature (convex > 0)": (k2, k2 + 1 / 16.0),
        "entry shock: speed jump w2/w1": (jump, 0.0),
        "time at the tray": (0.25, 0.0),
    }
    assert set(rows) == set(want)
    for name, (value, margin) in want.items():
        assert rows[name].value == pytest.approx(value, abs=TOL), name
        assert rows[name].margin == pytest.approx(margin, abs=TOL), name
        assert rows[name].ok, name
    assert view.pose.lines.shape == (360, 9, 2) and view.pose.label == "driver angle (deg)"
    assert f"a = {pair.centre_distance:.3f} mm" in view.panels[0].title
    # the driven's pitch curve posed at driver angle 0 touches the driver's on the line of centres
    driver = view.panels[0].curves[0].xy
    driven = view.panels[0].curves[2].xy
    r1 = float(pair.driver.r(np.zeros(1))[0])
    for curve in (driver, driven):
        assert np.nanmin(np.hypot(curve[:, 0] - r1, curve[:, 1])) < 0.05
    # the slow judgement: the family's cut gears' lock and first contact
    later = _rows(DesignView(rows=view.later()))
    gears = study.gears
    entry = study.entry_contacts(gears.driver.polygon, gears.driven.polygon)[0]
    assert later["lock: nominal locking play in all"].value == pytest.approx(
        2 * gears.locks[0].nominal_play_deg, abs=TOL
    )
    assert later["first contact after the dwell's end"].value == entry["after_dwell_end_deg"]
    below = max(entry["driver_radius_below_tip_m"], entry["driven_radius_from_tip_m"])
    assert later["first contact: below a tip by"].value == below
    assert all(r.ok for r in later.values())


def test_a_law_the_picker_cannot_carry_is_refused(picker_page):
    problem, _ = picker_page
    x = np.array([40.0, 0.8, 20.0])  # 320 deg of motion in 20 teeth: the driver's sector does not close
    view = problem.view(x)
    with pytest.raises(TransplanterError, match="sector"):
        view.later()
    assert problem(x) == problem.infeasible


def test_an_incomplete_pair_s_curvature_and_pressure_deviation():
    # a constant ratio: the sectors are circles
    law = IntermittentLaw.parse("0..90: dwell; 90..360: 4/3*phi")
    pair = IncompletePair(law, 70.0)
    phi = np.radians(np.linspace(95.0, 355.0, 9))
    r1 = 70.0 * (4 / 3) / (1 + 4 / 3)
    assert np.allclose(pair.curvature(phi, "driver"), 1 / r1, rtol=1e-12)
    assert np.allclose(pair.curvature(phi, "driven"), 1 / (70.0 - r1), rtol=1e-12)
    assert np.allclose(pair.pressure_deviation(phi), 0.0, atol=1e-12)
    # a modified sine: the curvature of the points themselves, by central differences
    law = IntermittentLaw.parse(
        "0..60: dwell; 60..360: 2*pi*(phi - pi/3)/(5*pi/3) - 0.3*sin(2*pi*(phi - pi/3)/(5*pi/3))"
    )
    for mesh in ("external", "internal"):
        if mesh == "internal":
            law = IntermittentLaw.parse("0..90: dwell; 90..360: 4/9*(phi - pi/2) - 0.1*sin(4*(phi - pi/2)/3)")
        pair = IncompletePair(law, 60.0, mesh)
        m = law.motions[0]
        phi = np.linspace(math.radians(m.start) + 0.1, math.radians(m.end) - 0.1, 7)
        h = 1e-4
        sense = -1.0 if mesh == "external" else 1.0
        for role in ("driver", "driven"):

            def points(f, role=role, m=m, pair=pair, sense=sense):
                if role == "driver":
                    r, th = pair.r1(f, motion=m), f
                else:
                    r, th = pair.r2(f, motion=m), sense * pair.psi_in(m, f)
                return np.stack([r * np.cos(th), r * np.sin(th)], axis=1)

            a, b, c = points(phi - h), points(phi), points(phi + h)
            d1, d2 = (c - a) / (2 * h), (c - 2 * b + a) / h**2
            k = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(d1[:, 0], d1[:, 1]) ** 3
            k *= -1.0 if (role == "driven" and mesh == "external") else 1.0  # the driven's angle runs back
            assert np.allclose(pair.curvature(phi, role, m), k, rtol=1e-6), (mesh, role)
        nu = np.arctan2(np.abs(pair.r1(phi, 1, motion=m)) / m.ratio(phi), pair.r2(phi, motion=m))
        assert np.allclose(np.abs(pair.pressure_deviation(phi, m)), np.abs(nu), rtol=0, atol=1e-12)


# -- make parts: the design written where the part script reads it, and made ----------------------


def _written(tmp_path: Path, script: str, design_module: str, name: str, x) -> dict:
    """The part script's namespace after ``x`` is recorded in ``name`` of a copy of ``parts/``
    (the writer ``make parts`` and ``optimise --write`` use)."""
    import shutil

    from transplanter.families.builder.optimum import find_optimum, module_file, record_optimum

    copy = tmp_path / "parts"
    shutil.copytree(PARTS, copy, ignore=shutil.ignore_patterns("__pycache__"))
    problem, _ = script_problem(copy / script, {}, None)
    choices = tuple(v[0] in problem.choices for v in problem.variables)
    place = find_optimum(module_file(copy / design_module), name, len(problem.variables))
    assert record_optimum(place, x, choices) is not None
    _, names = script_problem(copy / script, {}, None)
    return names


def test_a_design_written_from_the_picker_page_is_the_pair_the_family_makes(tmp_path):
    names = _written(tmp_path, "picking_dwell.py", "picking_dwell.py", "AS_MADE", (72.5, 0.3, 28.7))
    assert names["AS_MADE"] == (72.5, 0.3, 28)  # a choice: its integer part, as the model uses it
    study = names["family"]().parts[0]
    assert study.teeth == 28
    asked = IntermittentLaw.parse(names["law_text"](72.5, 0.3))
    assert study.pair.law.describe() == asked.describe() == "dwell 143.75..216.25 deg, motion 216.25..503.75 deg"
    assert study.pair.law.motions[0].law == asked.motions[0].law
    assert "for 72.5 deg of the driver" in names["family"]().description


def test_a_design_written_from_the_arm_b_page_is_the_arm_the_family_makes(tmp_path):
    x = (130.0, 38.0, 104.0, 88.0, -280.0, 60.0, 318.0)
    names = _written(tmp_path, "fourbar_seed000.py", "fourbar_seed000.py", "MADE_B", x)
    parts = {p.name: p for p in names["family"]().parts}
    assert parts["mechanism_B"].arm == names["arm_b"](x)
    assert parts["mechanism_B_plates"].arm == names["arm_b"](x)
    assert parts["mechanism_A"].arm == names["arm"]("mechanism_A")  # A and C as published


def test_a_design_written_from_the_seed_002_page_is_the_machine_the_family_makes(tmp_path):
    """Seed 002's page writes OPTIMUM_X in _seed002.py; the part script makes its chain, its cam's
    follower and its gear stages cut at EXPONENT — the split the page's slow judgement judges."""
    x = (-0.0304, 0.0694, 0.0219, -0.0212, 0.0176, -0.0013, -0.0532, 0.0364, 150.0, 55.0, 104.0)
    names = _written(tmp_path, "potseedling_seed002.py", "_seed002.py", "OPTIMUM_X", x)
    assert names["OPTIMUM"] == (x[0:4], x[4:8], x[8:11])
    script = run_script(tmp_path / "parts" / "potseedling_seed002.py")
    parts = {p.name: p for p in script["family"]().parts}
    ch = names["chain"](x[0:4], x[4:8])
    assert np.array_equal(parts["open_chain_3R"].chain.beta2(np.linspace(0, 6, 7)), ch.beta2(np.linspace(0, 6, 7)))
    cut = names["cut_split"](ch)
    assert cut.exponent == names["EXPONENT"]
    sized, _ = cut.stage23.sized(module=script["MODULE"])
    phi = np.linspace(0.0, 2 * math.pi, 9)
    assert np.array_equal(parts["gears_2_3"].pair.driver.r(phi), sized.driver.r(phi))
    assert parts["swing_cam"].follower == names["follower"](*x[8:11])
