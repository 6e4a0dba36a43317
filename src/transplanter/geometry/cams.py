"""Disc cams: oscillating and translating roller followers, translating flat-faced followers.

The follower motion is any periodic function of the cam angle θ (rad, period 2π) with exact
first and second derivatives — a :class:`~transplanter.geometry.pitch.periodic.PeriodicSpline` through
samples, or :class:`MotionProgram` built from dwells and standard rise/return laws
(cycloidal, 3-4-5 polynomial, modified sine). The cam turns counter-clockwise by θ relative to
the follower's frame; the profile is built in the cam's frame:

- **roller followers**: the roller centre ``C(θ)`` in the follower frame, the *pitch curve*
  ``P(θ) = R(-θ) C(θ)`` with exact derivatives, the *working profile* offset inwards by the
  roller radius, the *pressure angle* between the pitch curve's normal and the direction the
  follower can move at the roller centre, and the pitch curve's radius of curvature: where it
  is convex and smaller than the roller, the working profile folds (undercut) and the cam
  cannot be made;
- **flat-faced translating followers**: contact at ``x = s'(θ)`` on the face, the profile's
  radius of curvature is ``R0 + s + s''`` and must stay positive; the pressure angle is 0.

Examples
--------
>>> import math
>>> from transplanter.geometry.cams import MotionProgram, OscillatingRollerFollower, disc_cam
>>> swing = MotionProgram.rise_return(lift=math.radians(20), rise=math.radians(120),
...                                   dwell=math.radians(60), ret=math.radians(120), law="cycloidal")
>>> cam = disc_cam(swing, OscillatingRollerFollower(pivot_distance=80, arm_length=50,
...                                                 roller_radius=8, base_radius=35))
>>> round(math.degrees(cam.max_pressure_angle), 2) < 45
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import MAX_MAGNITUDE, GeometryError, SpecError, check_int, check_number, finite_positive
from transplanter.geometry.pitch.periodic import Periodic

__all__ = [
    "MotionProgram",
    "OscillatingRollerFollower",
    "TranslatingRollerFollower",
    "FlatFacedFollower",
    "CamProfile",
    "disc_cam",
    "roller_centre",
]

TWO_PI = 2 * math.pi


def _law(name: str, u: np.ndarray, nu: int) -> np.ndarray:
    """Normalised rise y(u), u in [0, 1], y(0) = 0, y(1) = 1, and its derivatives in u."""
    if name == "cycloidal":
        return (u - np.sin(TWO_PI * u) / TWO_PI, 1 - np.cos(TWO_PI * u), TWO_PI * np.sin(TWO_PI * u))[nu]
    if name == "345":
        return (
            10 * u**3 - 15 * u**4 + 6 * u**5,
            30 * u**2 - 60 * u**3 + 30 * u**4,
            60 * u - 180 * u**2 + 120 * u**3,
        )[nu]
    if name == "modified_sine":  # Neklutin's modified sine, three pieces
        k = 1 / (4 + math.pi)
        outer = (u <= 1 / 8) | (u >= 7 / 8)
        a = 4 * math.pi * u
        b = math.pi / 3 + 4 * math.pi * u / 3
        shift = np.where(u >= 7 / 8, 4.0, 0.0)
        if nu == 0:
            return k * np.where(outer, shift + math.pi * u - np.sin(a) / 4, 2 + math.pi * u - 9 * np.sin(b) / 4)
        if nu == 1:
            return k * np.where(outer, math.pi - math.pi * np.cos(a), math.pi - 3 * math.pi * np.cos(b))
        return k * np.where(outer, 4 * math.pi**2 * np.sin(a), 4 * math.pi**2 * np.sin(b))
    raise SpecError.out_of_range("motion law", name, "'cycloidal', '345' or 'modified_sine'")


@dataclass(frozen=True)
class MotionProgram(Periodic):
    """Follower displacement over one cam turn from segments ``(duration, change, law)``.

    ``change`` is the rise (> 0), return (< 0) or 0 for a dwell; durations (rad) sum to 2π and
    the changes to 0. Units of ``change`` are the follower's (rad for oscillating, mm for
    translating followers).
    """

    segments: tuple[tuple[float, float, str], ...]
    period: float = field(default=TWO_PI, init=False)

    def __post_init__(self) -> None:
        segs = tuple(
            (
                check_number("segment duration", d, 0.0, TWO_PI, low_open=True, unit="rad"),
                check_number("segment change", c, -MAX_MAGNITUDE, MAX_MAGNITUDE),
                str(law),
            )
            for d, c, law in self.segments
        )
        if not segs:
            raise SpecError("a motion program needs at least one segment")
        total = sum(d for d, _, _ in segs)
        if abs(total - TWO_PI) > 1e-9:
            raise SpecError.out_of_range("sum of segment durations", total, "2π rad (one cam turn)")
        if abs(sum(c for _, c, _ in segs)) > 1e-12 * max(1.0, max(abs(c) for _, c, _ in segs)):
            raise SpecError("motion segments must return to the start: the changes must sum to 0")
        for _, c, law in segs:
            if c != 0:
                _law(law, np.zeros(1), 0)
        object.__setattr__(self, "segments", segs)

    @classmethod
    def rise_return(cls, lift: float, rise: float, dwell: float, ret: float, law: str = "cycloidal") -> MotionProgram:
        """Rise by ``lift`` over ``rise``, dwell ``dwell``, return over ``ret``, dwell the rest (rad)."""
        rest = TWO_PI - rise - dwell - ret
        segs = [(rise, lift, law), (dwell, 0.0, law), (ret, -lift, law)]
        if rest > 1e-12:
            segs.append((rest, 0.0, law))
        return cls(tuple((d, c, law) for d, c, law in segs if d > 0))

    @property
    def breakpoints(self) -> np.ndarray:
        return np.cumsum([0.0] + [d for d, _, _ in self.segments[:-1]])

    def _eval(self, x, nu):
        x = np.mod(x, TWO_PI)
        out = np.zeros(x.shape)
        start, level = 0.0, 0.0
        for d, c, law in self.segments:
            m = (x >= start) & (x < start + d)
            if c != 0:
                u = (x[m] - start) / d
                val = _law(law, u, nu)
                out[m] = (level if nu == 0 else 0.0) + c * val / d**nu
            elif nu == 0:
                out[m] = level
            start += d
            level += c
        return out


@dataclass(frozen=True)
class OscillatingRollerFollower:
    """Follower arm pivoted ``pivot_distance`` from the cam axis (mm), roller at ``arm_length``.

    ``base_radius`` is the cam's base circle (smallest working radius), so the roller centre
    starts on the prime circle ``base_radius + roller_radius``; positive swing moves the roller
    away from the cam axis when ``swing_sense`` is +1.
    """

    pivot_distance: float
    arm_length: float
    roller_radius: float
    base_radius: float
    swing_sense: int = 1

    def __post_init__(self) -> None:
        for name in ("pivot_distance", "arm_length", "roller_radius", "base_radius"):
            finite_positive(name, getattr(self, name))
        if self.swing_sense not in (1, -1):
            raise SpecError.out_of_range("swing_sense", self.swing_sense, "+1 or -1")
        prime = self.base_radius + self.roller_radius
        d, arm = self.pivot_distance, self.arm_length
        if not abs(d - arm) < prime < d + arm:
            raise GeometryError(
                f"the roller cannot reach the prime circle (radius {prime:g} mm) from a pivot {d:g} mm away "
                f"with a {arm:g} mm arm: need |d - arm| < base + roller < d + arm"
            )


@dataclass(frozen=True)
class TranslatingRollerFollower:
    """Roller follower sliding along +y at ``offset`` (mm) from the cam axis."""

    roller_radius: float
    base_radius: float
    offset: float = 0.0

    def __post_init__(self) -> None:
        finite_positive("roller_radius", self.roller_radius)
        finite_positive("base_radius", self.base_radius)
        if not abs(self.offset) < self.base_radius + self.roller_radius:
            raise SpecError.out_of_range("offset", self.offset, "|offset| < base + roller radius")


@dataclass(frozen=True)
class FlatFacedFollower:
    """Flat face perpendicular to the follower's travel (+y), base circle ``base_radius`` (mm)."""

    base_radius: float

    def __post_init__(self) -> None:
        finite_positive("base_radius", self.base_radius)


