"""The toothed sectors of incomplete gears: each motion's teeth, cut by the cutter's envelope.

Each motion's pitch curve is completed to a closed *virtual* curve (the true curve over the
motion, a smooth Hermite bridge over the rest, :func:`virtual_curve`) and its spaces are generated
by the same shaper or rack cutter models as full gears (``teeth.generate(spaces=...)``): only the
sector's spaces, one circular pitch apart. The teeth are phased by the path of contact
(:func:`sector_pitches`): the first pair's contact begins as the motion begins and the last
pair's ends as it ends. ``_sector`` gives one motion's sector on either gear, turned into the
body frame; ``_edge_line``, ``_between`` and ``_radial`` are the regions that bound a sector
where it meets its neighbour. :mod:`transplanter.geometry.incomplete` joins the sectors and the
locking arcs into the two gears.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.linalg import LinAlgWarning
from shapely import affinity

from transplanter.core.errors import GeometryError, TransplanterError
from transplanter.geometry.cutter import Cutter
from transplanter.geometry.pitch.curve import PitchCurve
from transplanter.geometry.pitch.intermittent import IncompletePair, Motion
from transplanter.geometry.pitch.periodic import PeriodicSpline
from transplanter.geometry.sweep import turned
from transplanter.geometry.teeth import generate

__all__ = ["CURVE_SAMPLES_PER_DEG", "SectorFitError", "sector_pitches", "virtual_curve"]

#: samples per degree of a sector's true pitch curve in its virtual closed curve
CURVE_SAMPLES_PER_DEG = 8


def virtual_curve(theta: np.ndarray, r: np.ndarray, dr: tuple[float, float], period: float) -> PitchCurve:
    """A closed pitch curve through the true radii ``r`` at body angles ``theta`` (increasing,
    spanning less than ``period``), bridged over the rest of the period by a cubic Hermite from the
    last sample to the first with the end slopes ``dr`` (dr/dθ at the first and last sample)."""
    span = period - (theta[-1] - theta[0])
    n = max(16, int(math.degrees(span) * CURVE_SAMPLES_PER_DEG))
    t = np.arange(1, n) / n
    h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    bridge = h00 * r[-1] + h10 * span * dr[1] + h01 * r[0] + h11 * span * dr[0]
    angles = np.concatenate([theta, theta[-1] + span * t])
    radii = np.concatenate([r, bridge])
    if np.any(radii <= 0):
        raise GeometryError("a sector's closing bridge passes through its axis: the sector's radius varies too much")
    return PitchCurve(PeriodicSpline(angles, radii, period=period, degree=5))


def _span(a0: float, a1: float, radius: float, tol: float = 1e-4) -> np.ndarray:
    """Points of the circle of ``radius`` from angle a0 to a1 (rad), chords within ``tol`` (mm)."""
    step = 2 * math.acos(max(-1.0, 1 - tol / radius))
    a = np.linspace(a0, a1, max(8, int(math.ceil(abs(a1 - a0) / step))) + 1)
    return np.column_stack([radius * np.cos(a), radius * np.sin(a)])


def _edge_line(point: np.ndarray, normal: np.ndarray, module: float, far: float) -> np.ndarray:
    """The cut between a sector and its neighbour through a tooth space: from the axis to below
    the space's root along its centre line, out along it past the tips, then radially to ``far``."""
    inner, outer = point - 1.5 * module * normal, point + 4.0 * module * normal
    return np.array([[0.0, 0.0], inner, outer, outer / np.linalg.norm(outer) * far])


def _between(first: np.ndarray, last: np.ndarray, far: float) -> shapely.Polygon:
    """The region from the edge line ``first`` counter-clockwise to the edge line ``last``."""
    a0 = math.atan2(first[-1, 1], first[-1, 0])
    a1 = math.atan2(last[-1, 1], last[-1, 0])
    a1 = a1 if a1 > a0 else a1 + 2 * math.pi
    ring = np.vstack([first, _span(a0, a1, far, tol=far * 1e-3), last[::-1][:-1]])
    poly = shapely.Polygon(ring)
    return poly if poly.is_valid else shapely.make_valid(poly, method="structure", keep_collapsed=False)


def _radial(a0: float, a1: float, far: float) -> shapely.Polygon:
    return shapely.Polygon(np.vstack([[0.0, 0.0], _span(a0, a1, far, tol=far * 1e-3)]))


class SectorFitError(GeometryError):
    """A motion's toothed sector does not fit the law at this size: ``motion`` (its index in the
    law's motions), the gear (``role``) and what does not fit (``reason``) — said before anything
    is cut, so the caller can name the segment and the sizes the user gave."""

    def __init__(self, motion: int, role: str, reason: str) -> None:
        self.motion, self.role, self.reason = motion, role, reason
        super().__init__(f"the motion {motion + 1}'s sector on the {role}: {reason}")


