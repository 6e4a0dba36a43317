"""Open-chain 3R model of a double-planetary-carrier transplanting mechanism (seed 002 §4).

Link 1 (first carrier) turns clockwise about the centre point ``A_0`` at constant speed; link 2
(second carrier) is hinged to it at the circle point ``A_c`` and swings relative to it; link 3
(the planting arm, length ``L3``) is hinged to link 2 at ``Q`` and turns once
counter-clockwise relative to it per cycle, so the arm returns to its attitude with no net
rotation. With ``τ`` the carrier rotation since pose 1 (``abs1 = abs1_1 - τ``):

- ``β2(τ)`` — link 2 relative to link 1: a periodic B-spline through the four poses and the
  user's intermediate points (seed 002 §4.1: equal end tangents, i.e. periodic);
- ``β3(τ) = τ + g(τ)`` — link 3 relative to link 2, ``g`` periodic likewise.

**A picking beak** (:class:`Beak`, seed 002 §2.1: "a trajectory with a sharp shape for picking
seedlings"): at one carrier rotation the tip stands still and turns back — a cusp whose two
branches leave along the claw, so the claw goes into a pot and comes out along its own line. The
tip is still when the arm turns about it: with link 1 at ``a1' = -1`` that fixes ``a2'`` and
``a3'`` (two linear equations), and the tip's acceleration, set to point back along the arm,
fixes ``a2''`` and ``a3''`` (two more). Knots of β2 and g on either side of the beak take the
values that give the splines those derivatives there (the splines are linear in their knot values),
so the cusp is exact, not fitted.

**Ratio distribution** (eqs 12-18, with gears 9, 10, 11 equal spur gears so ``i^8_{5,11} = 1``
and the sun gear 2 fixed): the cam (fixed to the sun) drives link 2's swing ``β2`` through the
follower and sector gears 7-8 (ratio 1); the gear train 2-3-(4)-5 on carrier 1 must turn the
arm relative to carrier 1 by ``β2 + β3``, so its two-stage ratio (eq 18) is
``I = ω1/(ω1 - ω11) = 1 / (β2' + β3')`` as a function of the sun's rotation relative to the
carrier (``τ``). It is split into two non-circular stages ``i23 = c I^λ`` and ``i35 = I / i23``
(``c`` makes gear 3 turn exactly once per cycle, so both stages close); :meth:`distribute`
picks ``λ`` to maximise the smaller seed-002 convexity index when asked.

Examples
--------
>>> from transplanter.design.linkage.open_chain import seed002_poses
>>> poses, attitudes = seed002_poses()
>>> len(poses.poses), [round(math.degrees(a)) for a in attitudes]
(4, [171, 130, 154, 167])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from transplanter.core.errors import GeometryError, SpecError, finite_array, finite_positive
from transplanter.design.linkage.burmester import FourPoses, Pose
from transplanter.geometry.pitch import GearPair, PeriodicIntegral, PeriodicSpline

__all__ = ["Beak", "OpenChain3R", "ChainState", "RatioDistribution", "cusp_rates", "seed002_poses"]

TWO_PI = 2 * math.pi


def seed002_poses() -> tuple[FourPoses, tuple[float, ...]]:
    """Seed 002 Table 1 (link 2 poses) and the four attitudes of link 3 (171, 130, 154, 167 deg)."""
    table = ((124.03, 86.22, 230), (-33.07, -96.40, 120), (-125.45, 39.02, 14), (97.03, 116.80, 241))
    poses = FourPoses(tuple(Pose(x, y, math.radians(t)) for x, y, t in table))
    return poses, tuple(math.radians(a) for a in (171, 130, 154, 167))


@dataclass(frozen=True)
class ChainState:
    """The chain at carrier rotations ``tau`` (rad): hinge and tip positions (mm), angles (rad)."""

    tau: np.ndarray
    circle: np.ndarray
    q: np.ndarray
    tip: np.ndarray
    link1: np.ndarray
    link2: np.ndarray
    arm: np.ndarray


@dataclass(frozen=True, eq=False)
class RatioDistribution:
    """Two non-circular gear stages and the cam swing realising the chain.

    Attributes
    ----------
    stage23, stage35 : GearPair
        External pairs; stage 2-3 is driven by the sun's rotation relative to carrier 1,
        stage 3(4)-5 by gear 3.
    exponent : float
        λ of ``i23 = c I^λ``.
    convexity : (float, float)
        Seed-002 convexity index p of each stage.
    """

    stage23: GearPair
    stage35: GearPair
    exponent: float
    convexity: tuple[float, float]

    @property
    def p(self) -> float:
        return min(self.convexity)


@dataclass(frozen=True)
class Beak:
    """Where the tip stands still and turns back along the arm (module docstring), rad and mm.

    At carrier rotation ``tau`` link 2 stands ``beta2`` from link 1 and the arm points at
    ``attitude`` (absolute, the poses' frame); the tip's acceleration there is ``sharpness``
    (mm/rad², > 0) pointing back along the arm, so the tip leaves the beak by ``sharpness·t²/2``
    along the claw's line. The knots that make it stand ``spread`` either side of ``tau`` (solved
    for the cusp); ``shape`` moves β2 and β3 at ``tau ∓ 2.5·spread`` (rad, from the chain without
    the beak: before, after for β2, then for β3).
    """

    tau: float
    beta2: float
    attitude: float
    sharpness: float
    spread: float = 0.08
    shape: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        for name in ("tau", "beta2", "attitude"):
            finite_array(f"beak {name}", [getattr(self, name)])
        if not 0.0 < self.tau < TWO_PI:
            raise SpecError.out_of_range("beak tau", self.tau, "inside (0, 2π) rad")
        finite_positive("beak sharpness", self.sharpness)
        if not 0.0 < self.spread <= 0.5:
            raise SpecError.out_of_range("beak spread", self.spread, "in (0, 0.5] rad")
        if len(finite_array("beak shape", list(self.shape))) != 4:
            raise SpecError(f"beak shape needs 4 offsets, got {len(self.shape)}")
        first, *_, last = self.knots()
        if first <= 0.0 or last >= TWO_PI:
            raise SpecError.out_of_range(
                "beak tau", self.tau, f"its knots inside (0, 2π) rad: {2.5 * self.spread:.4g} rad from either end"
            )

    def knots(self) -> tuple[float, ...]:
        """The carrier rotations (rad) of the knots the beak adds, in order."""
        h, far = self.spread, 2.5 * self.spread
        return (self.tau - far, self.tau - h, self.tau, self.tau + h, self.tau + far)


def cusp_rates(l1: float, l2: float, l3: float, beta2: float, beta3: float) -> tuple[float, float]:
    """What a beak asks of the chain where link 2 stands ``beta2`` from link 1 and the arm ``beta3``
    from link 2 (rad; links ``l1``, ``l2``, arm ``l3``, mm): ``(β2', φ3')``, link 2's rate relative
    to link 1 — the swing cam's — and the arm's absolute rate, per rad of carrier 1 (turning
    clockwise at unit rate).

    The tip stands still when ``-l1 e(θ1) + l2 θ2' e(θ2) + l3 φ3' e(φ3) = 0`` (velocities turned a
    quarter); crossing it with ``e(φ3)`` and ``e(θ2)`` gives ``β2' = 1 + (l1/l2) sin(β2+β3)/sin β3``
    and ``φ3' = -(l1/l3) sin β2 / sin β3``. The arm turns about the still tip at ``φ3'``, so the claw
    sweeps the pot it picks from unless ``φ3'`` is small — which needs ``sin β2`` small: link 2 in
    line with link 1 (``β2 ≈ 0``, where the cam must swing it at ``β2' ≈ 1 + l1/l2``) or folded back
    on it (``β2 ≈ π``, ``β2' ≈ 1 - l1/l2``).

    >>> b2, ph = cusp_rates(73.6, 75.0, 125.0, 0.0, math.pi / 2)
    >>> round(b2, 4), round(ph, 4)
    (1.9813, -0.0)
    """
    s3 = math.sin(beta3)
    if abs(s3) < 1e-9:
        raise GeometryError(f"beta3 = {beta3!r} rad: with the arm in line with link 2 the tip cannot stand still")
    return 1.0 + (l1 / l2) * math.sin(beta2 + beta3) / s3, -(l1 / l3) * math.sin(beta2) / s3


@dataclass(frozen=True, eq=False)
class OpenChain3R:
    """A synthesised open-chain 3R mechanism through four poses.

    Parameters
    ----------
    poses : FourPoses
        Link 2's poses (point Q and attitude).
    circle : (float, float)
        Circle point A_c1 (on the circle-point curve), mm.
    arm_length : float
        L3, mm.
    arm_attitudes : 4 floats
        Absolute attitude of link 3 at the poses, rad.
    extra_link2, extra_link3 : sequences of (τ, angle)
        Intermediate points of β2(τ) and β3(τ) (rad), τ in (0, 2π) between the poses' τ.
    beak : Beak or None
        A picking beak (module docstring): knots added to both curves so the tip stands still there
        and leaves along the arm.
    degree : int
        Spline degree (3 or 5).
    """

    poses: FourPoses
    circle: tuple[float, float]
    arm_length: float
    arm_attitudes: tuple[float, ...]
    extra_link2: tuple[tuple[float, float], ...] = ()
    extra_link3: tuple[tuple[float, float], ...] = ()
    beak: Beak | None = None
    degree: int = 3
    centre: tuple[float, float] = field(init=False)
    pose_tau: np.ndarray = field(init=False, repr=False)
    # set once by __post_init__: the chain at its first pose, and β2(τ), g(τ) = β3(τ) - τ as splines
    _abs1_start: float = field(init=False, repr=False)
    _link1: float = field(init=False, repr=False)
    _link2: float = field(init=False, repr=False)
    _beta2: PeriodicSpline = field(init=False, repr=False)
    _g: PeriodicSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        finite_positive("arm_length", self.arm_length)
        att = finite_array("arm_attitudes", list(self.arm_attitudes))
        if att.size != 4:
            raise SpecError(f"arm_attitudes needs 4 angles, got {att.size}")
        dyad = self.poses.dyad(self.circle)
        if dyad.residual > 1e-6 * max(1.0, dyad.crank_length**2):
            raise GeometryError(
                f"circle point {self.circle} is not on the circle-point curve (eq 5 residual {dyad.residual:.3g}); "
                "take it from FourPoses.circle_points_at"
            )
        object.__setattr__(self, "centre", dyad.centre)
        a0 = np.array(dyad.centre)
        ac = np.array([self.poses.displacement(i + 1) @ [*self.circle, 1.0] for i in range(4)])[:, :2]
        q = np.array([[p.x, p.y] for p in self.poses.poses])
        abs1 = np.arctan2(ac[:, 1] - a0[1], ac[:, 0] - a0[0])
        abs2 = np.arctan2(q[:, 1] - ac[:, 1], q[:, 0] - ac[:, 0])
        tau = np.mod(abs1[0] - abs1, TWO_PI)
        if not np.all(np.diff(tau) > 0):
            raise GeometryError(
                "with link 1 turning clockwise the poses are not met in the order 1-2-3-4 "
                f"(carrier rotations {np.round(np.degrees(tau), 2).tolist()} deg); reverse the pose order"
            )
        b2 = np.angle(np.exp(1j * (abs2 - abs1)))
        raw3 = att - abs2
        b3 = [math.remainder(raw3[0], TWO_PI)]
        for k in range(1, 4):  # link 3 turns counter-clockwise relative to link 2
            b3.append(b3[-1] + math.fmod(raw3[k] - raw3[k - 1], TWO_PI) % TWO_PI)
        object.__setattr__(self, "pose_tau", tau)
        object.__setattr__(self, "_abs1_start", float(abs1[0]))
        object.__setattr__(self, "_link1", float(np.linalg.norm(ac[0] - a0)))
        object.__setattr__(self, "_link2", float(np.linalg.norm(q[0] - ac[0])))
        k2 = self._knots(tau, b2, self.extra_link2, "extra_link2", offset=False)
        k3 = self._knots(tau, np.array(b3), self.extra_link3, "extra_link3", offset=True)
        object.__setattr__(self, "_beta2", PeriodicSpline(*k2, degree=self.degree))
        object.__setattr__(self, "_g", PeriodicSpline(*k3, degree=self.degree))
        if self.beak is not None:
            k2, k3 = self._beak_knots(self.beak, tau, b2, np.array(b3))
            object.__setattr__(self, "_beta2", PeriodicSpline(*k2, degree=self.degree))
            object.__setattr__(self, "_g", PeriodicSpline(*k3, degree=self.degree))

    def _beak_knots(self, beak: Beak, tau, b2, b3) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
        """Both curves' knots with the beak's (module docstring): the tip still at ``beak.tau``,
        its acceleration ``beak.sharpness`` back along the arm."""
        t = beak.tau
        l1, l2, l3 = self.link_lengths
        a1 = self._abs1_start - t
        a2 = a1 + beak.beta2
        a3 = beak.attitude

        def e(a):
            return np.array([math.cos(a), math.sin(a)])

        def n(a):
            return np.array([-math.sin(a), math.cos(a)])

        m = np.column_stack([l2 * n(a2), l3 * n(a3)])
        if abs(np.linalg.det(m)) < 1e-9 * l2 * l3:
            raise GeometryError(
                f"beak at τ = {math.degrees(t):.3f} deg: link 2 and the arm are in line, so the tip cannot stand "
                "still there; move the beak's beta2 or attitude"
            )
        # tip velocity 0 (cusp_rates): link 2's absolute rate a2' = β2' - 1, the arm's a3' = φ3'
        swing, d3 = cusp_rates(l1, l2, l3, beak.beta2, a3 - a2)
        d2 = swing - 1.0
        # tip acceleration -sharpness e(a3): -l1 e(a1) + l2 (a2'' n - a2'^2 e)(a2) + l3 (a3'' n - a3'^2 e)(a3)
        rhs = -beak.sharpness * e(a3) + l1 * e(a1) + l2 * d2**2 * e(a2) + l3 * d3**2 * e(a3)
        dd2, dd3 = np.linalg.solve(m, rhs)
        before, inner, _, after, outer = beak.knots()
        near = float(self.beta3(t))
        b3v = near + math.remainder(a3 - a2 - near, TWO_PI)
        curves = []
        for values, extra, shape, (v, d1, dd), offset, name in (
            (b2, self.extra_link2, beak.shape[:2], (beak.beta2, d2 + 1.0, dd2), False, "β2"),
            (b3, self.extra_link3, beak.shape[2:], (b3v, d3 - d2, dd3 - dd2), True, "β3"),
        ):
            base = self.beta2 if not offset else self.beta3
            ends = ((before, float(base(before)) + shape[0]), (outer, float(base(outer)) + shape[1]))

            def knots(u, extra=extra, ends=ends, v=v, values=values, offset=offset, name=name):
                ex = (*extra, *ends, (inner, u[0]), (t, v), (after, u[1]))
                return self._knots(tau, values, ex, f"{name} with the beak", offset=offset)

            def slopes(u, knots=knots, offset=offset):
                s = PeriodicSpline(*knots(u), degree=self.degree)
                return np.array([float(s(t, 1)) + (1.0 if offset else 0.0), float(s(t, 2))])

            # the splines are linear in the knot values: three evaluations solve for the two
            guess = np.array([v - beak.spread * d1, v + beak.spread * d1])
            f0 = slopes(guess)
            jac = np.column_stack([slopes(guess + step) - f0 for step in np.eye(2)])
            curves.append(knots(guess + np.linalg.solve(jac, np.array([d1, dd]) - f0)))
        return curves[0], curves[1]

    @staticmethod
    def _knots(tau, values, extra, name, offset) -> tuple[np.ndarray, np.ndarray]:
        ex = finite_array(name, [list(p) for p in extra], ndim=2) if extra else np.zeros((0, 2))
        if ex.size and (np.any(ex[:, 0] <= 0) or np.any(ex[:, 0] >= TWO_PI)):
            raise SpecError.out_of_range(f"{name} τ", ex[:, 0].tolist(), "inside (0, 2π) rad")
        t = np.concatenate([tau, ex[:, 0]])
        v = np.concatenate([values, ex[:, 1]])
        if offset:
            v = v - t  # g = β3 - τ is periodic
        order = np.argsort(t)
        t, v = t[order], v[order]
        if np.any(np.diff(t) <= 1e-9):
            raise SpecError(f"{name}: intermediate points must not repeat a pose's or each other's τ")
        return t, v

    # -- kinematics ------------------------------------------------------------------------

    @property
    def link_lengths(self) -> tuple[float, float, float]:
        return self._link1, self._link2, self.arm_length

    def beta2(self, tau, nu: int = 0) -> np.ndarray:
        return self._beta2(tau, nu)

    def beta3(self, tau, nu: int = 0) -> np.ndarray:
        tau = np.asarray(tau, dtype=float)
        g = self._g(tau, nu)
        return g + (tau if nu == 0 else (1.0 if nu == 1 else 0.0))

    def state(self, tau) -> ChainState:
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        a1 = self._abs1_start - tau
        a2 = a1 + self.beta2(tau)
        a3 = a2 + self.beta3(tau)

        def e(a):
            return np.stack([np.cos(a), np.sin(a)], axis=-1)

        circle = np.array(self.centre) + self._link1 * e(a1)
        q = circle + self._link2 * e(a2)
        tip = q + self.arm_length * e(a3)
        return ChainState(tau, circle, q, tip, a1, a2, a3)

    def pose_error(self) -> float:
        """Largest distance (mm) between Q at the poses' τ and the prescribed points."""
        s = self.state(self.pose_tau)
        q = np.array([[p.x, p.y] for p in self.poses.poses])
        return float(np.max(np.linalg.norm(s.q - q, axis=1)))

    def two_stage_ratio(self, tau) -> np.ndarray:
        """I = ω1/(ω1 - ω11) = 1/(β2' + β3') (eq 18)."""
        return 1.0 / (self.beta2(tau, 1) + self.beta3(tau, 1))

    # -- ratio distribution ----------------------------------------------------------------

    def distribute(
        self,
        centre_distances: tuple[float, float] = (45.0, 45.0),
        exponent: float | None = 0.5,
        samples: int = 1440,
    ) -> RatioDistribution:
        """Split I into two closed external non-circular stages (see the module docstring).

        ``exponent`` None searches λ in [0.1, 0.9] for the largest convexity index.
        """
        tau = TWO_PI * np.arange(samples) / samples
        rel = self.beta2(tau, 1) + self.beta3(tau, 1)
        if np.any(rel <= 0):
            k = int(np.argmin(rel))
            raise GeometryError(
                f"the arm stops or reverses relative to carrier 1 at τ = {math.degrees(tau[k]):.2f} deg "
                f"(β2' + β3' = {rel[k]:.4g}): a gear train cannot make that motion; move the intermediate points"
            )
        inv_total = rel  # 1/I

        def build(lam: float) -> RatioDistribution:
            shape = PeriodicSpline(tau, inv_total**lam, degree=5)
            c = PeriodicIntegral(shape, shape.period, shape.breakpoints).total / TWO_PI
            r23 = PeriodicSpline(tau, inv_total**lam / c, degree=5)  # ω3/ω2 = 1/i23
            phi3 = PeriodicIntegral(r23, r23.period, r23.breakpoints)(tau)
            r35 = PeriodicSpline(phi3, inv_total ** (1 - lam) * c, degree=5)  # ω5/ω3 = 1/i35
            p23 = GearPair.from_ratio(_normalised(r23), centre_distances[0])
            p35 = GearPair.from_ratio(_normalised(r35), centre_distances[1])
            conv = (p23.convexity_index().p, p35.convexity_index().p)
            return RatioDistribution(p23, p35, lam, conv)

        if exponent is not None:
            return build(float(exponent))
        res = optimize.minimize_scalar(lambda lam: -build(lam).p, bounds=(0.1, 0.9), method="bounded")
        return build(float(res.x))


def _normalised(ratio: PeriodicSpline) -> PeriodicSpline:
    """The sampled ratio scaled so it integrates to exactly 2π (the samples' spline is off by ~1e-12)."""
    total = PeriodicIntegral(ratio, ratio.period, ratio.breakpoints).total
    return PeriodicSpline(ratio.angles, ratio.values * (TWO_PI / total), period=ratio.period, degree=ratio.degree)
