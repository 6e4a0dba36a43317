"""Disc cams: the follower moved on the cut contour must reproduce the prescribed motion.

Tolerance 1e-6 rad (1e-5 mm for translating followers): the contour is a polygon of n points
whose chords lie within ~(2π R / n)² / (8 ρ) of the exact profile (2e-6 mm at n = 20000,
R = 60 mm, ρ = 20 mm), which moves a 50 mm follower arm by < 1e-7 rad.
"""

import math

import numpy as np
import pytest
import shapely
from scipy import optimize

from transplanter.core.errors import GeometryError, SpecError
from transplanter.geometry.cams import (
    FlatFacedFollower,
    MotionProgram,
    OscillatingRollerFollower,
    TranslatingRollerFollower,
    disc_cam,
)

RAD = math.radians


@pytest.mark.parametrize("law", ["cycloidal", "345", "modified_sine"])
def test_motion_laws(law):
    m = MotionProgram.rise_return(lift=2.0, rise=RAD(100), dwell=RAD(50), ret=RAD(140), law=law)
    x = np.linspace(0.01, 2 * math.pi - 0.01, 3001)
    h = 1e-6
    for nu in (1, 2):
        fd = (m(x + h, nu - 1) - m(x - h, nu - 1)) / (2 * h)
        assert np.max(np.abs(fd - m(x, nu))) < 1e-5 * max(1.0, np.max(np.abs(m(x, nu))))
    # position and velocity are continuous at every segment joint, the lift is reached
    for b in [*m.breakpoints[1:], 2 * math.pi - 1e-12]:
        for nu in (0, 1):
            assert m(b - 1e-9, nu) == pytest.approx(m(b + 1e-9, nu), abs=1e-6)
    assert float(m(RAD(100))) == pytest.approx(2.0, abs=1e-12)
    assert float(m(0.0)) == 0.0


def _roller_centre(follower, v):
    """Roller centre (follower frame) at follower displacement v."""
    prime = follower.base_radius + follower.roller_radius
    if isinstance(follower, OscillatingRollerFollower):
        d, arm = follower.pivot_distance, follower.arm_length
        g = math.acos((d * d + arm * arm - prime * prime) / (2 * d * arm)) + v
        return d - arm * math.cos(g), arm * math.sin(g)
    return follower.offset, math.sqrt(prime**2 - follower.offset**2) + v


def _move_on_contour(cam, follower, thetas, motion):
    """Largest error of the follower displacement found by touching the roller to the contour."""
    poly = shapely.Polygon(cam.profile)
    boundary = poly.boundary

    def gap(v, th):
        x, y = _roller_centre(follower, v)
        p = shapely.Point(math.cos(th) * x + math.sin(th) * y, -math.sin(th) * x + math.cos(th) * y)
        dist = boundary.distance(p)
        return (-dist if poly.contains(p) else dist) - follower.roller_radius

    errs = []
    for th in thetas:
        want = float(motion(th))
        got = optimize.brentq(gap, want - 0.05, want + 0.05, args=(th,), xtol=1e-13)
        errs.append(got - want)
    return float(np.max(np.abs(errs)))


def test_oscillating_roller_cam_reproduces_the_swing():
    swing = MotionProgram.rise_return(RAD(25), RAD(110), RAD(40), RAD(130), "modified_sine")
    f = OscillatingRollerFollower(pivot_distance=80, arm_length=50, roller_radius=8, base_radius=35)
    cam = disc_cam(swing, f, n=20000)
    assert _move_on_contour(cam, f, np.linspace(0.05, 6.2, 30), swing) < 1e-6


def test_translating_roller_cam_reproduces_the_lift():
    lift = MotionProgram.rise_return(12.0, RAD(120), RAD(30), RAD(120), "345")
    f = TranslatingRollerFollower(roller_radius=6, base_radius=30, offset=5)
    cam = disc_cam(lift, f, n=20000)
    assert _move_on_contour(cam, f, np.linspace(0.05, 6.2, 30), lift) < 1e-5


def test_pressure_angle_matches_a_numerical_check():
    swing = MotionProgram.rise_return(RAD(25), RAD(110), RAD(40), RAD(130), "cycloidal")
    f = OscillatingRollerFollower(80, 50, 8, 35)
    cam = disc_cam(swing, f, n=7200)
    # numerical: the pitch curve's tangent by central differences, rotated back to the follower frame
    th = cam.theta
    tang = (np.roll(cam.pitch, -1, axis=0) - np.roll(cam.pitch, 1, axis=0)) / (2 * (th[1] - th[0]))
    c, s = np.cos(th), np.sin(th)
    tf = np.stack([c * tang[:, 0] - s * tang[:, 1], s * tang[:, 0] + c * tang[:, 1]], axis=1)
    centre = np.stack([c * cam.pitch[:, 0] - s * cam.pitch[:, 1], s * cam.pitch[:, 0] + c * cam.pitch[:, 1]], axis=1)
    arm = centre - [80.0, 0.0]
    move = np.stack([-arm[:, 1], arm[:, 0]], axis=1)
    cosang = np.abs(np.einsum("ij,ij->i", tf, move)) / (np.linalg.norm(tf, axis=1) * np.linalg.norm(move, axis=1))
    numeric = np.arcsin(np.clip(cosang, 0, 1))  # tangent vs motion: the complement of normal vs motion
    assert np.max(np.abs(numeric - cam.pressure_angle)) < 1e-5  # central differences, h = 0.05 deg


def test_flat_faced_follower_touches_the_profile():
    lift = MotionProgram.rise_return(8.0, RAD(150), RAD(20), RAD(150), "cycloidal")
    cam = disc_cam(lift, FlatFacedFollower(base_radius=30.0), n=7200)
    for th in np.linspace(0.1, 6.0, 12):
        c, s = math.cos(th), math.sin(th)
        # the face is the support line of the profile in the follower's +y direction
        y = s * cam.profile[:, 0] + c * cam.profile[:, 1]
        assert y.max() == pytest.approx(30.0 + float(lift(th)), abs=1e-3)
    assert np.all(cam.radius_of_curvature > 0) and cam.max_pressure_angle == 0


def test_cams_that_cannot_be_made():
    swing = MotionProgram.rise_return(RAD(40), RAD(60), RAD(20), RAD(60), "cycloidal")
    with pytest.raises(GeometryError, match=r"pressure angle .* exceeds the limit 45.0 deg"):
        disc_cam(swing, OscillatingRollerFollower(60, 40, 5, 22))
    with pytest.raises(GeometryError, match="undercuts at"):
        disc_cam(
            MotionProgram.rise_return(15.0, RAD(40), RAD(10), RAD(40), "cycloidal"),
            TranslatingRollerFollower(roller_radius=20, base_radius=25),
            max_pressure_angle=RAD(89),
        )
    with pytest.raises(GeometryError, match="cusps"):
        disc_cam(MotionProgram.rise_return(20.0, RAD(40), RAD(10), RAD(40), "cycloidal"), FlatFacedFollower(10.0))
    with pytest.raises(GeometryError, match="cannot reach the prime circle"):
        OscillatingRollerFollower(pivot_distance=200, arm_length=50, roller_radius=8, base_radius=30)
    with pytest.raises(SpecError, match="2π"):
        MotionProgram(((1.0, 1.0, "cycloidal"), (1.0, -1.0, "cycloidal")))
    with pytest.raises(SpecError, match="motion law"):
        MotionProgram.rise_return(1.0, RAD(90), RAD(90), RAD(90), "parabolic")
