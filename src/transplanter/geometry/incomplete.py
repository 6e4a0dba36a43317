"""Incomplete non-circular gears: toothed sectors, locking arcs and dwell, external and internal.

From an :class:`~transplanter.geometry.pitch.intermittent.IncompletePair` (a law of dwells and motions at a
centre distance) and a cutter, :func:`cut_incomplete` makes both gears:

* **toothed sectors by the cutter's envelope** (:mod:`~transplanter.geometry.toothed_sectors`).
  Each motion's pitch curve is completed to a closed *virtual* curve (the true curve over the
  motion, a smooth Hermite bridge over the rest, ``virtual_curve``) and its spaces are generated
  by the same shaper or rack cutter models as full gears (``teeth.generate(spaces=...)``): only
  the sector's spaces, one circular pitch apart. The teeth are **phased by the path of contact**
  (``sector_pitches``): the first pair's contact begins as the motion begins (the driven's tip
  entering on the driver's flank) and the last pair's ends as it ends, so neither stands in the
  way of the driven at rest; the driver keeps its sector between the space centres outside its
  end teeth;
* **locking arcs.** Over each dwell the driver carries a convex arc about its axis reaching
  ``lock_depth`` modules (``LOCK_DEPTH``) into the driven's tips on the line of centres, and the
  driven — standing still — the concave pocket ``c`` beyond it that the arc leaves as it turns past
  (``c`` the lock's radial clearance, 0.4 of the backlash by default). Rotating the driven by ε
  closes that gap by ``a ε sin γ`` at an angle γ from the line of centres (seen from the driver's
  axis), so the pocket spanning ±β between its horns (where it meets the driven's tips) holds it
  to ``c / (a sin β)`` either way (:class:`Lock`: the nominal locking play); a shallow arc keeps
  the entry and exit teeth out of the pocket. Inside a ring the tip circles are nearly conformal
  and the planet's end teeth would sweep a long lens of the standing ring beyond the arc: there
  the arc reaches to ``INTERNAL_LOCK_SHORT_OF_TIPS`` below the planet's tips and the planet's
  end teeth (the last before each dwell, the first after it) are **shortened to the arc**, so
  the pocket stays conforming to both horns;
* **the transitions.** The driven gear is the blank with the sector spaces, minus the region the
  driver's body (grown by ``c``) sweeps through it over each dwell and ``TRANSITION_PITCHES``
  pitches of roll beyond its lock either side (:func:`transplanter.geometry.sweep.swept`): where the
  driven stands while the driver turns on, whatever of the driver still passes through driven
  material is taken from the driven — the relief of its end teeth (``relief`` states per dwell
  the area and depth taken from cutter-made teeth) and the pocket itself.

Where the first tooth meets the driven held at its dwell angle
(:func:`~transplanter.geometry.dwell_entry.entry_contacts`, on the outlines or on the sections
re-read) is what the proof reports as the entry: tip on tip within ``dwell_entry.TIP_BAND``
modules of both tips is refused.

The gears are plain data (:class:`SectorGear`: outline, blank and what is cut from it for the
3D Boolean subtraction); :mod:`transplanter.families.pairs.incomplete_pair` proves and makes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import shapely

from transplanter.core.errors import GeometryError, SpecError, check_number
from transplanter.core.forwarding import forward
from transplanter.geometry.cutter import Cutter
from transplanter.geometry.pair_gate import per_gear
from transplanter.geometry.pitch.intermittent import Dwell, IncompletePair, Motion
from transplanter.geometry.sector_outline import CORNER_RADIUS_MM, GRID_MM, SLIVER_MM  # noqa: F401 - its constants
from transplanter.geometry.sector_outline import largest as _largest
from transplanter.geometry.sector_outline import made_of as _made_of
from transplanter.geometry.sector_outline import one_piece as _one
from transplanter.geometry.sector_outline import wire_cut as _wire_cut
from transplanter.geometry.sweep import swept
from transplanter.geometry.teeth import require_cutter
from transplanter.geometry.toothed_sectors import _between, _edge_line, _layout, _radial, _sector, _turn

__all__ = [
    "SectorGear",
    "Lock",
    "IncompleteGears",
    "LockFitError",
    "check_fit",
    "cut_incomplete",
    "LOCK_DEPTH",
    "INTERNAL_LOCK_SHORT_OF_TIPS",
    "default_lock_depth",
]

#: names this module gave before issue 41 moved them to modules of their own, still found here
__getattr__ = forward(
    __name__,
    {
        "entry_contacts": "transplanter.geometry.dwell_entry",
        "TIP_BAND": "transplanter.geometry.dwell_entry",
        "sector_pitches": "transplanter.geometry.toothed_sectors",
        "virtual_curve": "transplanter.geometry.toothed_sectors",
        "CURVE_SAMPLES_PER_DEG": "transplanter.geometry.toothed_sectors",
    },
)

#: the transition window either side of a dwell, in circular pitches of roll
TRANSITION_PITCHES = 1.5
#: how far an external driver's locking arc reaches into the driven's tips on the line of centres,
#: modules: a shallow arc keeps the driven's entry and exit teeth out of the pocket it sweeps (the
#: lock's lever, the horns' half-angle, grows as its square root)
LOCK_DEPTH = 0.3
#: how far short of its own tips a planet's locking arc stops, modules (its depth into the ring's
#: tips is then the working depth less this). Inside a ring the two tip circles are nearly
#: conformal: while the ring stands, the planet's end teeth sweep the long lens between them
#: (±15-40 deg of ring), so a shallow arc leaves the ring's pocket as wide and deep as that lens
#: and the horns hold nothing (a ring of ratio 0.54, m 2, a 40 mm: free play 3.3 deg with the arc
#: 0.3 m into the ring's tips, 3.2 at 1.0 m; 1.24 at 1.3 m, 1.19 at 1.6 m; at 1.8 m, the tips' own
#: radius, the first tooth meets the ring tip on tip)
INTERNAL_LOCK_SHORT_OF_TIPS = 0.3


@dataclass(frozen=True, eq=False)
class SectorGear:
    """One incomplete gear as made: ``polygon`` = ``blank`` minus ``cut`` (body frame, mm)."""

    polygon: shapely.Polygon
    blank: shapely.Geometry = field(repr=False)
    cut: shapely.Geometry = field(repr=False)
    internal: bool
    module: float
    #: teeth on its toothed sectors
    teeth: int
    cutter: Cutter = field(repr=False)
    #: (n, 2) pitch points of the cutter-cut space centres
    space_points: np.ndarray = field(repr=False)
    #: the toothed sectors' body angles (deg), each (start, end)
    sectors_deg: tuple[tuple[float, float], ...] = ()

    @property
    def toothed_contour(self) -> np.ndarray:
        ring = self.polygon.interiors[0] if self.internal else self.polygon.exterior
        return np.asarray(ring.coords)

    def nearest_space(self, point) -> int:
        d = np.linalg.norm(self.space_points - np.asarray(point, dtype=float), axis=1)
        return int(np.argmin(d))


@dataclass(frozen=True)
class Lock:
    """The locking arcs of one dwell: driver angles (deg), the driver's convex arc radius and the
    radial clearance to the driven's concave arc (mm), the half-angle β between the horns seen
    from the driver's axis (deg), and the nominal locking play ``c / (a sin β)`` either way (deg)."""

    dwell_deg: tuple[float, float]
    radius: float
    clearance: float
    horn_deg: float
    nominal_play_deg: float


