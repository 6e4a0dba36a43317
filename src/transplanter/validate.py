"""Kinematic validation of the made parts: do the gears mesh, does the train and the cam move as designed?

**Gear pairs** (:func:`mesh_check`). The driver is turned through a full turn in ``steps``
positions (raised to be coprime with the driver's tooth count, so the samples fall at every
phase of the tooth mesh); the driven gear is placed where the *design* ratio puts it
(``GearPair.driven_rotation``); and the actual tooth outlines — the generated polygons, or
the contours re-read from the DXF, or a mid-plane section of the STL — are compared:

- **penetration**: overlap area of the two whole outlines (mm²), split into the part near the
  pitch point (within ``FOULING_PITCHES`` circular pitches) and **fouling** — overlap further away,
  where teeth that are not meant to be in mesh yet (or any more) hit each other: tip-to-tip
  fouling on entry and exit of an internal mesh, or teeth of a non-circular pair whose ratio
  changes too fast for the teeth beside the pitch point to follow;
- **transmission error**: the driven gear is turned back from its design angle until its
  teeth first touch the driver's — in closed form, the nearest turn at which a vertex of one
  outline meets an edge of the other (``transplanter.contact``; exact for the polygons, every
  step at once); that angle as arc length at the
  pitch point (mm) minus its cycle mean (the constant share of the backlash) is the
  geometric transmission error, reported as max and rms; the raw angle is kept
  (``driven_error``) for rebuilding a train from the parts;
- **backlash**: the same search forwards; backlash is the arc between the two contacts
  (checked against ``backlash.backlash_band``: above the tolerance budget, below the target's band);
- **contact**: with the driving flanks closed up, the number of separate places where the
  outlines are within ``contact_tol`` — never zero for a working pair; its mean over the
  cycle is the geometric contact ratio (both flanks count when there is no backlash).

Placement follows the ``pitch.pair`` conventions: the driver turns clockwise about the
origin, the driven centre is at (a, 0) — (-a, 0) for a driven ring, which encloses the
planet; an external driven gear's body frame is turned by π at the start and turns
counter-clockwise; an internal one (ring or planet) turns clockwise
with the driver.

**Trains** (:func:`train_check`): the seed-004 train rebuilt with the planet attitude taken
from the geometric meshing of the parts (the design contact angle plus the measured
``driven_error``) instead of the pitch curves; the report is the needle-tip distance from the
designed trajectory at every meshing step.

**Cams** (:func:`follower_check`): the follower is pressed onto the made cam contour at each
cam angle (roller followers: the roller position where it just touches the contour, by
``brentq``; flat-faced: the contour's support point) and its motion is compared with the
prescribed law.

Examples
--------
A pair of 20-tooth circular gears cut with the default backlash meshes: no overlap, the
backlash inside its band, about 1.5 pairs of teeth in contact (``tests/test_validate.py``
holds the check to the root-finding reference it replaced).

>>> from transplanter.cutter import ShaperCutter
>>> from transplanter.pitch import GearPair, PitchCurve
>>> from transplanter.teeth import generate_pair
>>> pair, sizing = GearPair.from_driver(PitchCurve.circle(20.0), "external", 1).sized(teeth=20)
>>> driver, driven = generate_pair(pair, ShaperCutter(12, sizing.module), sizing.teeth)
>>> report = mesh_check(pair, driver.polygon, driven.polygon, sizing.module, steps=40, teeth=20)
>>> report.problems(), report.max_penetration, 1.4 < report.contact_ratio < 1.8
([], 0.0, True)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy import optimize

from transplanter import cams, contact
from transplanter.errors import GeometryError, SpecError
from transplanter.precision import significant
from transplanter.tolerances import AREA_ROUND_OFF_MM2, CONTACT_TOL_MM, PENETRATION_TOL

__all__ = [
    "MeshReport",
    "mesh_check",
    "TrainReport",
    "train_check",
    "FollowerReport",
    "follower_check",
    "turned_by",
]

#: overlap further than this many circular pitches from the pitch point is fouling: the path
#: of contact of involute teeth ends about one pitch (contact ratio ~1.5-2) from it
FOULING_PITCHES = 1.5


@dataclass(frozen=True)
class MeshReport:
    """Meshing figures over a cycle (arrays per step, summaries as properties)."""

    driver_angle: np.ndarray = field(repr=False)
    #: overlap area of the whole outlines, mm²
    penetration: np.ndarray = field(repr=False)
    transmission_error: np.ndarray = field(repr=False)
    backlash: np.ndarray = field(repr=False)
    contacts: np.ndarray = field(repr=False)
    #: overlap area further than FOULING_PITCHES circular pitches from the pitch point, mm²
    fouling: np.ndarray = field(repr=False)
    #: distance of the largest overlap from the pitch point, mm (0 where none)
    overlap_distance: np.ndarray = field(repr=False)
    #: whose tooth tips the largest overlap is in: 1 driver, 2 driven, 0 none
    overlap_side: np.ndarray = field(repr=False)
    #: driven rotation at first contact of the driving flanks beyond the design angle, rad
    driven_error: np.ndarray = field(repr=False)
    #: mean driving-flank contact offset (mm at the driven pitch point): half the backlash
    #: for symmetric tooth thinning; the transmission error is measured from it
    offset: float = 0.0

    @property
    def max_penetration(self) -> float:
        return float(self.penetration.max())

    @property
    def max_fouling(self) -> float:
        return float(self.fouling.max())

    @property
    def max_transmission_error(self) -> float:
        return float(np.max(np.abs(self.transmission_error)))

    @property
    def rms_transmission_error(self) -> float:
        return float(np.sqrt(np.mean(self.transmission_error**2)))

    @property
    def contact_ratio(self) -> float:
        return float(self.contacts.mean())

    @property
    def min_contacts(self) -> int:
        return int(self.contacts.min())

    def summary(self) -> dict:
        """The figures a report carries (mm, mm², deg); overlaps below 1e-12 mm² (round-off of
        the polygon Booleans) are reported as 0."""
        return {
            "steps": len(self.driver_angle),
            "max_penetration_mm2": significant(self.max_penetration)
            if self.max_penetration > AREA_ROUND_OFF_MM2
            else 0.0,
            "max_fouling_mm2": significant(self.max_fouling) if self.max_fouling > AREA_ROUND_OFF_MM2 else 0.0,
            "max_transmission_error_mm": significant(self.max_transmission_error),
            "rms_transmission_error_mm": significant(self.rms_transmission_error),
            "backlash_mm": [significant(self.backlash.min()), significant(self.backlash.max())],
            "contact_ratio": round(self.contact_ratio, 4),
            "min_contacts": self.min_contacts,
        }

    def problems(
        self,
        max_penetration: float = PENETRATION_TOL,
        backlash: tuple[float, float] | None = None,
        names: tuple[str, str] = ("driver", "driven"),
    ) -> list[str]:
        """What a designer must fix, in words (empty when the pair meshes).

        ``max_penetration`` is the overlap-area tolerance (mm²); ``backlash`` the design band
        (mm at the driven pitch point); ``names`` what to call the two gears.
        """
        out = []
        deg = np.degrees(self.driver_angle)
        near = self.penetration - self.fouling
        k = int(np.argmax(near))
        if near[k] > max_penetration:
            tips, other = (names[0], names[1]) if self.overlap_side[k] == 1 else (names[1], names[0])
            out.append(
                f"the teeth interfere at the pitch point: {near[k]:.3g} mm² of overlap at driver angle "
                f"{deg[k]:.1f} deg (limit {max_penetration:g} mm²), the {tips}'s tooth tips in the {other}'s "
                "flanks — the centre distance, the tooth counts or the cutter do not match the pitch curves, "
                f"or the {tips}'s addendum is too long for the {other}'s tooth count (shorten it: "
                "generate(..., addendum=...))"
            )
        k = int(np.argmax(self.fouling))
        if self.fouling[k] > max_penetration:
            tips = names[0] if self.overlap_side[k] == 1 else names[1]
            out.append(
                f"the teeth foul {self.overlap_distance[k]:.1f} mm from the pitch point: {self.fouling[k]:.3g} mm² of "
                f"overlap at driver angle {deg[k]:.1f} deg (limit {max_penetration:g} mm²), the {tips}'s tips hitting "
                "teeth that are entering or leaving mesh — the pitch curves stay within the teeth's reach too long "
                "while the ratio changes; use a finer module, shorter teeth or a pitch curve with a smaller pressure "
                "deviation"
            )
        k = int(np.argmin(self.contacts))
        if self.contacts[k] == 0:
            out.append(
                f"no tooth pair is in contact at driver angle {deg[k]:.1f} deg — the gears would jump; check the "
                "centre distance and the addendum"
            )
        if backlash is not None:
            lo, hi = backlash
            k = int(np.argmin(self.backlash))
            j = int(np.argmax(self.backlash))
            if self.backlash[k] < lo or self.backlash[j] > hi:
                out.append(
                    f"backlash {self.backlash[k]:.4g}..{self.backlash[j]:.4g} mm leaves the design band "
                    f"{lo:.4g}..{hi:.4g} mm (at driver angles {deg[k]:.1f} and {deg[j]:.1f} deg)"
                )
        return out


def _coprime(steps: int, teeth: int | None) -> int:
    if teeth is None:
        return steps
    while math.gcd(steps, int(teeth)) > 1:
        steps += 1
    return steps


def _polygon(name: str, poly):
    if not isinstance(poly, shapely.Polygon | shapely.MultiPolygon) or poly.is_empty or not poly.is_valid:
        raise GeometryError(f"{name} must be a valid, non-empty shapely polygon (the gear outline)")
    return poly


#: meshing steps computed together (their vertex/edge pairs held at once)
MESH_CHUNK = 64


def mesh_check(
    pair,
    driver_polygon,
    driven_polygon,
    module: float,
    steps: int = 120,
    window: float = 3.0,
    contact_tol: float = CONTACT_TOL_MM,
    teeth: int | None = None,
) -> MeshReport:
    """Mesh ``driver_polygon`` and ``driven_polygon`` (body frames) per ``pair``'s design ratio.

    ``window`` (modules) is the half-size of the square around the pitch point where the
    contact is searched (the path of contact reaches ~2.5 modules either side);
    ``contact_tol`` (mm) the gap that counts as contact; ``teeth`` the driver's tooth count
    (``steps`` is raised until coprime with it).

    How: in closed form on the outlines' vertices and edges, every step at once
    (:mod:`transplanter.contact`), no root finding and no whole-outline Booleans:

    - **first contact** either way of the design angle: the nearest turn of the driven gear at
      which a vertex of one gear meets an edge of the other inside the window — exact for the
      polygons (the root search it replaced stopped at 1e-8 mm; ``tests/reference_meshing.py``
      keeps it). The driven gear's vertices are first taken within half a module of the window,
      which holds any contact within that arc; a step whose contact lies further is redone
      with the full reach (a tooth of free play);
    - **overlap**: the vertices in the sectors where the gears reach each other are tested
      against the other gear (radius bounds, then prepared point-in-polygon); only where some
      lie inside is the overlap intersected, on both outlines clipped to their bounds;
    - **contacts**: with the driving flanks closed up, the runs of the driven boundary within
      ``contact_tol`` of the driver (point–segment distances).
    """
    if not isinstance(steps, int) or steps < 4:
        raise SpecError.out_of_range("steps", steps, "an integer >= 4")
    drv = contact.Outline(_polygon("driver_polygon", driver_polygon))
    drn = contact.Outline(_polygon("driven_polygon", driven_polygon))
    steps = _coprime(steps, teeth)
    mesh = _Mesh(pair, drv, drn, module, steps, window * module, contact_tol)
    for start in range(0, steps, MESH_CHUNK):
        mesh.run(np.arange(start, min(steps, start + MESH_CHUNK)))
    arc = mesh.te * mesh.r2
    offset = float(arc.mean())
    return MeshReport(
        mesh.phi1, mesh.pen, arc - offset, mesh.bl, mesh.nc, mesh.foul, mesh.dist, mesh.side, mesh.te, offset
    )


class _Mesh:
    """The arrays of one :func:`mesh_check` and the stages that fill them, a chunk of steps at a time."""

    def __init__(self, pair, drv, drn, module, steps, half, tol):
        self.pair, self.drv, self.drn, self.module, self.half, self.tol = pair, drv, drn, module, half, tol
        self.external = pair.ring is None
        self.centre = -pair.centre_distance if pair.ring == "driven" else pair.centre_distance
        self.turn = 1.0 if self.external else -1.0  # the driven gear's sense for a positive δ
        self.phi1 = 2 * math.pi * np.arange(steps) / steps
        self.r1 = pair.driver.r(self.phi1)
        theta2 = pair.driven_rotation(self.phi1)
        self.r2 = np.abs(self.r1 - self.centre)
        self.psi1 = -self.phi1
        self.psi2 = (math.pi + theta2) if self.external else -theta2
        self.span = 2 * module / np.maximum(self.r2, module)  # about a tooth of free play
        self.sectors = (
            contact.reach_sector(drv, 0.0, drn, self.centre, pair.ring == "driven"),
            contact.reach_sector(drn, self.centre, drv, 0.0, pair.ring == "driver"),
        )
        self.pen, self.foul, self.dist, self.te, self.bl, self.nc = (np.zeros(steps) for _ in range(6))
        self.side = np.zeros(steps, dtype=np.int8)

    def _in_box(self, p, px, grow=0.0):
        g = self.half + grow
        return (np.abs(p[..., 0] - px) <= g) & (np.abs(p[..., 1]) <= g)

    def run(self, ks: np.ndarray) -> None:
        overlapping, marks = self._overlap(ks)
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
        s1, j1 = drv.gather([(-hw, hw)], psi1)
        q1 = drv.placed(j1, psi1, at=s1)
        keep = self._in_box(q1, px[s1], drv.longest)
        s1, j1, q1 = s1[keep], j1[keep], q1[keep]
        e1 = drv.placed(drv.next[j1], psi1, -c, s1)
        in_box1 = self._in_box(q1, px[s1])
        q1 = q1 - (c, 0.0)  # about the driven centre from here on
        # driven vertices within reach of the window
        g2 = self.half + reach + drn.longest
        d = px - c
        hw = np.where(np.abs(d) > g2, np.arctan2(g2, np.maximum(np.abs(d) - g2, 1e-300)), math.pi)
        mid = np.where(d >= 0, 0.0, math.pi)
        s2, j2 = drn.gather([(mid - hw, mid + hw)], psi2)
        q2 = drn.placed(j2, psi2, c, s2)
        keep = self._in_box(q2, px[s2], (reach + drn.longest)[s2])
        s2, j2, q2 = s2[keep], j2[keep], q2[keep] - (c, 0.0)
        e2 = drn.placed(drn.next[j2], psi2, at=s2)

        # driven vertex meets driver edge (a), driver vertex in the window meets driven edge (b)
        # (only pairs close enough to meet within the limit, or to be within tol once turned by it)
        va, ea = contact.pairs(q2, s2, q1, e1, s1, tol)
        va, ea = contact.within(q2, va, q1, ea, limit[s1[ea]], drv.longest + tol)
        b1 = np.flatnonzero(in_box1)
        vb, eb = contact.pairs(q1[b1], s1[b1], q2, e2, s2, tol)
        vb = b1[vb]
        vb, eb = contact.within(q1, vb, q2, eb, limit[s1[vb]], drn.longest + tol)
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
        keys = [sel[s2[va[near_a]]] * size + j2[va[near_a]], sel[s2[eb[near_b]]] * size + j2[eb[near_b]]]
        mine = np.isin(marks // size, sel[over])
        keys = np.unique(np.concatenate([*keys, marks[mine]]))
        starts = keys[~np.isin((keys // size) * size + drn.prev[keys % size], keys)]
        counted = np.bincount(starts // size, minlength=len(ks))[sel]
        self.nc[k] = np.where(valid, counted, self.nc[k])
        return valid


@dataclass(frozen=True)
class _MeshedPair:
    """A pair whose driven contact angle comes from the parts' geometric meshing."""

    pair: object
    angle: np.ndarray
    error: np.ndarray

    @property
    def centre_distance(self) -> float:
        return self.pair.centre_distance

    @property
    def lobes(self) -> tuple[int, int]:
        return self.pair.lobes

    @property
    def driver(self):
        return self.pair.driver

    @property
    def ring(self) -> str | None:
        return self.pair.ring

    def ratio(self, phi1):
        return self.pair.ratio(phi1)

    def driven_contact_angle(self, phi1):
        phi1 = np.asarray(phi1, dtype=float)
        extra = np.interp(np.mod(phi1, 2 * math.pi), self.angle, self.error, period=2 * math.pi)
        return self.pair.driven_contact_angle(phi1) + self.pair.contact_sense * extra


