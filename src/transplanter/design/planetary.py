"""Differential internal-engagement non-circular planetary transplanting train (seed 004).

The ring gear and the carrier turn clockwise about the same fixed axis O at different
speeds ω1 (ring) and ω2 (carrier); ``planets`` identical non-circular planets sit on the
carrier at equal spacing and mesh inside the ring; a planting arm is fixed to each planet.
Seed 004 eqs 1-10, with all angles counter-clockwise-positive in the frame, carrier turned by
``θ2 = ω2 t`` (clockwise), ring by ``θ1 = (ω1/ω2) θ2``:

- carrier line of arm k: ``φH = φH0 - θ2 - 2πk/N`` (eq 3; arm k+1 is where arm k will be
  after a further 2π/N of carrier rotation);
- the ring turns counter-clockwise relative to the carrier by ``γ1 = θ2 - θ1`` (eq 4);
- the planet turns counter-clockwise relative to the carrier by ``γ2``, the rolling integral
  of ``r1/r2`` over the *relative* angle γ1 (eq 5 prints ``dθ1``, the ring's absolute angle;
  rolling depends only on the relative motion, so γ1 is the physically consistent reading);
- planet attitude ``φ2 = φH + γ2`` (eq 7), planet centre ``|OO1| e(φH)`` (eq 8) with
  ``|OO1|`` the pair's centre distance, knee ``A = O1 + H1 e(φ2 + β + acos(H1/S))`` and tip
  ``B = O1 + S e(φ2 + β)`` (eqs 9-10): the needle AB is perpendicular to O1A.

Each planet's orientation is set by its own mesh with the ring (its contact lies on its
carrier line), so the N arms are computed independently; :meth:`DifferentialTrain.phase_error`
checks that they really are copies of one another shifted by 2π/N of carrier rotation.

The default speed ratio ``ω1/ω2 = 1 - n2/n1`` (n1 ring lobes, n2 planet lobes) makes the
planet turn exactly once relative to the carrier per carrier turn, i.e. the arm returns to
the same attitude every cycle without net rotation, as a transplanting arm must. The N arms
are copies of each other only if the next arm's planet finds the ring and its own attitude as
the first will after 2π/N of carrier rotation: the ring then turns ``(ω1/ω2) 2π/N`` relative
to that arm's contact, and the state repeats only every n2 ring lobes (a planet lobe meshes a
ring lobe, and the arm needs the planet's whole turn), so ``(ω1/ω2) n1 / (N n2)`` must be a
whole number — with the default ratio ``(n1 - n2)/(N n2)`` (n2 = 1: n1 = 4, 7, ... for N = 3;
seed 004's n = 4 is the smallest). The constructor refuses other combinations, naming them.

Examples
--------
>>> from transplanter.geometry.pitch import GearPair, PitchCurve
>>> from transplanter.design.planetary import ArmGeometry, DifferentialTrain
>>> pair = GearPair.from_driver(PitchCurve.ellipse(80.0, 0.1, lobes=4), "internal", driven_lobes=1)
>>> train = DifferentialTrain(pair, ArmGeometry(tip=150.0, knee=80.0, mount=-0.7), carrier_start=0.7)
>>> train.speed_ratio
0.75
>>> bool(train.phase_error() < 1e-9)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol, cast

import numpy as np

from transplanter.core.errors import MAX_MAGNITUDE, SpecError, check_int, check_number, finite_positive
from transplanter.geometry.pitch import FourierSeries, GearPair

__all__ = ["Transmission", "ArmGeometry", "ArmState", "DifferentialTrain"]


class Transmission(Protocol):
    """What the train needs from a ring-driven internal pair (``pitch.GearPair`` is one)."""

    @property
    def centre_distance(self) -> float: ...

    @property
    def lobes(self) -> tuple[int, int]: ...

    @property
    def ring(self) -> str | None: ...

    def driven_contact_angle(self, phi1): ...

    def ratio(self, phi1): ...


@dataclass(frozen=True)
class ArmGeometry:
    """A planting arm fixed to a planet (seed 004 eqs 9-10).

    Parameters
    ----------
    tip : float
        S, planet centre to the needle tip, mm.
    knee : float
        H1, planet centre to the knee (break point) A, mm; < S.
    mount : float
        β, angle of O1B from the planet's body x-axis, rad.
    """

    tip: float
    knee: float
    mount: float

    def __post_init__(self) -> None:
        finite_positive("tip (S)", self.tip)
        finite_positive("knee (H1)", self.knee)
        if not self.knee < self.tip:
            raise SpecError.out_of_range("knee (H1)", self.knee, f"< tip S = {self.tip} mm (acos(H1/S) must exist)")
        check_number("mount (β)", self.mount, -MAX_MAGNITUDE, MAX_MAGNITUDE, unit="rad")

    @property
    def knee_angle(self) -> float:
        """acos(H1/S): angle between O1A and O1B, rad."""
        return math.acos(self.knee / self.tip)

    @property
    def needle_length(self) -> float:
        """|AB| = sqrt(S² - H1²), mm."""
        return math.sqrt(self.tip**2 - self.knee**2)


@dataclass(frozen=True)
class ArmState:
    """One arm at carrier rotations ``theta`` (rad, clockwise from the start).

    Attributes
    ----------
    theta : (n,) float
    centre, knee, tip : (n, 2) float
        Planet centre O1, knee A and needle tip B in the frame, mm (O at the origin).
    planet_angle : (n,) float
        φ2, absolute attitude of the planet's body x-axis, rad.
    attitude : (n,) float
        Direction of the needle A→B, rad in [0, 2π) (seed 004's arm angle).
    """

    theta: np.ndarray
    centre: np.ndarray
    knee: np.ndarray
    tip: np.ndarray
    planet_angle: np.ndarray
    attitude: np.ndarray


def _unit(angle: np.ndarray) -> np.ndarray:
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


@dataclass(frozen=True, eq=False)
class DifferentialTrain:
    """Seed-004 train: ring-driven internal pair, N planets, one arm per planet.

    Parameters
    ----------
    pair : Transmission
        Internal pair with the ring as driver (``GearPair.from_driver(ring, "internal", n2)``).
    arm : ArmGeometry
    carrier_start : float
        φH0, angle of arm I's carrier line at the start, rad (the ring's and planet I's
        polar angle 0 lie on it: the initial meshing point).
    planets : int
        N, planets at equal spacing.
    speed_ratio : float or None
        ω1/ω2; None gives ``1 - n2/n1`` (no net arm rotation per cycle).
    carrier_speed : float
        |ω2|, rad/s (clockwise).
    """

    pair: Transmission
    arm: ArmGeometry
    carrier_start: float
    planets: int = 3
    speed_ratio: float | None = None
    carrier_speed: float = 2 * math.pi

    def __post_init__(self) -> None:
        if getattr(self.pair, "ring", None) != "driver":
            raise SpecError("pair must be an internal pair with the ring as driver (GearPair.from_driver(ring, ...))")
        check_int("planets", self.planets, 1, 64)
        check_number("carrier_start (φH0)", self.carrier_start, -MAX_MAGNITUDE, MAX_MAGNITUDE, unit="rad")
        finite_positive("carrier_speed", self.carrier_speed)
        n1, n2 = self.pair.lobes
        if self.speed_ratio is None:
            object.__setattr__(self, "speed_ratio", 1.0 - n2 / n1)
        elif check_number("speed_ratio ω1/ω2", self.speed_ratio, -1e3, 1e3) == 1.0:
            raise SpecError.out_of_range("speed_ratio ω1/ω2", self.speed_ratio, "finite and != 1 (differential)")
        copies = self.omega_ratio * n1 / (self.planets * n2)
        if self.planets > 1 and abs(copies - round(copies)) > 1e-9:
            raise SpecError(
                f"the {self.planets} arms would not be copies of each other: (ω1/ω2)·n1/(N·n2) = "
                f"{self.speed_ratio:.6g}·{n1}/({self.planets}·{n2}) = {copies:.6g} must be a whole number "
                f"(with the default ratio: (n1 - n2)/(N·n2)); choose other lobe numbers or planets"
            )

    @property
    def omega_ratio(self) -> float:
        """ω1/ω2, ring to carrier speed: ``speed_ratio`` as given or its default (set at creation)."""
        return cast(float, self.speed_ratio)

    @property
    def period(self) -> float:
        """Time of one carrier turn, s."""
        return 2 * math.pi / self.carrier_speed

    @property
    def relative_turns(self) -> float:
        """Planet turns relative to the carrier per carrier turn."""
        n1, n2 = self.pair.lobes
        return (1 - self.omega_ratio) * n1 / n2

    def state(self, theta, arm_index: int = 0) -> ArmState:
        """Arm ``arm_index`` (0 = arm I) at carrier rotations ``theta`` (rad, clockwise)."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        offset = 2 * math.pi * arm_index / self.planets
        phi_h = self.carrier_start - theta - offset
        gamma1 = (1.0 - self.omega_ratio) * theta
        # ring body angle of this planet's contact, then the planet's own contact angle
        contact = self.pair.driven_contact_angle(-offset - gamma1)
        planet = phi_h - contact
        centre = self.pair.centre_distance * _unit(phi_h)
        g = self.arm
        knee = centre + g.knee * _unit(planet + g.mount + g.knee_angle)
        tip = centre + g.tip * _unit(planet + g.mount)
        needle = tip - knee
        attitude = np.mod(np.arctan2(needle[:, 1], needle[:, 0]), 2 * math.pi)
        return ArmState(theta, centre, knee, tip, planet, attitude)

    def cycle(self, n: int = 3600, arm_index: int = 0) -> ArmState:
        """One carrier turn sampled uniformly (n points, end point excluded)."""
        return self.state(2 * math.pi * np.arange(n) / n, arm_index)

    @classmethod
    def from_ratio(
        cls,
        lobes: int,
        harmonics,
        centre_distance: float,
        arm: ArmGeometry,
        carrier_start: float,
        planets: int = 3,
    ) -> DifferentialTrain:
        """The train whose ring drives a one-lobed planet with the ratio law

        ``i(φ) = ω_planet/ω_ring = n (1 + Σ_k c_k cos(k n φ) + s_k sin(k n φ))``, relative to the
        carrier, ``n = lobes``, ``harmonics = ((c_1, s_1), (c_2, s_2), ...)``; φ is the ring's
        angle relative to the carrier (rad). Its mean is n, so both pitch curves close exactly:
        the ring's radius is ``a i/(i - 1)`` and the planet's ``a/(i - 1)``, with ``a`` the
        carrier radius ``centre_distance`` (mm). ``i`` must stay above 1 (GeometryError if not).
        """
        n = check_int("lobes", lobes, 2, 64)
        coeffs = np.asarray(harmonics, dtype=float).reshape(-1, 2) if len(harmonics) else np.zeros((0, 2))
        ratio = FourierSeries(float(n), tuple(n * coeffs[:, 0]), tuple(n * coeffs[:, 1]), lobes=n)
        pair = GearPair.from_ratio(ratio, centre_distance, "internal", ring="driver")
        return cls(pair, arm, carrier_start, planets=planets)

    def phase_error(self, n: int = 720) -> float:
        """Largest distance (mm) between arm k and arm I shifted by 2πk/N of carrier rotation."""
        theta = 2 * math.pi * np.arange(n) / n
        worst = 0.0
        for k in range(1, self.planets):
            a = self.state(theta, k)
            b = self.state(theta + 2 * math.pi * k / self.planets, 0)
            worst = max(worst, float(np.max(np.linalg.norm(a.tip - b.tip, axis=1))))
        return worst

    def closure_error(self) -> float:
        """Distance (mm) between the tip at the start and after one carrier turn."""
        s = self.state(np.array([0.0, 2 * math.pi]))
        return float(np.linalg.norm(s.tip[1] - s.tip[0]))
