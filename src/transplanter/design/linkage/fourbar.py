"""Planar four-bar linkage: closed-form position, analytic velocity and acceleration.

Convention (the vector loop of seeds 001 and 003)
-------------------------------------------------
The crank turns about the crank pivot ``O2`` (``origin``); the rocker about the rocker
pivot ``O4 = O2 + ground * e(ground_angle)``. The crank pin ``B`` and rocker pin ``C``
close the loop::

    crank * e(t2) + coupler * e(t3) = ground * e(ground_angle) + rocker * e(t4)

with every angle absolute (counter-clockwise from +x) and ``e(t) = (cos t, sin t)``:
``t2`` is the direction O2->B, ``t3`` the direction B->C and ``t4`` the direction O4->C.
Lengths are in mm, angles in rad, time in s.

Each moving link carries a frame: the crank frame has its origin at ``O2`` and its x axis
along O2->B, the coupler frame its origin at ``B`` and x along B->C, the rocker frame its
origin at ``O4`` and x along O4->C. A point fixed on a link is given by its (u, v) in
that frame (seed 003 gives centres of mass exactly this way).

``branch`` picks one of the two assemblies: +1 puts ``C`` to the left of the directed line
B->O4 (seed 003's L = 1, "C above at t2 = 0"), -1 to the right. A linkage whose input
link turns fully never passes a toggle, so the branch holds over the whole revolution and
the closed form is continuous in the crank angle.

Examples
--------
>>> import numpy as np
>>> from transplanter.design.linkage.fourbar import FourBar
>>> fb = FourBar(ground=125.0, crank=40.0, coupler=100.0, rocker=85.0)
>>> fb.grashof_class().name
'CRANK_ROCKER'
>>> m = fb.solve(np.radians([0.0, 90.0]), omega2=8 * np.pi)
>>> bool(np.max(fb.loop_closure_error(m)) < 1e-9)
True
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import MAX_MAGNITUDE, AssemblyError, SpecError, check_number, finite_positive
from transplanter.core.tolerances import ASSEMBLY_MARGIN

__all__ = [
    "Link",
    "GrashofClass",
    "FourBar",
    "FourBarMotion",
    "PointMotion",
]


class Link(enum.Enum):
    """The four links; a point is fixed on one of them."""

    GROUND = "ground"
    CRANK = "crank"
    COUPLER = "coupler"
    ROCKER = "rocker"


class GrashofClass(enum.Enum):
    """Grashof classification (s + l against p + q) with the link that is shortest."""

    CRANK_ROCKER = "crank-rocker: the crank turns fully, the rocker oscillates"
    DOUBLE_CRANK = "double-crank (drag link): both side links turn fully"
    DOUBLE_ROCKER = "Grashof double-rocker: only the coupler turns fully"
    ROCKER_CRANK = "rocker-crank: the output turns fully, the input only rocks"
    CHANGE_POINT = "change point (s + l = p + q): the linkage can fold flat and switch branch"
    TRIPLE_ROCKER = "non-Grashof triple rocker: no link turns fully"


def _require_finite_positive(name: str, value: float) -> float:
    return finite_positive(name, value)


def _require_finite(name: str, value: float) -> float:
    return check_number(name, value, -MAX_MAGNITUDE, MAX_MAGNITUDE)


def _as_xy(c: np.ndarray) -> np.ndarray:
    """Complex (n,) -> (n, 2) float."""
    return np.stack([c.real, c.imag], axis=-1)


@dataclass(frozen=True)
class PointMotion:
    """Position, velocity and acceleration of one point over a set of crank angles.

    Attributes
    ----------
    position, velocity, acceleration : (n, 2) float
        mm, mm/s and mm/s^2 in the linkage's drawing frame.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray

    @property
    def speed(self) -> np.ndarray:
        """(n,) float, mm/s."""
        return np.hypot(self.velocity[:, 0], self.velocity[:, 1])

    @property
    def acceleration_magnitude(self) -> np.ndarray:
        """(n,) float, mm/s^2."""
        return np.hypot(self.acceleration[:, 0], self.acceleration[:, 1])