@dataclass(frozen=True, eq=False)
class IncompleteGears:
    """Both gears of an incomplete pair, its locks and the relief of each transition."""

    pair: IncompletePair
    driver: SectorGear
    driven: SectorGear
    locks: tuple[Lock, ...]
    #: per dwell: area carved in its lock zone and area (mm²) and depth (mm) of cutter-made
    #: driven teeth the sweep removed beside it
    relief: tuple[dict, ...]
    backlash: float
    #: per motion: the roll (mm) at its start and end kept clear of driven spaces for the locks
    zones: tuple[tuple[float, float], ...] = ()

    @property
    def gears(self) -> tuple[SectorGear, SectorGear]:
        return self.driver, self.driven


def _dwells(pair: IncompletePair) -> list[tuple[Dwell, int, int]]:
    """Each dwell with the index of the motion before and after it (in the law's motions)."""
    segs, motions = pair.law.segments, pair.law.motions
    out = []
    for i, s in enumerate(segs):
        if isinstance(s, Dwell):
            before = motions.index(segs[i - 1])
            after = motions.index(segs[(i + 1) % len(segs)])
            out.append((s, before, after))
    return out


def _roll_angle(pair: IncompletePair, motion: Motion, distance: float, from_end: bool) -> float:
    """The driver angle (rad) that rolls ``distance`` (mm) from the motion's start or end."""
    phi, u = pair.roll(motion)
    d = min(distance, float(u[-1]))
    at = float(np.interp(u[-1] - d if from_end else d, u, phi))
    return float(phi[-1] - at) if from_end else float(at - phi[0])


