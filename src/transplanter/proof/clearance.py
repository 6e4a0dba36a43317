"""The smallest distance between two moving rigid bodies over a cycle, bounded, not sampled.

A body is a plane section (a shapely polygon in its own frame, e.g. as re-read from its DXF)
posed by ``(x, y, angle)`` of its frame in the machine frame, a function of the driver angle θ.
The distance ``d(θ)`` between two posed sections is Lipschitz: no point of a body moves faster
than ``|dc/dθ| + |dα/dθ|·R`` (``c`` its frame origin, ``α`` its angle, ``R`` its reach — the
largest distance of its section from its frame origin), so ``|d(θ) - d(θ')| <= L |θ - θ'|`` with
``L`` the sum of both bodies' speed bounds. Over an interval ``[θ0, θ1]`` of width ``h`` the
distance can therefore not fall below ``(d(θ0) + d(θ1) - L h) / 2``.

:func:`closest_approach` samples ``d`` on every few of the given positions (about
``START_POSES`` of them) and cuts every interval whose bound reaches below the smallest value
found by more than the tolerance (``tol``, or a share of the distance, or, given the clearance
``need`` the pair must keep, of its margin over it) — into as many pieces as its ends' bounds would
need were ``d`` no lower between them — until none does: the figure it returns is
within the tolerance of the true minimum over the continuous cycle (however narrow the approach — a
tip passing a tip for 0.01° is bracketed like any other), and the angle where it lies. The
bound holds if the poses between the samples move no faster than the stated speeds, which is
what the caller certifies (:mod:`transplanter.machine.bodies` derives them from the train's ratios).

Examples
--------
>>> import numpy as np, shapely
>>> square = shapely.box(-1.0, -1.0, 1.0, 1.0)
>>> # a square on a 10 mm crank (not turning) passes a fixed square 1 mm away at θ = 0, between
>>> # samples 52° apart: the bound brackets it
>>> a = Posed(square, lambda t: (10 * np.cos(t), 10 * np.sin(t), np.zeros_like(t)), speed=10.0)
>>> b = Posed(shapely.box(12.0, -1.0, 14.0, 1.0), Posed.fixed, speed=0.0)
>>> found = closest_approach(a, b, np.linspace(0.0, 2 * np.pi, 7, endpoint=False) + 0.3)
>>> round(found.distance, 2), round(float(np.cos(found.theta)), 4), found.bound >= 1.0 - CLEARANCE_TOL_MM
(1.0, 1.0, True)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.core.tolerances import WIRE_EDM_TOLERANCE

__all__ = [
    "CLEARANCE_TOL_MM",
    "Approach",
    "Posed",
    "Samples",
    "closest_approach",
    "cycle_samples",
    "least_of",
    "out_of_round",
    "overlap_areas",
    "posed_sections",
    "reach",
    "relative",
    "split_intervals",
]

#: how close to the true minimum over the cycle a stated clearance is, mm: the wire-EDM
#: tolerance the parts are cut to (a finer figure would be noise; a judge re-poses to 0.05 mm)
CLEARANCE_TOL_MM = WIRE_EDM_TOLERANCE
#: ... or this fraction of the distance, whichever is larger (a 60 mm gap is stated to 60 µm)
CLEARANCE_REL_TOL = 1e-3
#: ... or, for a pair that must keep a clearance, this fraction of its margin over it (issue 46): a
#: planet 22 mm from a screw that must keep 3 mm is found to 0.19 mm, and stated as its lower bound
MARGIN_REL = 1e-2
#: bisection rounds at most (a 0.5° grid is bisected to 3e-8 rad in 20)
MAX_ROUNDS = 40
#: the search starts from about this many of the given samples, evenly spread, and bisects from
#: there (issue 46: starting from all 360 of a machine's positions, nine in ten poses measured were
#: the grid's, most of them where the bound settles whole degrees at once)
START_POSES = 48
#: an open interval is cut into at most this many pieces a round
SPLIT_MAX = 16


def reach(section: shapely.Polygon) -> float:
    """The largest distance (mm) of ``section`` from its frame origin: a polygon's farthest
    point is a vertex."""
    xy = shapely.get_coordinates(section)
    return float(np.hypot(xy[:, 0], xy[:, 1]).max()) if len(xy) else 0.0


@dataclass(frozen=True)
class Posed:
    """A section and its pose ``pose(theta) -> (x, y, angle)`` (arrays, mm and rad), with
    ``speed`` the largest speed (mm per rad of driver) of any of its points."""

    section: shapely.Polygon
    pose: Callable
    speed: float
    #: simpler outlines, coarsest first, each ``(outline, slack)``: within ``slack`` mm of
    #: ``section`` both ways; a pose is measured on the coarsest first and on a finer one only
    #: where the coarser cannot settle it (empty: always on the section)
    levels: tuple[tuple[shapely.Polygon, float], ...] = ()
    #: (least, largest) distance of its points from the machine's origin over the cycle, for a
    #: body fixed or turning about the origin (None: it moves otherwise)
    radii: tuple[float, float] | None = None
    #: the rigid frames its frame origin is a fixed point of, ``(frame, x, y)`` (mm): two bodies
    #: whose origins share a frame are never nearer than the origins less both reaches
    origin_in: tuple[tuple[str, float, float], ...] = ()
    #: how far the body's true outline may lie from the posed one, mm: a round body posed without
    #: its own turn (its speed its origin's) is out of round by this much (:func:`out_of_round`),
    #: so every distance it is measured at is that uncertain both ways
    wobble: float = 0.0

    @staticmethod
    def fixed(theta):
        z = np.zeros_like(np.asarray(theta, dtype=float))
        return z, z, z


def out_of_round(section: shapely.Polygon) -> float:
    """How far ``section`` and any turn of it about its frame origin can lie apart, mm: each of its
    boundaries lies between the circles about the origin through its nearest and farthest point,
    and so does every turn of it, which therefore lies within that band's width of it."""
    origin = shapely.Point(0.0, 0.0)
    rings = shapely.get_rings(shapely.get_parts(section))
    return max((reach(r) - float(shapely.distance(origin, r)) for r in rings), default=0.0)


