"""Where two outlines turned against each other about a centre first touch — in closed form.

The geometry under :func:`transplanter.proof.validate.mesh_check`, vectorised over the vertices and
over the meshing steps at once (every array carries the step it belongs to).

Turning a polygon about a centre moves each of its vertices on a circle about that centre;
turning it against a fixed polygon, the two first touch where a vertex of one meets an edge of
the other. So for every vertex–edge pair whose radii (about the centre) overlap, the
circle–segment crossing gives the turn at which they meet (:func:`crossings`); the nearest
turn either way is the first contact, exact for the polygons. Pairs are found by sorting the
vertices by radius and taking, for each edge, those within the radii it spans
(:func:`pairs`), per step by offsetting each step's radii by a key.

:class:`Outline` holds one polygon prepared for this: its vertices and edges, its polar
angles in sorted order (a sector of it is an index range, :meth:`Outline.gather`), and radius
bounds per angular bin that settle most point-in-polygon questions without GEOS
(:meth:`Outline.inside`).

All lengths mm, angles rad; a "turn" is counter-clockwise.

Examples
--------
A vertex at radius 1 on the x axis, turned about the origin, meets the edge y = 0.5 (x from 0
to 2) after 30 degrees:

>>> import numpy as np
>>> v = np.array([[1.0, 0.0]])
>>> x, ok = crossings(v, np.array([[0.0, 0.5]]), np.array([[2.0, 0.5]]))
>>> ok[:, 0].tolist()  # the circle's other crossing is off the segment
[False, True]
>>> round(float(np.degrees(angle_between(v, x[1]))[0]), 9)
30.0
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

__all__ = [
    "Outline",
    "EdgeIndex",
    "reach_sector",
    "pairs",
    "within",
    "crossings",
    "angle_between",
    "segment_distance",
    "distance_to_ring",
    "rotate",
    "wrap",
]


def wrap(a):
    """Angles wrapped to [-π, π)."""
    return (np.asarray(a) + math.pi) % (2 * math.pi) - math.pi


def rotate(p: np.ndarray, angle, at: np.ndarray | None = None) -> np.ndarray:
    """(n, 2) points turned about the origin by ``angle``: a scalar, one angle per point, or with
    ``at`` one angle per step and ``at`` the step of each point."""
    c, s = np.cos(angle), np.sin(angle)
    if at is not None:
        c, s = c[at], s[at]
    x, y = p[:, 0], p[:, 1]
    out = np.empty((len(p), 2))
    a, b = out[:, 0], out[:, 1]  # c x - s y and s x + c y, written in place (the same bits)
    np.multiply(c, x, out=a)
    a -= s * y
    np.multiply(s, x, out=b)
    b += c * y
    return out


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]


class Outline:
    """A polygon's boundary prepared for turning it about its body origin.

    Attributes
    ----------
    xy : (n, 2) float
        Boundary vertices of every ring (exterior and holes), without the closing repeat, mm.
    next, prev : (n,) int
        Each vertex's successor and predecessor along its ring; edge ``i`` runs from vertex
        ``i`` to ``next[i]``.
    longest : float
        The longest edge, mm.
    r_min, r_max : float
        The vertices' radius range, mm.
    polygon : shapely.Polygon or MultiPolygon
        The polygon, prepared.
    """

    #: angular bins of the radius bounds
    BINS = 2048

    def __init__(self, polygon):
        rings = [r for g in getattr(polygon, "geoms", [polygon]) for r in (g.exterior, *g.interiors)]
        xy, nxt, prv, n0 = [], [], [], 0
        for ring in rings:
            pts = shapely.get_coordinates(ring)[:-1]
            idx = np.arange(n0, n0 + len(pts))
            xy.append(pts)
            nxt.append(np.roll(idx, -1))
            prv.append(np.roll(idx, 1))
            n0 += len(pts)
        self.xy = np.concatenate(xy)
        self.next = np.concatenate(nxt)
        self.prev = np.concatenate(prv)
        r = np.hypot(self.xy[:, 0], self.xy[:, 1])
        self.r_min, self.r_max = float(r.min()), float(r.max())
        theta = np.arctan2(self.xy[:, 1], self.xy[:, 0])
        self._order = np.argsort(theta, kind="stable")
        self._theta = theta[self._order]
        d = self.xy[self.next] - self.xy
        self.longest = float(np.max(np.hypot(d[:, 0], d[:, 1])))
        self.polygon = shapely.Polygon(polygon) if isinstance(polygon, shapely.Polygon) else polygon
        shapely.prepare(self.polygon)
        # radius bounds per angular bin, over the edges crossing the bin: along any ray the body
        # ends before r_out (a body around its origin) and starts after r_in (a ring, whose
        # origin is in its hole) — points beyond are outside without a point-in-polygon test
        w = 2 * math.pi / self.BINS
        dt = wrap(theta[self.next] - theta)
        low = np.where(dt >= 0, theta, theta + dt) + math.pi
        start = np.floor(low / w).astype(int)
        count = np.floor((low + np.abs(dt)) / w).astype(int) - start + 1
        e = np.repeat(np.arange(len(r)), count)
        bins = (start[e] + np.arange(len(e)) - (np.cumsum(count) - count)[e]) % self.BINS
        dd = _dot(d, d)
        t = np.clip(-_dot(self.xy, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
        foot = np.hypot(*(self.xy + t[:, None] * d).T)
        self._r_out = np.full(self.BINS, -np.inf)
        np.maximum.at(self._r_out, bins, np.maximum(r, r[self.next])[e])
        self._r_in = np.full(self.BINS, np.inf)
        np.minimum.at(self._r_in, bins, foot[e])
        self._near: dict = {}

    def gather(self, intervals, turn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The vertices whose polar angle, once the outline is turned by ``turn[k]``, lies in an
        interval, for every step k.

        ``intervals`` is a list of (lo, hi) pairs, each a scalar or one value per step (rad,
        fixed frame; ``hi - lo >= 2π`` or None: every vertex). Returns (step, vertex index)
        arrays, grouped by interval.
        """
        turn = np.asarray(turn, dtype=float)
        n, size = len(turn), len(self.xy)
        if intervals is None:
            intervals = [(-math.pi, math.pi)]
        starts, ends, owners = [], [], []
        for lo, hi in intervals:
            lo = np.broadcast_to(np.asarray(lo, dtype=float), turn.shape)
            hi = np.broadcast_to(np.asarray(hi, dtype=float), turn.shape)
            full = hi - lo >= 2 * math.pi
            a = wrap(lo - turn)
            b = a + (hi - lo)
            i0 = np.where(full, 0, np.searchsorted(self._theta, a))
            i1 = np.where(full, size, np.searchsorted(self._theta, np.minimum(b, math.pi), "right"))
            j1 = np.where(~full & (b > math.pi), np.searchsorted(self._theta, b - 2 * math.pi, "right"), 0)
            starts += [i0, np.zeros(n, dtype=int)]
            ends += [i1, j1]
            owners += [np.arange(n), np.arange(n)]
        first, last, owner = np.concatenate(starts), np.concatenate(ends), np.concatenate(owners)
        count = np.maximum(last - first, 0)
        step = np.repeat(owner, count)
        pos = np.repeat(first - (np.cumsum(count) - count), count) + np.arange(len(step))
        return step, self._order[pos]

    def placed(self, idx: np.ndarray, turn, x=0.0, at: np.ndarray | None = None) -> np.ndarray:
        """Vertices ``idx`` turned by ``turn`` about the body origin, which is then put at (x, 0)
        (``turn`` and ``at`` as for :func:`rotate`)."""
        p = rotate(self.xy[idx], turn, at)
        p[:, 0] += x
        return p

    def whole(self, turn: float, x: float = 0.0):
        """The polygon turned by ``turn`` and put at (x, 0)."""
        c, s = math.cos(turn), math.sin(turn)
        return shapely.affinity.affine_transform(self.polygon, (c, -s, s, c, x, 0.0))

    def inside(self, p: np.ndarray, ring: bool) -> np.ndarray:
        """Mask of body-frame points ``p`` (n, 2) strictly inside the body; ``ring``: the body
        lies around its origin's hole (a ring gear)."""
        b = ((np.arctan2(p[:, 1], p[:, 0]) + math.pi) * (self.BINS / (2 * math.pi))).astype(int) % self.BINS
        rr = np.hypot(p[:, 0], p[:, 1])
        out = rr >= self._r_in[b] if ring else rr <= self._r_out[b]
        if out.any():
            out[out] = shapely.contains_xy(self.polygon, p[out, 0], p[out, 1])
        return out

    def near(self, p: np.ndarray, ring: bool, cap: float) -> np.ndarray:
        """Mask of body-frame points ``p`` (n, 2) that may lie within ``cap`` of the body (or in
        it); the others are farther, by the radius bounds of every bin that a point within
        ``cap`` of them can lie in (``ring``: the body lies around its origin's hole)."""
        key = (ring, cap)
        if key not in self._near:
            rho = max(0.5 * self.r_min, cap)
            k = int(math.ceil(math.asin(min(1.0, cap / rho)) * self.BINS / (2 * math.pi))) + 1
            bound = self._r_in if ring else self._r_out
            spread = np.stack([np.roll(bound, j) for j in range(-k, k + 1)])
            self._near[key] = spread.min(axis=0) - cap if ring else spread.max(axis=0) + cap
        b = ((np.arctan2(p[:, 1], p[:, 0]) + math.pi) * (self.BINS / (2 * math.pi))).astype(int) % self.BINS
        rr = np.hypot(p[:, 0], p[:, 1])
        return rr >= self._near[key][b] if ring else rr <= self._near[key][b]


