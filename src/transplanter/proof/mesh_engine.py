"""The meshing sweep: the arrays of one :func:`meshing.mesh_check` and the stages that fill them,
a chunk of driver angles at a time (contacts both ways, overlaps, contacts closed up, mid-play
clearance). :mod:`transplanter.proof.mesh_refine` samples it again where the extremes lie.

The conventions are the meshing module's (driver clockwise about the origin, the driven centre at
(a, 0), (-a, 0) for a driven ring); the vertex–edge contact search is :mod:`transplanter.geometry.contact`.
"""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

import numpy as np
import shapely

from transplanter.geometry import contact
from transplanter.geometry.pitch import driven_axis, driven_turn

__all__ = ["CHUNK_VERTICES", "CLEARANCE_CAP_MM", "FOULING_PITCHES", "MESH_CHUNK", "MeshSweep", "MeshingPair"]


class _Radius(Protocol):
    def r(self, phi, nu: int = 0) -> np.ndarray: ...


@runtime_checkable
class MeshingPair(Protocol):
    """What the meshing proof needs of a pair of pitch curves (``pitch.GearPair`` is one): where
    the driven gear's axis is, which gear (if any) is a ring, the driver's polar radius, and the
    design motion."""

    @property
    def centre_distance(self) -> float: ...

    @property
    def ring(self) -> str | None: ...

    @property
    def driver(self) -> _Radius: ...

    def driven_rotation(self, phi1) -> np.ndarray:
        """The driven gear's rotation (rad, its own sense) at driver rotations ``phi1`` (rad)."""
        ...


#: overlap further than this many circular pitches from the pitch point is fouling: the path
#: of contact of involute teeth ends about one pitch (contact ratio ~1.5-2) from it
FOULING_PITCHES = 1.5

#: clearances beyond this (mm) are not measured: they are reported as this value
CLEARANCE_CAP_MM = 0.5


def _in_band(p: np.ndarray, other: contact.Outline, ring: bool, pad) -> np.ndarray:
    """Points ``p`` (n, 2, about ``other``'s origin) within ``pad`` of ``other``'s radius range
    (a body reaches to r_max; a ring's teeth reach in to r_min)."""
    r = np.hypot(p[:, 0], p[:, 1])
    return r >= other.r_min - pad if ring else r <= other.r_max + pad


#: meshing steps computed together (their vertex/edge pairs held at once), for a pair of up to
#: :data:`CHUNK_VERTICES` outline vertices in all; a larger pair takes proportionally fewer steps at
#: once, down to 8 (:meth:`MeshSweep.chunk`): seed 004's 560-tooth ring with its planet (86 473
#: vertices) held ~560 MB of candidate pairs at 64 steps a chunk, ~150 MB at 8, and ran faster
MESH_CHUNK = 64
#: see :data:`MESH_CHUNK`
CHUNK_VERTICES = 12_000