def posed_sections(section: shapely.Polygon, x, y, angle) -> np.ndarray:
    """``section`` rotated by ``angle`` and moved to ``(x, y)``, for each pose (array of polygons)."""
    x, y, angle = (np.atleast_1d(np.asarray(v, dtype=float)) for v in (x, y, angle))
    parts = [section] if isinstance(section, shapely.Polygon) else list(getattr(section, "geoms", [section]))
    out = []
    for poly in parts:
        rings = [np.asarray(poly.exterior.coords)[:-1], *(np.asarray(r.coords)[:-1] for r in poly.interiors)]
        moved = []
        for ring in rings:
            c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
            px = c * ring[None, :, 0] - s * ring[None, :, 1] + x[:, None]
            py = s * ring[None, :, 0] + c * ring[None, :, 1] + y[:, None]
            moved.append(np.stack([px, py], axis=-1))
        shells = shapely.linearrings(moved[0])
        holes = [shapely.linearrings(m) for m in moved[1:]]
        out.append(
            shapely.polygons(shells, np.stack(holes, axis=1) if holes else None) if holes else shapely.polygons(shells)
        )
    return out[0] if len(out) == 1 else np.asarray(shapely.multipolygons(np.stack(out, axis=1)))


@dataclass(frozen=True, eq=False)
class Samples:
    """A pair's distance at each of ``theta`` (rad) on its coarsest outlines, for display (the
    machine's slider), measured when asked for: ``lower`` bounds it from below at each position
    from what the search measured (its Lipschitz bound), ``known`` holds it where the search
    measured it on those outlines (nan elsewhere)."""

    a: Posed | None
    b: Posed | None
    theta: np.ndarray
    lower: np.ndarray
    known: np.ndarray

    @classmethod
    def steady(cls, theta: np.ndarray, d: float) -> Samples:
        """A distance ``d`` at every position (two bodies that keep it all round)."""
        same = np.full(len(theta), float(d))
        return cls(None, None, np.asarray(theta, dtype=float), same, same)

    def __len__(self) -> int:
        return len(self.theta)

    def __getitem__(self, key) -> Samples:
        """The samples at ``theta[key]`` (a slice or an index array)."""
        return Samples(self.a, self.b, self.theta[key], self.lower[key], self.known[key])

    def at(self, where: np.ndarray) -> np.ndarray:
        """The distance at the positions ``where`` (a boolean mask), measured where not known."""
        out = self.known[where].copy()
        todo = np.isnan(out)
        if todo.any():
            assert self.a is not None and self.b is not None  # (steady samples are all known)
            out[todo] = _distances(self.a, self.b, np.mod(self.theta[where][todo], 2 * math.pi))
        return out

    @cached_property
    def values(self) -> np.ndarray:
        """The distance at every position, mm."""
        return self.at(np.ones(len(self.theta), dtype=bool))


