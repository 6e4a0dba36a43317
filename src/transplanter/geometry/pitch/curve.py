"""A closed pitch curve in polar form about its gear's rotation centre.

The curve lives in the gear's body frame: polar radius ``r(φ)`` (mm) at polar angle ``φ``
(rad, counter-clockwise). ``r`` is any :class:`~transplanter.geometry.pitch.periodic.Periodic`
function, so the curve closes by construction and every quantity below is evaluated from
the exact definition (no polyline):

- tangent and outward normal, curvature ``κ = (r² + 2r'² - r r'') / (r² + r'²)^{3/2}``
  (positive where the curve is convex, seen from outside);
- arc length ``s(φ) = ∫ sqrt(r² + r'²) dφ`` and its inverse;
- the pressure angle of the pitch curve ``μ`` = angle between the radius vector and the
  tangent (π/2 on a circle, Litvin's μ), and its deviation ``ν = π/2 - μ = atan(r'/r)``,
  whose largest magnitude limits the force direction in the mesh.

Examples
--------
>>> import numpy as np
>>> from transplanter.geometry.pitch.curve import PitchCurve
>>> c = PitchCurve.ellipse(semi_major=40.0, eccentricity=0.3)
>>> from scipy.special import ellipe
>>> bool(abs(c.perimeter - 4 * 40.0 * ellipe(0.3**2)) < 1e-12)  # exact: 4 a E(e²)
True
>>> round(float(np.degrees(c.max_pressure_deviation())), 6)  # asin(e)
17.457603
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from transplanter.core.errors import GeometryError, SpecError, finite_array, finite_positive
from transplanter.core.extrema import refine_extreme
from transplanter.geometry.pitch.periodic import (
    Constant,
    EccentricCircle,
    FocalEllipse,
    FourierSeries,
    Periodic,
    PeriodicIntegral,
    PeriodicSpline,
    Scaled,
    check_lobes,
    invert_increasing,
)

__all__ = ["PitchCurve", "CurvatureExtreme"]

#: Samples per lobe used to locate extremes before they are refined by scipy.
_SCAN = 2048


@dataclass(frozen=True)
class CurvatureExtreme:
    """An extreme of a pitch-curve quantity: its polar angle (rad) and value."""

    angle: float
    value: float


@dataclass(frozen=True, eq=False)
class PitchCurve:
    """A closed pitch curve ``r(φ)`` in its gear's body frame.

    Parameters
    ----------
    radius : Periodic
        Polar radius in mm as a function of the polar angle in rad; must be > 0.
    """

    radius: Periodic

    def __post_init__(self) -> None:
        if not isinstance(self.radius, Periodic):
            raise SpecError(
                f"radius must be a transplanter.geometry.pitch.periodic.Periodic, "
                f"got {type(self.radius).__name__}"
            )
        lobes = 2 * math.pi / self.radius.period
        if abs(lobes - round(lobes)) > 1e-9:
            raise GeometryError(
                f"radius period = {self.radius.period!r} rad does not divide a full turn: a closed curve needs "
                "period = 2π/n for an integer number of lobes n"
            )
        phi = self.scan()
        r = self.r(phi)
        if not np.all(np.isfinite(r)):
            raise GeometryError("the pitch-curve radius is not finite everywhere")
        k = int(np.argmin(r))
        if r[k] <= 0:
            raise GeometryError(
                f"pitch-curve radius = {r[k]:.6g} mm at φ = {math.degrees(phi[k]):.3f} deg: must be > 0 everywhere"
            )

    # -- constructors ----------------------------------------------------------------------

    @classmethod
    def circle(cls, radius: float) -> PitchCurve:
        return cls(Constant(finite_positive("radius", radius)))

    @classmethod
    def ellipse(cls, semi_major: float, eccentricity: float, lobes: int = 1) -> PitchCurve:
        """Ellipse about a focus (lobes = 1) or Litvin's n-lobed ellipse ``p / (1 - e cos nφ)``."""
        return cls(FocalEllipse(semi_major, eccentricity, lobes))

    @classmethod
    def eccentric_circle(cls, radius: float, offset: float) -> PitchCurve:
        return cls(EccentricCircle(radius, offset))

    @classmethod
    def from_polar_points(cls, angles, radii, lobes: int = 1, degree: int = 3) -> PitchCurve:
        """Periodic spline through radii (mm) at polar angles (rad) within one lobe (seed 004 style)."""
        lobes = check_lobes(lobes)
        radii = finite_array("radii", radii)
        if np.any(radii <= 0):
            i = int(np.flatnonzero(radii <= 0)[0])
            raise SpecError.out_of_range(f"radii[{i}]", float(radii[i]), "> 0 mm")
        return cls(PeriodicSpline(angles, radii, period=2 * math.pi / lobes, degree=degree))

    @classmethod
    def from_fourier(cls, a0: float, a=(), b=(), lobes: int = 1) -> PitchCurve:
        return cls(FourierSeries(a0, a, b, lobes))

    # -- evaluation --------------------------------------------------------------------------

    @property
    def lobes(self) -> int:
        return self.radius.lobes

    def r(self, phi, nu: int = 0) -> np.ndarray:
        """Polar radius (nu = 0, mm) or its nu-th derivative in φ."""
        return self.radius(phi, nu)

    def scan(self, per_lobe: int = _SCAN) -> np.ndarray:
        """Polar angles sampling one full turn uniformly (rad), without the end point."""
        n = per_lobe * self.lobes
        return 2 * math.pi * np.arange(n) / n

    def points(self, phi) -> np.ndarray:
        """(n, 2) float, mm: the curve at polar angles ``phi``."""
        phi = np.asarray(phi, dtype=float)
        r = self.r(phi)
        return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=-1)

    def derivative(self, phi) -> np.ndarray:
        """(n, 2) float, mm/rad: d(point)/dφ."""
        phi = np.asarray(phi, dtype=float)
        r, r1 = self.r(phi), self.r(phi, 1)
        c, s = np.cos(phi), np.sin(phi)
        return np.stack([r1 * c - r * s, r1 * s + r * c], axis=-1)

    def tangent(self, phi) -> np.ndarray:
        """(n, 2) unit tangent in the direction of increasing φ."""
        d = self.derivative(phi)
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def normal(self, phi) -> np.ndarray:
        """(n, 2) unit outward normal (the tangent turned clockwise by 90°)."""
        t = self.tangent(phi)
        return np.stack([t[..., 1], -t[..., 0]], axis=-1)

    def speed(self, phi) -> np.ndarray:
        """ds/dφ = sqrt(r² + r'²), mm/rad."""
        return np.hypot(self.r(phi), self.r(phi, 1))

    def curvature(self, phi) -> np.ndarray:
        """Signed curvature, 1/mm; > 0 where convex."""
        r, r1, r2 = self.r(phi), self.r(phi, 1), self.r(phi, 2)
        return (r * r + 2 * r1 * r1 - r * r2) / (r * r + r1 * r1) ** 1.5

    def radius_of_curvature(self, phi) -> np.ndarray:
        """1/κ, mm; negative where concave, ±inf where straight."""
        with np.errstate(divide="ignore"):
            return 1.0 / self.curvature(phi)

    def pressure_angle(self, phi) -> np.ndarray:
        """Angle μ between the radius vector and the tangent, rad (π/2 on a circle)."""
        return np.arctan2(self.r(phi), self.r(phi, 1))

    def pressure_deviation(self, phi) -> np.ndarray:
        """ν = π/2 - μ = atan(r'/r), rad: how far the tangent leans from the circle's."""
        return np.arctan2(self.r(phi, 1), self.r(phi))

    # -- arc length ----------------------------------------------------------------------

    @cached_property
    def _arc(self) -> PeriodicIntegral:
        return PeriodicIntegral(self.speed, self.radius.period, self.radius.breakpoints)

    @property
    def perimeter(self) -> float:
        """Length of the closed curve, mm."""
        return self._arc.total * self.lobes

    def arc_length(self, phi) -> np.ndarray:
        """Arc length from φ = 0 to ``phi`` (mm; keeps growing past one turn)."""
        return self._arc(phi)

    def angle_at_arc_length(self, s) -> np.ndarray:
        """Polar angle (rad) at arc length ``s`` (mm) from φ = 0; inverse of :meth:`arc_length`."""
        s = np.asarray(s, dtype=float)
        lobe = self._arc.total
        turns = np.floor(s / lobe)
        grid = np.linspace(0, self.radius.period, 257)
        return (
            invert_increasing(self._arc, self.speed, s - turns * lobe, grid, self._arc(grid))
            + turns * self.radius.period
        )

    # -- manufacturability summaries -------------------------------------------------------

    def _refined(self, fn, largest: bool) -> CurvatureExtreme:
        """Global extreme of ``fn`` over a turn: dense scan, then bounded scipy refinement."""
        phi = self.scan()
        angle, best = refine_extreme(lambda t: fn(np.array([t]))[0], phi, fn(phi), largest)
        return CurvatureExtreme(angle=float(np.mod(angle, 2 * math.pi)), value=best)

    def min_radius(self) -> CurvatureExtreme:
        return self._refined(self.r, largest=False)

    def max_radius(self) -> CurvatureExtreme:
        return self._refined(self.r, largest=True)

    def min_curvature(self) -> CurvatureExtreme:
        """Smallest signed curvature (most concave point when negative)."""
        return self._refined(self.curvature, largest=False)

    def max_curvature(self) -> CurvatureExtreme:
        """Largest curvature: its inverse is the smallest convex radius of curvature."""
        return self._refined(self.curvature, largest=True)

    @property
    def is_convex(self) -> bool:
        return self.min_curvature().value >= 0

    def min_concave_radius(self) -> float:
        """Smallest radius of curvature where the curve is concave, mm (inf if convex).

        An external gear's shaper cutter must have a pitch radius below it.
        """
        k = self.min_curvature().value
        return math.inf if k >= 0 else -1.0 / k

    def min_convex_radius(self) -> float:
        """Smallest radius of curvature where the curve is convex, mm.

        A cutter rolling *inside* (ring gear) must have a pitch radius below it.
        """
        k = self.max_curvature().value
        return math.inf if k <= 0 else 1.0 / k

    def max_pressure_deviation(self) -> float:
        """Largest |ν| = |π/2 - μ| over the curve, rad."""
        return abs(self._refined(lambda p: np.abs(self.pressure_deviation(p)), largest=True).value)

    def require_convex(self, name: str = "pitch curve") -> None:
        """GeometryError naming the angle and radius of curvature if the curve is not convex."""
        m = self.min_curvature()
        if m.value < 0:
            raise GeometryError(
                f"{name} is concave at φ = {math.degrees(m.angle):.3f} deg (radius of curvature "
                f"{-1 / m.value:.4g} mm): it must be convex (curvature >= 0) here"
            )

    # -- transforms ------------------------------------------------------------------------

    def scaled(self, factor: float) -> PitchCurve:
        """The curve scaled about its centre by ``factor`` (> 0)."""
        return PitchCurve(Scaled(self.radius, finite_positive("scale factor", factor)))
