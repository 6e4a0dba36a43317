"""Pitch curves and conjugate pairs against closed forms and independent quadrature.

Tolerance: PITCH_REFERENCE = 1e-9 (mm, rad, ratio). Both sides are exact to round-off
(~1e-13 at these sizes), so the bound is sharp; PITCH_CLOSURE_RAD = 1e-9 for closure.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate
from scipy.special import ellipe

from transplanter.core.errors import GeometryError, SpecError
from transplanter.core.tolerances import PITCH_CLOSURE_RAD, PITCH_REFERENCE
from transplanter.geometry.pitch import FourierSeries, GearPair, Mesh, PeriodicIntegral, PeriodicSpline, PitchCurve

ANGLES = np.linspace(-7.0, 13.0, 41)  # several turns, both signs


def test_ellipse_pair_matches_closed_form():
    big_a, e = 40.0, 0.3
    p = big_a * (1 - e * e)
    pair = GearPair.from_driver(PitchCurve.ellipse(big_a, e), Mesh.EXTERNAL, driven_lobes=1)
    assert pair.centre_distance == pytest.approx(2 * big_a, abs=PITCH_REFERENCE)
    assert pair.closure_error < PITCH_CLOSURE_RAD
    psi = np.linspace(0, 2 * math.pi, 37)
    assert np.max(np.abs(pair.driven.r(psi) - p / (1 + e * np.cos(psi)))) < PITCH_REFERENCE
    k = (1 + e) / (1 - e)
    ref = 2 * np.arctan(k * np.tan(ANGLES / 2))
    ref += 2 * math.pi * np.round((ANGLES - ref) / (2 * math.pi))
    assert np.max(np.abs(pair.driven_rotation(ANGLES) - ref)) < PITCH_REFERENCE
    assert pair.ratio_error() < PITCH_REFERENCE


def _lobed_reference(p, e, a, n1, phi, sign):
    """θ2(φ1) for r1 = p/(1 - e cos n1 φ) in closed form; sign -1 external, +1 ring driver."""
    big_a, big_b = (a - p, a * e) if sign < 0 else (p - a, -a * e)
    root = math.sqrt(big_a**2 - big_b**2)
    half = n1 * phi / 2
    t = 2 * np.arctan(math.sqrt((big_a + big_b) / (big_a - big_b)) * np.tan(half))
    t += 2 * math.pi * np.round((2 * half - t) / (2 * math.pi))
    return p / n1 / root * t


@pytest.mark.parametrize(("n1", "n2"), [(1, 2), (2, 1), (2, 3), (3, 2), (3, 3)])
def test_lobed_ellipse_external_pairs(n1, n2):
    big_a, e = 40.0, 0.2
    p = big_a * (1 - e * e)
    kk = n2 / n1
    a_ref = (p + math.sqrt(p * p - (1 - e * e) * p * p * (1 - kk * kk))) / (1 - e * e)
    pair = GearPair.from_driver(PitchCurve.ellipse(big_a, e, n1), "external", n2)
    assert pair.centre_distance == pytest.approx(a_ref, abs=PITCH_REFERENCE)
    assert pair.closure_error < PITCH_CLOSURE_RAD
    ref = _lobed_reference(p, e, pair.centre_distance, n1, ANGLES, -1)
    assert np.max(np.abs(pair.driven_rotation(ANGLES) - ref)) < PITCH_REFERENCE
    assert pair.driven.lobes == n2


@pytest.mark.parametrize(("n1", "n2"), [(4, 1), (3, 1), (5, 2)])
def test_lobed_ellipse_ring_drives_planet(n1, n2):
    big_a, e = 80.0, 0.05
    p = big_a * (1 - e * e)
    kk = n2 / n1
    a_ref = (p - math.sqrt(p * p - (1 - e * e) * p * p * (1 - kk * kk))) / (1 - e * e)
    pair = GearPair.from_driver(PitchCurve.ellipse(big_a, e, n1), Mesh.INTERNAL, n2)
    assert pair.ring == "driver"
    assert pair.centre_distance == pytest.approx(a_ref, abs=PITCH_REFERENCE)
    assert pair.closure_error < PITCH_CLOSURE_RAD
    ref = _lobed_reference(p, e, pair.centre_distance, n1, ANGLES, +1)
    assert np.max(np.abs(pair.driven_rotation(ANGLES) - ref)) < PITCH_REFERENCE
    assert pair.ratio_error() < PITCH_REFERENCE
    assert pair.centre_distance_error() < PITCH_REFERENCE


@pytest.mark.parametrize("n2", [1, 2])
def test_eccentric_pair_against_quadrature(n2):
    # The conjugate of an eccentric circle has no elementary closed form (elliptic integrals);
    # the reference is the closed-form driver radius integrated by adaptive quadrature.
    big_r, off = 30.0, 8.0

    def r1(t):
        return off * math.cos(t) + math.sqrt(big_r**2 - off**2 * math.sin(t) ** 2)

    pair = GearPair.from_driver(PitchCurve.eccentric_circle(big_r, off), "external", n2)
    a = pair.centre_distance
    turn = integrate.quad(lambda t: r1(t) / (a - r1(t)), 0, 2 * math.pi, epsabs=1e-13, epsrel=1e-13, limit=200)[0]
    assert turn == pytest.approx(2 * math.pi / n2, abs=PITCH_REFERENCE)
    for phi in (0.3, 2.0, 4.5, 6.0):
        ref = integrate.quad(lambda t: r1(t) / (a - r1(t)), 0, phi, epsabs=1e-13, epsrel=1e-13)[0]
        assert float(pair.driven_rotation(phi)) == pytest.approx(ref, abs=PITCH_REFERENCE)
        assert float(pair.driven.r(-ref)) == pytest.approx(a - r1(phi), abs=PITCH_REFERENCE)


def test_planet_drives_ring():
    pair = GearPair.from_driver(PitchCurve.ellipse(20.0, 0.2), "internal", 3)
    assert pair.ring == "driven"
    assert pair.closure_error < PITCH_CLOSURE_RAD
    assert pair.ratio_error() < PITCH_REFERENCE
    assert pair.centre_distance_error() < PITCH_REFERENCE
    assert pair.driven.perimeter == pytest.approx(3 * pair.driver.perimeter, rel=1e-12)


def test_ratio_is_recovered_from_the_curves():
    ratio = FourierSeries(1.0, (0.3, 0.05), (0.1,))  # mean 1: one driven lobe
    pair = GearPair.from_ratio(ratio, centre_distance=100.0)
    phi = np.linspace(0, 2 * math.pi, 721)
    assert np.max(np.abs(pair.ratio(phi) - ratio(phi))) < PITCH_REFERENCE
    assert pair.ratio_error() < PITCH_REFERENCE
    assert pair.closure_error < PITCH_CLOSURE_RAD


def test_ratio_from_samples_internal():
    # ring with 3 lobes drives a 1-lobed planet: ratio ω2/ω1 > 1 with mean 3 over a ring lobe
    lobe = 2 * math.pi / 3
    x = np.linspace(0, lobe, 9, endpoint=False)
    shape = 1 + 0.1 * np.sin(3 * x) ** 2
    total = PeriodicIntegral(PeriodicSpline(x, shape, period=lobe), lobe).total
    ratio = PeriodicSpline(x, shape * 2 * math.pi / total, period=lobe)  # spline is linear in its values
    pair = GearPair.from_ratio(ratio, 40.0, "internal", ring="driver")
    assert pair.ring == "driver" and pair.lobes == (3, 1)
    assert pair.ratio_error() < PITCH_REFERENCE
    assert np.max(np.abs(pair.ratio(x) - ratio(x))) < PITCH_REFERENCE
    off = PeriodicSpline(x, shape * 2.5 / 3 * 2 * math.pi / total, period=lobe)
    with pytest.raises(GeometryError, match="integer number of lobes"):
        GearPair.from_ratio(off, 40.0, "internal", ring="driver")


def test_bad_ratios_are_rejected():
    with pytest.raises(GeometryError, match="ratio .* must be > 0"):
        GearPair.from_ratio(FourierSeries(0.5, (0.6,)), 100.0)
    with pytest.raises(GeometryError, match="integer number of lobes"):
        GearPair.from_ratio(FourierSeries(0.9, (0.2,)), 100.0)
    with pytest.raises(GeometryError, match="needs ratio"):
        GearPair.from_ratio(FourierSeries(1.0, (0.2,)), 50.0, "internal", ring="driven")


def test_bad_curves_are_rejected():
    with pytest.raises(SpecError, match="radii"):
        PitchCurve.from_polar_points([0, 1, 2, 3], [10, float("nan"), 10, 10])
    with pytest.raises(SpecError, match=r"radii\[1\]"):
        PitchCurve.from_polar_points([0, 1, 2, 3], [10, -1, 10, 10])
    with pytest.raises(GeometryError, match="must be > 0 everywhere"):
        PitchCurve.from_fourier(1.0, (2.0,))
    with pytest.raises(SpecError, match="angles must increase"):
        PitchCurve.from_polar_points([0, 2, 1, 3], [10, 11, 12, 10])
    with pytest.raises(GeometryError, match="different lobe numbers"):
        GearPair.from_driver(PitchCurve.ellipse(40, 0.2), "internal", 1)
    with pytest.raises(GeometryError, match="does not close"):
        GearPair.from_driver(PitchCurve.ellipse(40, 0.2), "external", 1, centre_distance=81.0)


def test_curve_geometry_against_closed_forms():
    big_a, e = 40.0, 0.3
    c = PitchCurve.ellipse(big_a, e)
    assert c.perimeter == pytest.approx(4 * big_a * ellipe(e * e), abs=PITCH_REFERENCE)
    b = big_a * math.sqrt(1 - e * e)
    assert c.max_curvature().value == pytest.approx(big_a / b**2, abs=PITCH_REFERENCE)  # major vertex
    assert c.min_curvature().value == pytest.approx(b / big_a**2, abs=PITCH_REFERENCE)  # minor vertex
    assert c.max_pressure_deviation() == pytest.approx(math.asin(e), abs=PITCH_REFERENCE)
    s = np.array([1.0, 100.0, 245.0, 500.0])
    assert np.max(np.abs(c.arc_length(c.angle_at_arc_length(s)) - s)) < PITCH_REFERENCE
    phi = np.linspace(0, 2 * math.pi, 50)
    assert np.max(np.abs(c.pressure_angle(phi) + c.pressure_deviation(phi) - math.pi / 2)) < 1e-15
    circle = PitchCurve.circle(25.0)
    assert circle.perimeter == pytest.approx(50 * math.pi, abs=PITCH_REFERENCE)
    assert np.allclose(circle.curvature(phi), 1 / 25.0, atol=1e-15)


def _wavy_pair():
    driver = PitchCurve.from_fourier(40.0, (0.0, 0.0, 0.0, 3.5), (2.0,))  # 16 * 3.5 > 40: concave in places
    return GearPair.from_driver(driver, "external", 1)


def test_convexity_index_matches_curvature():
    pair = _wavy_pair()
    ci = pair.convexity_index(720)
    phi = ci.angles
    k1 = pair.driver.curvature(phi)
    k2 = pair.driven.curvature(pair.driven_contact_angle(phi))
    assert np.array_equal(ci.p_a > 0, k1 > 0)
    assert np.array_equal(ci.p_b > 0, k2 > 0)
    assert not pair.driver.is_convex and ci.p < 0
    # seed 002 eq 19 with the primes restored gives the driver's radius of curvature
    a = pair.centre_distance
    r, r1, r2 = pair.driver.r(phi), pair.driver.r(phi, 1), pair.driver.r(phi, 2)
    big_i, di = a / r - 1, -a * r1 / r**2
    ddi = a * (2 * r1**2 / r**3 - r2 / r**2)
    rho1 = a * (1 + (di / (1 + big_i)) ** 2) ** 1.5 / (1 + big_i + ddi)
    assert np.max(np.abs(rho1 * k1 - 1)) < PITCH_REFERENCE
    with pytest.raises(GeometryError, match="concave at"):
        pair.driver.require_convex()
    assert pair.driver.min_concave_radius() == pytest.approx(-1 / pair.driver.min_curvature().value)


def test_sizing():
    pair = GearPair.from_driver(PitchCurve.ellipse(40.0, 0.3, 2), "external", 2)
    same, s = pair.sized(teeth=40)
    assert same is pair and s.teeth == (40, 40) and s.scale == 1.0
    assert s.module == pytest.approx(pair.driver.perimeter / (40 * math.pi), rel=1e-15)
    scaled, s2 = pair.sized(module=2.5)
    assert s2.teeth[0] % 2 == 0
    assert scaled.driver.perimeter == pytest.approx(s2.teeth[0] * math.pi * 2.5, abs=PITCH_REFERENCE)
    assert scaled.driven.perimeter == pytest.approx(s2.teeth[1] * math.pi * 2.5, abs=PITCH_REFERENCE)
    assert scaled.closure_error < PITCH_CLOSURE_RAD
    with pytest.raises(SpecError, match="multiple of the driver's 2 lobes"):
        pair.sized(teeth=41)
    with pytest.raises(SpecError, match="exactly one"):
        pair.sized()


@settings(max_examples=25, deadline=None)
@given(
    c1=st.floats(-0.15, 0.15),
    s1=st.floats(-0.15, 0.15),
    c2=st.floats(-0.05, 0.05),
    n1=st.integers(1, 4),
    n2=st.integers(1, 4),
    internal=st.booleans(),
)
def test_random_pairs_close(c1, s1, c2, n1, n2, internal):
    driver = PitchCurve.from_fourier(50.0, (50 * c1, 50 * c2), (50 * s1,), lobes=n1)
    if internal and n1 == n2:
        n2 = n1 + 1
    pair = GearPair.from_driver(driver, "internal" if internal else "external", n2)
    assert pair.closure_error < PITCH_CLOSURE_RAD
    assert pair.ratio_error() < PITCH_REFERENCE
    assert pair.centre_distance_error() < PITCH_REFERENCE
    # rolling: equal arc lengths per lobe
    assert pair.driver.perimeter / n1 == pytest.approx(pair.driven.perimeter / n2, rel=1e-11)
