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


def _pairs_then_within(v, v_key, ps, pe, e_key, tol, turn, extra):
    """What :func:`contact.pairs_within` finds, the way it was found before it: every pair of the
    radius band listed, then those within reach kept."""
    vi, ei = contact.pairs(v, v_key, ps, pe, e_key, tol)
    return contact.within(v, vi, ps, ei, turn[e_key[ei]], extra)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(0.0, 4.0), st.integers(1, 6))
def test_the_pairs_within_reach_are_those_of_the_radius_band_within_reach(seed, turn_max, keys):
    """Vertices anywhere (at the origin, across the ±π cut, on edges through the origin), edges of
    any length, turns up to a whole one: the set of pairs asked by angle too is the set the radius
    band gives, kept within reach."""
    rng = np.random.default_rng(seed)
    n, m = int(rng.integers(0, 300)), int(rng.integers(0, 200))
    v = rng.normal(0.0, 10.0, (n, 2)) * rng.choice([1.0, 1e-3], (n, 1))
    v[: n // 10] = [-5.0, 0.0] + rng.normal(0.0, 1e-9, (n // 10, 2))  # on the cut at ±π
    ps = rng.normal(0.0, 10.0, (m, 2))
    pe = ps + rng.normal(0.0, 1.0, (m, 2)) * rng.choice([0.0, 0.1, 1.0, 10.0], (m, 1))
    turn = rng.uniform(0.0, turn_max, keys)
    if seed % 2:  # gear-like: everything near one circle, small turns, reach ~0.1 rad of it
        at = rng.uniform(-np.pi, np.pi, n + m)
        ring = 10.0 + rng.normal(0.0, 0.05, n + m)
        xy = np.stack([ring * np.cos(at), ring * np.sin(at)], axis=1)
        v, ps = xy[:n], xy[n:]
        pe = ps + rng.normal(0.0, 0.05, (m, 2))
        turn = turn / 80.0
    v_key, e_key = rng.integers(0, keys, n), rng.integers(0, keys, m)
    want = _pairs_then_within(v, v_key, ps, pe, e_key, 0.01, turn, 0.5)
    got = contact.pairs_within(v, v_key, ps, pe, e_key, 0.01, turn, 0.5)
    assert sorted(zip(*got, strict=True)) == sorted(zip(*want, strict=True))


def test_the_proof_asks_each_edge_within_its_reach_with_the_same_figures(seed004_full_tips, proof60, monkeypatch):
    """Issue 46: the meshing sweep's vertex/edge pairs found by radius and angle at once
    (``contact.pairs_within``) give the proof it gave when every pair of a radius band was listed
    first, bit for bit."""
    pair, sizing, ring, planet = seed004_full_tips
    monkeypatch.setattr(contact, "pairs_within", _pairs_then_within)
    reference = meshing.mesh_check(pair, ring, planet, sizing.module, steps=60, teeth=72)
    assert proof60.summary() == reference.summary()
    for field in ("penetration", "backlash", "transmission_error", "contacts", "clearance", "clearance_points"):
        assert np.array_equal(getattr(proof60, field), getattr(reference, field)), field


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