@dataclass(frozen=True, eq=False)
class CamProfile:
    """A disc cam sampled over one turn (cam frame, mm).

    Attributes
    ----------
    theta : (n,) float
        Cam angles, rad.
    pitch : (n, 2) float or None
        Roller-centre path (roller followers).
    profile : (n, 2) float
        Working profile (the contour to cut).
    pressure_angle : (n,) float
        rad.
    radius_of_curvature : (n,) float
        Of the working profile, mm (negative where concave).
    """

    theta: np.ndarray
    pitch: np.ndarray | None
    profile: np.ndarray
    pressure_angle: np.ndarray
    radius_of_curvature: np.ndarray
    motion: Periodic = field(repr=False)
    follower: object = field(repr=False)

    @property
    def max_pressure_angle(self) -> float:
        return float(np.max(np.abs(self.pressure_angle)))

    @property
    def min_convex_radius(self) -> float:
        rho = self.radius_of_curvature
        pos = rho[rho > 0]
        return float(pos.min()) if pos.size else math.inf

    def follower_position(self, theta) -> np.ndarray:
        """The follower's prescribed displacement at cam angles ``theta``."""
        return self.motion(theta)


def _rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return c, s


def _to_cam(theta, v):
    """R(-θ) v for arrays v (n, 2)."""
    c, s = _rot(theta)
    return np.stack([c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1]], axis=1)