@dataclass(frozen=True)
class TrainReport:
    """Needle-tip path of the train rebuilt from the parts against the designed one."""

    theta: np.ndarray = field(repr=False)
    deviation: np.ndarray = field(repr=False)
    attitude_error: np.ndarray = field(repr=False)
    #: the train as rebuilt from the parts (its planets turned by the parts' meshing)
    made: object = field(default=None, repr=False, compare=False)

    @property
    def max_deviation(self) -> float:
        return float(self.deviation.max())

    def summary(self) -> dict:
        return {
            "samples": len(self.theta),
            "carrier_turns": round(float(np.ptp(self.theta)) / (2 * math.pi), 3),
            "max_tip_deviation_mm": significant(self.max_deviation),
            "rms_tip_deviation_mm": significant(np.sqrt(np.mean(self.deviation**2))),
            "max_needle_attitude_error_deg": significant(math.degrees(np.max(np.abs(self.attitude_error)))),
        }


def train_check(train, report: MeshReport) -> TrainReport:
    """Rebuild ``train`` (a ``planetary.DifferentialTrain``) with the planet attitude from the
    parts' meshing in ``report`` (from :func:`mesh_check` of its ring and planet) and compare the
    needle tip with the designed one at every meshing step (ring body angle → carrier angle)."""
    pair = train.pair
    meshed = dataclasses.replace(train, pair=_MeshedPair(pair, report.driver_angle, report.driven_error))
    # arm I's contact is at ring body angle -(1 - ω1/ω2) θ
    theta = (2 * math.pi - report.driver_angle) / (1.0 - train.speed_ratio)
    design, made = train.state(theta), meshed.state(theta)
    dev = np.linalg.norm(made.tip - design.tip, axis=1)
    att = np.angle(np.exp(1j * (made.attitude - design.attitude)))
    return TrainReport(theta, dev, att, meshed)


