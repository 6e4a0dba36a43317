"""How far one moving body crosses into another over a cycle: the deepest point, bounded, not sampled.

Where :mod:`~transplanter.proof.clearance` proves two bodies apart, this measures by how much two
bodies that do meet cross — the figure a requirement that is not met states as its margin (seed
002's claw in its pot tray). The measure at one pose is the signed depth

    s = max over points p of body a of  sd(p, b)

with ``sd`` the signed distance to body ``b``: inside it the distance to its boundary, outside it
minus the distance to it. So ``s`` is how deep the deepest point of ``a`` lies inside ``b`` when
they overlap, and minus their distance when they do not. Inside ``b``, a point lies at least ``t``
deep exactly when it lies in ``b`` eroded by ``t`` (``b.buffer(-t)``): ``s`` is found by bisection
on ``t``, each step one intersection test against an erosion of ``b`` (cut on the dyadic points of
``b``'s inradius, so poses share them).

``sd`` is 1-Lipschitz in the point, and no point of ``a`` moves faster relative to ``b`` than both
speed bounds together (``Posed.speed``, mm per rad of driver), so ``s`` is Lipschitz in the driver
angle with that constant ``L``: over an interval of width ``h`` it cannot rise above ``(s0 + s1 + L
h) / 2``. :func:`deepest_crossing` measures ``s`` on the given positions and cuts every interval whose
bound reaches above the deepest found by more than ``tol`` until none does — a narrow plunge between
two positions is bracketed like any other — and returns that deepest figure, the angle where it
lies and the bound.

Examples
--------
>>> import numpy as np, shapely
>>> from transplanter.proof.clearance import Posed
>>> # a 2 mm square on a 10 mm crank dips 0.5 mm into a block at θ = 0, between samples 52° apart
>>> sq = shapely.box(-1.0, -1.0, 1.0, 1.0)
>>> a = Posed(sq, lambda t: (10 * np.cos(t), 10 * np.sin(t), np.zeros_like(t)), speed=10.0)
>>> b = Posed(shapely.box(10.5, -5.0, 20.0, 5.0), Posed.fixed, speed=0.0)
>>> found = deepest_crossing(a, b, np.linspace(0.0, 2 * np.pi, 7, endpoint=False) + 0.3)
>>> round(found.depth, 2), round(float(np.cos(found.theta)), 4), found.bound <= 0.5 + 0.01
(0.5, 1.0, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.proof.clearance import (
    CHUNK,
    CLEARANCE_REL_TOL,
    CLEARANCE_TOL_MM,
    Posed,
    cycle_samples,
    posed_sections,
    relative,
    split_intervals,
)

__all__ = ["Crossing", "deepest_crossing", "signed_depths"]

#: segments a quarter circle of an erosion's arcs is cut into. GEOS puts the chords' ends on the true
#: arc (round a reflex corner of ``b``), so the polygon it returns holds the true erosion and a sliver
#: more, whose points lie at least ``t cos(π / 512)`` deep: a hit at ``t`` proves that much
QUAD_SEGS = 128
#: what a hit on the erosion at ``t`` proves of the depth, as a fraction of ``t``
CHORD = math.cos(math.pi / (4 * QUAD_SEGS))  # half of a segment's π / 256
#: rounds at most
MAX_ROUNDS = 60


@dataclass(frozen=True)
class Crossing:
    """The deepest crossing of body ``a`` into body ``b`` over the cycle: ``depth`` (mm; negative:
    they never meet, and it is minus their least distance) at driver angle ``theta`` (rad);
    ``bound`` the deepest it can be anywhere on the cycle (within the tolerance of ``depth``);
    ``evaluations`` poses measured; ``inradius`` the deepest any point can be inside ``b`` (mm): a
    depth that reaches it has buried a point at ``b``'s deepest spot (a strip's mid-plane)."""

    depth: float
    theta: float
    bound: float
    evaluations: int
    inradius: float


class _Erosions:
    """``b`` eroded by ``t`` on the dyadic points of its inradius, each made once and prepared."""

    def __init__(self, section: shapely.Geometry) -> None:
        self.section = section
        circle = shapely.maximum_inscribed_circle(section, tolerance=1e-4)
        # the inradius found to 1e-4 mm, and a little over: nothing lies deeper inside ``b``
        self.inradius = float(shapely.length(circle))
        self.top = self.inradius + 2e-4
        self._made: dict[tuple[int, int], shapely.Geometry] = {}

    def at(self, num: int, level: int) -> shapely.Geometry:
        """The erosion at ``t = top * num / 2**level``."""
        key = (num, level)
        if key not in self._made:
            g = shapely.buffer(self.section, -self.top * num / 2**level, quad_segs=QUAD_SEGS)
            shapely.prepare(g)
            self._made[key] = g
        return self._made[key]


def signed_depths(a: Posed, b: Posed, theta, tol: float = CLEARANCE_TOL_MM, erosions=None) -> tuple:
    """``(low, high)``: the signed depth ``s`` (module docstring) of ``a`` into ``b`` at each of
    ``theta`` (rad) lies in ``[low, high]``, the two within ``tol`` mm and the erosions' chords
    (``low`` is a hit's depth times :data:`CHORD`) where they overlap, equal where they do not: minus
    the distance."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    er = erosions if erosions is not None else _Erosions(b.section)
    low = np.empty(len(theta))
    high = np.empty(len(theta))
    shapely.prepare(b.section)
    levels = max(1, math.ceil(math.log2(max(er.top / max(tol, 1e-9), 1.0))))
    for start in range(0, len(theta), CHUNK):
        t = theta[start : start + CHUNK]
        pose_a = tuple(np.broadcast_to(v, t.shape) for v in a.pose(t))
        pose_b = tuple(np.broadcast_to(v, t.shape) for v in b.pose(t))
        placed = posed_sections(a.section, *relative(pose_a, pose_b))
        d = shapely.distance(b.section, placed)
        lo, hi = -d, -d.copy()
        inside = np.flatnonzero(d <= 0.0)
        num = np.zeros(len(inside), int)  # s in [top num / 2^k, top (num + 1) / 2^k]
        for k in range(1, levels + 1):
            num *= 2
            for m in np.unique(num + 1):
                sel = num + 1 == m
                hit = shapely.intersects(er.at(int(m), k), placed[inside[sel]])
                num[np.flatnonzero(sel)[hit]] += 1
        step = er.top / 2**levels
        lo[inside] = num * step * CHORD  # a hit proves t cos(π / 512) (QUAD_SEGS); a miss, less than t
        hi[inside] = (num + 1) * step
        low[start : start + CHUNK] = lo
        high[start : start + CHUNK] = hi
    return low, high


def deepest_crossing(a: Posed, b: Posed, theta, tol: float = CLEARANCE_TOL_MM) -> Crossing:
    """The deepest signed depth of ``a`` into ``b`` over the cycle sampled by ``theta`` (rad,
    increasing, less than one turn), by branch and bound under the Lipschitz bound (module
    docstring), to within ``tol`` mm or ``CLEARANCE_REL_TOL`` of it, whichever is larger. The
    figure returned is a lower bound of the true deepest (a pose where it is reached), ``bound``
    an upper one."""
    theta = cycle_samples(theta, "deepest_crossing")
    lip = float(a.speed + b.speed)
    er = _Erosions(b.section)
    t = theta.copy()
    lo, hi = signed_depths(a, b, t, tol / 4, er)
    evaluations = len(t)
    if lip == 0.0:
        k = int(np.argmax(lo))
        return Crossing(float(lo[k]), float(np.mod(t[k], 2 * math.pi)), float(hi.max()), evaluations, er.inradius)
    for _ in range(MAX_ROUNDS):
        k = int(np.argmax(lo))
        best = float(lo[k])
        within = max(tol, CLEARANCE_REL_TOL * abs(best))
        h = np.diff(np.append(t, t[0] + 2 * math.pi))
        # no point lies deeper inside ``b`` than its inradius, whatever the speed
        up = np.minimum(0.5 * (hi + np.roll(hi, -1) + lip * h), er.top)
        open_ = np.flatnonzero(up > best + within)
        if not len(open_):
            break
        if np.min(h[open_]) < 1e-12:
            raise GeometryError(f"deepest_crossing did not settle to {tol} mm")
        # as many pieces as the ends' bounds would settle were s no higher between them
        room = 2 * (best + within) - hi[open_] - hi[(open_ + 1) % len(t)]
        cut, mid = split_intervals(t, h, open_, room, lip)
        ml, mh = signed_depths(a, b, np.mod(mid, 2 * math.pi), tol / 4, er)
        evaluations += len(mid)
        t = np.insert(t, cut + 1, mid)
        lo = np.insert(lo, cut + 1, ml)
        hi = np.insert(hi, cut + 1, mh)
    else:
        raise GeometryError(f"deepest_crossing did not settle to {tol} mm in {MAX_ROUNDS} rounds")
    # settled: the last round's deepest pose and bounds are the answer
    return Crossing(best, float(np.mod(t[k], 2 * math.pi)), max(float(up.max()), best), evaluations, er.inradius)
