"""The clearance search starts from a few of the motion grid's positions and measures the rest
only for display, and only where a pair may be the nearest (issue 46): its figure still brackets
the continuous minimum, the display's bound below holds at every position, and the slider's
nearest pair per position is the full table's."""

from __future__ import annotations

import functools
import math

import numpy as np
import shapely

from transplanter.machine.bodies import Pair, judge_pairs
from transplanter.proof import clearance
from transplanter.proof.clearance import CLEARANCE_TOL_MM, Posed, closest_approach, least_of

THETA = 2 * math.pi * np.arange(360) / 360


def _crank(radius: float, phase: float, rate: float = 1.0):
    def pose(t):
        t = np.asarray(t, dtype=float)
        a = rate * t + phase
        return radius * np.cos(a), radius * np.sin(a), a

    return pose


def _pairs():
    """Blocks on cranks of different radii and phases, each against a fixed pin: some pass it
    close, some stay far."""
    block = shapely.box(-2.0, -1.0, 2.0, 1.0)
    pin = shapely.Point(40.0, 0.0).buffer(1.5, quad_segs=32)
    fixed = Posed(pin, Posed.fixed, speed=0.0)
    out = []
    for radius, phase in ((35.0, 0.3), (30.0, 1.1), (20.0, 2.0), (36.0, -0.7), (10.0, 0.0)):
        moving = Posed(block, _crank(radius, phase), speed=radius + math.hypot(2.0, 1.0))
        out.append((moving, fixed))
    return out


@functools.cache
def _truths(n: int = 72_000) -> tuple[float, ...]:
    """Each of :func:`_pairs`' least distance over ``n`` poses (measured once per session)."""
    t = 2 * math.pi * np.arange(n) / n
    return tuple(float(clearance._distances(a, b, t).min()) for a, b in _pairs())


def test_the_figure_brackets_the_continuous_minimum_and_far_pairs_measure_few_poses():
    for (a, b), truth in zip(_pairs(), _truths(), strict=True):
        found = closest_approach(a, b, THETA)
        # the dense scan is itself a sample: it may sit above the true minimum by its step's worth
        step = (a.speed + b.speed) * math.pi / 72_000
        assert truth - step - 1e-9 <= found.distance <= truth + max(CLEARANCE_TOL_MM, 1e-3 * truth)
        assert found.bound <= truth + 1e-9
    far_a, far_b = _pairs()[-1]  # 10 mm crank, the pin 40 mm out: never nearer than ~26 mm
    assert closest_approach(far_a, far_b, THETA).evaluations < len(THETA) / 2


def test_the_display_bound_holds_and_the_nearest_per_position_is_the_full_tables(monkeypatch):
    found = [closest_approach(a, b, THETA) for a, b in _pairs()]
    measured = []
    real = clearance._distances

    def counted(a, b, t):
        measured.append(len(t))
        return real(a, b, t)

    monkeypatch.setattr(clearance, "_distances", counted)
    least, which = least_of([f.samples for f in found])
    pruned = sum(measured)
    table = np.stack([f.sampled for f in found])  # every position of every pair (the old way)
    assert np.array_equal(least, table.min(axis=0)) and np.array_equal(which, table.argmin(axis=0))
    for f in found:
        assert np.all(f.samples.lower <= f.sampled + 1e-9)
    assert pruned < sum(measured) - pruned  # the nearest found measuring fewer than the table's rest
    # a slice of the samples (a there-and-back figure unwound onto the grid) is the same samples
    half = found[0].samples[:180]
    assert np.array_equal(half.values, found[0].sampled[:180])


def test_steady_samples_need_no_bodies():
    s = clearance.Samples.steady(THETA, 2.5)
    assert np.all(s.values == 2.5) and np.all(s.lower == 2.5) and len(s[::2]) == 180


def test_a_narrow_pass_between_the_starting_positions_is_bracketed():
    """A thin blade on a crank just misses a pin between two of the ~48 positions the search
    starts from (every 7th of a 360-position grid): the bound still finds the 0.15 mm pass."""
    blade = shapely.box(0.0, -0.05, 29.75, 0.05)
    pin = shapely.Point(30.0, 0.3).buffer(0.1, quad_segs=64)

    def pose(t):
        t = np.asarray(t, dtype=float)
        return np.zeros_like(t), np.zeros_like(t), t - math.radians(2.93)  # the pass 3.5° after a start

    found = closest_approach(Posed(blade, pose, speed=29.75), Posed(pin, Posed.fixed, speed=0.0), THETA)
    start = found.samples.known[~np.isnan(found.samples.known)]
    assert len(start) <= 60 and start.min() > 1.0  # the starting positions see nothing near
    near = np.linspace(-0.05, 0.05, 20_001)
    truth = min(
        shapely.distance(shapely.affinity.rotate(blade, float(t), origin=(0, 0), use_radians=True), pin) for t in near
    )
    assert 0.14 < truth < 0.16 and truth - 1e-6 <= found.distance <= truth + CLEARANCE_TOL_MM


