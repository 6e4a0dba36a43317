"""Intermittent motion laws and the incomplete pitch pair that carries them.

A designer who needs the driven gear to **stop** (to take a seedling from the tray, to let a pot
drop) states its motion over one driver turn as segments: a **dwell** (the driven angle held) or
a **motion** ψ(φ) over an interval of driver angle. The driver turns at constant speed; the
driven gear is toothed where it moves and held by a locking arc where it dwells
(:mod:`transplanter.geometry.incomplete` cuts both).

Three ways in, one way out (an :class:`IntermittentLaw`):

* **text** (``transplanter pair``): segments ``A..B: dwell`` or ``A..B: EXPR`` separated by ``;``
  or a new line, A and B driver angles in degrees, contiguous over one turn; EXPR is ψ(φ) in
  ``phi`` (rad, the driver's absolute angle; only its rise over the segment counts — a dwell holds
  the angle), with the expression rules of :mod:`transplanter.geometry.pitch.transmission` (checked
  syntax tree, no eval); the grammar, and each refusal naming the segment, in
  :mod:`transplanter.geometry.pitch.law_text`::

      0..60: dwell; 60..360: 2*pi*(phi - pi/3)/(5*pi/3) - 0.35*sin(2*pi*(phi - pi/3)/(5*pi/3))

* **CSV** of ratio samples ``phi_deg, ratio`` over one turn: a row with ratio 0 marks a dwell; a
  motion segment runs from its first to its last positive row (a cubic spline through them), a
  dwell spans from the last positive row of one motion to the first of the next;
* **Python**: ``IntermittentLaw((Dwell(0, 60), Motion(60, 360, "...")))``, angles in degrees.

**What a law must do.** Over one driver turn the driven gear turns 1/n2 of a turn for a whole
n2 (else it is refused, naming what it turns and the factor that would close it); its ratio
ψ' = ω2/ω1 is positive over every motion (a ratio that reaches 0 needs a pitch radius of 0 on
the driver — no tooth carries it: the law must start and end each motion with a finite ratio,
and that **jump** of the driven speed at each dwell/motion boundary is the shock these
mechanisms wear from; :meth:`IntermittentLaw.transitions` states it); an internal pair (the
planet drives a ring) needs ψ' < 1.

:class:`IncompletePair` is the law at a centre distance: the pitch radii of the moving sectors
(external ``r1 = a i/(1 + i)``; planet in a ring ``r1 = a i/(1 - i)``), the driven angle, and
what the meshing proof needs of a pair (``meshing.MeshingPair``: ``centre_distance``, ``ring``,
``driver.r``, ``driven_rotation``); during a dwell the driver's "pitch radius" is its locking
arc's, so the proof's free play there is measured at the lock.

Examples
--------
>>> law = IntermittentLaw.parse("0..90: dwell; 90..360: 4/3*phi")
>>> law.turn_fraction, [round(t.speed_jump, 6) for t in law.transitions()]
(1, [1.333333, -1.333333])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.polynomial import Chebyshev
from scipy.interpolate import CubicSpline

from transplanter.core.errors import GeometryError, SpecError, check_number, finite_positive
from transplanter.geometry.pitch.law_text import MAX_SEGMENTS, is_segmented, segments
from transplanter.geometry.pitch.transmission import _compile, csv_table

__all__ = ["Dwell", "Motion", "IntermittentLaw", "IncompletePair", "Transition", "is_segmented", "MAX_SEGMENTS"]

#: Chebyshev degrees tried for a motion's ψ(φ), lowest first; the last coefficients must have died
#: out to ``CHEB_TAIL`` of the largest (else the expression is not smooth over its segment)
CHEB_DEGREES = (8, 16, 32, 64, 128, 256)
CHEB_TAIL = 1e-10
#: the closure misfit (relative) taken as round-off of the law's integral
CLOSURE_ROUND_OFF = 1e-9
#: smallest ratio a motion may reach (the driver's pitch radius a i/(1+i) falls with it)
MIN_RATIO = 0.05


@dataclass(frozen=True)
class Dwell:
    """The driven gear held from driver angle ``start`` to ``end`` (deg)."""

    start: float
    end: float


@dataclass(frozen=True)
class Motion:
    """The driven gear moved by ψ(φ) from driver angle ``start`` to ``end`` (deg): ``law`` is an
    expression in ``phi`` (rad, the driver's absolute angle) or a callable ``law(phi, nu)`` giving
    the ratio ψ' (nu = 0) and its derivative (nu = 1) on arrays; ``rise`` its driven turn (rad)."""

    start: float
    end: float
    law: object = field(compare=False)

    @cached_property
    def _fit(self):
        """(ψ, dψ/dφ, d²ψ/dφ², d³ψ/dφ³) as callables: a Chebyshev series of an expression, or the
        antiderivative of a ratio spline (CSV)."""
        a, b = math.radians(self.start), math.radians(self.end)
        if isinstance(self.law, CubicSpline):
            return self.law.antiderivative(), self.law, self.law.derivative(), self.law.derivative(2)
        if callable(self.law):
            raise SpecError("a motion's law must be an expression in phi or a scipy CubicSpline of the ratio")
        psi = _compile(str(self.law))
        for degree in CHEB_DEGREES:  # the lowest degree that converges: its derivatives lose least
            with np.errstate(all="ignore"):
                cheb = Chebyshev.interpolate(lambda x: psi(np.asarray(x, dtype=float)), degree, domain=[a, b])
            coef = cheb.coef
            if not np.all(np.isfinite(coef)):
                raise SpecError(f"the motion {self.start:g}..{self.end:g} deg: psi = {self.law!r} is not finite there")
            size = max(float(np.max(np.abs(coef[1:]))), 1e-300)
            if float(np.max(np.abs(coef[-4:]))) <= CHEB_TAIL * size:
                break
        else:
            raise SpecError(
                f"the motion {self.start:g}..{self.end:g} deg: psi = {self.law!r} is not smooth over its segment (its "
                f"Chebyshev series has not converged at degree {CHEB_DEGREES[-1]})"
            )
        return cheb, cheb.deriv(1), cheb.deriv(2), cheb.deriv(3)

    def ratio(self, phi, nu: int = 0) -> np.ndarray:
        """ψ'(φ) (nu = 0), ψ''(φ) (nu = 1) or ψ'''(φ) (nu = 2) at driver angles ``phi`` (rad,
        within the segment)."""
        if nu not in (0, 1, 2):
            raise SpecError.out_of_range("nu", nu, "0, 1 or 2 (the ratio and its first two derivatives)")
        return np.asarray(self._fit[1 + nu](np.asarray(phi, dtype=float)), dtype=float)

    def rise(self, phi=None):
        """ψ(φ) - ψ(start), rad (at ``phi``; the whole rise without)."""
        a = math.radians(self.start)
        end = math.radians(self.end) if phi is None else np.asarray(phi, dtype=float)
        f = self._fit[0]
        out = np.asarray(f(end), dtype=float) - float(f(a))
        return float(out) if phi is None else out


@dataclass(frozen=True)
class Transition:
    """A dwell/motion boundary: driver angle (deg), ``"entry"`` (dwell → motion) or ``"exit"``,
    and the jump of the driven speed and acceleration there per unit driver speed (ω2/ω1, 1/rad):
    ``Δω2 = speed_jump · ω1``, ``Δα2 = accel_jump · ω1²``."""

    at_deg: float
    kind: str
    speed_jump: float
    accel_jump: float


@dataclass(frozen=True, eq=False)
class IntermittentLaw:
    """A driven motion over one driver turn as dwells and motions (see the module docstring)."""

    segments: tuple

    def __post_init__(self) -> None:
        segs = tuple(self.segments)
        if not segs or not all(isinstance(s, Dwell | Motion) for s in segs):
            raise SpecError("an intermittent law is a sequence of Dwell and Motion segments")
        if len(segs) > MAX_SEGMENTS:
            raise SpecError.out_of_range("the law's number of segments", len(segs), f"<= {MAX_SEGMENTS}")
        for k, s in enumerate(segs, 1):
            check_number(f"segment {k}'s start", s.start, -360.0, 720.0, unit="deg")
            check_number(f"segment {k}'s end", s.end, -360.0, 720.0, unit="deg")
            if not s.end > s.start:
                where = f"segment {k} ({s.start:g}..{s.end:g} deg): its end"
                raise SpecError.out_of_range(where, s.end, f"> {s.start:g}")
        for k, (prev, nxt) in enumerate(zip(segs, segs[1:], strict=False), 2):
            if abs(nxt.start - prev.end) > 1e-9:
                raise SpecError(
                    f"the segments must follow each other: segment {k - 1} ends at {prev.end:g} deg, segment {k} "
                    f"starts at {nxt.start:g} deg"
                )
        if abs(segs[-1].end - segs[0].start - 360.0) > 1e-9:
            raise SpecError.out_of_range("the segments' span", segs[-1].end - segs[0].start, "one driver turn, 360 deg")
        if not any(isinstance(s, Dwell) for s in segs) or not any(isinstance(s, Motion) for s in segs):
            raise SpecError("an intermittent law needs at least one dwell and one motion (else it is a plain pair)")
        for prev, nxt in zip(segs, segs[1:], strict=False):
            if type(prev) is type(nxt):
                raise SpecError(f"two {type(prev).__name__.lower()}s follow each other at {prev.end:g} deg: join them")
        if type(segs[0]) is type(segs[-1]):
            raise SpecError(
                "the law's first and last segments are both " + type(segs[0]).__name__.lower() + "s: join them"
            )
        object.__setattr__(self, "segments", segs)
        for m in self.motions:
            phi = np.linspace(math.radians(m.start), math.radians(m.end), 2001)
            i = m.ratio(phi)
            if not np.all(np.isfinite(i)):
                raise SpecError(f"the motion {m.start:g}..{m.end:g} deg: its ratio is not finite")
            k = int(np.argmin(i))
            if i[k] < MIN_RATIO:
                raise GeometryError(
                    f"the motion {m.start:g}..{m.end:g} deg: its ratio w2/w1 = {i[k]:.4g} at "
                    f"{math.degrees(phi[k]):.2f} deg is below {MIN_RATIO:g}: the driver's pitch radius a*i/(1+i) "
                    "shrinks to nothing there and no "
                    "tooth carries it — start and end each motion with a finite speed (the jump is reported)"
                )
        total = self.total_rise
        n2 = 2 * math.pi / total
        if abs(n2 - round(n2)) > CLOSURE_ROUND_OFF * n2 or round(n2) < 1:
            k = max(1, round(n2))
            raise SpecError(
                f"the law does not close: over a driver turn it turns the driven gear {total / (2 * math.pi):.9g} "
                f"turns, and a closed driven gear turns 1/n2 of a turn for a whole n2; scaled by "
                f"{2 * math.pi / k / total:.9g} it would turn 1/{k}"
            )

    # -- construction ----------------------------------------------------------------------

    @classmethod
    def parse(cls, text: str) -> IntermittentLaw:
        """The law of ``A..B: dwell; A..B: EXPR; ...`` (module docstring): segments separated by ``;``
        or a line break, at most ``MAX_SEGMENTS``; SpecError naming the segment and what was expected."""
        segs = []
        for start, end, body in segments(text):
            segs.append(Dwell(start, end) if body is None else Motion(start, end, body))
        return cls(tuple(segs))

    @classmethod
    def from_csv(cls, data: bytes) -> IntermittentLaw:
        """The law of ratio samples (module docstring): rows ``phi_deg, ratio``, 0 marking dwells."""
        return cls.from_table(*csv_table(data))

    @classmethod
    def from_table(cls, deg: np.ndarray, ratio: np.ndarray) -> IntermittentLaw:
        """The law of ratio samples already read (:func:`transmission.csv_table`): 0 marks dwells."""
        if np.any(ratio < 0):
            i = int(np.argmax(ratio < 0))
            raise SpecError.out_of_range(f"ratio at {deg[i]:g} deg", float(ratio[i]), ">= 0 (0 marks a dwell)")
        moving = ratio > 0
        if moving.all() or not moving.any():
            raise SpecError("the ratio CSV needs rows with ratio 0 (a dwell) and rows with a positive ratio (a motion)")
        # turn the table so that it starts with a motion's first row
        k = int(np.flatnonzero(moving & ~np.roll(moving, 1))[0])
        deg = np.concatenate([deg[k:], deg[:k] + 360.0])
        ratio, moving = np.roll(ratio, -k), np.roll(moving, -k)
        segs: list = []
        i = 0
        while i < len(deg):
            j = i
            while j + 1 < len(deg) and moving[j + 1]:
                j += 1
            if j - i < 3:
                raise SpecError(f"the motion starting at {deg[i] % 360:g} deg has {j - i + 1} rows: it needs >= 4")
            segs.append(Motion(float(deg[i]), float(deg[j]), CubicSpline(np.radians(deg[i : j + 1]), ratio[i : j + 1])))
            nxt = j + 1
            while nxt < len(deg) and not moving[nxt]:
                nxt += 1
            segs.append(Dwell(float(deg[j]), float(deg[nxt]) if nxt < len(deg) else float(deg[0]) + 360.0))
            i = nxt
        return cls(tuple(segs))

    # -- kinematics ------------------------------------------------------------------------

    @property
    def motions(self) -> tuple[Motion, ...]:
        return tuple(s for s in self.segments if isinstance(s, Motion))

    @property
    def dwells(self) -> tuple[Dwell, ...]:
        return tuple(s for s in self.segments if isinstance(s, Dwell))

    @cached_property
    def rises(self) -> tuple[float, ...]:
        return tuple(float(m.rise()) for m in self.motions)

    @property
    def total_rise(self) -> float:
        """The driven gear's turn over one driver turn, rad."""
        return float(sum(self.rises))

    @property
    def turn_fraction(self) -> int:
        """n2: the driven gear turns 1/n2 of a turn per driver turn."""
        return int(round(2 * math.pi / self.total_rise))

    def _where(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Segment index of each driver angle (rad, any turn) and the number of whole turns."""
        start = math.radians(self.segments[0].start)
        turns = np.floor((phi - start) / (2 * math.pi))
        deg = np.degrees(phi - turns * 2 * math.pi)
        ends = np.array([s.end for s in self.segments])
        return np.minimum(np.searchsorted(ends, deg, side="right"), len(ends) - 1), turns

    def psi(self, phi) -> np.ndarray:
        """The driven angle ψ (rad, from 0 at the first segment's start) at driver angles ``phi``."""
        phi = np.asarray(phi, dtype=float)
        idx, turns = self._where(phi)
        local = phi - turns * 2 * math.pi
        out = turns * self.total_rise
        base = 0.0
        k = 0
        result = np.array(out, dtype=float)
        for j, s in enumerate(self.segments):
            sel = idx == j
            if isinstance(s, Motion):
                if np.any(sel):
                    result[sel] += base + np.asarray(s.rise(local[sel]), dtype=float)
                base += self.rises[k]
                k += 1
            else:
                result[sel] += base
        return result

    def ratio(self, phi, nu: int = 0) -> np.ndarray:
        """ψ' (nu = 0) or ψ'' (nu = 1) at driver angles ``phi`` (0 in a dwell)."""
        phi = np.asarray(phi, dtype=float)
        idx, turns = self._where(phi)
        local = phi - turns * 2 * math.pi
        out = np.zeros(np.shape(phi))
        for j, s in enumerate(self.segments):
            sel = idx == j
            if isinstance(s, Motion) and np.any(sel):
                out[sel] = s.ratio(local[sel], nu)
        return out

    def transitions(self) -> list[Transition]:
        """The speed and acceleration jumps at each dwell/motion boundary (per unit driver speed)."""
        out = []
        for s in self.motions:
            a, b = math.radians(s.start), math.radians(s.end)
            ia, ib = s.ratio(np.array([a, b])), s.ratio(np.array([a, b]), 1)
            out.append(Transition(s.start % 360, "entry", float(ia[0]), float(ib[0])))
            out.append(Transition(s.end % 360, "exit", -float(ia[1]), -float(ib[1])))
        return out

    def describe(self) -> str:
        parts = []
        for s in self.segments:
            what = "dwell" if isinstance(s, Dwell) else "motion"
            parts.append(f"{what} {s.start:g}..{s.end:g} deg")
        return ", ".join(parts)


class _Radius:
    """The driver's pitch radius over the cycle (``driver.r`` of the meshing protocol): the moving
    sectors' pitch radius, the locking arc's radius in a dwell."""

    def __init__(self, pair: IncompletePair) -> None:
        self.pair = pair

    def r(self, phi, nu: int = 0) -> np.ndarray:
        phi = np.asarray(phi, dtype=float)
        moving = self.pair.moving(phi)
        body = self.pair.r1(phi, nu)
        lock = self.pair.lock_radius_at(phi) if nu == 0 else 0.0
        return np.where(moving, body, lock)


@dataclass(frozen=True, eq=False)
class IncompletePair:
    """An intermittent ``law`` at centre distance ``centre_distance`` (mm), ``mesh`` external or
    internal (the planet drives a ring); ``lock_radii`` (mm, one per dwell) are the driver's locking
    arcs, set by :mod:`transplanter.geometry.incomplete` when it cuts the pair (None until then)."""

    law: IntermittentLaw
    centre_distance: float
    mesh: str = "external"
    lock_radii: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        finite_positive("centre_distance", self.centre_distance)
        if self.mesh not in ("external", "internal"):
            raise SpecError.out_of_range("mesh", self.mesh, "'external' or 'internal'")
        if self.mesh == "internal":
            for m in self.law.motions:
                phi = np.linspace(math.radians(m.start), math.radians(m.end), 2001)
                top = float(m.ratio(phi).max())
                if top >= 1 - 1e-6:
                    raise GeometryError(
                        "an internal incomplete pair (a planet driving its ring) needs the ratio w2/w1 < 1: the "
                        f"motion {m.start:g}..{m.end:g} deg reaches {top:.4g}"
                    )

    @property
    def ring(self) -> str | None:
        """The ring of an internal pair is the driven gear."""
        return None if self.mesh == "external" else "driven"

    @property
    def driver(self) -> _Radius:
        return _Radius(self)

    def driven_rotation(self, phi1) -> np.ndarray:
        return self.law.psi(phi1)

    def moving(self, phi) -> np.ndarray:
        """Whether the driver angles ``phi`` (rad) are in a motion."""
        idx, _ = self.law._where(np.asarray(phi, dtype=float))
        kinds = np.array([isinstance(s, Motion) for s in self.law.segments])
        return kinds[idx]

    def r1(self, phi, nu: int = 0, motion: Motion | None = None) -> np.ndarray:
        """The driver's pitch radius (nu = 0) or its first or second derivative in φ (nu = 1, 2)
        from the law's ratio (meaningful in a motion; ``motion`` evaluates that motion's law, its
        ends included)."""
        a = self.centre_distance
        ratio = self.law.ratio if motion is None else motion.ratio
        i = ratio(phi)
        f = (lambda x: x / (1 + x), lambda x: 1 / (1 + x) ** 2, lambda x: -2 / (1 + x) ** 3)
        if self.mesh == "internal":
            f = (lambda x: x / (1 - x), lambda x: 1 / (1 - x) ** 2, lambda x: 2 / (1 - x) ** 3)
        with np.errstate(all="ignore"):
            if nu == 0:
                return a * f[0](i)
            if nu == 1:
                return a * f[1](i) * ratio(phi, 1)
            di = ratio(phi, 1)
            return a * (f[2](i) * di * di + f[1](i) * ratio(phi, 2))

    def curvature(self, phi, role: str = "driver", motion: Motion | None = None) -> np.ndarray:
        """The signed curvature (1/mm, > 0 where convex: ``PitchCurve.curvature``) of the ``role``
        gear's pitch curve (``"driver"`` or ``"driven"``) at its contact when the driver is at
        ``phi`` (rad, in a motion; ``motion`` as :meth:`r1`). The driven's curve is ``r2`` at its
        body angle ``σ ψ`` (σ = -1 external, +1 a ring), so its derivatives in its own angle are
        those in φ over ``σ ψ'``. The exact curves a cut's virtual curves sample."""
        if role not in ("driver", "driven"):
            raise SpecError.out_of_range("role", role, "'driver' or 'driven'")
        r, dr, ddr = (self.r1(phi, nu, motion) for nu in (0, 1, 2))
        if role == "driven":
            ratio = self.law.ratio if motion is None else motion.ratio
            i, di = ratio(phi), ratio(phi, 1)
            sign = -1.0 if self.mesh == "external" else 1.0  # r2 = a - r1 or a + r1, and σ
            r = self.centre_distance + sign * r
            with np.errstate(all="ignore"):
                # d/dθ2 = d/dφ / (σ i), r2_φ = σ r1': r2' = r1'/i, r2'' = σ (r1'' i - r1' i') / i³
                dr, ddr = dr / i, sign * (ddr * i - dr * di) / i**3
        with np.errstate(all="ignore"):
            return (r * r + 2 * dr * dr - r * ddr) / (r * r + dr * dr) ** 1.5

    def pressure_deviation(self, phi, motion: Motion | None = None) -> np.ndarray:
        """ν = atan(r1'/r1), rad, at driver angles ``phi`` (in a motion; ``motion`` as :meth:`r1`):
        how far both pitch curves' tangent leans from their circle's at the contact (the same angle
        on both: ``r1'/r1 = r2'/r2`` in each gear's own angle, as ``i = r1/r2``)."""
        return np.arctan2(self.r1(phi, 1, motion), self.r1(phi, motion=motion))

    def r2(self, phi, motion: Motion | None = None) -> np.ndarray:
        """The driven pitch radius at the contact when the driver is at ``phi``."""
        r1 = self.r1(phi, motion=motion)
        return self.centre_distance - r1 if self.mesh == "external" else self.centre_distance + r1

    def psi_in(self, motion: Motion, phi) -> np.ndarray:
        """ψ at driver angles ``phi`` within ``motion`` (its ends included), rad."""
        k = self.law.motions.index(motion)
        before = sum(self.law.rises[:k])
        return before + np.asarray(motion.rise(phi), dtype=float)

    def lock_radius_at(self, phi) -> np.ndarray:
        """The locking arc's radius of the dwell each driver angle is in (mm; the sector's pitch
        radius at its nearest end before the arcs are cut)."""
        phi = np.asarray(phi, dtype=float)
        idx, _ = self.law._where(phi)
        radii = []
        k = 0
        for s in self.law.segments:
            if isinstance(s, Dwell):
                if self.lock_radii is not None:
                    radii.append(self.lock_radii[k])
                else:
                    before = self.law.segments[self.law.segments.index(s) - 1]
                    radii.append(float(self.r1(np.radians([before.end]), motion=before)[0]))
                k += 1
            else:
                radii.append(math.nan)
        return np.asarray(radii)[idx]

    def scaled(self, factor: float) -> IncompletePair:
        k = finite_positive("scale factor", factor)
        radii = None if self.lock_radii is None else tuple(r * k for r in self.lock_radii)
        return IncompletePair(self.law, self.centre_distance * k, self.mesh, radii)

    def roll(self, motion: Motion, samples: int = 4001) -> tuple[np.ndarray, np.ndarray]:
        """Driver angles (rad, ``samples`` over ``motion``) and the pitch-curve length rolled from the
        motion's start to each (mm, trapezoidal in the exact speed ``hypot(r1, r1')``)."""
        phi = np.linspace(math.radians(motion.start), math.radians(motion.end), samples)
        speed = np.hypot(self.r1(phi, motion=motion), self.r1(phi, 1, motion=motion))
        return phi, np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(phi))])

    def sector_lengths(self) -> list[float]:
        """The pitch-curve length each motion rolls, mm (the same on both gears), by :meth:`roll`:
        the motion's own law up to its ends (the law's dispatch puts a boundary in the dwell)."""
        return [float(self.roll(m)[1][-1]) for m in self.law.motions]
