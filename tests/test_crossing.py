"""How far a moving body crosses into another (``proof.crossing``): the deepest point over the
continuous cycle, bracketed between coarse samples, and minus the distance where they never meet."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from transplanter.core.errors import GeometryError
from transplanter.proof.clearance import Posed
from transplanter.proof.crossing import deepest_crossing, signed_depths


def _crank(section, radius=50.0):
    """``section`` carried round a ``radius`` crank without turning (every point at radius mm/rad)."""
    return Posed(section, lambda t: (radius * np.cos(t), radius * np.sin(t), np.zeros_like(t)), speed=radius)


def test_a_narrow_plunge_between_coarse_samples_is_found_to_the_tolerance():
    """A needle on a 50 mm crank dips 1.2 mm into a block for about 25° of the turn, between
    samples 30° apart that all miss it: the figure is the true 1.2 mm, at θ = 0, and the bound
    holds it within the tolerance; a dense scan never reads deeper than the bound."""
    needle = shapely.box(-0.5, -0.5, 0.5, 0.5)
    a = _crank(needle)
    block = Posed(shapely.box(49.7, -20.0, 80.0, 20.0), Posed.fixed, speed=0.0)  # 50.5 - 49.7 = 0.8 into it
    coarse = np.deg2rad(np.arange(15.0, 360.0, 30.0))  # 15, 45, ...: none of them in the block
    assert signed_depths(a, block, coarse)[1].max() < 0.0
    found = deepest_crossing(a, block, coarse)
    assert found.depth == pytest.approx(0.8, abs=0.01) and found.depth <= 0.8 + 1e-9
    assert abs(math.remainder(found.theta, 2 * math.pi)) < 0.02
    assert found.depth <= found.bound <= found.depth + 0.011
    dense = signed_depths(a, block, np.linspace(0.0, 2 * np.pi, 7200, endpoint=False))[0]
    assert dense.max() <= found.bound + 1e-9


def test_apart_it_is_minus_the_distance_and_through_a_wall_half_its_thickness():
    a = _crank(shapely.box(-0.5, -0.5, 0.5, 0.5))
    far = Posed(shapely.box(60.0, -5.0, 70.0, 5.0), Posed.fixed, speed=0.0)
    found = deepest_crossing(a, far, np.linspace(0.0, 2 * np.pi, 36, endpoint=False))
    assert found.depth == pytest.approx(-9.5, abs=0.01)  # 60 - 50.5 at θ = 0
    # a long bar sweeping through a 6 mm wall: its deepest point is 3 mm inside (the least it
    # must move to leave the wall), whatever the bar's length
    bar = Posed(shapely.box(-40.0, -1.0, 40.0, 1.0), lambda t: (np.zeros_like(t), 10 * np.sin(t), 0 * t), speed=10.0)
    wall = Posed(shapely.box(-3.0, -30.0, 3.0, 30.0), Posed.fixed, speed=0.0)
    assert deepest_crossing(bar, wall, np.linspace(0.0, 2 * np.pi, 12, endpoint=False)).depth == pytest.approx(
        3.0, abs=0.01
    )
    with pytest.raises(GeometryError, match="theta"):
        deepest_crossing(a, far, np.array([1.0, 0.5]))