@dataclass(frozen=True)
class FourBarMotion:
    """State of every link at n crank angles (all arrays (n,), rad, rad/s, rad/s^2).

    ``theta[k]``, ``omega[k]`` and ``alpha[k]`` are indexed by :class:`Link`
    (the ground link has the constant ``ground_angle`` and zero rates).
    """

    linkage: FourBar
    theta: dict[Link, np.ndarray]
    omega: dict[Link, np.ndarray]
    alpha: dict[Link, np.ndarray]
    #: ``exp(i theta)`` of the moving links, as :meth:`FourBar.solve` found them (saves the trig)
    unit: dict[Link, np.ndarray] = field(default_factory=dict, repr=False, compare=False)

    def _unit(self, link: Link) -> np.ndarray:
        found = self.unit.get(link)
        return np.exp(1j * self.theta[link]) if found is None else found

    @property
    def crank_angle(self) -> np.ndarray:
        return self.theta[Link.CRANK]

    def _frame(self, link: Link) -> tuple[complex | np.ndarray, complex | np.ndarray, complex | np.ndarray]:
        """Origin position, velocity, acceleration of a link frame, as complex (n,)."""
        fb = self.linkage
        o2 = complex(*fb.origin)
        n = self.crank_angle.shape[0]
        zero = np.zeros(n, dtype=complex)
        if link in (Link.GROUND, Link.CRANK):
            return zero + o2, zero, zero
        if link is Link.ROCKER:
            return zero + complex(*fb.rocker_pivot), zero, zero
        w2 = self.omega[Link.CRANK]
        a2 = self.alpha[Link.CRANK]
        e2 = self._unit(Link.CRANK)
        return o2 + fb.crank * e2, fb.crank * 1j * w2 * e2, fb.crank * (1j * a2 - w2**2) * e2

    def point(self, link: Link, local: tuple[float, float] | np.ndarray) -> PointMotion:
        """Motion of a point fixed on ``link`` at ``local`` = (u, v) mm in the link frame.

        Velocity and acceleration are the rigid-body formulas
        ``v = v_O + w x r`` and ``a = a_O + alpha x r - w^2 r``, exact to round-off.
        """
        u, v = (float(x) for x in np.asarray(local, dtype=float).reshape(2))
        p0, v0, a0 = self._frame(link)
        r = (u + 1j * v) * self._unit(link)
        w = self.omega[link]
        al = self.alpha[link]
        return PointMotion(
            position=_as_xy(p0 + r),
            velocity=_as_xy(v0 + 1j * w * r),
            acceleration=_as_xy(a0 + (1j * al - w**2) * r),
        )

    def joints(self) -> dict[str, np.ndarray]:
        """Joint positions ``O2``, ``B``, ``C``, ``O4`` as (n, 2) float, mm."""
        fb = self.linkage
        b = self.point(Link.CRANK, (fb.crank, 0.0)).position
        c = self.point(Link.ROCKER, (fb.rocker, 0.0)).position
        n = b.shape[0]
        return {
            "O2": np.tile(np.asarray(fb.origin, dtype=float), (n, 1)),
            "B": b,
            "C": c,
            "O4": np.tile(np.asarray(fb.rocker_pivot, dtype=float), (n, 1)),
        }