def test_a_pair_that_must_keep_a_clearance_is_found_to_a_share_of_its_margin():
    """Issue 46: given the clearance a pair must keep, the search stops once it has shown the pair
    ``MARGIN_REL`` of its margin near its minimum; the bracket still holds the continuous minimum,
    a pair under its clearance is found exactly, and a far pair measures fewer poses."""
    for (a, b), truth in zip(_pairs(), _truths(), strict=True):
        step = (a.speed + b.speed) * math.pi / 72_000
        for need in (1.0, 3.0):
            found = closest_approach(a, b, THETA, need=need)
            assert found.bound <= truth + 1e-9 and truth - step - 1e-9 <= found.distance
            exact = max(CLEARANCE_TOL_MM, clearance.CLEARANCE_REL_TOL * found.distance)
            width = found.distance - found.bound
            assert width <= max(exact, clearance.MARGIN_REL * (found.distance - need)) + 1e-12
            assert found.exact == (width <= exact)
            if truth < need:  # under its clearance: the figure a failure states is exact
                assert found.exact
    far_a, far_b = _pairs()[-1]
    far = closest_approach(far_a, far_b, THETA, need=3.0)
    assert not far.exact and far.evaluations < closest_approach(far_a, far_b, THETA).evaluations


def test_a_group_the_record_states_by_its_nearest_gets_it_exactly():
    """``judge_pairs``: far pairs are stated by their lower bound, not exact, but the nearest of
    each group ``stated`` names (and the pair nearest its clearance overall) is found exactly."""
    bodies, pairs = {}, []
    for k, (a, b) in enumerate(_pairs()):
        bodies[f"block_{k}"], bodies[f"pin_{k}"] = a, b
        pairs.append(Pair(f"block_{k}", f"pin_{k}", axial_gap=-1.0))
    far = {"block_1", "block_2", "block_4"}  # 30, 20 and 10 mm cranks: ~6.5, ~16.5, ~26.5 mm from the pin

    def judged(stated):
        verdicts = judge_pairs(bodies, pairs, THETA, 0.5, lambda p: 0.2, stated=stated)
        return {v.pair.a: v.judged for v in verdicts}

    plain = judged(None)
    grouped = judged(lambda p: "far" if p.a in far else None)
    for name, j in grouped.items():
        a, b = bodies[name], bodies[name.replace("block", "pin")]
        truth, step = _truths()[int(name[-1])], (a.speed + b.speed) * math.pi / 72_000
        # the figure (a lower bound where not exact) and the least distance measured bracket the truth
        assert j.bound <= j.distance <= (j.nearest or j.distance) and j.bound <= truth + 1e-9
        assert (j.nearest or j.distance) >= truth - step - 1e-9 and (j.exact or j.distance <= truth + 1e-9)
        if name == "block_3":  # the nearest overall (36 mm crank, ~0.5 mm) is exact either way
            assert j.exact and plain[name].exact
    # the group's nearest, the 30 mm crank: exact only where the group is stated
    assert grouped["block_1"].exact and not plain["block_1"].exact
    assert grouped["block_1"].distance == closest_approach(bodies["block_1"], bodies["pin_1"], THETA).distance
    assert not grouped["block_2"].exact and not grouped["block_4"].exact
    assert grouped["block_2"].distance < grouped["block_2"].nearest
    # without the two near pairs the 30 mm crank is the nearest overall, by margin: exact unasked
    far_pairs = [pairs[k] for k in (1, 2, 4)]
    alone = {v.pair.a: v.judged for v in judge_pairs(bodies, far_pairs, THETA, 0.5, lambda p: 0.2)}
    assert alone["block_1"].exact and not alone["block_2"].exact
    # ... and by distance alone (a report's smallest clearance) where another pair is nearer its
    # own clearance: the 20 mm crank 0.4 mm over its, the 30 mm crank 6.3 mm over 0.2 mm
    needs = {"block_1": 0.2, "block_2": _truths()[2] - 0.4, "block_4": 0.2}
    mixed = {v.pair.a: v.judged for v in judge_pairs(bodies, far_pairs, THETA, 0.5, lambda p: needs[p.a])}
    assert mixed["block_1"].exact and mixed["block_2"].exact and not mixed["block_4"].exact


def test_a_round_body_posed_without_its_turn_keeps_the_bound_below_the_truth():
    """A flattened circle turning about its centre, posed without its turn (its speed its centre's,
    as the machines pose a bearing on a planet): the bound still lies below the turning polygon's
    true minimum, by its wobble (``Posed.wobble``, how far it is out of round) — standing still, and
    with its centre moving."""
    disc = shapely.affinity.rotate(shapely.Point(0.0, 0.0).buffer(10.0, quad_segs=4), 11.25, origin=(0, 0))
    wobble = clearance.out_of_round(disc)  # a 16-gon: 10 (1 - cos(π/16)) = 0.19 mm
    assert abs(wobble - 10 * (1 - math.cos(math.pi / 16))) < 1e-9
    wall = Posed(shapely.box(10.05, -5.0, 15.0, 5.0), Posed.fixed, speed=0.0)
    t = 2 * math.pi * np.arange(20_000) / 20_000
    for shift in (0.0, 0.5):  # the centre still, or moving up to 1 mm back from the wall and up

        def turning(theta, shift=shift):
            theta = np.asarray(theta, dtype=float)
            return shift * (np.cos(theta) - 1.0), shift * np.sin(theta), 3.0 * theta

        def unturned(theta, shift=shift):
            x, y, _ = turning(theta)
            return x, y, np.zeros_like(x)

        truth = float(clearance._distances(Posed(disc, turning, 30.0), wall, t).min())
        found = closest_approach(Posed(disc, unturned, shift, wobble=wobble), wall, THETA)
        assert found.bound <= truth + 1e-9 < found.distance + wobble
        # without its wobble the search would state a bound above the truth
        blind = closest_approach(Posed(disc, unturned, shift), wall, THETA)
        assert blind.bound > truth + 0.05
