"""Periodic scalar functions with exact derivatives: the building blocks of pitch curves.

A pitch curve is defined by a periodic function of an angle — its polar radius, or a
transmission ratio. Every function here evaluates itself and its first two derivatives to
machine precision of its definition (closed form, Fourier series, or a scipy periodic
B-spline; never a polyline), and knows its ``period`` and the ``breakpoints`` inside one
period where a higher derivative jumps (spline knots), so integrals can put panel edges there.

:class:`PeriodicIntegral` integrates such a function to machine precision (Gauss–Legendre
panels aligned with the breakpoints) and evaluates the antiderivative at any angle; it gives
arc length and the driven gear's rotation angle.

Examples
--------
>>> import math
>>> import numpy as np
>>> from transplanter.geometry.pitch.periodic import FocalEllipse, PeriodicIntegral
>>> e = FocalEllipse(semi_major=40.0, eccentricity=0.3)
>>> round(float(e(0.0)), 9), round(float(e(np.pi)), 9)  # A(1+e), A(1-e)
(52.0, 28.0)
>>> area = PeriodicIntegral(lambda t: 0.5 * e(t) ** 2, e.period, e.breakpoints)
>>> round(area.total / (math.pi * 40.0 * 40.0 * math.sqrt(1 - 0.09)), 12)  # pi a b
1.0
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from scipy.interpolate import BSpline, PPoly, make_interp_spline

from transplanter.core.errors import SpecError, check_int, check_number, finite_array, finite_positive

__all__ = [
    "Periodic",
    "Constant",
    "FourierSeries",
    "PeriodicSpline",
    "FocalEllipse",
    "EccentricCircle",
    "Scaled",
    "PeriodicIntegral",
    "invert_increasing",
    "quintic_hermite",
    "check_lobes",
]

_MAX_NU = 2


def _check_nu(nu: int) -> None:
    if nu not in (0, 1, 2):
        raise SpecError.out_of_range("derivative order nu", nu, "0, 1 or 2")


def check_lobes(lobes) -> int:
    """``lobes`` as an int from 1 to MAX_LOBES, or SpecError."""
    return check_int("lobes", lobes, 1, MAX_LOBES)


#: more lobes than this cannot carry even one tooth each at any module worth cutting
MAX_LOBES = 1000


class Periodic:
    """A periodic function ``f(x)``; subclasses implement :meth:`_eval` for nu = 0, 1, 2.

    Attributes
    ----------
    period : float
        rad.
    breakpoints : (k,) float
        Points in ``[0, period)`` where the function is less smooth (spline knots).
    """

    if TYPE_CHECKING:  # read-only to users: a field in some subclasses, a property in others

        @property
        def period(self) -> float: ...

        @property
        def breakpoints(self) -> np.ndarray: ...

    def __call__(self, x, nu: int = 0) -> np.ndarray:
        """Value (nu = 0) or derivative of order nu at ``x`` (array-like, rad)."""
        _check_nu(nu)
        return self._eval(np.asarray(x, dtype=float), nu)

    def _eval(self, x: np.ndarray, nu: int) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def lobes(self) -> int:
        """Number of periods in one turn (2π / period, an integer for pitch curves)."""
        return int(round(2 * math.pi / self.period))


@dataclass(frozen=True)
class Constant(Periodic):
    """A constant (a circle of radius ``value``, or a constant ratio)."""

    value: float
    period: float = 2 * math.pi
    breakpoints: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

    def _eval(self, x, nu):
        return np.full(x.shape, self.value if nu == 0 else 0.0)


class _Lobed(Periodic):
    """Smooth everywhere, with ``lobes_`` periods in one turn: no breakpoints."""

    lobes_: int

    @property
    def period(self) -> float:
        return 2 * math.pi / self.lobes_

    @property
    def breakpoints(self) -> np.ndarray:
        return np.zeros(0)


@dataclass(frozen=True)
class FourierSeries(_Lobed):
    """``a0 + Σ_k a_k cos(k L x) + b_k sin(k L x)``, k = 1..K, with ``L = lobes``.

    Examples
    --------
    >>> f = FourierSeries(1.0, (0.2,), (0.0,), lobes=2)
    >>> float(f(0.0)), round(float(f(np.pi / 2)), 12), round(f.period, 12)
    (1.2, 0.8, 3.14159265359)
    """

    a0: float
    a: tuple[float, ...] = ()
    b: tuple[float, ...] = ()
    lobes_: int = field(default=1, repr=False)

    def __init__(self, a0: float, a=(), b=(), lobes: int = 1) -> None:
        a_arr = finite_array("Fourier cosine coefficients a", list(a))
        b_arr = finite_array("Fourier sine coefficients b", list(b))
        n = max(a_arr.size, b_arr.size)
        a_arr = np.pad(a_arr, (0, n - a_arr.size))
        b_arr = np.pad(b_arr, (0, n - b_arr.size))
        lobes = check_lobes(lobes)
        object.__setattr__(self, "a0", float(finite_array("a0", [a0])[0]))
        object.__setattr__(self, "a", tuple(float(v) for v in a_arr))
        object.__setattr__(self, "b", tuple(float(v) for v in b_arr))
        object.__setattr__(self, "lobes_", int(lobes))

    def _eval(self, x, nu):
        k = self.lobes_ * np.arange(1, len(self.a) + 1)
        if not len(k):
            return np.full(np.shape(x), self.a0 if nu == 0 else 0.0)
        # cos(kLx) + i sin(kLx) as powers of one exponential: a cos and a sin per x, not per term
        z = np.exp(1j * self.lobes_ * np.asarray(x, dtype=float))
        zk = np.empty((*z.shape, len(k)), dtype=complex)
        zk[..., 0] = z
        for j in range(1, len(k)):
            zk[..., j] = zk[..., j - 1] * z
        c, s = zk.real, zk.imag
        a, b = np.array(self.a), np.array(self.b)
        if nu == 0:
            return self.a0 + c @ a + s @ b
        if nu == 1:
            return (-s * k) @ a + (c * k) @ b
        return (-c * k**2) @ a + (-s * k**2) @ b


class PeriodicSpline(Periodic):
    """Periodic interpolating B-spline through ``values`` at ``angles`` (scipy).

    Parameters
    ----------
    angles : (n,) float
        rad, strictly increasing, spanning less than one period.
    values : (n,) float
    period : float
        rad; 2π/lobes for an n-lobed curve.
    degree : int
        Odd spline degree (3 or 5); the function is C^(degree-1).

    Examples
    --------
    >>> s = PeriodicSpline(np.radians([0, 90, 180, 270]), [2.0, 1.0, 2.0, 1.0])
    >>> round(float(s(2 * np.pi)), 12), round(float(s(0.0, 1)), 12)  # periodic, symmetric
    (2.0, 0.0)
    """

    period: float
    breakpoints: np.ndarray

    def __init__(self, angles, values, period: float = 2 * math.pi, degree: int = 3) -> None:
        x = finite_array("angles", angles)
        y = finite_array("values", values)
        period = finite_positive("period", period)
        if x.size != y.size:
            raise SpecError(f"angles and values must have the same length, got {x.size} and {y.size}")
        if degree not in (3, 5):
            raise SpecError.out_of_range("degree", degree, "3 or 5")
        if x.size < degree + 1:
            raise SpecError.out_of_range("number of control points", x.size, f">= {degree + 1} for degree {degree}")
        if np.any(np.diff(x) <= 0):
            i = int(np.flatnonzero(np.diff(x) <= 0)[0])
            raise SpecError(f"angles must increase strictly; angle {i + 1} ({x[i + 1]!r}) <= angle {i} ({x[i]!r})")
        if x[-1] - x[0] >= period:
            raise SpecError.out_of_range("angle span", float(x[-1] - x[0]), f"< one period ({period!r} rad)")
        xx = np.append(x, x[0] + period)
        yy = np.append(y, y[0])
        spl = make_interp_spline(xx, yy, k=degree, bc_type="periodic")
        self._splines = tuple(
            BSpline(d.t, d.c, d.k, extrapolate="periodic") for d in (spl, spl.derivative(1), spl.derivative(2))
        )
        self.period = period
        self.breakpoints = np.sort(np.mod(x, period))
        self.angles = x
        self.values = y
        self.degree = degree

    def _eval(self, x, nu):
        return self._splines[nu](x)


@dataclass(frozen=True)
class FocalEllipse(_Lobed):
    """Polar radius of an ellipse about a focus, or of Litvin's n-lobed ellipse.

    ``r(φ) = p / (1 - e cos nφ)`` with ``p = A (1 - e²)``; n = 1 is the ellipse with
    semi-major axis ``A`` turning about a focus, largest radius ``A (1 + e)`` at φ = 0.
    """

    semi_major: float
    eccentricity: float
    lobes_: int = 1

    def __init__(self, semi_major: float, eccentricity: float, lobes: int = 1) -> None:
        finite_positive("semi_major", semi_major)
        e = check_number("eccentricity", eccentricity, 0.0, 1.0, high_open=True)
        lobes = check_lobes(lobes)
        object.__setattr__(self, "semi_major", float(semi_major))
        object.__setattr__(self, "eccentricity", e)
        object.__setattr__(self, "lobes_", int(lobes))

    @property
    def semi_latus_rectum(self) -> float:
        return self.semi_major * (1 - self.eccentricity**2)

    def _eval(self, x, nu):
        p, e, n = self.semi_latus_rectum, self.eccentricity, self.lobes_
        d = 1 - e * np.cos(n * x)
        if nu == 0:
            return p / d
        d1 = e * n * np.sin(n * x)
        if nu == 1:
            return -p * d1 / d**2
        d2 = e * n * n * np.cos(n * x)
        return -p * d2 / d**2 + 2 * p * d1**2 / d**3


@dataclass(frozen=True)
class EccentricCircle(Periodic):
    """Polar radius of a circle of ``radius`` turning about a point ``offset`` from its centre.

    ``r(φ) = e cos φ + sqrt(R² - e² sin² φ)``, largest (R + e) at φ = 0.
    """

    radius: float
    offset: float

    def __post_init__(self) -> None:
        finite_positive("radius", self.radius)
        check_number("offset", self.offset, 0.0, float(self.radius), high_open=True, unit="mm")

    period = 2 * math.pi
    breakpoints = np.zeros(0)

    def _eval(self, x, nu):
        e, big_r = self.offset, self.radius
        s, c = np.sin(x), np.cos(x)
        q = np.sqrt(big_r**2 - e**2 * s**2)
        if nu == 0:
            return e * c + q
        if nu == 1:
            return -e * s - e**2 * s * c / q
        return -e * c - e**2 * (c**2 - s**2) / q - e**4 * s**2 * c**2 / q**3


@dataclass(frozen=True)
class Scaled(Periodic):
    """``factor * f(x)``."""

    base: Periodic
    factor: float

    @property
    def period(self) -> float:
        return self.base.period

    @property
    def breakpoints(self) -> np.ndarray:
        return self.base.breakpoints

    def _eval(self, x, nu):
        return self.factor * self.base(x, nu)


# 16-point Gauss-Legendre: exact for degree-31 polynomials; on panels of <= period/256 a
# smooth integrand is integrated to round-off.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)


class PeriodicIntegral:
    """Antiderivative ``F(x) = ∫_0^x f`` of a periodic function, to machine precision.

    Parameters
    ----------
    f : callable
        Vectorised ``f(x)``; periodic with ``period``; smooth between ``breakpoints``.
    period : float
    breakpoints : (k,) float
        Extra panel edges in ``[0, period)``.
    panels : int
        Uniform panels per period (on top of the breakpoints).

    Attributes
    ----------
    total : float
        ∫ over one period.
    """

    def __init__(self, f: Callable[[np.ndarray], np.ndarray], period: float, breakpoints=(), panels: int = 256):
        edges = np.unique(np.concatenate([np.linspace(0.0, period, panels + 1), np.mod(breakpoints, period)]))
        edges = edges[np.concatenate([[True], np.diff(edges) > 1e-14 * period])]
        edges[-1] = period
        a, b = edges[:-1], edges[1:]
        half = 0.5 * (b - a)
        nodes = (a + half)[:, None] + half[:, None] * _GL_X[None, :]
        vals = np.asarray(f(nodes), dtype=float)
        if not np.all(np.isfinite(vals)):
            raise SpecError("the integrand is not finite on the curve (a radius or ratio reaches 0 or infinity)")
        panel = (vals * _GL_W).sum(axis=1) * half
        self._f = f
        self.period = float(period)
        self.edges = edges
        self.cumulative = np.concatenate([[0.0], np.cumsum(panel)])
        self.total = float(self.cumulative[-1])

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        turns = np.floor(x / self.period)
        xr = x - turns * self.period
        k = np.clip(np.searchsorted(self.edges, xr, side="right") - 1, 0, len(self.edges) - 2)
        a = self.edges[k]
        half = 0.5 * (xr - a)
        nodes = (a + half)[..., None] + half[..., None] * _GL_X
        part = (np.asarray(self._f(nodes)) * _GL_W).sum(axis=-1) * half
        return turns * self.total + self.cumulative[k] + part


def invert_increasing(
    fn: Callable[[np.ndarray], np.ndarray],
    dfn: Callable[[np.ndarray], np.ndarray],
    targets,
    grid_x: np.ndarray,
    grid_y: np.ndarray,
    tol: float = 1e-15,
) -> np.ndarray:
    """Solve ``fn(x) = y`` for an increasing ``fn`` by Newton's method, vectorised.

    ``grid_x, grid_y`` tabulate ``fn`` over the range of interest (start guesses by linear
    interpolation). Converges quadratically; stops when every step is below ``tol`` times
    the grid span, or after 30 iterations.
    """
    y = np.asarray(targets, dtype=float)
    x = np.interp(y, grid_y, grid_x)
    span = float(grid_x[-1] - grid_x[0])
    lo, hi = grid_x[0], grid_x[-1]
    for _ in range(30):
        step = (fn(x) - y) / dfn(x)
        x = np.clip(x - step, lo - span, hi + span)
        if np.all(np.abs(step) <= tol * span):
            break
    return x


def quintic_hermite(x, p, d, a) -> PPoly:
    """scipy PPoly through values ``p``, first ``d`` and second ``a`` derivatives at ``x``.

    ``p, d, a`` have shape (n, ...); the coefficients are the standard quintic Hermite ones.
    """
    h = np.diff(x).reshape((-1,) + (1,) * (p.ndim - 1))
    p0, p1, d0, d1, a0, a1 = p[:-1], p[1:], d[:-1], d[1:], a[:-1], a[1:]
    dp = p1 - p0
    c5 = (12 * dp - 6 * (d1 + d0) * h - (a0 - a1) * h**2) / (2 * h**5)
    c4 = (-30 * dp + (14 * d1 + 16 * d0) * h + (3 * a0 - 2 * a1) * h**2) / (2 * h**4)
    c3 = (20 * dp - (8 * d1 + 12 * d0) * h - (3 * a0 - a1) * h**2) / (2 * h**3)
    return PPoly(np.stack([c5, c4, c3, a0 / 2, d0, p0]), x)
