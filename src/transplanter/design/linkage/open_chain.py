"""Open-chain 3R model of a double-planetary-carrier transplanting mechanism (seed 002 §4).

Link 1 (first carrier) turns clockwise about the centre point ``A_0`` at constant speed; link 2
(second carrier) is hinged to it at the circle point ``A_c`` and swings relative to it; link 3
(the planting arm, length ``L3``) is hinged to link 2 at ``Q`` and turns once
counter-clockwise relative to it per cycle, so the arm returns to its attitude with no net
rotation. With ``τ`` the carrier rotation since pose 1 (``abs1 = abs1_1 - τ``):

- ``β2(τ)`` — link 2 relative to link 1: a periodic B-spline through the four poses and the
  user's intermediate points (seed 002 §4.1: equal end tangents, i.e. periodic);
- ``β3(τ) = τ + g(τ)`` — link 3 relative to link 2, ``g`` periodic likewise.

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

__all__ = ["OpenChain3R", "ChainState", "RatioDistribution", "seed002_poses"]

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
    degree : int
        Spline degree (3 or 5).
    """

    poses: FourPoses
    circle: tuple[float, float]
    arm_length: float
    arm_attitudes: tuple[float, ...]
    extra_link2: tuple[tuple[float, float], ...] = ()
    extra_link3: tuple[tuple[float, float], ...] = ()
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