class EdgeIndex:
    """An outline's boundary prepared for distances: samples along every edge at most
    ``SPACING`` apart in a k-d tree (scipy), the exact segment distance taken only for the points
    that the samples cannot settle."""

    #: boundary samples at most this far apart along every edge, mm
    SPACING = 0.02
    #: nearest samples looked at per point before a ball query is needed
    NEAREST = 8

    def __init__(self, outline: Outline):
        self.start = outline.xy
        self.end = outline.xy[outline.next]
        d = self.end - self.start
        length = np.hypot(d[:, 0], d[:, 1])
        pieces = np.maximum(1, np.ceil(length / self.SPACING)).astype(int)
        edge = np.repeat(np.arange(len(length)), pieces)
        t = (np.arange(len(edge)) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / pieces[edge]
        self._edge = edge
        self._tree = cKDTree(self.start[edge] + t[:, None] * d[edge])
        #: every boundary point lies within this of a sample
        self._half = 0.5 * float(np.max(length / pieces))

    def nearest(self, p: np.ndarray, group: np.ndarray, groups: int) -> tuple[np.ndarray, np.ndarray]:
        """For each group (a meshing step) of points ``p`` (n, 2; ``group`` (n,) int < ``groups``):
        the smallest distance (groups,) from the boundary, inf for an empty group, and the point
        with its nearest boundary point (groups, 2, 2), NaN for an empty group.

        The nearest sample bounds each point's distance d within [d_s - half, d_s]; only points
        whose lower bound reaches their group's smallest d_s are measured exactly, against every
        edge with a sample within d_s + half (the edge holding the nearest boundary point has one).
        """
        best = np.full(groups, np.inf)
        pts = np.full((groups, 2, 2), np.nan)
        if not len(p):
            return best, pts
        d_s = self._nearest_samples(p, group, groups)
        upper = np.full(groups, np.inf)
        np.minimum.at(upper, group, d_s)
        keep = np.flatnonzero(d_s - self._half <= upper[group])
        # the edge holding a point's nearest boundary point has a sample within d_s + half of it: the
        # K nearest samples hold it where the K-th is farther than that; the ball query settles the rest
        k = min(self.NEAREST, len(self._edge))
        d_k, i_k = self._tree.query(p[keep], k=k)
        d_k, i_k = d_k.reshape(len(keep), k), i_k.reshape(len(keep), k)
        sure = d_k[:, -1] >= d_k[:, 0] + self._half
        owner = [np.repeat(keep[sure], k)]
        edges = [self._edge[i_k[sure]].ravel()]
        rest = keep[~sure]
        if len(rest):
            found = self._tree.query_ball_point(p[rest], d_s[rest] + self._half)
            counts = np.fromiter((len(f) for f in found), dtype=int, count=len(found))
            owner.append(np.repeat(rest, counts))
            edges.append(self._edge[np.concatenate(found).astype(int)] if counts.sum() else np.zeros(0, dtype=int))
        key = np.unique(np.concatenate(owner) * len(self.start) + np.concatenate(edges))
        o, e = key // len(self.start), key % len(self.start)
        foot = _foot(p[o], self.start[e], self.end[e])
        dist = np.hypot(*(foot - p[o]).T)
        np.minimum.at(best, group[o], dist)
        hit = np.flatnonzero(dist == best[group[o]])
        pts[group[o[hit]], 0] = p[o[hit]]
        pts[group[o[hit]], 1] = foot[hit]
        return best, pts

    #: a group's bound on its smallest sample distance is taken from every STRIDE-th point
    STRIDE = 16
    #: the other points are asked with a distance bound, in this many batches of like bounds
    BATCHES = 32

    def _nearest_samples(self, p: np.ndarray, group: np.ndarray, groups: int) -> np.ndarray:
        """Each point's distance to its nearest sample — exactly the tree's, for every point that
        :meth:`nearest` can keep — and inf for points that cannot be kept (issue 46: most points of
        a step lie far beyond its nearest approach, and a bounded query passes them quickly).

        A group's smallest sample distance is at most ``bound``, the smallest over every
        ``STRIDE``-th point of it; a point is kept only within ``half`` of the group's smallest, so a
        point whose nearest sample lies beyond ``bound + half`` is never kept, and only that is what
        the tree's ``distance_upper_bound`` leaves inf (the bound is raised by a relative 1e-9 so no
        point on it is lost to round-off)."""
        d_s = np.full(len(p), np.inf)
        some = np.arange(0, len(p), self.STRIDE)
        d_some, _ = self._tree.query(p[some])
        bound = np.full(groups, np.inf)
        np.minimum.at(bound, group[some], d_some)
        reach = (bound[group] + self._half) * (1 + 1e-9) + 1e-12
        unbounded = np.flatnonzero(~np.isfinite(reach))
        if len(unbounded):
            d_s[unbounded] = self._tree.query(p[unbounded])[0]
        bounded = np.flatnonzero(np.isfinite(reach))
        order = bounded[np.argsort(reach[bounded], kind="stable")]
        for batch in np.array_split(order, min(self.BATCHES, len(order))) if len(order) else ():
            if len(batch):
                d_s[batch] = self._tree.query(p[batch], distance_upper_bound=float(reach[batch].max()))[0]
        return d_s


def _foot(p: np.ndarray, ps: np.ndarray, pe: np.ndarray) -> np.ndarray:
    d = pe - ps
    dd = _dot(d, d)
    t = np.clip(_dot(p - ps, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    return ps + t[:, None] * d


def reach_sector(own: Outline, own_x: float, other: Outline, other_x: float, other_ring: bool, pad: float = 0.0):
    """Polar angles (fixed frame, about ``own``'s origin put at (own_x, 0)) where a vertex of
    ``own`` can lie inside ``other`` (origin at (other_x, 0)), or within ``pad`` of it: within its
    largest radius, or beyond its smallest for a ring. A list of (lo, hi) intervals, or None:
    everywhere."""
    pad = pad + (own.r_max - own.r_min) / 64 + own.longest + other.longest
    r = np.linspace(own.r_min, own.r_max, 65)[:, None]
    th = np.linspace(-math.pi, math.pi, 1441)
    d = np.hypot(own_x + r * np.cos(th) - other_x, r * np.sin(th))
    ok = ((d >= other.r_min - pad) if other_ring else (d <= other.r_max + pad)).any(axis=0)[:-1]
    if ok.all():
        return None
    step = th[1] - th[0]
    k = int(np.argmin(ok))  # start the scan at a refused angle, so no run wraps
    runs, start = [], None
    for j in range(k, k + len(ok) + 1):
        if ok[j % len(ok)] and start is None:
            start = j
        elif not ok[j % len(ok)] and start is not None:
            runs.append((th[0] + (start - 1) * step, th[0] + j * step))  # a grid step of margin
            start = None
    return runs


def _radius_keys(v, v_key, ps, pe, e_key, tol: float):
    """Each vertex's radius, each edge's least and largest radius a vertex may have to touch it
    under a turn about the origin, and the span that keeps the steps' keys apart (``key = step ·
    span + radius``)."""
    d = pe - ps
    dd = _dot(d, d)
    t = np.clip(-_dot(ps, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    foot = ps + t[:, None] * d
    r_s, r_e = _dot(ps, ps), _dot(pe, pe)
    lo = np.sqrt(np.minimum(_dot(foot, foot), np.minimum(r_s, r_e))) - tol
    hi = np.sqrt(np.maximum(r_s, r_e)) + tol
    rho = np.hypot(v[:, 0], v[:, 1])
    span = 2.0 * (max(float(hi.max(initial=0.0)), float(rho.max(initial=0.0))) + 1.0)  # keys apart by more
    return rho, lo, hi, span


def pairs(v: np.ndarray, v_key: np.ndarray, ps: np.ndarray, pe: np.ndarray, e_key: np.ndarray, tol: float):
    """Vertex/edge pairs that can touch under a turn about the origin: same key (step), and the
    vertex's radius within ``tol`` of the radii the edge ``ps``–``pe`` spans.

    Keys are small non-negative integers. Returns (vertex index, edge index) arrays.
    """
    rho, lo, hi, span = _radius_keys(v, v_key, ps, pe, e_key, tol)
    vk = v_key * span + rho
    order = np.argsort(vk)
    sk = vk[order]
    i0 = np.searchsorted(sk, e_key * span + lo, "left")
    count = np.searchsorted(sk, e_key * span + hi, "right") - i0
    e = np.repeat(np.arange(len(ps)), count)
    return order[np.repeat(i0 - (np.cumsum(count) - count), count) + np.arange(len(e))], e


def pairs_within(v, v_key, ps, pe, e_key, tol: float, turn: np.ndarray, extra: float):
    """The pairs ``within(v, *pairs(v, v_key, ps, pe, e_key, tol), ps, turn[e_key[e]], extra)``
    keeps — the same set, in another order — without listing every pair of a radius band first
    (issue 46: on seed 004's ring and planet 97 % of those lay around the gear from their edge
    and were dropped; 0.61 → 0.38 s of the 1.85 s of its 180-step meshing proof).

    Each edge asks only for the vertices of its radius band within its angle of reach: a vertex
    at most ``R = turn·ρ + extra`` from the edge's start ``p`` lies within ``asin(R/|p|)`` of
    ``p``'s direction (anywhere, for ``R >= |p|``). The vertices are sorted by step, radius bin and
    angle, each edge's bins are searched between two angles with a slack far above round-off, and
    the exact tests of :func:`pairs` and :func:`within`, on the same values, keep the same pairs.
    ``turn`` (per step, i.e. per key) and ``extra`` are at least 0. The radius bins are at least
    1/64 of the widest band and 1/n of the largest radius wide: an edge asks at most 65 bins, and
    there are at most n + 2 per step, whatever the outlines."""
    rho, lo, hi, span = _radius_keys(v, v_key, ps, pe, e_key, tol)
    vk, lo_key, hi_key = v_key * span + rho, e_key * span + lo, e_key * span + hi
    slack = 1e-9 * span + 1e-12
    band = hi - lo
    width = max(
        8.0 * float(np.median(band)) if len(band) else 1.0,
        float(band.max(initial=0.0)) / 64.0,
        float(rho.max(initial=0.0)) / max(len(rho), 1),
        1e-6,
    )
    rbin = np.floor(rho / width).astype(np.int64)
    nbins = int(rbin.max(initial=0)) + 2
    key = (v_key.astype(np.int64) * nbins + rbin) * 8.0 + (np.arctan2(v[:, 1], v[:, 0]) + math.pi)
    by_angle = np.argsort(key, kind="stable")
    sorted_key = key[by_angle]
    # each edge's bins and window of angles (0 .. 2π, split where it wraps)
    b0 = np.floor(np.maximum(lo - slack, 0.0) / width).astype(np.int64)
    b1 = np.minimum(np.floor((hi + slack) / width).astype(np.int64), nbins - 1)
    nb = np.maximum(b1 - b0 + 1, 0)
    r_p = np.hypot(ps[:, 0], ps[:, 1])
    reach = (turn[e_key] * (hi + slack) + extra) * (1 + 1e-9) + 1e-12
    half = np.where(reach < r_p, np.arcsin(np.minimum(reach / np.where(r_p > 0, r_p, 1.0), 1.0)) + 1e-7, math.pi)
    mid = np.arctan2(ps[:, 1], ps[:, 0]) + math.pi
    a, b = mid - half, mid + half
    whole = half >= math.pi
    a, b = np.where(whole, 0.0, a), np.where(whole, 2 * math.pi, b)
    windows = [
        (np.maximum(a, 0.0), np.minimum(b, 2 * math.pi), np.ones(len(a), bool)),
        (a + 2 * math.pi, np.full(len(a), 2 * math.pi), a < 0.0),
        (np.zeros(len(a)), b - 2 * math.pi, b > 2 * math.pi),
    ]
    edges, lows, highs = [], [], []
    for w0, w1, use in windows:
        e = np.repeat(np.flatnonzero(use), nb[use])
        first = np.repeat(b0[use] - (np.cumsum(nb[use]) - nb[use]), nb[use]) + np.arange(len(e))
        base = (e_key[e].astype(np.int64) * nbins + first) * 8.0
        edges.append(e)
        lows.append(base + w0[e])
        highs.append(base + w1[e])
    # asked in ascending order: numpy's search starts each from the last one's place
    low = np.concatenate(lows)
    o = np.argsort(low)
    e, low, high = np.concatenate(edges)[o], low[o], np.concatenate(highs)[o]
    i0 = np.searchsorted(sorted_key, low, "left")
    count = np.maximum(np.searchsorted(sorted_key, high, "right") - i0, 0)
    ei = np.repeat(e, count)
    vi = by_angle[np.repeat(i0 - (np.cumsum(count) - count), count) + np.arange(len(ei))]
    # pairs()' own test of the radius band, then within()'s, on the same values: the same pairs
    keep = (vk[vi] >= lo_key[ei]) & (vk[vi] <= hi_key[ei])
    return within(v, vi[keep], ps, ei[keep], turn[e_key[ei[keep]]], extra)


def within(v: np.ndarray, vi: np.ndarray, p: np.ndarray, ei: np.ndarray, turn, extra: float):
    """The pairs (``vi``, ``ei``) whose vertex ``v[vi]``, turned about the origin by at most
    ``turn`` (per pair), can come within ``extra`` of the point ``p[ei]``."""
    # |v - p|² <= (turn ρ + extra)², each vertex's radius ρ once, in place: the same bits
    d = v[vi]
    d -= p[ei]
    d *= d
    reach = np.hypot(v[:, 0], v[:, 1])[vi]
    reach *= turn
    reach += extra
    reach *= reach
    keep = d[:, 0] + d[:, 1] <= reach
    return vi[keep], ei[keep]


def angle_between(u: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Counter-clockwise angle from each ``u[k]`` (n, 2) to ``x[..., k, :]`` ((m, n, 2) or (n, 2)), in (-π, π]."""
    return np.arctan2(u[:, 0] * x[..., 1] - u[:, 1] * x[..., 0], u[:, 0] * x[..., 0] + u[:, 1] * x[..., 1])


def crossings(v: np.ndarray, ps: np.ndarray, pe: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the circle about the origin through each vertex ``v[k]`` meets the segment
    ``ps[k]``–``pe[k]``: both roots as (2, n, 2) points and a (2, n) mask of the real ones."""
    d = pe - ps
    a = _dot(d, d)
    b = _dot(ps, d)
    c = _dot(ps, ps) - _dot(v, v)
    disc = b * b - a * c
    ok = (disc >= 0) & (a > 0)
    sq = np.sqrt(np.where(ok, disc, 0.0))
    a = np.where(a > 0, a, 1.0)
    t = np.stack(((-b - sq) / a, (-b + sq) / a))
    ok = ok & (t >= 0.0) & (t <= 1.0)
    return ps + t[..., None] * d, ok


def segment_distance(p: np.ndarray, ps: np.ndarray, pe: np.ndarray) -> np.ndarray:
    """Distance of each point ``p[k]`` from the segment ``ps[k]``–``pe[k]``."""
    q = _foot(p, ps, pe) - p
    return np.hypot(q[:, 0], q[:, 1])


def distance_to_ring(ring: np.ndarray):
    """A function giving the distance (n,) of points (n, 2) from the closed polyline ``ring``
    ((m, 2), the closing repeat optional): an STRtree of its segments, built once and queried
    as often as needed (GEOS measures a point against a whole ring with no index)."""
    ring = np.asarray(ring, dtype=float)
    if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    tree = shapely.STRtree(shapely.linestrings(np.stack((ring, np.roll(ring, -1, axis=0)), axis=1)))

    def distance(points: np.ndarray) -> np.ndarray:
        (which, _), near = tree.query_nearest(shapely.points(points), return_distance=True, all_matches=False)
        out = np.empty(len(points))
        out[which] = near
        return out

    return distance