def _roller_frame(follower, s, s1, s2):
    """Roller centre C and its first two θ-derivatives in the follower frame, and the follower's
    unit direction of motion at C, for follower coordinate s and its θ-derivatives s1, s2."""
    if isinstance(follower, OscillatingRollerFollower):
        d, arm = follower.pivot_distance, follower.arm_length
        prime = follower.base_radius + follower.roller_radius
        g0 = math.acos((d * d + arm * arm - prime * prime) / (2 * d * arm))
        g = g0 + follower.swing_sense * s
        g1, g2 = follower.swing_sense * s1, follower.swing_sense * s2
        # pivot at (d, 0); the arm makes angle g with the line from the pivot to the cam axis
        c = np.stack([d - arm * np.cos(g), arm * np.sin(g)], axis=1)
        c1 = np.stack([arm * np.sin(g) * g1, arm * np.cos(g) * g1], axis=1)
        c2 = np.stack([arm * (np.cos(g) * g1**2 + np.sin(g) * g2), arm * (-np.sin(g) * g1**2 + np.cos(g) * g2)], axis=1)
        move = np.stack([np.sin(g), np.cos(g)], axis=1)
        return c, c1, c2, move
    e = follower.offset
    prime = follower.base_radius + follower.roller_radius
    y0 = math.sqrt(prime * prime - e * e)
    c = np.stack([np.full_like(s, e), y0 + s], axis=1)
    c1 = np.stack([np.zeros_like(s), s1], axis=1)
    c2 = np.stack([np.zeros_like(s), s2], axis=1)
    move = np.tile([0.0, 1.0], (len(s), 1))
    return c, c1, c2, move


def roller_centre(follower, s, theta) -> np.ndarray:
    """Roller centre (n, 2) in the cam frame at follower coordinates ``s`` and cam angles ``theta``."""
    s = np.atleast_1d(np.asarray(s, dtype=float))
    theta = np.broadcast_to(np.asarray(theta, dtype=float), s.shape)
    zero = np.zeros_like(s)
    return _to_cam(theta, _roller_frame(follower, s, zero, zero)[0])