class LockFitError(GeometryError):
    """A dwell's lock does not fit the law at this size: ``dwell`` (its index in the law's dwells)
    and what does not fit (``reason``) — said before anything is cut, so the caller can name the
    segment and the sizes the user gave."""

    def __init__(self, dwell: int, reason: str) -> None:
        self.dwell, self.reason = dwell, reason
        super().__init__(f"the dwell {dwell + 1}'s lock: {reason}")


def _horns(a: float, radius: float, tip: float, dwell: int = 0) -> tuple[float, float]:
    """Where the concave arc (``radius`` about the driver's axis, ``a`` from the driven's) meets the
    driven's tip circle ``tip``: the half-angle seen from the driver's axis from the line of
    centres (rad, the lever of the lock) and seen from the driven's axis (rad); :class:`LockFitError`
    (naming ``dwell``) where they do not meet."""
    c1 = (a * a + radius * radius - tip * tip) / (2 * a * radius)
    c2 = (a * a + tip * tip - radius * radius) / (2 * a * tip)
    if not (-1 < c1 < 1 and -1 < c2 < 1):
        raise LockFitError(
            dwell,
            f"the locking arc ({radius:.4g} mm about the driver's axis) does not cross the driven's tip circle "
            f"({tip:.4g} mm, centres {a:.4g} mm apart): no concave arc can hold the driven there",
        )
    return math.acos(c1), math.acos(c2)


@dataclass(frozen=True, eq=False)
class _Plan:
    """What :func:`cut_incomplete` settles before it cuts: sizes, tool, locks, zones, arcs."""

    pair: IncompletePair
    tool: Cutter
    backlash: float
    addendum: tuple[float, float]
    clearance: float
    locks: tuple[Lock, ...]
    zones: list
    dwells: list


def _plan(pair, cutter, backlash, addendum, lock_clearance, lock_depth) -> _Plan:
    """The sizes checked and the locks placed (module docstring): :class:`LockFitError` naming the
    dwell whose locking arc has no radius or does not cross the driven's tips."""
    require_cutter(cutter)
    if not isinstance(pair, IncompletePair):
        raise SpecError(f"pair must be an IncompletePair, got {type(pair).__name__}")
    m = cutter.module
    backlash = check_number("backlash", backlash, 0.0, m, high_open=True, unit="mm")
    add1, add2 = per_gear("addendum", addendum)
    c = 0.4 * backlash if lock_clearance is None else lock_clearance
    c = check_number("lock_clearance", c, 0.0, m, low_open=True, high_open=True, unit="mm")
    depth = default_lock_depth(pair.mesh, (add1, add2)) if lock_depth is None else lock_depth
    depth = check_number("lock_depth", depth, 0.0, add1 + add2, low_open=True, high_open=True, unit="modules")
    a = pair.centre_distance
    ext = pair.mesh == "external"
    tool = replace(cutter, thickening=backlash / 4) if backlash else cutter
    motions = pair.law.motions
    dwells = _dwells(pair)
    # the locks: the driver's arc reaches ``lock_depth`` into the driven's tips on the line of
    # centres; its horns, where the concave arc meets the tips, set the lever that holds the driven
    locks, zones, radii = [], [[0.0, 0.0] for _ in motions], []
    for k, (dwell, before, after) in enumerate(dwells):
        r2b = 0.5 * float(
            pair.r2(np.radians([motions[before].end]), motion=motions[before])[0]
            + pair.r2(np.radians([motions[after].start]), motion=motions[after])[0]
        )
        tip2 = r2b + add2 * m if ext else r2b - add2 * m
        r_lock = (a - tip2 if ext else tip2 - a) + depth * m
        if not r_lock > 0:
            raise LockFitError(
                k,
                f"its locking arc, {depth:g} modules into the driven's tips (their radius {tip2:.4g} mm, centres "
                f"{a:.4g} mm apart), would have a radius of {r_lock:.4g} mm, not > 0",
            )
        beta, alpha = _horns(a, r_lock + c, tip2, k)
        lever = beta if ext else math.pi - beta
        zone = alpha * r2b  # the lock's half-width, as roll on the driven
        zones[before][1], zones[after][0] = zone, zone
        play = math.degrees(c / (a * abs(math.sin(lever))))
        locks.append(Lock((dwell.start, dwell.end), r_lock, c, math.degrees(lever), play))
        radii.append(r_lock)
    located = IncompletePair(pair.law, a, pair.mesh, tuple(radii))
    return _Plan(located, tool, backlash, (add1, add2), c, tuple(locks), zones, dwells)