class MeshSweep:
    """The arrays of one :func:`mesh_check` and the stages that fill them, a chunk of steps at a time."""

    def __init__(self, pair: MeshingPair, drv, drn, module, phi1, half, tol, sectors=None):
        self.pair, self.drv, self.drn, self.module, self.half, self.tol = pair, drv, drn, module, half, tol
        self.external = pair.ring is None
        self.centre = driven_axis(pair)
        self.turn = 1.0 if self.external else -1.0  # the driven gear's sense for a positive δ
        self.phi1 = np.asarray(phi1, dtype=float)
        steps = len(self.phi1)
        self.r1 = pair.driver.r(self.phi1)
        self.r2 = np.abs(self.r1 - self.centre)
        self.psi1 = -self.phi1
        self.psi2 = driven_turn(pair, self.phi1)
        self.span = 2 * module / np.maximum(self.r2, module)  # about a tooth of free play
        self.sectors = sectors or (
            contact.reach_sector(drv, 0.0, drn, self.centre, pair.ring == "driven"),
            contact.reach_sector(drn, self.centre, drv, 0.0, pair.ring == "driver"),
        )
        # a vertex of one gear can meet the other only within the other's radius band (a pad of
        # an edge of each, and the contact gap)
        self.pad = tol + drv.longest + drn.longest
        self.whole = half >= drv.r_max + drn.r_max + abs(self.centre)
        self._reach = None  # with ``whole``: where the contact search gathers each gear's vertices
        self.pen, self.foul, self.dist, self.te, self.bl, self.nc = (np.zeros(steps) for _ in range(6))
        self.clear = np.zeros(steps)
        self.clear_points = np.full((steps, 2, 2), np.nan)
        self._index = None  # edge indexes and reach sectors of the clearance, made on first use
        self.side = np.zeros(steps, dtype=np.int8)

    @classmethod
    def like(cls, mesh: MeshSweep, phi1) -> MeshSweep:
        """A mesh of the same pair at other driver angles (the outlines and sectors shared)."""
        out = cls(mesh.pair, mesh.drv, mesh.drn, mesh.module, phi1, mesh.half, mesh.tol, mesh.sectors)
        out._index, out._reach = mesh.index, mesh.reach
        return out

    @property
    def reach(self):
        """The sectors where a vertex of each gear can meet the other within a tooth of free play
        (the overlap's reach sectors, grown by the arc a driven vertex moves through that turn)."""
        if self._reach is None:
            turn = float(self.span.max()) * (self.drv.r_max + self.drn.r_max) + self.tol
            c = self.centre
            self._reach = (
                contact.reach_sector(self.drv, 0.0, self.drn, c, self.pair.ring == "driven", turn),
                contact.reach_sector(self.drn, c, self.drv, 0.0, self.pair.ring == "driver", turn),
            )
        return self._reach

    @property
    def chunk(self) -> int:
        """Steps computed together: :data:`MESH_CHUNK`, fewer for outlines past :data:`CHUNK_VERTICES`
        (each step's figures are its own: the same for any chunk)."""
        vertices = len(self.drv.xy) + len(self.drn.xy)
        return max(8, min(MESH_CHUNK, MESH_CHUNK * CHUNK_VERTICES // max(1, vertices)))

    def all(self) -> None:
        """Fill every array, a chunk of steps at a time."""
        steps, chunk = len(self.phi1), self.chunk
        for start in range(0, steps, chunk):
            ks = np.arange(start, min(steps, start + chunk))
            self.run(ks)
            self._clearance(ks)

    @property
    def index(self):
        """Edge indexes of both outlines and the reach sectors of the clearance, made on first use."""
        if self._index is None:
            c, pad = self.centre, CLEARANCE_CAP_MM
            self._index = (
                contact.EdgeIndex(self.drv),
                contact.EdgeIndex(self.drn),
                contact.reach_sector(self.drv, 0.0, self.drn, c, self.pair.ring == "driven", pad),
                contact.reach_sector(self.drn, c, self.drv, 0.0, self.pair.ring == "driver", pad),
            )
        return self._index

    def _clearance(self, ks) -> None:
        """Smallest distance between the outlines with the driven gear at the middle of its play
        (0 where they overlap), and the two nearest points (driver frame)."""
        drv, drn, c = self.drv, self.drn, self.centre
        edges1, edges2, sector1, sector2 = self.index
        psi1 = self.psi1[ks]
        psi2 = self.psi2[ks] + self.turn * (self.te[ks] + 0.5 * self.bl[ks] / self.r2[ks])
        n = len(ks)
        # driver vertices against the driven edges, in the driven body's frame
        s1, i1 = drv.gather(sector1, psi1)
        b1 = contact.rotate(drv.placed(i1, psi1, -c, s1), -psi2, s1)
        keep = drn.near(b1, self.pair.ring == "driven", CLEARANCE_CAP_MM)
        d1, p1 = edges2.nearest(b1[keep], s1[keep], n)
        # driven vertices against the driver edges, in the driver body's frame
        s2, i2 = drn.gather(sector2, psi2)
        b2 = contact.rotate(drn.placed(i2, psi2, c, s2), -psi1, s2)
        keep = drv.near(b2, self.pair.ring == "driver", CLEARANCE_CAP_MM)
        d2, p2 = edges1.nearest(b2[keep], s2[keep], n)
        # the two nearest points in the driver's frame: (driver point, driven point)
        for j in np.flatnonzero(d1 < d2):  # driven frame -> world -> driver frame
            p1[j] = contact.rotate(contact.rotate(p1[j], psi2[j]) + (c, 0.0), -psi1[j])
        pts = np.where((d1 < d2)[:, None, None], p1, p2[:, ::-1])
        best = np.minimum(np.minimum(d1, d2), CLEARANCE_CAP_MM)
        best[self.pen[ks] > 0] = 0.0
        self.clear[ks] = best
        self.clear_points[ks] = pts

    def _in_box(self, p, px, grow=0.0):
        g = self.half + grow
        return (np.abs(p[..., 0] - px) <= g) & (np.abs(p[..., 1]) <= g)

    def run(self, ks: np.ndarray) -> None:
        overlapping, marks = self._overlap(ks)
        if self.whole:  # every vertex in reach: contacts within a quarter module of turn first
            near = np.minimum(0.25 * self.module / self.r2[ks], self.span[ks])
            reach = near * (self.drn.r_max + self.drv.r_max) + self.module
            valid = self._window(ks, np.arange(len(ks)), reach, near, overlapping, marks)
            redo = np.flatnonzero(~valid)  # then a tooth of free play where either side is farther
            if len(redo):
                k = ks[redo]
                reach = self.span[k] * (self.drn.r_max + self.drv.r_max) + self.module
                self._window(ks, redo, reach, self.span[k], overlapping, marks, final=True)
            return
        px = self.r1[ks]
        box_rho = np.abs(px - self.centre) + math.sqrt(2) * (self.half + self.drv.longest)
        near = 0.5 * self.module  # first pass: the driven gear's vertices within this of the window
        valid = self._window(ks, np.arange(len(ks)), np.full(len(ks), near), near / box_rho, overlapping, marks)
        redo = np.flatnonzero(~valid)
        if len(redo):
            k = ks[redo]
            reach = self.span[k] * (np.abs(self.r1[k] - self.centre) + 2 * self.half) + self.module
            self._window(ks, redo, reach, self.span[k], overlapping, marks, final=True)

    def _overlap(self, ks):
        """Overlap anywhere, by the vertices of each gear inside the other; fills pen, foul, dist,
        side. Returns whether the overlap reaches the window, and the driven vertices inside the
        driver in the window as keys (chunk step × size + index)."""
        drv, drn, c = self.drv, self.drn, self.centre
        psi1, psi2 = self.psi1[ks], self.psi2[ks]
        s1, i1 = drv.gather(self.sectors[0], psi1)
        p1 = drv.placed(i1, psi1, at=s1)
        in1 = drn.inside(contact.rotate(p1 - (c, 0.0), -psi2, s1), self.pair.ring == "driven")
        s2, i2 = drn.gather(self.sectors[1], psi2)
        p2 = drn.placed(i2, psi2, c, s2)
        in2 = drv.inside(contact.rotate(p2, -psi1, s2), self.pair.ring == "driver")
        pts = np.concatenate((p1[in1], p2[in2]))
        st = np.concatenate((s1[in1], s2[in2]))
        px = self.r1[ks]
        overlapping = np.zeros(len(ks), dtype=bool)
        overlapping[st[self._in_box(pts, px[st])]] = True
        s2, i2, p2 = s2[in2], i2[in2], p2[in2]
        boxed = self._in_box(p2, px[s2])
        marks = s2[boxed] * len(drn.xy) + i2[boxed]
        margin = 2 * max(drv.longest, drn.longest) + 1e-6
        for j in np.unique(st):
            k = int(ks[j])
            mine = pts[st == j]
            x0, y0 = mine.min(axis=0) - margin
            x1, y1 = mine.max(axis=0) + margin
            overlap = shapely.intersection(
                shapely.clip_by_rect(drv.whole(float(psi1[j])), x0, y0, x1, y1),
                shapely.clip_by_rect(drn.whole(float(psi2[j]), c), x0, y0, x1, y1),
            )
            self._pieces(k, overlap)
        return overlapping, marks

    def _pieces(self, k: int, overlap) -> None:
        pieces = [g for g in getattr(overlap, "geoms", [overlap]) if g.area > 0]
        if not pieces:
            return
        px, module = float(self.r1[k]), self.module
        self.pen[k] = overlap.area
        away = [g for g in pieces if math.hypot(g.centroid.x - px, g.centroid.y) > FOULING_PITCHES * math.pi * module]
        self.foul[k] = sum(g.area for g in away)
        big = max(pieces, key=lambda g: g.area)
        cx, cy = big.centroid.x, big.centroid.y
        self.dist[k] = math.hypot(cx - px, cy)
        body = math.atan2(cy, cx) + self.phi1[k]  # polar angle in the driver body
        beyond = math.hypot(cx, cy) > float(self.pair.driver.r(body))
        # a gear's tips are beyond its pitch curve, a ring's inside
        self.side[k] = 1 if beyond != (self.pair.ring == "driver") else 2

    def _window(self, ks, sel, reach, limit, overlapping, marks, final=False) -> np.ndarray:
        """First contact either way, backlash and contact count for chunk steps ``sel``, with the
        driven gear's vertices taken within ``reach`` of the window and contacts within turns of
        ``limit``. Writes te, bl, nc for the steps it settles; returns which ones."""
        drv, drn, c, turn, tol = self.drv, self.drn, self.centre, self.turn, self.tol
        k = ks[sel]
        px = self.r1[k]
        psi1, psi2 = self.psi1[k], self.psi2[k]
        # driver vertices within an edge of the window (every edge reaching it starts there)
        g1 = self.half + drv.longest
        hw = np.where(px > g1, np.arctan2(g1, np.maximum(px - g1, 1e-300)), math.pi)
        s1, j1 = drv.gather(self.reach[0] if self.whole else [(-hw, hw)], psi1)
        q1 = drv.placed(j1, psi1, at=s1)
        keep = self._in_box(q1, px[s1], drv.longest)
        keep &= _in_band(q1 - (c, 0.0), drn, self.pair.ring == "driven", self.pad)
        s1, j1, q1 = s1[keep], j1[keep], q1[keep]
        e1 = drv.placed(drv.next[j1], psi1, -c, s1)
        in_box1 = self._in_box(q1, px[s1])
        q1 = q1 - (c, 0.0)  # about the driven centre from here on
        # driven vertices within reach of the window
        g2 = self.half + reach + drn.longest
        d = px - c
        hw = np.where(np.abs(d) > g2, np.arctan2(g2, np.maximum(np.abs(d) - g2, 1e-300)), math.pi)
        mid = np.where(d >= 0, 0.0, math.pi)
        s2, j2 = drn.gather(self.reach[1] if self.whole else [(mid - hw, mid + hw)], psi2)
        q2 = drn.placed(j2, psi2, c, s2)
        keep = self._in_box(q2, px[s2], (reach + drn.longest)[s2])
        keep &= _in_band(q2, drv, self.pair.ring == "driver", self.pad + limit[s2] * drn.r_max)
        s2, j2, q2 = s2[keep], j2[keep], q2[keep] - (c, 0.0)
        e2 = drn.placed(drn.next[j2], psi2, at=s2)

        # driven vertex meets driver edge (a), driver vertex in the window meets driven edge (b)
        # (only pairs close enough to meet within the limit, or to be within tol once turned by it)
        va, ea = contact.pairs_within(q2, s2, q1, e1, s1, tol, limit, drv.longest + tol)
        b1 = np.flatnonzero(in_box1)
        vb, eb = contact.pairs_within(q1[b1], s1[b1], q2, e2, s2, tol, limit, drn.longest + tol)
        vb = b1[vb]
        sa, sb = s1[ea], s1[vb]
        xa, oka = contact.crossings(q2[va], q1[ea], e1[ea])
        oka &= self._in_box(xa + (c, 0.0), px[sa])
        da = turn * contact.angle_between(q2[va], xa)
        xb, okb = contact.crossings(q1[vb], q2[eb], e2[eb])
        db = -turn * contact.angle_between(q1[vb], xb)
        meet = np.concatenate((da[oka], db[okb]))
        owner = np.concatenate((np.broadcast_to(sa, oka.shape)[oka], np.broadcast_to(sb, okb.shape)[okb]))
        ok = np.abs(meet) <= limit[owner]
        meet, owner = meet[ok], owner[ok]
        back = np.full(len(k), -np.inf)
        fwd = np.full(len(k), np.inf)
        np.maximum.at(back, owner[meet <= 0], meet[meet <= 0])
        np.minimum.at(fwd, owner[meet >= 0], meet[meet >= 0])
        over = overlapping[sel]
        valid = over | (np.isfinite(back) & np.isfinite(fwd)) | final
        back = np.where(over, 0.0, np.where(np.isfinite(back), back, -limit))
        fwd = np.where(over, 0.0, np.where(np.isfinite(fwd), fwd, limit))
        self.te[k] = np.where(valid, back, self.te[k])
        self.bl[k] = np.where(valid, (fwd - back) * self.r2[k], self.bl[k])

        # contact places with the driving flanks closed up: runs of the driven boundary within
        # tol of the driver (a driver vertex near a driven edge marks that edge's start)
        pa = contact.rotate(q2[va], turn * back, sa)
        near_a = (contact.segment_distance(pa, q1[ea], e1[ea]) <= tol) & self._in_box(pa + (c, 0.0), px[sa])
        pb = contact.rotate(q1[vb], -turn * back, sb)
        near_b = contact.segment_distance(pb, q2[eb], e2[eb]) <= tol
        size = len(drn.xy)
        found = [sel[s2[va[near_a]]] * size + j2[va[near_a]], sel[s2[eb[near_b]]] * size + j2[eb[near_b]]]
        mine = np.isin(marks // size, sel[over])
        keys = np.unique(np.concatenate([*found, marks[mine]]))
        starts = keys[~np.isin((keys // size) * size + drn.prev[keys % size], keys)]
        counted = np.bincount(starts // size, minlength=len(ks))[sel]
        self.nc[k] = np.where(valid, counted, self.nc[k])
        return valid