@dataclass(frozen=True)
class _Layout:
    """Where one motion's sector is cut on one gear: its virtual closed curve, the arc-length
    positions of its tooth spaces, the seam's angle, and what :func:`teeth.generate` is told."""

    curve: PitchCurve
    spaces: np.ndarray
    origin: float
    internal: bool
    teeth: int
    lobes: int


@dataclass(frozen=True)
class _Sector:
    """One motion's toothed sector as generated on one gear: the virtual gear turned into the body
    frame (polygon, tip region and what was cut), its space centres' pitch points and normals,
    and its tooth count."""

    polygon: shapely.Geometry
    tip: shapely.Geometry
    removed: shapely.Geometry
    points: np.ndarray
    normals: np.ndarray
    teeth: int


def _turn(geom, angle: float):
    return affinity.rotate(geom, angle, origin=(0.0, 0.0), use_radians=True)


def _path(pair: IncompletePair, motion: Motion, cutter: Cutter, addendum, end: bool) -> tuple[float, float]:
    """(approach, recess) of the path of contact at the motion's start or ``end``, as pitch-curve
    roll (mm): the osculating circles of the two pitch curves there, involute teeth of the
    cutter's pressure angle, the driven's tip entering and the driver's leaving."""
    at = np.radians([motion.end if end else motion.start])
    r1, r2 = float(pair.r1(at, motion=motion)[0]), float(pair.r2(at, motion=motion)[0])
    alpha, m = cutter.pressure_angle, cutter.module
    c = math.cos(alpha)
    recess = math.sqrt((r1 + addendum[0] * m) ** 2 - (r1 * c) ** 2) - r1 * math.sin(alpha)
    if pair.mesh == "external":
        approach = math.sqrt((r2 + addendum[1] * m) ** 2 - (r2 * c) ** 2) - r2 * math.sin(alpha)
    else:  # the ring's tips are inside its pitch curve
        approach = r2 * math.sin(alpha) - math.sqrt(max((r2 - addendum[1] * m) ** 2 - (r2 * c) ** 2, 0.0))
    return approach / c, recess / c


def sector_pitches(pair: IncompletePair, motion: Motion, cutter: Cutter, addendum, length: float) -> float:
    """How many pitches apart the first and the last tooth of ``motion``'s sector should be for its
    first pair's contact to begin as the motion begins and its last pair's to end as it ends: the
    first tooth's centre ``approach + p/4`` of roll ahead of the pitch point at the start (its driving
    flank a quarter pitch downstream of its centre), the last ``recess - p/4`` past it at the end;
    a whole number fits exactly."""
    pitch = math.pi * cutter.module
    approach, _ = _path(pair, motion, cutter, addendum, end=False)
    _, recess = _path(pair, motion, cutter, addendum, end=True)
    return (length - recess - approach) / pitch


def _tooth_centres(pair: IncompletePair, motion: Motion, cutter: Cutter, addendum, length: float) -> np.ndarray:
    """Roll positions (mm from the motion's start) of the driver's tooth centres: the first pair's
    contact begins as the motion begins (its driving flank at the start of the path of contact),
    the teeth a pitch apart, as many as fit best (:func:`sector_pitches`; the last pair leaves up
    to half a pitch before or after the motion's end: after, the dwell's sweep relieves it)."""
    pitch = math.pi * cutter.module
    approach, _ = _path(pair, motion, cutter, addendum, end=False)
    count = max(1, round(sector_pitches(pair, motion, cutter, addendum, length)) + 1)
    return approach + pitch / 4 + pitch * np.arange(count)


