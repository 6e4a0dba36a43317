"""The meshing proof without blind spots (``transplanter.proof.meshing``): every gap counts, and the
extremes are refined between the samples.

The case is the issue's: seed 004's optimised ring/planet (72/18 teeth, m = 3.33 mm) cut with
the screen's full 1.0 m planet addendum. Its free play closes to ~74 µm where a planet tip slides
down a ring flank 2-3 pitches from the pitch point (the windowed check of old reported 142 µm),
and a planet tip passes the ring 12.4 µm away at mid-play (under the 14.3 µm half budget).
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from transplanter.core.tolerances import CONTACT_TOL_MM
from transplanter.geometry import contact
from transplanter.geometry.backlash import tolerance_budget
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pair_gate import generate_pair
from transplanter.proof import mesh_engine, meshing

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "parts"))


@pytest.fixture(scope="module")
def seed004_full_tips():
    from _seed004 import OPTIMUM, design_train

    pair, sizing = design_train(OPTIMUM).pair.sized(teeth=72)
    ring, planet = generate_pair(pair, ShaperCutter(12, sizing.module), sizing.teeth, addendum=(0.43, 1.0))
    return pair, sizing, ring.polygon, planet.polygon


def _dense(pair, sizing, ring, planet, centre_deg, half_deg=0.6, n=241):
    """The judge: ``n`` driver positions within ``half_deg`` of an angle, exact at each."""
    phi = np.mod(math.radians(centre_deg) + np.radians(np.linspace(-half_deg, half_deg, n)), 2 * math.pi)
    m = mesh_engine.MeshSweep(
        pair, contact.Outline(ring), contact.Outline(planet), sizing.module, phi, math.inf, CONTACT_TOL_MM
    )
    m.all()
    return m


@pytest.fixture(scope="module")
def proof60(seed004_full_tips):
    """The pair's proof at 60 steps as the library makes it, with scipy.signal unimportable (the
    proof's scan of tip passes must not need it): the reference the next two tests hold a variant to."""
    pair, sizing, ring, planet = seed004_full_tips
    with pytest.MonkeyPatch.context() as patch:
        patch.setitem(sys.modules, "scipy.signal", None)  # an import of it fails
        return meshing.mesh_check(pair, ring, planet, sizing.module, steps=60, teeth=72)


def test_every_gap_and_between_the_samples(seed004_full_tips):
    pair, sizing, ring, planet = seed004_full_tips
    windowed = meshing.mesh_check(pair, ring, planet, sizing.module, steps=180, teeth=72, window=3.0, refine=False)
    proof = meshing.mesh_check(pair, ring, planet, sizing.module, steps=180, teeth=72)
    # the window beside the pitch point never sees the tip on the flank; the uniform samples (the
    # proof's own, before refining) step over the floor of the dips
    assert windowed.backlash_min.value > 0.14
    assert proof.backlash.min() > proof.backlash_min.value + 4e-3
    assert 0.070 < proof.backlash_min.value < 0.078
    assert proof.clearance.min() > proof.clearance_min.value + 20e-3
    # a judge 200x denser than the grid around the extremes the proof states finds nothing lower
    for extreme, values in ((proof.backlash_min, "bl"), (proof.clearance_min, "clear")):
        judge = getattr(_dense(pair, sizing, ring, planet, extreme.at_deg, n=121), values)
        assert judge.min() >= extreme.value - 1e-6, values
    # nor at another copy of the dip (the pair has four lobes, two dips each): the proof saw them all
    other = (proof.backlash_min.at_deg + 90.0) % 360.0
    judge = _dense(pair, sizing, ring, planet, other, half_deg=1.0, n=201)
    assert judge.bl.min() >= proof.backlash_min.value - 1e-6
    assert abs(judge.bl.min() - proof.backlash_min.value) < 2e-3
    # the clearance is a figure a designer acts on: below half the budget it is a problem, in µm
    limit = tolerance_budget() / 2
    assert proof.clearance_min.value < limit
    (problem,) = proof.problems(clearance=limit, names=("ring", "planet"))
    assert "µm" in problem and "planet at the middle of its play" in problem
    summary = proof.summary()
    assert summary["refined_samples"] > 0 and summary["backlash_at_driver_deg"][0] == round(
        proof.backlash_min.at_deg, 4
    )