def least_of(samples: list[Samples]) -> tuple[np.ndarray, np.ndarray]:
    """The smallest of ``samples``' distances at each position and which of them it is (the first
    of equal ones, as ``np.argmin`` over their table): each pair measured only where its lower
    bound does not exceed the least found so far, so the result is the full table's."""
    n = len(samples[0])
    least, which = np.full(n, np.inf), np.full(n, -1)
    for k in sorted(range(len(samples)), key=lambda i: float(np.min(samples[i].lower))):
        need = samples[k].lower <= least
        if not need.any():
            continue
        v = samples[k].at(need)
        cur, who = least[need], which[need]
        better = (v < cur) | ((v == cur) & (k < who))
        cur[better], who[better] = v[better], k
        least[need], which[need] = cur, who
    return least, which


@dataclass(frozen=True)
class Approach:
    """The closest approach of two bodies over the cycle: ``distance`` (mm, 0 when they
    overlap) at driver angle ``theta`` (rad); ``bound`` the lowest the distance can be anywhere
    on the cycle (within the search's tolerance of ``distance``); ``evaluations`` poses measured."""

    distance: float
    theta: float
    bound: float
    evaluations: int
    #: the distance at each of the given samples on the coarsest outlines (display), measured when asked for
    samples: Samples
    #: whether ``distance - bound`` is within the exact tolerance (``tol`` or ``CLEARANCE_REL_TOL`` of
    #: the distance); False: the search stopped at a share of the margin over ``need``
    exact: bool = True

    @property
    def sampled(self) -> np.ndarray:
        """The distance at each of the given samples, mm (:class:`Samples`, all measured)."""
        return self.samples.values


#: poses measured at once (bounds the memory of the posed copies)
CHUNK = 256