def disc_cam(
    motion: Periodic,
    follower,
    n: int = 3600,
    max_pressure_angle: float = math.radians(45.0),
) -> CamProfile:
    """Design the disc cam that gives ``follower`` the ``motion`` (see the module docstring).

    Raises GeometryError naming the cam angle and the limit when the pressure angle exceeds
    ``max_pressure_angle`` or the profile would undercut (radius of curvature vs roller).
    """
    if not isinstance(motion, Periodic) or abs(motion.period - TWO_PI) > 1e-12:
        raise SpecError("motion must be a Periodic function with period 2π (one cam turn)")
    n = check_int("n", n, 8, 1_000_000)
    max_pressure_angle = check_number(
        "max_pressure_angle", max_pressure_angle, 0.0, math.pi / 2, low_open=True, high_open=True, unit="rad"
    )
    theta = TWO_PI * np.arange(n) / n
    if isinstance(follower, FlatFacedFollower):
        s, s1, s2 = motion(theta), motion(theta, 1), motion(theta, 2)
        r0 = follower.base_radius
        if np.min(r0 + s) <= 0:
            raise GeometryError("the flat face reaches the cam axis: raise base_radius")
        contact = np.stack([s1, r0 + s], axis=1)  # in the follower frame
        profile = _to_cam(theta, contact)
        rho = r0 + s + s2
        k = int(np.argmin(rho))
        if rho[k] <= 0:
            raise GeometryError(
                f"flat-faced cam cusps at θ = {math.degrees(theta[k]):.2f} deg (radius of curvature {rho[k]:.4g} mm "
                f"must be > 0): raise base_radius above {r0 - rho[k]:.4g} mm"
            )
        return CamProfile(theta, None, profile, np.zeros(n), rho, motion, follower)
    if not isinstance(follower, OscillatingRollerFollower | TranslatingRollerFollower):
        raise SpecError(f"unknown follower type {type(follower).__name__}")
    c, c1, c2, move = _roller_frame(follower, motion(theta), motion(theta, 1), motion(theta, 2))
    jc = np.stack([-c[:, 1], c[:, 0]], axis=1)
    jc1 = np.stack([-c1[:, 1], c1[:, 0]], axis=1)
    rel1 = c1 - jc  # velocity of the roller centre relative to the cam, follower frame
    rel2 = c2 - 2 * jc1 - c
    pitch = _to_cam(theta, c)
    speed = np.linalg.norm(rel1, axis=1)
    cross = rel1[:, 0] * rel2[:, 1] - rel1[:, 1] * rel2[:, 0]
    rho_pitch = speed**3 / cross  # > 0 where the pitch curve turns left (convex for a CCW curve)
    # pitch curve normal (follower frame) and the pressure angle against the follower's motion
    normal = np.stack([rel1[:, 1], -rel1[:, 0]], axis=1) / speed[:, None]
    pressure = np.arccos(np.clip(np.abs(normal[:, 0] * move[:, 0] + normal[:, 1] * move[:, 1]), 0, 1))
    rr = follower.roller_radius
    # the working profile lies on the cam side of the pitch curve; the cam is on the side of
    # the cam axis, i.e. against the outward normal of a counter-clockwise pitch curve
    area = 0.5 * np.sum(pitch[:, 0] * np.roll(pitch[:, 1], -1) - np.roll(pitch[:, 0], -1) * pitch[:, 1])
    orient = 1.0 if area > 0 else -1.0
    out_normal_cam = _to_cam(theta, orient * normal)
    profile = pitch - rr * out_normal_cam
    rho_profile = orient * rho_pitch - rr
    convex = orient * rho_pitch > 0
    bad = convex & (orient * rho_pitch <= rr)
    if bad.any():
        k = int(np.flatnonzero(bad)[np.argmin((orient * rho_pitch)[bad])])
        raise GeometryError(
            f"the cam undercuts at θ = {math.degrees(theta[k]):.2f} deg: the pitch curve's radius of curvature "
            f"{orient * rho_pitch[k]:.4g} mm is not larger than the roller radius {rr:g} mm; use a smaller roller "
            "or a larger base circle"
        )
    k = int(np.argmax(pressure))
    if pressure[k] > max_pressure_angle:
        raise GeometryError(
            f"pressure angle {math.degrees(pressure[k]):.2f} deg at θ = {math.degrees(theta[k]):.2f} deg exceeds "
            f"the limit {math.degrees(max_pressure_angle):.1f} deg; enlarge the base circle or slow the motion"
        )
    return CamProfile(theta, pitch, profile, pressure, rho_profile, motion, follower)