def _driven_zone(module: float) -> tuple[float, float]:
    """The roll (mm) at each end of a motion the driven's spaces leave to its closing bridge."""
    return (0.25 * math.pi * module, 0.25 * math.pi * module)


def check_fit(
    pair: IncompletePair,
    cutter: Cutter,
    backlash: float,
    *,
    addendum: float | tuple[float, float] = 1.0,
    lock_clearance: float | None = None,
    lock_depth: float | None = None,
) -> None:
    """What :func:`cut_incomplete` finds before it cuts, without cutting (the same computations): the
    sizes, each dwell's lock (:class:`LockFitError`), each motion's sector on both gears
    (:class:`~transplanter.geometry.toothed_sectors.SectorFitError`: two spaces, room to close it)."""
    plan = _plan(pair, cutter, backlash, addendum, lock_clearance, lock_depth)
    for motion in plan.pair.law.motions:
        _layout(plan.pair, plan.tool, motion, "driver", plan.addendum)
        _layout(plan.pair, plan.tool, motion, "driven", plan.addendum, _driven_zone(plan.tool.module))


def cut_incomplete(
    pair: IncompletePair,
    cutter: Cutter,
    backlash: float,
    *,
    addendum: float | tuple[float, float] = 1.0,
    lock_clearance: float | None = None,
    lock_depth: float | None = None,
    corner_radius: float = CORNER_RADIUS_MM,
) -> IncompleteGears:
    """Both gears of the incomplete ``pair`` cut by ``cutter`` (module docstring).

    ``backlash`` (mm) is cut into the sector teeth as for full gears (the cutter thickened by
    half of it, ``cutter.thickening``); ``lock_clearance`` (mm, default 0.4 of the backlash: the
    sweep then stays off the flanks of teeth in mesh) is the radial clearance of the locking
    arcs and the growth of the relief sweep. The driver's locking arc's
    radius reaches ``lock_depth`` (modules) into the driven's tips on the line of centres (None:
    :func:`default_lock_depth`);
    ``corner_radius`` (mm) the wire's reach: the inside corners where a sector meets its locking
    arc, and those the sweep leaves in the driven, are given it as the wire leaves them (the
    proof then judges the gears as cut).
    """
    plan = _plan(pair, cutter, backlash, addendum, lock_clearance, lock_depth)
    pair, tool, backlash, (add1, add2), c = plan.pair, plan.tool, plan.backlash, plan.addendum, plan.clearance
    locks, zones, dwells, radii = plan.locks, plan.zones, plan.dwells, plan.pair.lock_radii
    m = cutter.module
    ext = pair.mesh == "external"
    sense = -1.0 if ext else 1.0  # the driven's body turns against ψ (external) or with it (a ring)
    motions = pair.law.motions
    # the driver: each sector between its outermost space centres, a locking sector over each dwell
    drv = [_sector(pair, tool, mo, "driver", (add1, add2)) for mo in motions]
    far = 2 * float(max(g.tip.bounds[2] for g in drv)) + 10 * m
    edges = [
        (_edge_line(s.points[0], s.normals[0], m, far), _edge_line(s.points[-1], s.normals[-1], m, far)) for s in drv
    ]
    blank, removed = [], []
    for s, (e0, e1) in zip(drv, edges, strict=True):
        w = _between(e0, e1, far)
        blank.append(shapely.intersection(s.tip, w))
        removed.append(shapely.intersection(s.removed, w))
    for (_dwell, before, after), r_lock in zip(dwells, radii, strict=True):
        disc = shapely.Point(0.0, 0.0).buffer(r_lock, quad_segs=max(64, int(math.pi * r_lock / 0.05)))
        blank.append(shapely.intersection(disc, _between(edges[before][1], edges[after][0], far)))
        if not ext:  # a planet's end teeth shortened to its locking arc (module docstring)
            for p, q in (
                (drv[before].points[-2], drv[before].points[-1]),
                (drv[after].points[0], drv[after].points[1]),
            ):
                a0, a1 = math.atan2(p[1], p[0]), math.atan2(q[1], q[0])
                removed.append(shapely.difference(_radial(a0, a1 if a1 > a0 else a1 + 2 * math.pi, far), disc))
    d_body = _wire_cut(
        _largest(shapely.difference(shapely.union_all(blank), shapely.union_all(removed)), m), corner_radius
    )
    if not isinstance(d_body, shapely.Polygon):
        raise GeometryError(f"the driver's sectors and locking arcs do not join into one part ({d_body.geom_type})")
    driver = SectorGear(
        d_body,
        *_made_of(d_body),
        False,
        m,
        sum(s.teeth for s in drv),
        tool,
        np.vstack([s.points for s in drv]),
        tuple(
            (
                round(math.degrees(math.atan2(e0[1, 1], e0[1, 0])), 6),
                round(math.degrees(math.atan2(e1[1, 1], e1[1, 0])), 6),
            )
            for e0, e1 in edges
        ),
    )
    # the driven: each motion's spaces off the lock zones, then what the driver sweeps through it
    drn = [_sector(pair, tool, mo, "driven", (add1, add2), _driven_zone(m)) for mo in motions]
    lobes = pair.law.turn_fraction
    turn = 2 * math.pi / lobes
    if len(motions) == 1:
        pieces = [(drn[0], None)]
    else:
        pieces = []
        for k, mo in enumerate(motions):
            lo = sense * float(pair.psi_in(mo, np.radians([mo.start]))[0])
            hi = sense * float(pair.psi_in(mo, np.radians([mo.end]))[0])
            lo, hi = min(lo, hi), max(lo, hi)
            wedges = [_radial(lo + i * turn, hi + i * turn, far * 4) for i in range(lobes)]
            pieces.append((drn[k], shapely.union_all(wedges)))
    r_out = max(float(np.linalg.norm(np.asarray(s.polygon.exterior.coords), axis=1).max()) for s in drn)
    if ext:
        n_blank = shapely.union_all([s.tip if w is None else shapely.intersection(s.tip, w) for s, w in pieces])
        reach_r = float(np.linalg.norm(shapely.get_coordinates(n_blank), axis=1).max()) + c + m
    else:
        n_blank = shapely.Point(0.0, 0.0).buffer(r_out, quad_segs=max(64, int(math.pi * r_out / 0.05)))
        reach_r = (
            min(float(np.linalg.norm(np.asarray(s.polygon.interiors[0].coords), axis=1).min()) for s in drn) - c - m
        )
    n_cut = [s.removed if w is None else shapely.intersection(s.removed, w) for s, w in pieces]
    pre = shapely.difference(n_blank, shapely.union_all(n_cut))

    def reacher(chi: float, half: float):
        """Driven-frame points that can meet driven material near the lock zone at ``chi``."""

        def reach(q):
            r = np.hypot(q[..., 0], q[..., 1])
            off = np.abs(np.mod(np.arctan2(q[..., 1], q[..., 0]) - chi + turn / 2, turn) - turn / 2)
            return (off <= half) & ((r <= reach_r) if ext else (r >= reach_r))

        return reach

    sweeps, relief = [], []
    for dwell, before, after in dwells:
        # the transition windows: the lock zone's roll and the teeth's reach beyond it
        w0 = _roll_angle(pair, motions[before], zones[before][1] + TRANSITION_PITCHES * math.pi * m, True)
        w1 = _roll_angle(pair, motions[after], zones[after][0] + TRANSITION_PITCHES * math.pi * m, False)
        d0, d1 = math.radians(dwell.start), math.radians(dwell.end)
        psi_b = float(pair.psi_in(motions[before], np.radians([motions[before].end]))[0])
        chi = sense * psi_b  # the line of centres in the driven's frame at the dwell
        r2b = float(pair.r2(np.radians([motions[before].end]), motion=motions[before])[0])
        half = (zones[before][1] + TRANSITION_PITCHES * math.pi * m) / r2b
        reach = reacher(chi, half)
        # the driven's lobes meet the dwell turn by turn: the same sweep, the driven turned on by a lobe
        once = swept(d_body, pair, (d0 - w0, d1 + w1), c, reach)
        sw = shapely.union_all([_turn(once, sense * k * turn) for k in range(lobes)])
        sweeps.append((sw, chi, zones[before][1] / r2b))
    sweep = shapely.union_all([sw for sw, _, _ in sweeps])
    n_body = _wire_cut(_largest(shapely.difference(pre, sweep), m), corner_radius)
    if not isinstance(n_body, shapely.Polygon) or n_body.is_empty:  # which dwell's sweep cuts it apart
        cut = [d for (d, _, _), (sw, _, _) in zip(dwells, sweeps, strict=True) if not _one(pre, sw, m)]
        at = ", ".join(f"{d.start:g}..{d.end:g}" for d in cut) or "all together"
        raise GeometryError(f"the driven gear falls apart where the driver sweeps through it at the dwells ({at} deg)")
    for (dwell, _before, _after), (sw, chi, zone_half) in zip(dwells, sweeps, strict=True):
        relief.append(_relief(shapely.intersection(pre, sw), n_body, dwell, chi, zone_half, r_out, lobes))
    driven = SectorGear(
        n_body,
        *_made_of(n_body),
        not ext,
        m,
        sum(s.teeth for s in drn),
        tool,
        np.vstack([s.points for s in drn]),
        (),
    )
    return IncompleteGears(pair, driver, driven, locks, tuple(relief), backlash, tuple(map(tuple, zones)))


