"""Seed 000's Denavit-Hartenberg matrix loop against the vector-loop solution."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from transplanter.design.linkage.dh import DHFourBar
from transplanter.design.linkage.fourbar import Link

MECHANISMS = {
    "A": DHFourBar(75.0, 35.0, 75.0, 80.0, np.radians(90.0)),
    "B": DHFourBar(125.0, 40.0, 100.0, 85.0, np.radians(322.0)),
    "C": DHFourBar(120.0, 38.0, 103.0, 75.0, np.radians(282.0)),
}


@pytest.mark.parametrize("name", MECHANISMS)
@pytest.mark.parametrize("branch", [1, -1])
def test_matrix_loop_is_identity(name, branch):
    dh = MECHANISMS[name]
    dh = DHFourBar(dh.a1, dh.a2, dh.a3, dh.a4, dh.phi, branch)
    m = dh.to_fourbar().solve(dh.crank_angle(np.radians(np.arange(0, 360, 5.0))))
    prod = dh.loop_product(m)
    # entries are mm (translations) and cosines: 1e-9 covers round-off of 4 matrix products
    assert np.max(np.abs(prod - np.eye(3))) < 1e-9


@settings(max_examples=50, deadline=None)
@given(st.sampled_from(sorted(MECHANISMS)), st.floats(-400, 400), st.floats(-400, 400), st.floats(0, 2 * np.pi))
def test_coupler_point_by_matrices_equals_vector_loop(name, x3, y3, t2):
    dh = MECHANISMS[name]
    m = dh.to_fourbar().solve(dh.crank_angle(np.array([t2])))
    via_matrices = dh.point_by_matrices(m, x3, y3)
    via_loop = m.point(Link.COUPLER, dh.coupler_point(x3, y3)).position
    np.testing.assert_allclose(via_matrices, via_loop, atol=1e-9)


@pytest.mark.parametrize("name", MECHANISMS)
def test_seed000_velocity_ratio_formulas(name):
    """Seed 000 eqs 6-3/6-4 with the relative pair variables:
    w3/w2 = 1 + a1 sin(t2+t3+t4) / (a3 sin t4), w4/w2 = 1 - a1 sin(t2+t3) / (a4 sin t4)."""
    dh = MECHANISMS[name]
    m = dh.to_fourbar().solve(dh.crank_angle(np.radians(np.arange(0, 360, 10.0))), 8 * np.pi)
    t = dh.relative_angles(m)
    r3 = 1 + dh.a1 * np.sin(t[2] + t[3] + t[4]) / (dh.a3 * np.sin(t[4]))
    r4 = 1 - dh.a1 * np.sin(t[2] + t[3]) / (dh.a4 * np.sin(t[4]))
    np.testing.assert_allclose(m.omega[Link.COUPLER] / (8 * np.pi), r3, atol=1e-12)
    np.testing.assert_allclose(m.omega[Link.ROCKER] / (8 * np.pi), r4, atol=1e-12)


def test_rocker_pivot_in_frame_axes_is_minus_a1():
    dh = MECHANISMS["B"]
    fb = dh.to_fourbar()
    c, s = np.cos(-dh.phi), np.sin(-dh.phi)
    x, y = fb.rocker_pivot
    np.testing.assert_allclose((c * x - s * y, s * x + c * y), (-dh.a1, 0.0), atol=1e-12)
