"""Seed 002's page in the design studio (``parts/_seed002.py`` ``view``): what it shows of a design
is what the library computes — the search's cost and the part script's build — and a design the
model rejects is said, not drawn. The quick view builds no gear stage (they are most of a design's
time); ``later`` draws and judges them."""

from __future__ import annotations

import math
import pickle
from pathlib import Path

import numpy as np
import pytest
import shapely

from transplanter.app.optimise import script_problem
from transplanter.app.studio import named_designs
from transplanter.app.studio.session import Session
from transplanter.core.errors import GeometryError, TransplanterError
from transplanter.design.linkage.open_chain import OpenChain3R
from transplanter.design.views import DesignView
from transplanter.families import run_script
from transplanter.geometry.cams import OscillatingRollerFollower, disc_cam
from transplanter.geometry.pitch import PeriodicSpline

PARTS = Path(__file__).resolve().parents[1] / "parts"
N = 720  # the search's samples of a cycle


@pytest.fixture(scope="module")
def seed():
    with pytest.MonkeyPatch.context() as mp:
        mp.syspath_prepend(str(PARTS))
        import _seed002

        yield _seed002


def _rows(view: DesignView) -> dict:
    return {r.name: r for r in view.rows}


def _cam(ch, pivot, arm, base, n=N):
    """The swing cam of chain ``ch`` built here from the library alone."""
    tau = 2 * math.pi * np.arange(720) / 720
    b = ch.beta2(tau)
    motion = PeriodicSpline(tau, b - b.min(), degree=5)
    f = OscillatingRollerFollower(pivot_distance=pivot, arm_length=arm, roller_radius=8.0, base_radius=base)
    return disc_cam(motion, f, n=n, max_pressure_angle=math.radians(89))


def test_the_view_at_the_optimum_is_what_the_library_computes(seed):
    x = seed.OPTIMUM_X
    view = seed.view(x)
    assert isinstance(view, DesignView) and len(view.panels) == 3
    rows = _rows(view)
    assert "gear stages: smaller convexity index p" not in rows  # later's
    ch = seed.chain(*seed.OPTIMUM[:2])
    pivot, arm, base = seed.OPTIMUM[2]
    cam = _cam(ch, pivot, arm, base)
    worst = math.degrees(cam.max_pressure_angle)
    r = rows["swing cam: largest pressure angle"]
    assert r.value == pytest.approx(worst, abs=1e-9) and r.margin == pytest.approx(46.0 - worst, abs=1e-9) and r.ok
    assert rows["swing cam: smallest convex radius of the profile"].value == pytest.approx(cam.min_convex_radius, 1e-9)
    tau = 2 * math.pi * np.arange(N) / N
    rel = float(np.min(ch.beta2(tau, 1) + ch.beta3(tau, 1)))
    r = rows["arm relative to carrier 1: min(β2' + β3')"]
    assert r.value == pytest.approx(rel, abs=1e-12) and r.margin == pytest.approx(rel - 0.05, abs=1e-12) and r.ok
    prime = base + 8.0
    r = rows["follower reaches the cam: prime radius (base + roller)"]
    reach = min(prime - abs(pivot - arm) - 1.0, pivot + arm - 1.0 - prime)
    assert r.value == prime and r.margin == pytest.approx(reach, abs=1e-12) and r.ok
    r = rows["Table 1 poses: claw tip off"]
    assert r.value < 1e-9 and r.ok
    # the search's cost is the pressure angle (the convexity floor met): the view judges as it does
    assert seed.problem()(np.array(x)) == pytest.approx(worst, abs=1e-9)
    # the recorded optimum: under the part script's limit
    assert worst < 46.0
    # the cam panel draws that profile
    profile = next(c for c in view.panels[1].curves if c.name == "cam profile")
    assert np.max(np.abs(profile.xy - cam.profile)) < 1e-9