def default_lock_depth(mesh: str, addendum: tuple[float, float]) -> float:
    """How deep (modules) the driver's locking arc reaches into the driven's tips unless told:
    ``LOCK_DEPTH`` for an external pair, the working depth less ``INTERNAL_LOCK_SHORT_OF_TIPS``
    for a planet in its ring."""
    return LOCK_DEPTH if mesh == "external" else addendum[0] + addendum[1] - INTERNAL_LOCK_SHORT_OF_TIPS


def _relief(relieved, body, dwell, chi, half, r_out, lobes) -> dict:
    """What the sweep of one dwell removed from the driven: in its lock zone (``half`` rad either
    side of the line of centres ``chi``: the concave arc and the spaces the driver's end teeth
    need), and from the cutter-made teeth beside it (the relief)."""
    turn = 2 * math.pi / lobes
    zone_wedges = shapely.union_all(
        [_radial(chi + i * turn - half, chi + i * turn + half, 4 * r_out) for i in range(lobes)]
    )
    in_zone = shapely.intersection(relieved, zone_wedges)
    teeth = shapely.difference(relieved, zone_wedges)
    pts = shapely.points(shapely.get_coordinates(teeth)) if not teeth.is_empty else []
    depth = float(shapely.distance(body, pts).max()) if len(pts) else 0.0
    return {
        "dwell_deg": [dwell.start, dwell.end],
        "lock_zone_carved_mm2": round(float(in_zone.area), 6),
        "teeth_relieved_mm2": round(float(teeth.area), 6),
        "teeth_relief_depth_mm": round(depth, 6),
    }
