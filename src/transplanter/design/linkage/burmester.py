"""Burmester four-pose synthesis of an open-chain 2R/3R linkage (seed 002 §3.2, eqs 1-11).

Four finitely separated poses of a moving body (link 2 of the 3R chain) are given as a
point ``Q_i = (x_i, y_i)`` and an attitude ``θ_i``. A moving hinge ``A_c`` (circle point,
fixed in link 2) and a fixed hinge ``A_0`` (centre point) form a crank that guides the body
through all four poses iff ``|A_ci - A_0|`` is the same for every pose (eq 3). With the
displacement matrices ``D_1i`` (eq 1) this is linear in ``A_0`` (eq 5:
``C_i x0 + E_i y0 + F_i = 0``, i = 2..4), so a circle point admits a centre point iff the
3x3 determinant of ``[C_i E_i F_i]`` vanishes (eqs 6-7): a cubic in ``(x_c1, y_c1)`` —
the circle-point curve, of the form of eq 9 (``H1 = coef(x³) = coef(x y²)``,
``H2 = coef(y³) = coef(x² y)``). Its centre point solves eq 5 (eqs 10-11; here by least
squares over all three equations, whose residual is reported).

The cubic is sampled robustly: for each ``x_c1`` the determinant is a cubic polynomial in
``y_c1``, recovered exactly from four evaluations, and all its real roots are kept (one or
three branches).

Examples
--------
>>> import math
>>> from transplanter.design.linkage.burmester import Pose, FourPoses
>>> poses = FourPoses((Pose(124.03, 86.22, math.radians(230)), Pose(-33.07, -96.40, math.radians(120)),
...                    Pose(-125.45, 39.02, math.radians(14)), Pose(97.03, 116.80, math.radians(241))))
>>> [round(y, 4) for y in poses.circle_points_at(70.0)]  # seed 002 §3.3: y = 33.4092 is one branch
[33.4092, 51.3381, 408.7485]
>>> [round(v, 4) for v in poses.centre_point((70.0, 33.4092))]
[3.9926, 0.4984]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import MAX_MAGNITUDE, GeometryError, SpecError, check_number

#: most abscissae :meth:`FourPoses.sample` evaluates in one call (16 000 take ~0.1 s)
MAX_SAMPLES = 1_000_000

__all__ = ["Pose", "FourPoses", "Dyad", "CircleCurveSample"]


@dataclass(frozen=True)
class Pose:
    """Point (mm) and attitude (rad, CCW from +x) of the moving body."""

    x: float
    y: float
    theta: float

    def __post_init__(self) -> None:
        for name in ("x", "y", "theta"):
            check_number(f"pose {name}", getattr(self, name), -MAX_MAGNITUDE, MAX_MAGNITUDE)


@dataclass(frozen=True)
class Dyad:
    """A crank ``A_0 -> A_c1`` guiding the body through the poses.

    Attributes
    ----------
    centre, circle : (float, float)
        Fixed hinge A_0 and moving hinge A_c at pose 1, mm.
    residual : float
        Largest |eq 5| at the solution, mm² (0 up to round-off on the curve).
    """

    centre: tuple[float, float]
    circle: tuple[float, float]
    residual: float

    @property
    def crank_length(self) -> float:
        return math.dist(self.centre, self.circle)


@dataclass(frozen=True)
class CircleCurveSample:
    """Points of the circle-point curve with their centre points and link lengths (arrays)."""

    circle: np.ndarray
    centre: np.ndarray
    link1: np.ndarray
    link2: np.ndarray


class FourPoses:
    """Four poses and everything the synthesis derives from them.

    Parameters
    ----------
    poses : sequence of 4 Pose
        Pose 1 is the reference of the displacement matrices.
    """

    def __init__(self, poses) -> None:
        poses = tuple(poses)
        if len(poses) != 4 or not all(isinstance(p, Pose) for p in poses):
            raise SpecError(f"FourPoses needs exactly 4 Pose objects, got {len(poses)}")
        self.poses = poses
        p1 = poses[0]
        mats = []
        for p in poses[1:]:
            th = p.theta - p1.theta
            c, s = math.cos(th), math.sin(th)
            d13 = p.x - p1.x * c + p1.y * s
            d23 = p.y - p1.x * s - p1.y * c
            mats.append((c, -s, d13, s, c, d23))
        for i in range(4):
            for j in range(i + 1, 4):
                a, b = poses[i], poses[j]
                if (
                    abs(math.remainder(a.theta - b.theta, 2 * math.pi)) < 1e-9
                    and math.hypot(a.x - b.x, a.y - b.y) < 1e-9
                ):
                    raise SpecError(f"pose {j + 1} repeats pose {i + 1}: four finitely separated poses are needed")
        if all(abs(math.remainder(p.theta - p1.theta, 2 * math.pi)) < 1e-9 for p in poses):
            raise GeometryError("the poses are pure translations: every circle point is at infinity; turn the link")
        #: rows (A11..A17) of eq 4 for poses 2, 3, 4
        self._a = np.array(
            [
                (1 - d11, d12, -d13, -d23, d11 * d13 + d21 * d23, d12 * d13 + d22 * d23, (d13**2 + d23**2) / 2)
                for d11, d12, d13, d21, d22, d23 in mats
            ]
        )
        self._coef = self.cubic_coefficients()
        if abs(self._coef[(0, 3)]) < 1e-12 * max(abs(v) for v in self._coef.values()):
            raise GeometryError("the poses give a degenerate circle-point curve (no y³ term): choose other poses")

    def displacement(self, i: int) -> np.ndarray:
        """D_1i (3x3, eq 1), i = 1..4."""
        if i == 1:
            return np.eye(3)
        p1, p = self.poses[0], self.poses[i - 1]
        th = p.theta - p1.theta
        c, s = math.cos(th), math.sin(th)
        return np.array([[c, -s, p.x - p1.x * c + p1.y * s], [s, c, p.y - p1.x * s - p1.y * c], [0.0, 0.0, 1.0]])

    def cef(self, xc, yc):
        """C_i, E_i, F_i (eq 5) for circle points (xc, yc); each (..., 3)."""
        xc = np.asarray(xc, dtype=float)[..., None]
        yc = np.asarray(yc, dtype=float)[..., None]
        a = self._a
        c = a[:, 0] * xc - a[:, 1] * yc + a[:, 2]
        e = a[:, 1] * xc + a[:, 0] * yc + a[:, 3]
        f = a[:, 4] * xc + a[:, 5] * yc + a[:, 6]
        return c, e, f

    def determinant(self, xc, yc) -> np.ndarray:
        """The compatibility determinant (eq 6) at circle points; zero on the circle-point curve."""
        c, e, f = self.cef(xc, yc)
        return np.linalg.det(np.stack([c, e, f], axis=-1))

    def cubic_coefficients(self) -> dict[tuple[int, int], float]:
        """Coefficients of x^a y^b (a + b <= 3) of the circle-point cubic, by exact fitting."""
        terms = [(a, b) for a in range(4) for b in range(4 - a)]
        rng = np.random.default_rng(0)
        pts = rng.uniform(-1.0, 1.0, (40, 2)) * 100.0
        m = np.stack([pts[:, 0] ** a * pts[:, 1] ** b for a, b in terms], axis=1)
        coef, *_ = np.linalg.lstsq(m, self.determinant(pts[:, 0], pts[:, 1]), rcond=None)
        return dict(zip(terms, coef, strict=True))

    def _roots(self, xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """All real roots y of the cubic at each abscissa: (x, y) pairs, vectorised."""
        c = self._coef
        xs = np.asarray(xs, dtype=float)
        a3 = np.full(xs.shape, c[(0, 3)])
        a2 = c[(0, 2)] + c[(1, 2)] * xs
        a1 = c[(0, 1)] + c[(1, 1)] * xs + c[(2, 1)] * xs**2
        a0 = c[(0, 0)] + c[(1, 0)] * xs + c[(2, 0)] * xs**2 + c[(3, 0)] * xs**3
        comp = np.zeros(xs.shape + (3, 3))
        comp[..., 0, 0], comp[..., 0, 1], comp[..., 0, 2] = -a2 / a3, -a1 / a3, -a0 / a3
        comp[..., 1, 0] = comp[..., 2, 1] = 1.0
        roots = np.linalg.eigvals(comp)
        scale = np.maximum(1.0, np.abs(roots))
        real = np.abs(roots.imag) <= 1e-7 * scale
        x = np.broadcast_to(xs[..., None], roots.shape)[real]
        y = roots.real[real]
        for _ in range(3):  # polish on the exact determinant
            h = 1e-6 * np.maximum(1.0, np.abs(y))
            f0 = self.determinant(x, y)
            df = (self.determinant(x, y + h) - f0) / h
            y = y - np.divide(f0, df, out=np.zeros_like(f0), where=df != 0)
        order = np.lexsort((y, x))
        return x[order], y[order]

    def circle_points_at(self, xc: float) -> list[float]:
        """All real y_c1 of the circle-point curve at abscissa ``xc`` (1 or 3 values), sorted."""
        _, y = self._roots(np.array([float(xc)]))
        return [float(v) for v in y]

    def centre_point(self, circle) -> tuple[float, float]:
        """Centre point A_0 of circle point A_c1 (eqs 10-11), mm."""
        return self.dyad(circle).centre

    def dyad(self, circle) -> Dyad:
        xc, yc = (float(v) for v in circle)
        c, e, f = self.cef(xc, yc)
        m = np.stack([c, e], axis=1)
        if np.linalg.matrix_rank(m, tol=1e-9 * max(1.0, float(np.abs(m).max()))) < 2:
            raise GeometryError(f"circle point ({xc}, {yc}) has no unique centre point (eq 10 is singular there)")
        sol, *_ = np.linalg.lstsq(m, -f, rcond=None)
        residual = float(np.max(np.abs(m @ sol + f)))
        return Dyad((float(sol[0]), float(sol[1])), (xc, yc), residual)

    def sample(self, x_range: tuple[float, float], step: float = 0.01) -> CircleCurveSample:
        """Circle-point curve over ``x_range`` (all real branches) with centres and link lengths.

        ``link1`` = |A_c1 - A_0|, ``link2`` = |Q_1 - A_c1|.
        """
        try:
            lo, hi = (check_number("x_range", v) for v in x_range)
        except (TypeError, ValueError) as exc:
            raise SpecError.out_of_range("x_range", x_range, "two numbers (lo, hi)") from exc
        if not lo < hi:
            raise SpecError.out_of_range("x_range", x_range, "(lo, hi) with lo < hi")
        step = check_number("step", step, 0.0, low_open=True, unit="mm")
        if (hi - lo) / step > MAX_SAMPLES:
            raise SpecError.out_of_range("step", step, f">= {(hi - lo) / MAX_SAMPLES:.3g} mm ({MAX_SAMPLES} abscissae)")
        xs = np.arange(lo, hi + 0.5 * step, step)
        x, y = self._roots(xs)
        c, e, f = self.cef(x, y)
        # eq 10: rows (2 - 3) and 4; eq 11 in closed form
        c23, e23, f23 = c[:, 0] - c[:, 1], e[:, 0] - e[:, 1], f[:, 0] - f[:, 1]
        den = e[:, 2] * c23 - c[:, 2] * e23
        ok = np.abs(den) > 1e-12 * np.maximum(1.0, np.abs(c23 * e[:, 2]))
        x0 = (f[:, 2] * e23 - e[:, 2] * f23) / np.where(ok, den, 1.0)
        y0 = (f[:, 2] * c23 - c[:, 2] * f23) / np.where(ok, -den, 1.0)
        circle_a = np.stack([x, y], axis=1)[ok]
        centre_a = np.stack([x0, y0], axis=1)[ok]
        q1 = np.array([self.poses[0].x, self.poses[0].y])
        return CircleCurveSample(
            circle_a,
            centre_a,
            np.linalg.norm(circle_a - centre_a, axis=1),
            np.linalg.norm(q1 - circle_a, axis=1),
        )

    @staticmethod
    def feasible(
        sample: CircleCurveSample,
        centre_x: tuple[float, float] | None = None,
        circle_x: tuple[float, float] | None = None,
        y_range: tuple[float, float] | None = None,
        link1: tuple[float, float] | None = None,
        link2: tuple[float, float] | None = None,
    ) -> np.ndarray:
        """Boolean mask of samples inside the workspace boxes and link-length ranges (mm)."""
        ok = np.ones(len(sample.circle), dtype=bool)

        def within(v, rng):
            return (v >= rng[0]) & (v <= rng[1]) if rng is not None else True

        ok &= within(sample.centre[:, 0], centre_x)
        ok &= within(sample.circle[:, 0], circle_x)
        if y_range is not None:
            ok &= within(sample.centre[:, 1], y_range) & within(sample.circle[:, 1], y_range)
        ok &= within(sample.link1, link1)
        ok &= within(sample.link2, link2)
        return ok