def test_the_chain_is_posed_in_the_machine_frame_at_every_sample(seed):
    from transplanter.machine.carriers import machine_frame

    view = seed.view(seed.OPTIMUM_X)
    ch = seed.chain(*seed.OPTIMUM[:2])
    pose = view.pose
    assert pose.panel == 0 and pose.label == "input angle (deg)"
    assert pose.lines.shape == (N, 4, 2) and pose.angles.shape == (N,)
    assert pose.angles[1] == pytest.approx(360.0 / N) and np.all(np.isfinite(pose.lines))
    assert np.all(pose.lines[:, 0] == 0.0)  # A0, the machine frame's origin
    curves = {c.name: c for c in view.panels[0].curves}
    assert np.array_equal(curves["claw tip"].xy, pose.lines[:, 3])
    # the links keep their lengths; the frame is the machine's turn about A0
    l1, l2, l3 = ch.link_lengths
    for k, length in enumerate((l1, l2, l3)):
        assert np.allclose(np.linalg.norm(pose.lines[:, k + 1] - pose.lines[:, k], axis=1), length, atol=1e-9)
    cx, cy, turn = machine_frame(ch)
    st = ch.state(np.radians(pose.angles))
    c, s = math.cos(turn), math.sin(turn)
    p = st.tip - [cx, cy]
    assert np.allclose(pose.lines[:, 3], np.stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]], 1), atol=1e-9)
    # Table 1's Q marked as far from A0 as in the paper's frame; the claw at pose 2 inside the picked pot
    table = np.array([[q.x, q.y] for q in ch.poses.poses])
    marks = curves["Table 1 poses (Q)"]
    assert marks.kind == "mark"
    assert np.allclose(np.linalg.norm(marks.xy, axis=1), np.linalg.norm(table - [cx, cy], axis=1), atol=1e-9)
    pot = shapely.Polygon(curves["picked pot"].xy)
    tip2 = curves["claw tip at the poses"].xy[1]
    assert pot.contains(shapely.Point(tip2))
    assert curves["pot tray"].kind == "obstacle" and curves["soil"].kind == "obstacle"
    # the charts are charts, the drawings drawings
    assert [p.equal for p in view.panels] == [True, True, False]


def test_later_draws_and_judges_the_gear_stages_and_the_part_script_s_cut(seed):
    later = seed.view(seed.OPTIMUM_X).later()
    assert isinstance(later, DesignView) and later.later is None
    rows = _rows(later)
    assert len(rows) == 4 == len(later.rows)
    ch = seed.chain(*seed.OPTIMUM[:2])
    # the gear stages as the search splits them (its cost's call): the convexity row and the panels
    dist = ch.distribute((45.0, 45.0), exponent=0.5, samples=N)
    r = rows["gear stages: smaller convexity index p"]
    assert r.value == pytest.approx(dist.p, abs=1e-9) and r.margin == pytest.approx(dist.p - 0.3, abs=1e-9) and r.ok
    assert dist.p > 0.5  # the recorded optimum: both stages convex
    assert [p.equal for p in later.panels] == [False, True, True]
    ratios = {c.name: c.xy for c in later.panels[0].curves}
    chart = np.linspace(0.0, 2 * math.pi, N + 1)
    assert np.allclose(ratios["stage 2-3: ω3/ω2"][:, 1], dist.stage23.ratio(chart), rtol=0, atol=1e-9)
    speeds = ch.beta2(chart, 1) + ch.beta3(chart, 1)
    assert np.allclose(ratios["β2' + β3' = 1/I (arm)"][:, 1], speeds, rtol=0, atol=1e-9)
    phi = 2 * math.pi * np.arange(N) / N
    for panel, pair, p in zip(later.panels[1:], (dist.stage23, dist.stage35), dist.convexity, strict=True):
        driver, driven = panel.curves
        assert f"p = {p:.3f}" in panel.title
        assert np.max(np.abs(driver.xy - pair.driver.points(phi))) < 1e-9
        p2 = pair.driven.points(phi)  # in mesh: turned by π about the driven centre at (a, 0)
        assert np.max(np.abs(driven.xy - np.stack([pair.centre_distance - p2[:, 0], -p2[:, 1]], 1))) < 1e-9
    # the part script's cut: λ = EXPONENT over 1440 samples, the cam over 3600
    cut = ch.distribute((45.0, 45.0), exponent=seed.EXPONENT)
    assert [r.value for r in later.rows[1:3]] == pytest.approx(list(cut.convexity), abs=1e-9)
    made = math.degrees(_cam(ch, *seed.OPTIMUM[2], n=3600).max_pressure_angle)
    assert later.rows[3].value == pytest.approx(made, abs=1e-9)
    assert all(r.ok for r in later.rows)
    # it travels back from the forked child that runs it
    back = pickle.loads(pickle.dumps(later))
    assert back.rows == later.rows and np.array_equal(back.panels[1].curves[0].xy, later.panels[1].curves[0].xy)


def test_the_quick_view_builds_no_gear_stage(seed, monkeypatch):
    def refused(*args, **kwargs):
        raise AssertionError("the quick view split the ratio")

    x = list(seed.OPTIMUM_X)
    x[0] += 0.0123  # a design not kept
    with monkeypatch.context() as mp:
        mp.setattr(OpenChain3R, "distribute", refused)
        view = seed.view(x)
        with pytest.raises(AssertionError, match="split the ratio"):
            view.later()
    assert _rows(view.later())["gear stages: smaller convexity index p"].value == pytest.approx(
        seed.chain(x[0:4], x[4:8]).distribute((45.0, 45.0), exponent=0.5, samples=N).p, abs=1e-12
    )