def relative(pose_a, pose_b) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pose ``(x, y, angle)`` of a frame posed at ``pose_a`` seen from one posed at ``pose_b``
    (both in the machine frame, arrays of one shape)."""
    (xa, ya, aa), (xb, yb, ab) = pose_a, pose_b
    c, s = np.cos(ab), np.sin(ab)
    dx, dy = xa - xb, ya - yb
    return c * dx + s * dy, -s * dx + c * dy, aa - ab


def _distances(a: Posed, b: Posed, theta: np.ndarray) -> np.ndarray:
    """``d(theta)``: the body with fewer vertices posed in the other's frame (its copies are what
    is built per pose), measured against the other prepared once (GEOS's indexed distance)."""
    if shapely.get_num_coordinates(a.section) > shapely.get_num_coordinates(b.section):
        a, b = b, a
    shapely.prepare(b.section)
    out = np.empty(len(theta))
    for start in range(0, len(theta), CHUNK):
        t = theta[start : start + CHUNK]
        pose_a = tuple(np.broadcast_to(v, t.shape) for v in a.pose(t))
        pose_b = tuple(np.broadcast_to(v, t.shape) for v in b.pose(t))
        out[start : start + CHUNK] = shapely.distance(b.section, posed_sections(a.section, *relative(pose_a, pose_b)))
    return out


def overlap_areas(a: Posed, b: Posed, theta) -> np.ndarray:
    """The area (mm²) the two posed sections share in projection at each ``theta`` (rad): how
    much of their faces two bodies in touching planes would rub."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    out = np.empty(len(theta))
    for start in range(0, len(theta), CHUNK):
        t = theta[start : start + CHUNK]
        pose_a = tuple(np.broadcast_to(v, t.shape) for v in a.pose(t))
        pose_b = tuple(np.broadcast_to(v, t.shape) for v in b.pose(t))
        out[start : start + CHUNK] = shapely.area(
            shapely.intersection(b.section, posed_sections(a.section, *relative(pose_a, pose_b)))
        )
    return out


def _ladder(a: Posed, b: Posed) -> list[tuple[Posed, Posed, float]]:
    """The pair's levels, coarsest first: both bodies at their k-th outline (or finer), and the
    slack of their distance there; the last is both sections, slack 0."""
    n = max(len(a.levels), len(b.levels))
    out = []
    for k in range(n):
        la = a.levels[k] if k < len(a.levels) else (a.section, 0.0)
        lb = b.levels[k] if k < len(b.levels) else (b.section, 0.0)
        out.append((Posed(la[0], a.pose, a.speed), Posed(lb[0], b.pose, b.speed), la[1] + lb[1]))
    # (a round body posed without its turn is uncertain by its wobble on every level)
    return [(pa, pb, slack + a.wobble + b.wobble) for pa, pb, slack in [*out, (a, b, 0.0)]]


def _origin_floor(a: Posed, b: Posed) -> float:
    """A distance the two bodies never come below when their frame origins are fixed points of
    one rigid frame (``Posed.origin_in``): the origins' distance there less both reaches — two
    gears on one carrier are never nearer than their centres less their tip radii; else 0."""
    here = {frame: (x, y) for frame, x, y in b.origin_in}
    best = 0.0
    for frame, x, y in a.origin_in:
        if frame in here:
            d = math.hypot(x - here[frame][0], y - here[frame][1])
            best = max(best, d - reach(a.section) - reach(b.section))
    return best


def cycle_samples(theta, who: str) -> np.ndarray:
    """``theta`` (rad) as the samples of one cycle a branch and bound starts from: a 1-D array of at
    least two angles, increasing over less than one turn (else ``who`` says so)."""
    theta = np.asarray(theta, dtype=float)
    if theta.ndim != 1 or len(theta) < 2 or np.any(np.diff(theta) <= 0) or theta[-1] - theta[0] >= 2 * math.pi:
        raise GeometryError(f"{who}: theta must increase over less than one turn")
    return theta


def split_intervals(t: np.ndarray, h: np.ndarray, open_: np.ndarray, room: np.ndarray, lip: float):
    """``(cut, mid)``: each open interval of the cyclic samples ``t`` (widths ``h``) cut into as many
    pieces as would settle it were the function no worse between its ends — ``room`` (mm) how far
    the ends' sum is from twice the bar, ``lip`` the Lipschitz constant — 2 to ``SPLIT_MAX``; ``cut``
    the index of each new point's interval, ``mid`` the point (rad)."""
    width = np.where(room > 0, room / lip, 0.0)
    pieces = np.where(width > 0, np.ceil(h[open_] / np.maximum(width, 1e-300)), SPLIT_MAX)
    pieces = np.clip(pieces, 2, SPLIT_MAX).astype(int)
    cut = np.repeat(open_, pieces - 1)
    frac = np.concatenate([np.arange(1, n) / n for n in pieces])
    return cut, t[cut] + h[cut] * frac


def closest_approach(a: Posed, b: Posed, theta, tol: float = CLEARANCE_TOL_MM, need: float | None = None) -> Approach:
    """The smallest distance between ``a`` and ``b`` over the cycle sampled by ``theta`` (rad,
    increasing, one period of 2π, end point excluded), found by branch and bound under the
    Lipschitz bound (module docstring) to within ``tol`` mm or ``CLEARANCE_REL_TOL`` of it,
    whichever is larger — or, given the clearance ``need`` (mm) the pair must keep, to within
    ``MARGIN_REL`` of its margin over it where that is larger still: the search only has to
    show how far above ``need`` the pair stays, and ``bound`` is then the figure to state
    (``exact`` False: ``distance - bound`` is wider than the exact tolerance).

    Every pose is measured on some level of the outlines (``Posed.levels``): the truth lies
    within that level's slack of the figure, and the smallest upper bound so far is the answer's
    candidate. An interval whose lower bound reaches below it by more than the tolerance has
    its ends measured on finer outlines until twice their slack is within the tolerance,
    then is halved; the others cannot hold the minimum and are set aside. The figure returned
    is an upper bound of the true minimum, and the true minimum is within the tolerance of it.
    Overlapping bodies (a distance of 0 on the finest outlines) stop the search at once; two
    bodies of which neither moves (both speeds 0: a symmetric shaft turning in its bore, seen from
    the bore's frame) keep one distance, measured once on the sections."""
    theta = cycle_samples(theta, "closest_approach")
    lip = float(a.speed + b.speed)
    if lip == 0.0:  # neither moves (a shaft in its bore seen from their frame): one pose tells all
        d, w = float(_distances(a, b, theta[:1])[0]), a.wobble + b.wobble
        exact = w <= max(tol, CLEARANCE_REL_TOL * d)
        return Approach(d, float(np.mod(theta[0], 2 * math.pi)), max(0.0, d - w), 1, Samples.steady(theta, d), exact)
    # two bodies fixed or turning about the origin are never nearer than their radial gap
    floor = 0.0
    if a.radii is not None and b.radii is not None:
        floor = max(0.0, b.radii[0] - a.radii[1], a.radii[0] - b.radii[1])
    floor = max(floor, _origin_floor(a, b))
    ladder = _ladder(a, b)
    slack = np.array([s for _, _, s in ladder])
    last = len(ladder) - 1

    def measure(times: np.ndarray, level: int) -> np.ndarray:
        pa, pb, _ = ladder[level]
        return _distances(pa, pb, np.mod(times, 2 * math.pi))

    # each pose: the distance on its level's outlines and the level; the truth lies within
    # that level's slack of it
    stride = max(1, len(theta) // START_POSES)
    t = theta[::stride].copy()
    level = np.zeros(len(t), int)
    v = measure(t, 0)
    known = np.full(len(theta), np.nan)
    known[::stride] = v  # on the coarsest outlines, for display
    evaluations = len(t)
    for _ in range(MAX_ROUNDS * 4):
        lo = np.maximum(v - slack[level], floor)
        hi = v + slack[level]
        k = int(np.argmin(hi))
        best = float(hi[k])
        within = max(_within(best, tol, need), 2.5 * slack[last])  # (a wobble no outline settles)
        h = np.diff(np.append(t, t[0] + 2 * math.pi))
        low = np.maximum(0.5 * (lo + np.roll(lo, -1) - lip * h), floor)
        open_ = np.flatnonzero(low < best - within)
        # the best pose itself must be settled to within the tolerance (as far as the finest
        # outlines can: a round body's wobble stays)
        if 2 * slack[level[k]] > within and level[k] < last:
            open_ = np.union1d(open_, [k, (k - 1) % len(t)])
        if lo[k] <= 0.0 or not len(open_):
            break
        ends = np.unique(np.concatenate([open_, (open_ + 1) % len(t)]))
        ends = ends[(2 * slack[level[ends]] > within) & (level[ends] < last)]
        if len(ends):  # the ends of the open intervals on a finer outline first
            level[ends] += 1
            for lv in np.unique(level[ends]):
                sel = ends[level[ends] == lv]
                v[sel] = measure(t[sel], int(lv))
            evaluations += len(ends)
            continue
        if np.min(h[open_]) < 1e-12:
            raise GeometryError(f"closest_approach did not settle to {tol} mm")
        # each open interval cut into as many pieces as its ends' bounds would settle were the
        # distance no lower between them (2 to SPLIT_MAX): fewer rounds where the bound is loose
        room = lo[open_] + lo[(open_ + 1) % len(t)] - 2 * (best - within)
        cut, mid = split_intervals(t, h, open_, room, lip)
        vm = measure(mid, 0)
        evaluations += len(mid)
        t = np.insert(t, cut + 1, mid)
        v = np.insert(v, cut + 1, vm)
        level = np.insert(level, cut + 1, 0)
    else:
        raise GeometryError(f"closest_approach did not settle to {tol} mm in {MAX_ROUNDS} rounds")
    lo = np.maximum(v - slack[level], floor)
    hi = v + slack[level]
    k = int(np.argmin(hi))
    best, at = (0.0 if lo[k] <= 0.0 else float(hi[k])), float(np.mod(t[k], 2 * math.pi))
    h = np.diff(np.append(t, t[0] + 2 * math.pi))
    low = float(np.min(np.maximum(0.5 * (lo + np.roll(lo, -1) - lip * h), floor)))
    # below the coarsest outlines' distance at each given sample: the truth's bound from the nearer
    # measured pose either side, less the coarsest level's slack
    i = np.searchsorted(t, theta, side="right") - 1
    j = (i + 1) % len(t)
    after = np.where(j == 0, t[0] + 2 * math.pi, t[j])
    below = np.maximum(np.maximum(lo[i] - lip * (theta - t[i]), lo[j] - lip * (after - theta)), floor)
    samples = Samples(ladder[0][0], ladder[0][1], theta, below - slack[0], known)
    bound = max(0.0, low) if best > 0 else 0.0  # every interval's, at least best - within
    return Approach(best, at, bound, evaluations, samples, best - bound <= _within(best, tol, None))


def _within(best: float, tol: float, need: float | None) -> float:
    """How near the true minimum a search that has found ``best`` (mm) must come: ``tol``,
    ``CLEARANCE_REL_TOL`` of ``best``, or ``MARGIN_REL`` of its margin over ``need``."""
    within = max(tol, CLEARANCE_REL_TOL * best)
    return within if need is None else max(within, MARGIN_REL * (best - need))