@dataclass(frozen=True)
class FourBar:
    """A planar four-bar linkage in the vector-loop convention (see module docstring).

    Parameters
    ----------
    ground, crank, coupler, rocker : float
        Link lengths O2-O4, O2-B, B-C, O4-C in mm.
    ground_angle : float
        Direction of O2->O4 in rad, counter-clockwise from +x.
    branch : int
        +1 or -1, the assembly (see module docstring).
    origin : (float, float)
        Position of the crank pivot O2 in mm.
    """

    ground: float
    crank: float
    coupler: float
    rocker: float
    ground_angle: float = 0.0
    branch: int = 1
    origin: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        for name in ("ground", "crank", "coupler", "rocker"):
            object.__setattr__(self, name, _require_finite_positive(name, getattr(self, name)))
        object.__setattr__(self, "ground_angle", _require_finite("ground_angle", self.ground_angle))
        if self.branch not in (1, -1):
            raise SpecError.out_of_range("branch", self.branch, "+1 or -1")
        ox, oy = (_require_finite("origin", c) for c in self.origin)
        object.__setattr__(self, "origin", (ox, oy))

    @classmethod
    def from_pivots(
        cls,
        crank_pivot: tuple[float, float],
        rocker_pivot: tuple[float, float],
        crank: float,
        coupler: float,
        rocker: float,
        branch: int = 1,
    ) -> FourBar:
        """Build from the two ground pivot positions (mm) and the moving link lengths."""
        o2 = np.asarray(crank_pivot, dtype=float).reshape(2)
        d = np.asarray(rocker_pivot, dtype=float).reshape(2) - o2
        return cls(
            ground=float(np.hypot(*d)),
            crank=crank,
            coupler=coupler,
            rocker=rocker,
            ground_angle=float(np.arctan2(d[1], d[0])),
            branch=branch,
            origin=(float(o2[0]), float(o2[1])),
        )

    @property
    def rocker_pivot(self) -> tuple[float, float]:
        """Position of O4 in mm."""
        return (
            self.origin[0] + self.ground * math.cos(self.ground_angle),
            self.origin[1] + self.ground * math.sin(self.ground_angle),
        )

    # -- classification ------------------------------------------------------------------
    def grashof_class(self) -> GrashofClass:
        """Grashof class of the linkage, with the crank as input link."""
        lengths = {
            Link.GROUND: self.ground,
            Link.CRANK: self.crank,
            Link.COUPLER: self.coupler,
            Link.ROCKER: self.rocker,
        }
        ordered = sorted(lengths.values())
        s, p, q, lg = ordered
        lhs, rhs = s + lg, p + q
        if abs(lhs - rhs) <= ASSEMBLY_MARGIN * rhs:
            return GrashofClass.CHANGE_POINT
        if lhs > rhs:
            return GrashofClass.TRIPLE_ROCKER
        shortest = min(lengths, key=lengths.__getitem__)
        return {
            Link.CRANK: GrashofClass.CRANK_ROCKER,
            Link.GROUND: GrashofClass.DOUBLE_CRANK,
            Link.COUPLER: GrashofClass.DOUBLE_ROCKER,
            Link.ROCKER: GrashofClass.ROCKER_CRANK,
        }[shortest]

    def crank_turns_fully(self) -> bool:
        """True when the crank can make whole revolutions without a toggle."""
        return self.grashof_class() in (GrashofClass.CRANK_ROCKER, GrashofClass.DOUBLE_CRANK)

    def require_full_rotation(self) -> None:
        """Raise :class:`AssemblyError` naming the broken limit unless the crank turns fully.

        Over a revolution the distance B-O4 sweeps [|ground - crank|, ground + crank]; the
        dyad coupler-rocker reaches every such distance without a toggle exactly when
        ``ground + crank < coupler + rocker`` and ``|ground - crank| > |coupler - rocker|``.
        """
        far = self.ground + self.crank
        reach = self.coupler + self.rocker
        margin = ASSEMBLY_MARGIN * max(far, reach)
        if far >= reach - margin:
            raise AssemblyError(
                f"crank cannot turn fully: ground + crank = {far:.6g} mm must be < "
                f"coupler + rocker = {reach:.6g} mm (Grashof class: {self.grashof_class().value})"
            )
        near = abs(self.ground - self.crank)
        fold = abs(self.coupler - self.rocker)
        if near <= fold + margin:
            raise AssemblyError(
                f"crank cannot turn fully: |ground - crank| = {near:.6g} mm must be > "
                f"|coupler - rocker| = {fold:.6g} mm (Grashof class: {self.grashof_class().value})"
            )

    # -- kinematics ----------------------------------------------------------------------
    def solve(
        self,
        theta2: float | np.ndarray,
        omega2: float | np.ndarray = 1.0,
        alpha2: float | np.ndarray = 0.0,
    ) -> FourBarMotion:
        """Positions, angular velocities and accelerations at crank angles ``theta2``.

        Parameters
        ----------
        theta2 : float or (n,) float
            Absolute crank angles, rad.
        omega2, alpha2 : float or (n,) float
            Crank angular velocity (rad/s) and acceleration (rad/s^2) at those angles.

        Returns
        -------
        FourBarMotion
            Closed-form positions (circle-circle intersection on ``branch``) and analytic
            rates from the differentiated loop equation; no finite differences.

        Raises
        ------
        AssemblyError
            If the loop cannot close at some requested angle (the message gives it).
        """
        t2 = np.atleast_1d(np.asarray(theta2, dtype=float))
        if t2.ndim != 1 or not np.all(np.isfinite(t2)):
            raise SpecError("theta2 must be a finite 1-D array of crank angles in rad")
        w2 = np.broadcast_to(np.asarray(omega2, dtype=float), t2.shape).astype(float)
        a2 = np.broadcast_to(np.asarray(alpha2, dtype=float), t2.shape).astype(float)
        if not (np.all(np.isfinite(w2)) and np.all(np.isfinite(a2))):
            raise SpecError("omega2 and alpha2 must be finite")

        o2 = complex(*self.origin)
        o4 = complex(*self.rocker_pivot)
        e2 = np.exp(1j * t2)
        b = o2 + self.crank * e2
        bd = o4 - b
        s = np.abs(bd)
        cos_g = (self.coupler**2 + s**2 - self.rocker**2) / (2.0 * self.coupler * s)
        bad = np.abs(cos_g) > 1.0 - ASSEMBLY_MARGIN
        if np.any(bad):
            first = float(np.degrees(t2[np.argmax(bad)]))
            raise AssemblyError(
                f"linkage cannot be assembled at crank angle theta2 = {first:.6g} deg: "
                f"distance B-O4 must lie strictly within [|coupler - rocker|, coupler + rocker] = "
                f"[{abs(self.coupler - self.rocker):.6g}, {self.coupler + self.rocker:.6g}] mm"
            )
        # the coupler's direction: B->O4 turned by +-gamma (cos gamma from the triangle B-C-O4),
        # as a unit phasor — no arccos and exp; C and the rocker's phasor follow
        e3 = bd / s * (cos_g + 1j * (self.branch * np.sqrt(1.0 - cos_g * cos_g)))
        c = b + self.coupler * e3
        e4 = (c - o4) / self.rocker
        t3, t4 = np.angle(e3), np.angle(e4)

        sin34 = (e3 * e4.conjugate()).imag  # sin(t3 - t4), non-zero away from toggles (checked above)
        w3, w4 = self._solve_dyad(-self.crank * w2 * e2, e3, e4, sin34)
        rhs = -self.crank * (1j * a2 - w2**2) * e2 + self.coupler * w3**2 * e3 - self.rocker * w4**2 * e4
        al3, al4 = self._solve_dyad(-1j * rhs, e3, e4, sin34)

        zeros = np.zeros_like(t2)
        theta = {Link.GROUND: zeros + self.ground_angle, Link.CRANK: t2, Link.COUPLER: t3, Link.ROCKER: t4}
        omega = {Link.GROUND: zeros, Link.CRANK: w2, Link.COUPLER: w3, Link.ROCKER: w4}
        alpha = {Link.GROUND: zeros, Link.CRANK: a2, Link.COUPLER: al3, Link.ROCKER: al4}
        unit = {Link.CRANK: e2, Link.COUPLER: e3, Link.ROCKER: e4}
        return FourBarMotion(linkage=self, theta=theta, omega=omega, alpha=alpha, unit=unit)

    def _solve_dyad(
        self, w: np.ndarray, e3: np.ndarray, e4: np.ndarray, sin34: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Solve ``coupler*x*e3 - rocker*y*e4 = w`` for real x, y (Cramer's rule; ``e3``, ``e4``
        the unit phasors of the coupler and the rocker)."""
        x = (w * e4.conjugate()).imag / (self.coupler * sin34)
        y = (w * e3.conjugate()).imag / (self.rocker * sin34)
        return x, y

    def transmission_angle(self, motion: FourBarMotion) -> np.ndarray:
        """Angle between coupler and rocker at C, in (0, pi) rad, (n,) float.

        90 deg is ideal; designers usually keep it within 40-140 deg.
        """
        # angle between C->B = -e(t3) and C->O4 = -e(t4)
        return np.arccos(np.clip(np.cos(motion.theta[Link.COUPLER] - motion.theta[Link.ROCKER]), -1.0, 1.0))

    def loop_closure_error(self, motion: FourBarMotion) -> np.ndarray:
        """|O2 + crank e2 + coupler e3 - O4 - rocker e4| in mm, (n,) float."""
        o2 = complex(*self.origin)
        o4 = complex(*self.rocker_pivot)
        lhs = o2 + self.crank * np.exp(1j * motion.theta[Link.CRANK])
        lhs = lhs + self.coupler * np.exp(1j * motion.theta[Link.COUPLER])
        rhs = o4 + self.rocker * np.exp(1j * motion.theta[Link.ROCKER])
        return np.abs(lhs - rhs)