def test_moving_the_follower_keeps_the_curves_work(seed):
    x = list(seed.OPTIMUM_X)
    first = seed.view(x)
    x[9] += 0.5  # arm_mm
    moved = seed.view(x)
    assert seed.curves(tuple(x[:8])) is seed.curves(tuple(seed.OPTIMUM_X[:8]))
    a, b = _rows(first), _rows(moved)
    for name in ("arm relative to carrier 1: min(β2' + β3')", "Table 1 poses: claw tip off"):
        assert b[name] == a[name]
    assert moved.panels[0] is first.panels[0] and moved.pose is first.pose
    ch = seed.chain(*seed.OPTIMUM[:2])
    worst = math.degrees(_cam(ch, x[8], x[9], x[10]).max_pressure_angle)
    assert b["swing cam: largest pressure angle"].value == pytest.approx(worst, abs=1e-9)
    assert b["swing cam: largest pressure angle"].value != a["swing cam: largest pressure angle"].value


@pytest.mark.parametrize(
    ("x", "said"),
    [
        ((0.0,) * 8 + (100.0, 25.0, 60.0), "cannot reach the prime circle"),  # prime 68 mm < |100 - 25|
        ((-0.1,) * 8 + (152.21, 54.45, 103.67), "stops or reverses"),  # β2' + β3' < 0 near τ = 58 deg
        ((0.0,) * 8 + (100.0, 25.0, 116.5), "exceeds the limit 89.0 deg"),  # the roller near the arm's full reach
    ],
)
def test_a_design_the_model_rejects_raises_and_the_studio_says_so(seed, x, said):
    with pytest.raises(GeometryError, match=said):
        seed.view(x)
    computed = Session(seed.problem(), x).compute()
    assert computed.view is None and "cannot be built" in computed.error and said in computed.error
    assert issubclass(GeometryError, TransplanterError)


def test_a_reversing_arm_is_refused_in_the_gear_stages_words(seed):
    """The quick view checks β2' + β3' itself (it builds no gear stage): the same refusal, the same words."""
    x = (-0.1,) * 8 + seed.OPTIMUM_X[8:]
    with pytest.raises(GeometryError) as quick:
        seed.view(x)
    with pytest.raises(GeometryError) as stages:
        seed.chain(x[0:4], x[4:8]).distribute((45.0, 45.0), exponent=0.5, samples=N)
    assert str(quick.value) == str(stages.value)


def test_a_design_short_of_the_search_floors_fails_its_rows(seed):
    plain = seed.view(seed.START)  # the plain start: above 46 deg, a stage not convex
    start = _rows(plain)
    assert not start["swing cam: largest pressure angle"].ok
    assert _rows(plain.later())["gear stages: smaller convexity index p"].margin < 0
    assert start["follower reaches the cam: prime radius (base + roller)"].ok
    slow = _rows(seed.view((-0.08,) * 4 + (-0.1,) * 4 + seed.OPTIMUM_X[8:]))
    r = slow["arm relative to carrier 1: min(β2' + β3')"]
    assert 0.0 < r.value < 0.05 and r.margin < 0 and not r.ok
    near = _rows(seed.view(seed.OPTIMUM_X[:8] + (100.0, 32.0, 60.5)))  # prime 68.5: 0.5 mm past |d - arm|
    r = near["follower reaches the cam: prime radius (base + roller)"]
    assert r.margin == pytest.approx(-0.5) and not r.ok


def test_the_part_script_opens_the_page_with_the_optimum_offered(seed):
    problem, names = script_problem(PARTS / "potseedling_seed002.py", {}, None)
    assert problem.view is not None
    designs = named_designs(problem, names)
    assert designs["OPTIMUM_X"] == tuple(seed.OPTIMUM_X) and "START" in designs


def test_the_problem_still_pickles_for_a_search_s_workers():
    """``transplanter optimise --workers`` ships the problem (its view too) by cloudpickle from a
    module that was run, not imported: the view's memo pickles, empty."""
    cloudpickle = pytest.importorskip("cloudpickle")
    ns = run_script(PARTS / "_seed002.py")
    problem = ns["problem"]()
    x = np.array(ns["OPTIMUM_X"])
    problem.view(x)  # something kept
    blob = cloudpickle.dumps(problem)
    assert len(blob) < 200_000  # the kept chains and gear stages are left behind
    assert cloudpickle.loads(blob)(x) == pytest.approx(problem(x), abs=1e-12)
