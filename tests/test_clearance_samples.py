"""The clearance search starts from a few of the motion grid's positions and measures the rest
only for display, and only where a pair may be the nearest (issue 46): its figure still brackets
the continuous minimum, the display's bound below holds at every position, and the slider's
nearest pair per position is the full table's."""

from __future__ import annotations

import math

import numpy as np
import shapely

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


def _truth(a: Posed, b: Posed, n: int = 72_000) -> float:
    t = 2 * math.pi * np.arange(n) / n
    return float(clearance._distances(a, b, t).min())


def test_the_figure_brackets_the_continuous_minimum_and_far_pairs_measure_few_poses():
    for a, b in _pairs():
        found = closest_approach(a, b, THETA)
        truth = _truth(a, b)
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