@dataclass(frozen=True)
class FollowerReport:
    """Follower motion on the made cam contour against the prescribed law."""

    theta: np.ndarray = field(repr=False)
    prescribed: np.ndarray = field(repr=False)
    actual: np.ndarray = field(repr=False)
    #: error as displacement at the roller centre (or face), mm
    error: np.ndarray = field(repr=False)
    unit: str = "mm"

    @property
    def max_error(self) -> float:
        return float(np.max(np.abs(self.error)))

    def summary(self) -> dict:
        return {
            "samples": len(self.theta),
            "max_error_mm": significant(self.max_error),
            "rms_error_mm": significant(np.sqrt(np.mean(self.error**2))),
            "stroke": significant(np.ptp(self.prescribed), 6),
            "stroke_unit": self.unit,
        }


def _bracketed_roots(f, lo, hi, f_lo, f_hi, xtol: float, maxiter: int = 200) -> np.ndarray:
    """Roots of the vectorised ``f`` in the brackets [lo, hi] (f_lo <= 0 <= f_hi elementwise),
    to ``xtol``: the Illinois variant of regula falsi (superlinear like brentq's secant steps,
    and never leaving the bracket), every bracket at once."""
    lo, hi, f_lo, f_hi = (np.array(v, dtype=float) for v in (lo, hi, f_lo, f_hi))
    x = 0.5 * (lo + hi)
    side = np.zeros(lo.shape, dtype=np.int8)  # which end was kept last time: -1 lo, +1 hi
    for _ in range(maxiter):
        width = hi - lo
        if np.all(width <= xtol):
            break
        denom = f_hi - f_lo
        x = np.where(denom > 0, hi - f_hi * width / np.where(denom > 0, denom, 1.0), 0.5 * (lo + hi))
        x = np.where((x > lo) & (x < hi), x, 0.5 * (lo + hi))
        fx = f(x)
        up = fx > 0  # the root is below x: x becomes hi
        zero = fx == 0
        lo = np.where(zero, x, np.where(up, lo, x))
        hi = np.where(zero, x, np.where(up, x, hi))
        # Illinois: an end kept twice in a row has its value halved, so the next secant moves it
        f_lo = np.where(up & (side == -1), 0.5 * f_lo, np.where(up, f_lo, fx))
        f_hi = np.where(~up & (side == 1), 0.5 * f_hi, np.where(up, fx, f_hi))
        side = np.where(up, -1, 1).astype(np.int8)
    return np.where(hi - lo <= xtol, 0.5 * (lo + hi), x)


