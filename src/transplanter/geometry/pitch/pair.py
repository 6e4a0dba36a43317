"""Conjugate non-circular gear pairs: external, and internal (ring and planet).

Conventions
-----------
Each gear's body frame has its x-axis through the contact point at the start of the mesh
(polar angle 0 on both curves), angles counter-clockwise. Put the driver centre at the
origin and the line of centres along +x.

- **External** pair, centre distance ``a = r1 + r2``: the driven centre is at (a, 0), its
  contact direction is -x. When the driver turns clockwise by ``θ1`` the driver's contact
  is at body angle ``θ1``; the driven gear turns counter-clockwise by
  ``θ2 = ∫_0^θ1 r1 / (a - r1) dθ`` and its contact is at body angle ``-θ2``.
- **Internal** pair, ``a = r_ring - r_planet``: both contact directions are +x (the contact
  lies beyond the planet centre), both gears turn the same way, the driven contact is at
  body angle ``+θ2``. Either gear can drive: a ring driver has more lobes than its planet
  (``r2 = r1 - a``); a planet driver has fewer lobes than its ring (``r2 = r1 + a``).

The transmission ratio is ``i = ω2/ω1 = dθ2/dθ1 = r1/r2`` (seed 002 uses its inverse
``I = ω1/ω2``). Both curves close when one driver lobe (2π/n1) turns the driven gear by
exactly one driven lobe (2π/n2); for a radius-defined driver the centre distance is solved
for that (scipy ``brentq``) and the residual is reported as ``closure_error`` (rad).

Examples
--------
>>> from transplanter.geometry.pitch.curve import PitchCurve
>>> from transplanter.geometry.pitch.pair import GearPair, Mesh
>>> pair = GearPair.from_driver(PitchCurve.ellipse(40.0, 0.3), Mesh.EXTERNAL, driven_lobes=1)
>>> round(pair.centre_distance, 12), pair.closure_error < 1e-9   # two equal ellipses: a = 2A
(80.0, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum
from typing import cast

import numpy as np
from scipy import optimize

from transplanter.core.errors import GeometryError, SpecError, check_int, finite_positive
from transplanter.core.tolerances import PITCH_CLOSURE_RAD
from transplanter.geometry.pitch.curve import PitchCurve
from transplanter.geometry.pitch.periodic import MAX_LOBES, Periodic, PeriodicIntegral, Scaled, quintic_hermite

__all__ = [
    "Mesh",
    "GearPair",
    "ConjugateRadius",
    "RatioRadius",
    "ToothSizing",
    "ConvexityIndex",
    "driven_axis",
    "driven_turn",
]


def driven_axis(pair) -> float:
    """Where the driven gear's axis is in the meshing frame (the driver's axis at the origin, the
    driver turning clockwise): ``(a, 0)`` — ``(-a, 0)`` for a driven ring; ``pair`` any pair with a
    ``centre_distance`` and a ``ring`` (None, "driver" or "driven")."""
    return -pair.centre_distance if pair.ring == "driven" else pair.centre_distance


def driven_turn(pair, phi1):
    """The driven body's counter-clockwise turn in the meshing frame at driver rotations ``phi1``
    (rad): ``π + θ2`` for an external pair (its +x axis faces the driver at the start), ``-θ2``
    with a ring; θ2 = ``pair.driven_rotation(phi1)``."""
    theta2 = pair.driven_rotation(phi1)
    return (np.pi + theta2) if pair.ring is None else -theta2


class Mesh(StrEnum):
    EXTERNAL = "external"
    INTERNAL = "internal"


def _mesh(mesh) -> Mesh:
    try:
        return Mesh(mesh)
    except ValueError as exc:
        raise SpecError.out_of_range("mesh", mesh, "'external' or 'internal'") from exc


def _affine(mesh: Mesh, n1: int, n2: int) -> tuple[float, float, float]:
    """(sign of centre distance in r2 = c0*a + c1*r1, c1, contact-angle sign σ)."""
    if mesh is Mesh.EXTERNAL:
        return 1.0, -1.0, -1.0
    if n1 == n2:
        raise GeometryError(
            f"an internal pair needs different lobe numbers (driver {n1}, driven {n2}): the ring's perimeter "
            "must exceed the planet's, so the ring has more lobes"
        )
    return (-1.0 if n1 > n2 else 1.0), 1.0, 1.0


class ConjugateRadius(Periodic):
    """Polar radius of the driven curve, evaluated exactly from the driver's definition.

    At driven body angle ψ the driver angle ``θ1`` solves ``σ θ2(θ1) = ψ`` (a quintic Hermite
    table of the inverse through exact values and derivatives of the machine-precision
    integral θ2, residual < 1e-12 rad) and ``r2 = c0 a + c1 r1(θ1)``; derivatives follow by
    the chain rule, so they are as exact as the driver's.
    """

    period: float
    breakpoints: np.ndarray

    def __init__(self, driver: Periodic, a: float, mesh: Mesh, driven_lobes: int, theta2: PeriodicIntegral):
        self.driver = driver
        self.a = a
        self.c0, self.c1, self.sigma = _affine(mesh, driver.lobes, driven_lobes)
        self.theta2 = theta2
        self.period = 2 * math.pi / driven_lobes
        self._grid = np.linspace(0.0, driver.period, 4097)
        self._grid_y = theta2(self._grid)
        # inverse map θ1(θ2) as a quintic Hermite through exact values and derivatives:
        # error ~ h⁶ below 1e-13 rad (tests check the residual θ2(θ1(y)) - y), so no Newton
        # step is needed on top
        r1, r1p = driver(self._grid), driver(self._grid, 1)
        r2 = self.c0 * a + self.c1 * r1
        i = r1 / r2
        di = (r1p * r2 - r1 * self.c1 * r1p) / r2**2
        self._guess = quintic_hermite(self._grid_y, self._grid, 1 / i, -di / i**3)
        self.breakpoints = np.sort(np.mod(self.sigma * theta2(driver.breakpoints), self.period))

    def r2_of_theta1(self, t1, nu: int = 0) -> np.ndarray:
        if nu == 0:
            return self.c0 * self.a + self.c1 * self.driver(t1)
        return self.c1 * self.driver(t1, nu)

    def ratio(self, t1) -> np.ndarray:
        """dθ2/dθ1 = r1 / r2 at driver angle ``t1``."""
        return self.driver(t1) / self.r2_of_theta1(t1)

    def driver_angle(self, psi) -> np.ndarray:
        """Driver angle θ1 whose contact meets driven body angle ψ."""
        y = self.sigma * np.asarray(psi, dtype=float)
        per = self.theta2.total  # driven rotation per driver lobe
        turns = np.floor(y / per)
        x = self._guess(y - turns * per)
        return x + turns * self.driver.period

    def _eval(self, psi, nu):
        t1 = self.driver_angle(psi)
        g = self.r2_of_theta1(t1)
        if nu == 0:
            return g
        r1, r1p = self.driver(t1), self.driver(t1, 1)
        h1 = self.sigma * r1 / g
        g1 = self.c1 * r1p
        if nu == 1:
            return g1 / h1
        g2 = self.c1 * self.driver(t1, 2)
        h2 = self.sigma * (r1p * g - r1 * g1) / g**2
        return (g2 * h1 - g1 * h2) / h1**3


class RatioRadius(Periodic):
    """Driver radius from a transmission ratio ``i(φ1) = ω2/ω1`` and centre distance ``a``.

    External: ``r1 = a i / (1 + i)``; internal, ring driving: ``r1 = a i / (i - 1)`` (i > 1);
    internal, planet driving: ``r1 = a i / (1 - i)`` (i < 1).
    """

    period: float
    breakpoints: np.ndarray

    def __init__(self, ratio: Periodic, a: float, kind: str):
        self.ratio, self.a, self.kind = ratio, a, kind
        self.period = ratio.period
        self.breakpoints = ratio.breakpoints

    def _f(self, i, nu):
        """r1/a as a function of the ratio i, or its ``nu``-th derivative in i (nu 0, 1, 2): only that one computed."""
        if self.kind == "external":
            if nu == 0:
                return i / (1 + i)
            return 1 / (1 + i) ** 2 if nu == 1 else -2 / (1 + i) ** 3
        if self.kind == "ring":
            if nu == 0:
                return i / (i - 1)
            return -1 / (i - 1) ** 2 if nu == 1 else 2 / (i - 1) ** 3
        if nu == 0:
            return i / (1 - i)
        return 1 / (1 - i) ** 2 if nu == 1 else 2 / (1 - i) ** 3

    def _eval(self, x, nu):
        i = self.ratio(x)
        if nu == 0:
            return self.a * self._f(i, 0)
        i1 = self.ratio(x, 1)
        if nu == 1:
            return self.a * self._f(i, 1) * i1
        return self.a * (self._f(i, 2) * i1**2 + self._f(i, 1) * self.ratio(x, 2))


@dataclass(frozen=True)
class ToothSizing:
    """Tooth counts (driver, driven), module (mm) and the scale applied to the curves."""

    teeth: tuple[int, int]
    module: float
    scale: float


@dataclass(frozen=True)
class ConvexityIndex:
    """Seed 002 eqs 19-23 over a driver turn.

    ``p_a = 1 + I + I''`` and ``p_b = 1 + I - I I'' + I'²`` with ``I = ω1/ω2`` and its
    derivatives in φ1 (the printed eqs 19-22 lose the primes: the derivation from the polar
    curvature formula gives these, and the tests check them against the curves' curvature).
    ``p = min(p_a, p_b) >= 0`` iff both pitch curves are convex.
    """

    angles: np.ndarray = field(repr=False)
    p_a: np.ndarray = field(repr=False)
    p_b: np.ndarray = field(repr=False)

    @property
    def p(self) -> float:
        return float(min(self.p_a.min(), self.p_b.min()))


def _scan_positive(name: str, fn, period: float, n: int = 4096) -> None:
    x = period * np.arange(n) / n
    v = fn(x)
    if not np.all(np.isfinite(v)):
        k = int(np.flatnonzero(~np.isfinite(v))[0])
        raise SpecError(f"{name} is not finite at φ = {math.degrees(x[k]):.3f} deg")
    k = int(np.argmin(v))
    if v[k] <= 0:
        raise GeometryError(f"{name} = {v[k]:.6g} at φ = {math.degrees(x[k]):.3f} deg: must be > 0 everywhere")


@dataclass(frozen=True, eq=False)
class GearPair:
    """A conjugate pair of closed pitch curves.

    Attributes
    ----------
    driver, driven : PitchCurve
    centre_distance : float
        mm.
    mesh : Mesh
    closure_error : float
        |driven rotation over one driver lobe - 2π/n2|, rad.
    """

    driver: PitchCurve
    driven: PitchCurve
    centre_distance: float
    mesh: Mesh
    closure_error: float

    # -- construction --------------------------------------------------------------------

    @classmethod
    def from_driver(
        cls, driver: PitchCurve, mesh: Mesh | str, driven_lobes: int, centre_distance: float | None = None
    ) -> GearPair:
        """The conjugate of ``driver`` with ``driven_lobes`` lobes.

        ``centre_distance`` (mm) is solved so that both curves close unless given; a given
        value must close them within ``PITCH_CLOSURE_RAD``.
        """
        mesh = _mesh(mesh)
        driven_lobes = check_int("driven_lobes", driven_lobes, 1, MAX_LOBES)
        n1, n2 = driver.lobes, int(driven_lobes)
        c0, c1, _ = _affine(mesh, n1, n2)
        r1 = driver.radius
        target = 2 * math.pi / n2

        def turn(a: float) -> PeriodicIntegral:
            def rate(t):  # dθ2/dθ1 = r1 / r2, r1 evaluated once
                r = r1(t)
                return r / (c0 * a + c1 * r)

            return PeriodicIntegral(rate, r1.period, r1.breakpoints)

        rmin, rmax = driver.min_radius().value, driver.max_radius().value
        if centre_distance is None:
            a = cls._solve_centre_distance(turn, mesh, c0, rmin, rmax, target, n1, n2)
        else:
            a = finite_positive("centre_distance", centre_distance)
            r2min = min(c0 * a + c1 * rmax, c0 * a + c1 * rmin)
            if r2min <= 0:
                raise GeometryError(
                    f"centre_distance = {a!r} mm makes the driven radius {r2min:.6g} mm somewhere: it must be > 0 "
                    f"({'> r1 max = ' + format(rmax, '.6g') if mesh is Mesh.EXTERNAL else 'r1 - a > 0'})"
                )
        theta2 = turn(a)
        err = abs(theta2.total - target)
        if err > PITCH_CLOSURE_RAD:
            raise GeometryError(
                f"the driven curve does not close: one driver lobe turns it by {theta2.total!r} rad, "
                f"{n2} lobes need {target!r} rad (error {err:.3g} rad > {PITCH_CLOSURE_RAD:g}); "
                "leave centre_distance unset to solve it"
            )
        driven = PitchCurve(ConjugateRadius(r1, a, mesh, n2, theta2))
        return cls(driver, driven, a, mesh, err)

    @staticmethod
    def _solve_centre_distance(turn, mesh, c0, rmin, rmax, target, n1, n2) -> float:
        def f(a: float) -> float:
            return turn(a).total - target

        if mesh is Mesh.EXTERNAL:
            lo = rmax * (1 + 1e-9)
            hi = 2 * rmax
            while f(hi) > 0:
                hi *= 2
            while f(lo) < 0:  # the integral diverges only slowly near a double root
                lo = rmax + 0.5 * (lo - rmax)
                if lo - rmax < 1e-15 * rmax:
                    raise GeometryError(
                        f"no centre distance closes an external pair with lobes {n1}:{n2} for this driver; "
                        f"try more driven lobes"
                    )
        elif c0 < 0:  # ring drives the planet: 0 < a < r1 min
            lo, hi = 0.0, rmin * (1 - 1e-12)
            if f(hi) < 0:
                raise GeometryError(
                    f"no centre distance below the ring's smallest radius {rmin:.6g} mm closes the planet with "
                    f"lobes {n1}:{n2}; the ring's radius varies too much for so few planet lobes"
                )
        else:  # planet drives the ring: any a > 0
            lo, hi = 0.0, rmax
            while f(hi) > 0:
                hi *= 2
        return float(optimize.brentq(f, lo, hi, xtol=1e-14, rtol=4 * np.finfo(float).eps, maxiter=200))

    @classmethod
    def from_ratio(
        cls, ratio: Periodic, centre_distance: float, mesh: Mesh | str = Mesh.EXTERNAL, ring: str = "driven"
    ) -> GearPair:
        """The pair realising ``ratio`` = ω2/ω1 as a function of the driver angle (rad).

        ``ring`` (internal pairs) says which gear is the ring: ``"driven"`` (needs i < 1 —
        the ring turns slower) or ``"driver"`` (needs i > 1).
        """
        mesh = _mesh(mesh)
        a = finite_positive("centre_distance", centre_distance)
        if not isinstance(ratio, Periodic):
            raise SpecError(
                f"ratio must be a transplanter.geometry.pitch.periodic.Periodic, got {type(ratio).__name__}"
            )
        _scan_positive("transmission ratio ω2/ω1", ratio, ratio.period)
        if mesh is Mesh.EXTERNAL:
            kind = "external"
        elif ring in ("driven", "driver"):
            kind = "planet" if ring == "driven" else "ring"
            limit = (lambda x: 1 - ratio(x)) if kind == "planet" else (lambda x: ratio(x) - 1)
            try:
                _scan_positive("|1 - ratio|", limit, ratio.period)
            except GeometryError as exc:
                need = "< 1" if kind == "planet" else "> 1"
                raise GeometryError(
                    f"an internal pair with the ring as {ring} needs ratio ω2/ω1 {need}: {exc}"
                ) from exc
        else:
            raise SpecError.out_of_range("ring", ring, "'driven' or 'driver'")
        turn = PeriodicIntegral(ratio, ratio.period, ratio.breakpoints).total
        n2 = 2 * math.pi / turn
        if abs(n2 - round(n2)) > PITCH_CLOSURE_RAD or round(n2) < 1:
            raise GeometryError(
                f"the ratio integrates to {turn!r} rad over one driver lobe: a closed driven gear needs 2π/n2 for an "
                f"integer number of lobes n2 (this gives n2 = {n2:.9g}); scale the ratio by "
                f"{2 * math.pi / max(round(n2), 1) / turn:.12g}"
            )
        driver = PitchCurve(RatioRadius(ratio, a, kind))
        return cls.from_driver(driver, mesh, int(round(n2)), centre_distance=a)

    # -- kinematics ----------------------------------------------------------------------

    @property
    def _conj(self) -> ConjugateRadius:
        return self.driven.radius  # type: ignore[return-value]

    @property
    def lobes(self) -> tuple[int, int]:
        return self.driver.lobes, self.driven.lobes

    @property
    def ring(self) -> str | None:
        """Which gear is the ring: "driver", "driven", or None for an external pair."""
        if self.mesh is Mesh.EXTERNAL:
            return None
        return "driver" if self._conj.c0 < 0 else "driven"

    @property
    def contact_sense(self) -> int:
        """+1 if the driven contact angle grows with the driven rotation (internal), -1 if not."""
        return int(self._conj.sigma)

    def ratio(self, phi1) -> np.ndarray:
        """ω2/ω1 = r1/r2 at driver rotation ``phi1`` (rad)."""
        return self._conj.ratio(np.asarray(phi1, dtype=float))

    def driven_rotation(self, phi1) -> np.ndarray:
        """Driven rotation (rad, magnitude) when the driver has turned by ``phi1``.

        Opposite sense to the driver for external pairs, same sense for internal pairs.
        """
        return self._conj.theta2(np.asarray(phi1, dtype=float))

    def driven_contact_angle(self, phi1) -> np.ndarray:
        """Polar angle of the contact in the driven body frame (rad)."""
        return self._conj.sigma * self.driven_rotation(phi1)

    def ratio_error(self, n: int = 4096) -> float:
        """Largest |r1(φ1)/r2(ψ(φ1)) - dθ2/dφ1|: the prescribed ratio recovered from the curves."""
        phi1 = self.driver.radius.period * np.arange(n) / n
        r1 = self.driver.r(phi1)
        r2 = self.driven.r(self.driven_contact_angle(phi1))
        return float(np.max(np.abs(r1 / r2 - self.ratio(phi1))))

    def centre_distance_error(self, n: int = 4096) -> float:
        """Largest |r1 ± r2 - a| at corresponding contact points, mm."""
        phi1 = 2 * math.pi * np.arange(n) / n
        r1 = self.driver.r(phi1)
        r2 = self.driven.r(self.driven_contact_angle(phi1))
        c = self._conj
        return float(np.max(np.abs(c.c0 * self.centre_distance + c.c1 * r1 - r2)))

    # -- manufacturability ---------------------------------------------------------------

    def convexity_index(self, n: int = 4096) -> ConvexityIndex:
        """Seed 002 convexity index (external pairs)."""
        if self.mesh is not Mesh.EXTERNAL:
            raise SpecError("the seed-002 convexity index is defined for external pairs; use PitchCurve.curvature")
        a = self.centre_distance
        x = 2 * math.pi * np.arange(n) / n
        r, r1, r2 = self.driver.r(x), self.driver.r(x, 1), self.driver.r(x, 2)
        big_i = a / r - 1
        di = -a * r1 / r**2
        ddi = a * (2 * r1**2 / r**3 - r2 / r**2)
        return ConvexityIndex(x, 1 + big_i + ddi, 1 + big_i - big_i * ddi + di**2)

    def scaled(self, factor: float) -> GearPair:
        """Both curves and the centre distance scaled by ``factor`` (ratios unchanged)."""
        k = finite_positive("scale factor", factor)
        if k == 1.0:
            return self
        return GearPair.from_driver(
            PitchCurve(Scaled(self.driver.radius, k)), self.mesh, self.driven.lobes, self.centre_distance * k
        )

    def sized(self, *, module: float | None = None, teeth: int | None = None) -> tuple[GearPair, ToothSizing]:
        """Tooth counts and module from the perimeter: ``perimeter = z π m``.

        Give ``teeth`` (driver tooth count, a multiple of the driver's lobes) to derive the
        module from the curves as they are, or ``module`` (mm) to scale the curves so a whole
        number of teeth of that module fits (the nearest count; the pair is returned scaled).
        """
        n1, n2 = self.lobes
        per_lobe_len = self.driver.perimeter / n1
        if (module is None) == (teeth is None):
            raise SpecError("give exactly one of module (scale the curves) or teeth (derive the module)")
        if teeth is not None:
            if not isinstance(teeth, int | np.integer) or teeth < n1 or teeth % n1:
                raise SpecError.out_of_range("teeth", teeth, f"a positive multiple of the driver's {n1} lobes")
            k = int(teeth) // n1
            return self, ToothSizing((k * n1, k * n2), per_lobe_len / (k * math.pi), 1.0)
        m = finite_positive("module", cast(float, module))  # exactly one of module and teeth is given
        k = max(1, round(per_lobe_len / (math.pi * m)))
        scale = k * math.pi * m / per_lobe_len
        return self.scaled(scale), ToothSizing((k * n1, k * n2), m, scale)