def _layout(pair: IncompletePair, cutter: Cutter, motion: Motion, role: str, addendum, zone=(0.0, 0.0)) -> _Layout:
    """Where ``motion``'s sector is cut on the ``role`` gear (:func:`_sector`), nothing cut yet:
    :class:`SectorFitError` when it does not fit — fewer than two tooth spaces, a closing bridge
    that is no pitch curve, or spaces spanning more than its virtual curve's perimeter less one
    and a half pitches (the room :func:`teeth.generate` needs to close the sector)."""
    m = cutter.module
    pitch = math.pi * m
    k_motion = pair.law.motions.index(motion)
    phi, u = pair.roll(motion, max(400, int((motion.end - motion.start) * CURVE_SAMPLES_PER_DEG)) + 1)
    r1, dr1 = pair.r1(phi, motion=motion), pair.r1(phi, 1, motion=motion)
    length = float(u[-1])
    centres = _tooth_centres(pair, motion, cutter, addendum, length)
    internal = role == "driven" and pair.mesh == "internal"
    if role == "driver":
        lobes, sigma = 1, 1.0
        theta, r, dr = phi, r1, dr1
        space_u = np.concatenate([centres - pitch / 2, [centres[-1] + pitch / 2]])
        teeth = len(centres)
        keep = np.ones(len(phi), dtype=bool)
    else:
        lobes = pair.law.turn_fraction
        sigma = -1.0 if pair.mesh == "external" else 1.0
        theta = sigma * pair.psi_in(motion, phi)
        r = pair.r2(phi, motion=motion)
        dr = (-dr1 if pair.mesh == "external" else dr1) / (sigma * motion.ratio(phi))
        space_u = centres  # a driven space where each driver tooth meets it
        teeth = max(0, len(space_u) - 1)
        # a quarter pitch at each end left to the bridge, which smooths a jump of radius between motions
        keep = (u >= zone[0]) & (u <= length - zone[1])
    if len(space_u) < 2 or keep.sum() < 4:
        raise SectorFitError(
            k_motion,
            role,
            f"the motion {motion.start:g}..{motion.end:g} deg rolls {length:.4g} mm: too short for a toothed sector "
            f"of module {m:g} on the {role} (it needs two tooth spaces, {pitch:.4g} mm apart, besides the lock zones)",
        )
    th, rr, d = theta[keep], r[keep], dr[keep]
    if sigma < 0:
        th, rr, d = th[::-1], rr[::-1], d[::-1]
    period = 2 * math.pi / lobes
    origin = float(th[0]) - (period - float(th[-1] - th[0])) / 2  # the seam mid-bridge
    # the spaces are a pitch apart along the curve: the closing bridge over the rest of the turn
    # must be long enough for 1.5 pitches beyond them (teeth.generate's room to close a sector)
    bridge = math.degrees(period - float(th[-1] - th[0]))
    need = (len(space_u) + 0.5) * pitch - float(u[keep][-1] - u[keep][0])
    radius = 0.5 * float(rr[0] + rr[-1])
    short = (
        f"the rest of the {role}'s turn beside the motion {motion.start:g}..{motion.end:g} deg ({bridge:.4g} deg) "
        f"must close a sector of {len(space_u)} tooth spaces with {need:.4g} mm of pitch curve (1.5 pitches beyond "
        f"them), about {math.degrees(max(need, 0.0) / radius):.3g} deg at its {radius:.4g} mm radius"
    )
    try:
        with warnings.catch_warnings():  # a bridge of nothing is ill-conditioned: said as too short below
            warnings.simplefilter("ignore", LinAlgWarning)
            curve = virtual_curve(th - origin, rr, (float(d[0]), float(d[-1])), period)
    except TransplanterError as exc:  # a bridge too short (or too bent) for a pitch curve
        raise SectorFitError(k_motion, role, f"{short}: {exc}") from exc
    # along the virtual curve from a kept sample, a pitch apart: beyond the motion's ends the teeth
    # run on along the bridge (the last may leave after the end; the dwell's sweep relieves it)
    k0 = int(np.flatnonzero(keep)[0])
    body0 = sigma * float(pair.psi_in(motion, phi[k0 : k0 + 1])[0]) if role == "driven" else float(phi[k0])
    s0 = float(curve.arc_length(np.array([np.mod(body0 - origin, period)]))[0])
    lobe_length = curve.perimeter / lobes
    s = np.sort(s0 + sigma * (space_u - u[k0]))  # the frame wraps: no seam to cross
    span, room = float(s[-1] - s[0]), lobe_length - 1.5 * pitch
    if span > room:
        raise SectorFitError(k_motion, role, f"{short}; it has {span - room:.3g} mm too little")
    spaces = np.concatenate([s + k * lobe_length for k in range(lobes)])
    return _Layout(curve, spaces, origin, internal, teeth * lobes, lobes)


def _sector(pair: IncompletePair, cutter: Cutter, motion: Motion, role: str, addendum, zone=(0.0, 0.0)):
    """The toothed sector of ``motion`` on the ``role`` gear: the driver's teeth phased by the
    path of contact at the motion's ends (:func:`_tooth_centres`), the driven's spaces where they
    meet them; ``zone`` (mm of roll at the motion's start and end) left to the closing bridge of
    the driven's virtual curve (:func:`_layout`: where, or why it does not fit)."""
    at = _layout(pair, cutter, motion, role, addendum, zone)
    gear = generate(
        at.curve, cutter, None, internal=at.internal, addendum=addendum[0 if role == "driver" else 1], spaces=at.spaces
    )
    points = np.array([sp.pitch_point for sp in gear.spaces])
    normals = np.array([sp.normal for sp in gear.spaces])
    tip = gear.removed[0] if at.internal else gear.blank
    return _Sector(
        _turn(gear.polygon, at.origin),
        _turn(tip, at.origin),
        _turn(gear.cut, at.origin),
        turned(points, at.origin),
        turned(normals, at.origin),
        at.teeth,
    )