def test_the_bounded_sample_query_keeps_every_figure_exactly(seed004_full_tips, proof60, monkeypatch):
    """Issue 46: the clearance's nearest samples are asked with a bound per step; every distance the
    proof can keep is the tree's own, so the proof's figures are the unbounded query's, bit for bit."""
    pair, sizing, ring, planet = seed004_full_tips
    index = contact.EdgeIndex(contact.Outline(planet))
    rng = np.random.default_rng(46)
    groups = 40
    p = rng.uniform(-40.0, 40.0, (20_000, 2)) + (float(np.mean(planet.exterior.coords, axis=0)[0]), 0.0)
    group = rng.integers(0, groups - 3, len(p))  # the last groups empty
    bounded = index._nearest_samples(p, group, groups)
    full, _ = index._tree.query(p)
    upper = np.full(groups, np.inf)
    np.minimum.at(upper, group, full)
    kept = full - index._half <= upper[group]
    assert np.array_equal(bounded[kept], full[kept])  # every point that can be kept: the same distance
    assert np.all(bounded[~kept] - index._half > upper[group[~kept]])  # the others: still never kept
    assert np.isinf(bounded).any()  # (the bound did spare the tree work)
    # and the proof itself, the same figures as with every point asked without a bound — and, its
    # scan of tip passes included, without importing scipy.signal (0.3 s of a pair call's CPU)
    proof = proof60
    monkeypatch.setattr(contact.EdgeIndex, "_nearest_samples", lambda self, p, g, n: self._tree.query(p)[0])
    reference = meshing.mesh_check(pair, ring, planet, sizing.module, steps=60, teeth=72)
    assert proof.summary() == reference.summary()
    assert np.array_equal(proof.clearance, reference.clearance)
    assert np.array_equal(proof.clearance_points, reference.clearance_points)


def test_a_large_pair_is_meshed_a_few_steps_at_a_time_with_the_same_figures(seed004_full_tips, proof60, monkeypatch):
    """Issue 46: the steps computed together shrink as the outlines grow (the vertex/edge pairs of a
    chunk are held at once: seed 004's 560-tooth ring took ~560 MB at 64 steps), and every figure is
    each step's own, so the proof is the same, bit for bit, for any chunk."""
    pair, sizing, ring, planet = seed004_full_tips
    sweep = _dense(pair, sizing, ring, planet, 0.0, n=9)
    vertices = len(sweep.drv.xy) + len(sweep.drn.xy)
    assert sweep.chunk == min(mesh_engine.MESH_CHUNK, mesh_engine.MESH_CHUNK * mesh_engine.CHUNK_VERTICES // vertices)
    proof = proof60
    monkeypatch.setattr(mesh_engine, "CHUNK_VERTICES", vertices // 8)  # the smallest chunk, 8 steps
    assert _dense(pair, sizing, ring, planet, 0.0, n=9).chunk == 8
    small = meshing.mesh_check(pair, ring, planet, sizing.module, steps=60, teeth=72)
    assert proof.summary() == small.summary()
    for field in ("penetration", "backlash", "transmission_error", "contacts", "clearance", "clearance_points"):
        assert np.array_equal(getattr(proof, field), getattr(small, field)), field


@given(
    st.lists(st.integers(-3, 3), min_size=0, max_size=40),
    st.sampled_from([0.0, 0.5, 1.0, 2.5]),
    st.booleans(),
)
@settings(max_examples=300, deadline=None, derandomize=True)
def test_the_tip_pass_scan_finds_the_peaks_scipy_finds(levels, prominence, noisy):
    """The scan of tip passes finds its dips as scipy.signal.find_peaks with a prominence would
    (written out: importing scipy.signal costs a pair call 0.36 s of CPU): on signals of few
    levels, so plateaus, equal neighbours and peaks at the ends are common, and with noise."""
    from scipy.signal import find_peaks

    from transplanter.core.extrema import prominent_peaks

    x = np.asarray(levels, dtype=float)
    if noisy:
        x = x + np.random.default_rng(len(levels)).normal(0.0, 0.3, len(x))
    assert np.array_equal(prominent_peaks(x, prominence), find_peaks(x, prominence=prominence)[0])
