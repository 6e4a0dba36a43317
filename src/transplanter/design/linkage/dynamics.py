"""Shaking force, crank torque and balancing of a four-bar (seed 003, Yamashita et al.).

Mass data follow seed 003: each moving link has a mass and a centre of mass (u, v) in its
link frame (crank: origin O2, x to B; coupler: origin B, x to C; rocker: origin O4, x to C,
exactly seed 003's g_b, g_c, g_d), and a moment of inertia about that centre of mass.
Units: kg, mm, kg mm^2; forces come out in N and torques in N m (``mm -> m`` done here).

* **Shaking force** is the force the moving links exert on the frame, ``-sum(m_i a_i)``
  (seed 003 eqs 17-18 times -M). Gravity's constant weight is not part of it.
* **Crank torque** is the torque that must be applied to the crank to drive the prescribed
  motion against inertia and gravity (seed 003 eqs 33-36). It is computed two independent
  ways: from the virtual power of the inertia and gravity forces (``crank_torque``) and from
  the full Newton-Euler system of seed 003 eqs 19-24 (``joint_forces``); the tests compare
  them. The printed form of eqs 34-36 is garbled in the seed (missing signs and factors), so
  it is not transcribed; both methods here are exact for rigid links and frictionless pins.
* **Harmonics** use seed 003's form ``y = R0 + sum R_n sin(n theta + phi_n)``, so
  ``A_n = R_n sin(phi_n)`` and ``B_n = R_n cos(phi_n)``. Seed 003 Table 4 prints
  ``phi_1 = 162.5 deg`` but its own ``A_1 = 13.6464``, ``B_1 = -5.1904`` give 110.8 deg,
  which is also the counterweight phase X = 111 deg of its section 5-3: the printed 162.5
  is the n = 2 value repeated. Its ``R_9 = 0.099`` likewise contradicts ``A_9, B_9`` (0.035).
* **Counterweight** on the crank axis: a mass moment ``m r`` at angle ``angle_on_crank``
  from the crank arm cancels either the vertical fundamental (seed 003 section 5-3) or the
  forward-rotating part of the 2-D fundamental (the most a single rotating mass can cancel).

Examples
--------
>>> import numpy as np
>>> from transplanter.design.linkage.dynamics import phasing_gain
>>> [round(g, 12) for g in phasing_gain([0.0, np.pi], 4)]  # two arms at 180 deg
[0.0, 2.0, 0.0, 2.0]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import MAX_MAGNITUDE, SpecError, check_number
from transplanter.design.linkage.fourbar import FourBar, FourBarMotion, Link, PointMotion

__all__ = [
    "STANDARD_GRAVITY",
    "LinkMass",
    "MassModel",
    "Harmonics",
    "Counterweight",
    "JointForces",
    "centre_of_mass",
    "shaking_force",
    "crank_torque",
    "joint_forces",
    "harmonics",
    "counterweight",
    "phasing_gain",
    "arm_phases",
    "sinusoidal_rocker_moment",
    "force_balance_moments",
]

#: m/s^2, acting along -y of the drawing frame.
STANDARD_GRAVITY = 9.80665

_MOVING = (Link.CRANK, Link.COUPLER, Link.ROCKER)


@dataclass(frozen=True)
class LinkMass:
    """Mass (kg), centre of mass (u, v) in the link frame (mm), inertia about it (kg mm^2)."""

    mass: float
    com: tuple[float, float] = (0.0, 0.0)
    inertia: float = 0.0

    def __post_init__(self) -> None:
        m = check_number("mass", self.mass, 0.0, unit="kg")
        u, v = (check_number("com", x, -MAX_MAGNITUDE, MAX_MAGNITUDE, unit="mm") for x in self.com)
        j = check_number("inertia", self.inertia, 0.0, None, unit="kg mm^2")
        object.__setattr__(self, "mass", m)
        object.__setattr__(self, "com", (u, v))
        object.__setattr__(self, "inertia", j)

    @property
    def moment(self) -> tuple[float, float]:
        """Mass moment m * com, kg mm."""
        return (self.mass * self.com[0], self.mass * self.com[1])


@dataclass(frozen=True)
class MassModel:
    """Mass data of the three moving links."""

    crank: LinkMass
    coupler: LinkMass
    rocker: LinkMass

    def of(self, link: Link) -> LinkMass:
        return {Link.CRANK: self.crank, Link.COUPLER: self.coupler, Link.ROCKER: self.rocker}[link]

    @property
    def total_mass(self) -> float:
        return self.crank.mass + self.coupler.mass + self.rocker.mass


@dataclass(frozen=True)
class Harmonics:
    """Fourier coefficients of a signal over one revolution, seed 003's convention.

    ``A[n]``, ``B[n]``: cos and sin coefficients; ``R[n]`` amplitude; ``phase[n]`` (rad) with
    ``A_n cos(n t) + B_n sin(n t) = R_n sin(n t + phase_n)``. Index 0 is the mean.
    """

    A: np.ndarray
    B: np.ndarray

    @property
    def R(self) -> np.ndarray:
        r = np.hypot(self.A, self.B)
        r[0] = self.A[0]
        return r

    @property
    def phase(self) -> np.ndarray:
        return np.arctan2(self.A, self.B)


@dataclass(frozen=True)
class Counterweight:
    """A mass on the crank axis: mass moment (kg mm) at ``angle_on_crank`` (rad) from O2->B."""

    mass_moment: float
    angle_on_crank: float

    def radius_for(self, mass: float) -> float:
        """mm, radius at which a mass (kg) gives this mass moment."""
        mass = check_number("mass", mass, 0.0, low_open=True, unit="kg")
        return self.mass_moment / mass


@dataclass(frozen=True)
class JointForces:
    """Pin forces (N, (n, 2)) and crank torque (N m, (n,)) from Newton-Euler.

    ``ground_on_crank`` at O2, ``crank_on_coupler`` at B, ``coupler_on_rocker`` at C,
    ``ground_on_rocker`` at O4.
    """

    ground_on_crank: np.ndarray
    crank_on_coupler: np.ndarray
    coupler_on_rocker: np.ndarray
    ground_on_rocker: np.ndarray
    torque: np.ndarray


def _com_motions(motion: FourBarMotion, masses: MassModel) -> dict[Link, PointMotion]:
    return {k: motion.point(k, masses.of(k).com) for k in _MOVING}


def centre_of_mass(motion: FourBarMotion, masses: MassModel) -> PointMotion:
    """Combined centre of mass of the moving links (seed 003 eqs 14-18), mm, mm/s, mm/s^2."""
    total = masses.total_mass
    if total <= 0.0:
        raise SpecError.out_of_range("total moving mass", total, "> 0 kg")
    pms = _com_motions(motion, masses)

    def avg(attr: str) -> np.ndarray:
        return sum(masses.of(k).mass * getattr(pms[k], attr) for k in _MOVING) / total

    return PointMotion(position=avg("position"), velocity=avg("velocity"), acceleration=avg("acceleration"))


def shaking_force(motion: FourBarMotion, masses: MassModel) -> np.ndarray:
    """Force of the moving links on the frame, ``-sum m_i a_i``, (n, 2) N."""
    pms = _com_motions(motion, masses)
    return -1e-3 * np.sum([masses.of(k).mass * pms[k].acceleration for k in _MOVING], axis=0)


def crank_torque(motion: FourBarMotion, masses: MassModel, gravity: float = STANDARD_GRAVITY) -> np.ndarray:
    """Driving torque on the crank (N m, (n,)) by virtual power.

    ``T = sum(m_i a_i . dv_i + I_i alpha_i dw_i + m_i g dy_i)`` where ``dv_i``, ``dw_i`` and
    ``dy_i`` are the velocity coefficients (velocities at unit crank speed). Exact at any
    crank speed, including zero (then it is the static gravity torque).
    """
    fb = motion.linkage
    unit = fb.solve(motion.theta[Link.CRANK], 1.0, 0.0)
    pms = _com_motions(motion, masses)
    coeff = _com_motions(unit, masses)
    t = np.zeros_like(motion.theta[Link.CRANK])
    g = gravity * 1e3  # mm/s^2
    for k in _MOVING:
        lm = masses.of(k)
        t = t + lm.mass * np.einsum("ij,ij->i", pms[k].acceleration, coeff[k].velocity)
        t = t + lm.inertia * motion.alpha[k] * unit.omega[k]
        t = t + lm.mass * g * coeff[k].velocity[:, 1]
    return t * 1e-6  # kg mm^2/s^2 -> N m


def joint_forces(motion: FourBarMotion, masses: MassModel, gravity: float = STANDARD_GRAVITY) -> JointForces:
    """Pin forces and crank torque from seed 003's Newton-Euler equations (19)-(24).

    Nine unknowns per crank angle (four pin forces and the torque) from three force and
    three moment balances, solved as one batched linear system.
    """
    n = motion.theta[Link.CRANK].shape[0]
    joints = motion.joints()
    pms = _com_motions(motion, masses)
    g = np.array([0.0, -gravity * 1e3])
    # unknown order: F12x F12y F32x F32y F43x F43y F14x F14y T
    a = np.zeros((n, 9, 9))
    rhs = np.zeros((n, 9))

    def cross_cols(r: np.ndarray) -> np.ndarray:
        """Row coefficients of r x F for F = (Fx, Fy): (-ry, rx)."""
        return np.stack([-r[:, 1], r[:, 0]], axis=-1)

    m2, m3, m4 = (masses.of(k) for k in _MOVING)
    g2, g3, g4 = (pms[k] for k in _MOVING)
    # crank: F12 + F32 + m2 g = m2 a2 ; (O2-G2)xF12 + (B-G2)xF32 + T = I2 alpha2
    a[:, 0:2, 0:2] = np.eye(2)
    a[:, 0:2, 2:4] = np.eye(2)
    rhs[:, 0:2] = m2.mass * (g2.acceleration - g)
    a[:, 2, 0:2] = cross_cols(joints["O2"] - g2.position)
    a[:, 2, 2:4] = cross_cols(joints["B"] - g2.position)
    a[:, 2, 8] = 1.0
    rhs[:, 2] = m2.inertia * motion.alpha[Link.CRANK]
    # coupler: -F32 + F43 + m3 g = m3 a3 ; (B-G3)x(-F32) + (C-G3)xF43 = I3 alpha3
    a[:, 3:5, 2:4] = -np.eye(2)
    a[:, 3:5, 4:6] = np.eye(2)
    rhs[:, 3:5] = m3.mass * (g3.acceleration - g)
    a[:, 5, 2:4] = -cross_cols(joints["B"] - g3.position)
    a[:, 5, 4:6] = cross_cols(joints["C"] - g3.position)
    rhs[:, 5] = m3.inertia * motion.alpha[Link.COUPLER]
    # rocker: -F43 + F14 + m4 g = m4 a4 ; (C-G4)x(-F43) + (O4-G4)xF14 = I4 alpha4
    a[:, 6:8, 4:6] = -np.eye(2)
    a[:, 6:8, 6:8] = np.eye(2)
    rhs[:, 6:8] = m4.mass * (g4.acceleration - g)
    a[:, 8, 4:6] = -cross_cols(joints["C"] - g4.position)
    a[:, 8, 6:8] = cross_cols(joints["O4"] - g4.position)
    rhs[:, 8] = m4.inertia * motion.alpha[Link.ROCKER]
    x = np.linalg.solve(a, rhs[..., None])[..., 0]
    return JointForces(
        ground_on_crank=x[:, 0:2] * 1e-3,
        crank_on_coupler=-x[:, 2:4] * 1e-3,
        coupler_on_rocker=-x[:, 4:6] * 1e-3,
        ground_on_rocker=x[:, 6:8] * 1e-3,
        torque=x[:, 8] * 1e-6,
    )


def harmonics(values: np.ndarray, n_harmonics: int) -> Harmonics:
    """Fourier coefficients of ``values`` sampled uniformly over one revolution.

    Parameters
    ----------
    values : (n,) float
        Samples at angles ``theta_k = 2 pi k / n``, k = 0..n-1 (the caller chooses the
        angle origin; its phases are relative to it).
    n_harmonics : int
        Highest harmonic returned; must be < n / 2.
    """
    y = np.asarray(values, dtype=float)
    n = y.shape[0]
    if y.ndim != 1 or not np.all(np.isfinite(y)):
        raise SpecError("values must be a finite 1-D array sampled over one revolution")
    if not (0 <= n_harmonics < n // 2):
        raise SpecError.out_of_range("n_harmonics", n_harmonics, f"in [0, {n // 2 - 1}] for {n} samples")
    c = np.fft.rfft(y) / n
    a = 2.0 * c.real[: n_harmonics + 1]
    b = -2.0 * c.imag[: n_harmonics + 1]
    a[0] = c.real[0]
    b[0] = 0.0
    return Harmonics(A=a, B=b)


def _fundamental_com_acceleration(fb: FourBar, masses: MassModel, crank_speed: float, n: int) -> np.ndarray:
    """Complex coefficients (c_plus, c_minus) of a_G = c+ e^{i t2} + c- e^{-i t2} (mm/s^2)."""
    t2 = 2 * math.pi * np.arange(n) / n
    acc = centre_of_mass(fb.solve(t2, crank_speed), masses).acceleration
    z = acc[:, 0] + 1j * acc[:, 1]
    c = np.fft.fft(z) / n
    return np.array([c[1], c[-1]])


def counterweight(
    fb: FourBar,
    masses: MassModel,
    crank_speed: float,
    component: str = "rotating",
    n: int = 720,
) -> Counterweight:
    """Counterweight on the crank axis that cancels the fundamental of the shaking force.

    Parameters
    ----------
    component : {"rotating", "vertical"}
        "rotating": cancel the forward-rotating part of the 2-D fundamental (minimises the
        RMS of the total shaking force with one rotating mass). "vertical": cancel the
        vertical fundamental only, as seed 003 section 5-3 does.
    """
    if not (math.isfinite(crank_speed) and crank_speed != 0.0):
        raise SpecError.out_of_range("crank_speed", crank_speed, "finite and non-zero rad/s")
    total = masses.total_mass
    w2 = crank_speed**2
    c_plus, c_minus = _fundamental_com_acceleration(fb, masses, crank_speed, n)
    if component == "rotating":
        # mass at crank-relative angle beta: a = -r w^2 e^{i(t2 + beta)} must cancel M c+
        target = total * c_plus
    elif component == "vertical":
        # a_y fundamental = Im(c+ e^{it} + c- e^{-it}) = Im((c+ - conj(c-)) e^{it})
        target = total * (c_plus - np.conj(c_minus))
    else:
        raise SpecError.out_of_range("component", component, "'rotating' or 'vertical'")
    # the counterweight's acceleration -r w^2 e^{i(t + beta)} cancels target e^{i t}
    return Counterweight(mass_moment=float(abs(target)) / w2, angle_on_crank=float(np.angle(target)))


def phasing_gain(phases: np.ndarray | list[float], n_harmonics: int) -> list[float]:
    """How much of harmonic n survives when arms run at crank phase offsets ``phases``.

    For identical arms the n-th harmonic of their summed shaking force is the single-arm
    one times ``|sum_k exp(i n phase_k)|`` (seed 003 eqs 70-72). Returned for n = 1..n_harmonics.
    """
    ph = np.asarray(phases, dtype=float)
    return [float(abs(np.sum(np.exp(1j * k * ph)))) for k in range(1, n_harmonics + 1)]


def arm_phases(n_arms: int, scheme: str = "paired") -> np.ndarray:
    """Crank phase offsets (rad) for ``n_arms`` identical arms.

    ``"paired"`` follows seed 003 section 5-6: arms in pairs at pi, pairs of pairs at pi/2,
    and so on by halving (for 2, 4 and 8 arms only harmonics that are multiples of 2, 4 and 8
    survive; 6 arms: the 4-arm set plus a pair at 0/pi, as Table 5 row 9). ``"even"`` spaces
    the arms at 2 pi / n, which leaves only multiples of n (best for force, but every arm
    plants at a different instant).
    """
    if not isinstance(n_arms, int) or n_arms < 1:
        raise SpecError.out_of_range("n_arms", n_arms, "an integer >= 1")
    if scheme == "even":
        return 2 * math.pi * np.arange(n_arms) / n_arms
    if scheme != "paired":
        raise SpecError.out_of_range("scheme", scheme, "'paired' or 'even'")
    if n_arms % 2:
        raise SpecError.out_of_range("n_arms", n_arms, "even for the paired scheme")
    phases: list[float] = [0.0]
    # van der Corput order: 0, pi, pi/2, 3pi/2, pi/4, 5pi/4, ...
    step = 0
    while len(phases) < n_arms:
        step += 1
        k, denom, x = step, 1.0, 0.0
        while k:
            denom *= 2.0
            x += (k & 1) / denom
            k >>= 1
        phases.append(2 * math.pi * x)
    return np.array(phases[:n_arms])


def sinusoidal_rocker_moment(fb: FourBar, coupler: LinkMass) -> tuple[float, float]:
    """Rocker mass moment (kg mm) making the shaking force purely sinusoidal (seed 003 eq. 80).

    ``m_d g_d = -m_c g_c d / c`` componentwise, with c the coupler and d the rocker length.
    """
    k = -fb.rocker / fb.coupler
    return (k * coupler.moment[0], k * coupler.moment[1])


def force_balance_moments(fb: FourBar, coupler: LinkMass) -> dict[Link, tuple[float, float]]:
    """Crank and rocker mass moments (kg mm) that cancel the shaking force (eqs 83-85).

    ``m_d g_d1 = -m_c g_c1 d/c``, ``m_d g_d2 = -m_c g_c2 d/c``,
    ``m_b g_b1 = -m_c (b/c)(c - g_c1)``, ``m_b g_b2 = m_c (b/c) g_c2``.
    """
    b, c = fb.crank, fb.coupler
    mc = coupler.mass
    gc1, gc2 = coupler.com
    return {
        Link.ROCKER: sinusoidal_rocker_moment(fb, coupler),
        Link.CRANK: (-mc * b / c * (c - gc1), mc * b / c * gc2),
    }