def follower_check(contour, motion, follower, n: int = 720) -> FollowerReport:
    """Press ``follower`` onto the made cam ``contour`` (shapely polygon, cam frame) at ``n``
    cam angles and compare its position with ``motion`` (the law the cam was designed for).

    Roller followers: the follower coordinate s at which the roller just touches the contour
    (signed roller-centre distance minus roller radius = 0, within ±10 % of the stroke plus
    1 mm of the law, to 1e-12; every cam angle at once, distances from an STRtree of the
    contour's segments). Flat-faced: the contour's support height minus the base
    radius. The cam turns counter-clockwise by θ (``cams`` conventions).
    """
    contour = _polygon("contour", contour)
    if not isinstance(n, int) or n < 8:
        raise SpecError.out_of_range("n", n, "an integer >= 8")
    theta = 2 * math.pi * np.arange(n) / n
    law = np.asarray(motion(theta), dtype=float)
    pts = shapely.get_coordinates(contour.exterior)
    if isinstance(follower, cams.FlatFacedFollower):
        # support height along the follower's +y, which is (sin θ, cos θ) in the cam frame
        actual = np.max(pts @ np.stack([np.sin(theta), np.cos(theta)]), axis=0) - follower.base_radius
        return FollowerReport(theta, law, actual, actual - law)
    if not isinstance(follower, cams.OscillatingRollerFollower | cams.TranslatingRollerFollower):
        raise SpecError(f"unknown follower type {type(follower).__name__}")
    rr = follower.roller_radius
    span = 0.1 * float(np.ptp(law)) + (1.0 / follower.arm_length if hasattr(follower, "arm_length") else 1.0)
    distance = contact.distance_to_ring(pts)
    shapely.prepare(contour)

    def gap(s):  # signed distance of the roller centres from the contour, minus the roller radius
        c = cams.roller_centre(follower, s, theta)
        d = distance(c)
        return np.where(shapely.contains_xy(contour, c[:, 0], c[:, 1]), -d, d) - rr

    lo, hi = law - span, law + span
    g_lo, g_hi = gap(lo), gap(hi)
    bad = (g_lo > 0) | (g_hi < 0)
    if bad.any():
        t = theta[int(np.argmax(bad))]
        raise GeometryError(
            f"the follower does not reach the cam contour near θ = {math.degrees(t):.1f} deg within ±{span:.3g} "
            "of the law — the contour is not this cam's"
        )
    actual = _bracketed_roots(gap, lo, hi, g_lo, g_hi, xtol=1e-12)
    err = actual - law
    unit = "mm"
    if isinstance(follower, cams.OscillatingRollerFollower):
        err = err * follower.arm_length  # swing error as displacement at the roller
        unit = "rad"
    return FollowerReport(theta, law, actual, err, unit)


def turned_by(made, design, max_deg: float = 10.0, band: float = 2e-3) -> float | None:
    """The angle (deg, counter-clockwise about the origin) by which the ``made`` contour
    (shapely polygon) is turned from the ``design``, or None when they already agree (on average
    within ``band`` mm along the contour) or no turn within ``max_deg`` makes them agree.

    ``check`` uses it to say "this file was rotated" instead of letting the meshing figures blame
    the centre distance or the tooth counts."""
    limit = band * design.exterior.length

    def mismatch(deg: float) -> float:
        turned = shapely.affinity.rotate(made, -deg, origin=(0.0, 0.0))
        return float(shapely.symmetric_difference(turned, design).area)

    if mismatch(0.0) <= limit:
        return None
    scan = np.arange(-max_deg, max_deg + 1e-9, 0.25)
    k = int(np.argmin([mismatch(a) for a in scan]))
    best = optimize.minimize_scalar(mismatch, bounds=(scan[k] - 0.25, scan[k] + 0.25), method="bounded")
    return float(best.x) if best.fun <= limit else None
