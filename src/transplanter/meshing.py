"""Gear meshing judged on the made outlines: overlap, transmission error, backlash, contacts and
clearance over the whole cycle, with the extremes refined between the samples.

:func:`mesh_check` turns the driver through a full turn in ``steps`` positions (raised to be
coprime with the driver's tooth count, so the samples fall at every phase of the tooth mesh);
the driven gear is placed where the *design* ratio puts it (``GearPair.driven_rotation``); and
the actual tooth outlines — the generated polygons, or the contours re-read from the DXF, or a
mid-plane section of the STL — are compared:

- **penetration**: overlap area of the two whole outlines (mm²), split into the part near the
  pitch point (within ``FOULING_PITCHES`` circular pitches) and **fouling** — overlap further away,
  where teeth that are not meant to be in mesh yet (or any more) hit each other: tip-to-tip
  fouling on entry and exit of an internal mesh, or teeth of a non-circular pair whose ratio
  changes too fast for the teeth beside the pitch point to follow;
- **transmission error**: the driven gear is turned back from its design angle until its
  teeth first touch the driver's — in closed form, the nearest turn at which a vertex of one
  outline meets an edge of the other (``transplanter.contact``; exact for the polygons, every
  step at once); that angle as arc length at the pitch point (mm) minus its cycle mean (the
  constant share of the backlash) is the geometric transmission error, reported as max and
  rms; the raw angle is kept (``driven_error``) for rebuilding a train from the parts;
- **backlash** (free play): the same search forwards; backlash is the arc at the driven pitch
  point between the two contacts. **Every gap counts**: by default (``window=None``) the
  contacts are searched over every vertex and edge of both outlines within reach of the other
  gear, not only beside the pitch point — on the seed-004 ring/planet the free play closes to
  half its flank value where a planet tip passes a ring flank near its tip, 2–3 pitches from
  the pitch point;
- **clearance**: the smallest distance between the two whole outlines (tips, roots, flanks)
  with the driven gear at the middle of its play — what is left between two parts that are
  each off by the manufacturing tolerance;
- **contact**: with the driving flanks closed up, the number of separate places where the
  outlines are within ``contact_tol`` — never zero for a working pair; its mean over the
  cycle is the geometric contact ratio (both flanks count when there is no backlash).

**Between the samples** (``refine=True``). Free play and clearance are piecewise smooth in the
driver angle: smooth while the same vertex–edge pairs bound them, with kinks and jumps where
the bounding pair changes — the free play of the seed-004 pair falls linearly by 85 µm over
1° while a planet tip slides down a ring flank, then jumps back when the tip leaves the
ring's tip corner. A sample grid steps over such a dip's floor — and, dips being 0.6–1° wide,
over whole dips (the default 2° grid saw two of the eight on that pair). So first every close
pass of a tooth tip is found on a 0.1° scan of the tips alone (:func:`_approaches`) and measured
exactly; then every local extreme of the samples is refined by bisection of the intervals
beside it, until each such interval is narrower than ``REFINE_RAD`` or the values at its ends
differ by less than ``REFINE_MM``: a jump is located to 1e-5 rad of driver turn and its floor
taken from the side where the function is continuous, a smooth extreme to 0.5 µm. An extreme's
figure is the extreme over the uniform and the refined samples, with the angle where it lies.
What this still assumes (it is not a certified bound): a dip is made by a tip passing the
other gear and lasts longer than the scan step, or shows in a uniform sample;
``tests/test_meshing.py`` holds the refined extremes to a 200× denser judge.

Placement follows the ``pitch.pair`` conventions: the driver turns clockwise about the
origin, the driven centre is at (a, 0) — (-a, 0) for a driven ring, which encloses the
planet; an external driven gear's body frame is turned by π at the start and turns
counter-clockwise; an internal one (ring or planet) turns clockwise
with the driver.

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
>>> 0.03 < report.clearance_min.value < report.backlash_min.value
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy.signal import find_peaks

from transplanter import contact
from transplanter.errors import GeometryError, SpecError
from transplanter.precision import significant
from transplanter.tolerances import AREA_ROUND_OFF_MM2, CONTACT_TOL_MM, PENETRATION_TOL, REFINE_MM, REFINE_RAD

__all__ = ["FOULING_PITCHES", "CLEARANCE_CAP_MM", "Extreme", "MeshReport", "mesh_check"]

#: overlap further than this many circular pitches from the pitch point is fouling: the path
#: of contact of involute teeth ends about one pitch (contact ratio ~1.5-2) from it
FOULING_PITCHES = 1.5

#: clearances beyond this (mm) are not measured: they are reported as this value
CLEARANCE_CAP_MM = 0.5

#: refinement rounds at most (each halves the intervals beside every extreme; 0.05 rad -> 1e-5 in 13)
REFINE_ROUNDS = 20


@dataclass(frozen=True)
class Extreme:
    """An extreme over the cycle: its value (mm) and the driver angle where it lies (deg)."""

    value: float
    at_deg: float


@dataclass(frozen=True)
class MeshReport:
    """Meshing figures over a cycle (arrays per uniform step, extremes over the refined samples too)."""

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
    #: smallest distance between the outlines with the driven gear at mid-play, mm (capped at
    #: CLEARANCE_CAP_MM; None where not measured)
    clearance: np.ndarray | None = field(default=None, repr=False)
    #: the samples the refinement added: driver angle (rad), backlash and clearance (mm)
    refined: tuple[np.ndarray, np.ndarray, np.ndarray] | None = field(default=None, repr=False)
    #: where the smallest clearance lies: the two nearest points, driver frame (mm), (2, 2)
    clearance_points: np.ndarray | None = field(default=None, repr=False)

    def _all(self, which: int) -> tuple[np.ndarray, np.ndarray]:
        values = (self.backlash, self.clearance)[which]
        if self.refined is None:
            return self.driver_angle, values
        return np.concatenate((self.driver_angle, self.refined[0])), np.concatenate((values, self.refined[1 + which]))

    def samples(self, quantity: str) -> tuple[np.ndarray, np.ndarray]:
        """``"backlash"`` or ``"clearance"`` at the uniform and the refined samples, by driver angle
        (rad, mm) — what a plot of the cycle should draw."""
        angle, values = self._all(("backlash", "clearance").index(quantity))
        order = np.argsort(angle, kind="stable")
        return angle[order], values[order]

    def _extreme(self, which: int, pick) -> Extreme:
        angle, values = self._all(which)
        k = int(pick(values))
        return Extreme(float(values[k]), math.degrees(angle[k]))

    @property
    def backlash_min(self) -> Extreme:
        """The smallest free play over the uniform and refined samples."""
        return self._extreme(0, np.argmin)

    @property
    def backlash_max(self) -> Extreme:
        """The largest free play over the uniform and refined samples."""
        return self._extreme(0, np.argmax)

    @property
    def clearance_min(self) -> Extreme | None:
        """The smallest mid-play clearance over the uniform and refined samples (None: not measured)."""
        return None if self.clearance is None else self._extreme(1, np.argmin)

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
        lo, hi = self.backlash_min, self.backlash_max
        out = {
            "steps": len(self.driver_angle),
            "refined_samples": 0 if self.refined is None else len(self.refined[0]),
            "max_penetration_mm2": significant(self.max_penetration)
            if self.max_penetration > AREA_ROUND_OFF_MM2
            else 0.0,
            "max_fouling_mm2": significant(self.max_fouling) if self.max_fouling > AREA_ROUND_OFF_MM2 else 0.0,
            "max_transmission_error_mm": significant(self.max_transmission_error),
            "rms_transmission_error_mm": significant(self.rms_transmission_error),
            "backlash_mm": [significant(lo.value), significant(hi.value)],
            "backlash_at_driver_deg": [round(lo.at_deg, 4), round(hi.at_deg, 4)],
            "contact_ratio": round(self.contact_ratio, 4),
            "min_contacts": self.min_contacts,
        }
        c = self.clearance_min
        if c is not None:
            out["clearance_mm"] = significant(c.value)
            out["clearance_at_driver_deg"] = round(c.at_deg, 4)
            if self.clearance_points is not None and c.value < CLEARANCE_CAP_MM:
                r = np.hypot(*self.clearance_points.T)
                out["clearance_driver_radius_mm"] = round(float(r[0]), 4)
        return out

    def problems(
        self,
        max_penetration: float = PENETRATION_TOL,
        backlash: tuple[float, float] | None = None,
        names: tuple[str, str] = ("driver", "driven"),
        clearance: float | None = None,
    ) -> list[str]:
        """What a designer must fix, in words (empty when the pair meshes).

        ``max_penetration`` is the overlap-area tolerance (mm²); ``backlash`` the design band
        (mm at the driven pitch point); ``names`` what to call the two gears; ``clearance`` the
        smallest mid-play clearance allowed (mm; None: not judged).
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
            b0, b1 = self.backlash_min, self.backlash_max
            if b0.value < lo or b1.value > hi:
                out.append(
                    f"backlash {b0.value:.4g}..{b1.value:.4g} mm leaves the design band "
                    f"{lo:.4g}..{hi:.4g} mm (at driver angles {b0.at_deg:.2f} and {b1.at_deg:.2f} deg)"
                )
        c = self.clearance_min
        if clearance is not None and c is not None and c.value < clearance and not out:
            out.append(
                f"clearance {c.value * 1e3:.1f} µm at driver angle {c.at_deg:.2f} deg, with the {names[1]} at the "
                f"middle of its play, is below {clearance * 1e3:.1f} µm (half the tolerance budget): two parts off "
                "by the tolerance can touch there — shorten the tips that pass there (addendum) or cut more backlash"
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


def _in_band(p: np.ndarray, other: contact.Outline, ring: bool, pad) -> np.ndarray:
    """Points ``p`` (n, 2, about ``other``'s origin) within ``pad`` of ``other``'s radius range
    (a body reaches to r_max; a ring's teeth reach in to r_min)."""
    r = np.hypot(p[:, 0], p[:, 1])
    return r >= other.r_min - pad if ring else r <= other.r_max + pad


#: meshing steps computed together (their vertex/edge pairs held at once)
MESH_CHUNK = 64


def mesh_check(
    pair,
    driver_polygon,
    driven_polygon,
    module: float,
    steps: int = 120,
    window: float | None = None,
    contact_tol: float = CONTACT_TOL_MM,
    teeth: int | None = None,
    refine: bool = True,
) -> MeshReport:
    """Mesh ``driver_polygon`` and ``driven_polygon`` (body frames) per ``pair``'s design ratio.

    ``window`` (modules) limits the contact search to a square of that half-size around the
    pitch point (the path of contact reaches ~2.5 modules either side; None: every vertex and
    edge within reach of the other gear — every gap counts); ``contact_tol`` (mm) the gap that
    counts as contact; ``teeth`` the driver's tooth count (``steps`` is raised until coprime
    with it); ``refine`` refines every extreme
    of the free play and the clearance between the samples (module docstring).

    How: in closed form on the outlines' vertices and edges, every step at once
    (:mod:`transplanter.contact`), no root finding and no whole-outline Booleans:

    - **first contact** either way of the design angle: the nearest turn of the driven gear at
      which a vertex of one gear meets an edge of the other — exact for the polygons (the root
      search it replaced stopped at 1e-8 mm; ``tests/reference_meshing.py`` keeps it), within
      about a tooth of free play; only vertices within the other gear's radius band take part;
    - **overlap**: the vertices in the sectors where the gears reach each other are tested
      against the other gear (radius bounds, then prepared point-in-polygon); only where some
      lie inside is the overlap intersected, on both outlines clipped to their bounds;
    - **clearance**: the vertices of each gear that may lie within ``CLEARANCE_CAP_MM`` of the
      other (radius bounds per angular bin), measured against the other's edges (STRtree);
    - **contacts**: with the driving flanks closed up, the runs of the driven boundary within
      ``contact_tol`` of the driver (point–segment distances).
    """
    if not isinstance(steps, int) or steps < 4:
        raise SpecError.out_of_range("steps", steps, "an integer >= 4")
    drv = contact.Outline(_polygon("driver_polygon", driver_polygon))
    drn = contact.Outline(_polygon("driven_polygon", driven_polygon))
    steps = _coprime(steps, teeth)
    half = math.inf if window is None else window * module
    mesh = _Mesh(pair, drv, drn, module, 2 * math.pi * np.arange(steps) / steps, half, contact_tol)
    mesh.all()
    arc = mesh.te * mesh.r2
    offset = float(arc.mean())
    refined = _refine(mesh) if refine else None
    return MeshReport(
        mesh.phi1,
        mesh.pen,
        arc - offset,
        mesh.bl,
        mesh.nc,
        mesh.foul,
        mesh.dist,
        mesh.side,
        mesh.te,
        offset,
        clearance=mesh.clear,
        refined=refined[:3] if refined else None,
        clearance_points=refined[3] if refined else mesh.clear_points[int(np.argmin(mesh.clear))],
    )


def _extremes(f: np.ndarray) -> np.ndarray:
    """Indices (into the sorted cyclic samples ``f``) of the local minima of ``f`` that the samples
    around them could hide a lower value beside: every local minimum whose drop to a
    neighbour reaches below the lowest sample (a jump, or the global minimum itself)."""
    left, right = np.roll(f, 1), np.roll(f, -1)
    local = (f <= left) & (f <= right)
    reach = f - np.maximum(left - f, right - f)
    return np.flatnonzero(local & (reach <= f.min() + REFINE_MM))


#: tip passes are scanned on a grid of this many driver positions per turn (module docstring)
APPROACH_STEPS = 3600
#: the vertices within this many modules of a gear's tip radius are its tips for that scan
TIP_BAND_MODULES = 0.35
#: a tip pass counts as a dip when it stands out of its surroundings by this much, mm
DIP_PROMINENCE_MM = 2e-3


def _approaches(mesh: _Mesh) -> np.ndarray:
    """Driver angles (rad) where a tooth tip of either gear passes closest to the other gear's
    outline — the places where the free play and the clearance dip — found on a grid of
    ``APPROACH_STEPS`` positions from the tips alone (the few vertices near each tip radius,
    with the driven gear at its design angle plus the mean play centre): each minimum of that
    distance that stands out of its surroundings by ``DIP_PROMINENCE_MM`` (within
    ``CLEARANCE_CAP_MM``), where no uniform sample lies within a grid step. A heuristic that finds
    candidates, not a bound: what it finds is then measured exactly and refined.

    A tip passing a flank makes a dip 0.6–1° wide on the seed-004 pair (free play falling by
    85 µm); the uniform meshing grid (2°) saw two of its eight copies, this scan (0.1°) all."""
    drv, drn, c = mesh.drv, mesh.drn, mesh.centre
    band = TIP_BAND_MODULES * mesh.module
    tips = []
    for outline, ring in ((drv, mesh.pair.ring == "driver"), (drn, mesh.pair.ring == "driven")):
        r = np.hypot(outline.xy[:, 0], outline.xy[:, 1])
        tips.append(np.flatnonzero(r <= outline.r_min + band) if ring else np.flatnonzero(r >= outline.r_max - band))
    phi = 2 * math.pi * np.arange(APPROACH_STEPS) / APPROACH_STEPS
    grid = _Mesh.like(mesh, phi)
    centre = float(np.mean(mesh.te + 0.5 * mesh.bl / mesh.r2))  # the mean play centre, rad
    psi1, psi2 = grid.psi1, grid.psi2 + mesh.turn * centre
    edges1, edges2 = mesh.index[:2]
    near = np.full(APPROACH_STEPS, np.inf)
    for start in range(0, APPROACH_STEPS, 4 * MESH_CHUNK):
        k = np.arange(start, min(APPROACH_STEPS, start + 4 * MESH_CHUNK))
        # driver tips in the driven frame, driven tips in the driver frame
        s1 = np.repeat(np.arange(len(k)), len(tips[0]))
        b1 = contact.rotate(drv.placed(np.tile(tips[0], len(k)), psi1[k], -c, s1), -psi2[k], s1)
        keep = drn.near(b1, mesh.pair.ring == "driven", CLEARANCE_CAP_MM)
        d1, _ = edges2.nearest(b1[keep], s1[keep], len(k))
        s2 = np.repeat(np.arange(len(k)), len(tips[1]))
        b2 = contact.rotate(drn.placed(np.tile(tips[1], len(k)), psi2[k], c, s2), -psi1[k], s2)
        keep = drv.near(b2, mesh.pair.ring == "driver", CLEARANCE_CAP_MM)
        d2, _ = edges1.nearest(b2[keep], s2[keep], len(k))
        near[k] = np.minimum(d1, d2)
    # a pass is a dip where the tips come closer than around it: a minimum standing out of its
    # surroundings by more than DIP_PROMINENCE_MM (the flank-gap plateau between passes has
    # minima of round-off depth); the grid is extended by a turn each way, so none wraps
    n = APPROACH_STEPS
    peaks, _ = find_peaks(-np.tile(np.minimum(near, CLEARANCE_CAP_MM), 3), prominence=DIP_PROMINENCE_MM)
    mine = (peaks >= n) & (peaks < 2 * n)
    peaks = peaks[mine] - n
    dips = np.unique(peaks)
    found = phi[dips]
    step = 2 * math.pi / APPROACH_STEPS
    gap = np.abs(contact.wrap(found[:, None] - mesh.phi1[None, :])).min(axis=1) if len(found) else found
    return found[gap > step]


def _refine(mesh: _Mesh):
    """Sample every close tip pass (:func:`_approaches`), then bisect the intervals beside every
    extreme of the free play (both ways) and the clearance (its minimum) until narrower than
    REFINE_RAD or resolved to REFINE_MM; returns the added samples (angle, backlash, clearance)
    and the nearest points at the smallest clearance."""
    columns = [(mesh.phi1, mesh.bl, mesh.clear, mesh.clear_points)]  # uniform, then each batch added

    def sample(phi):
        more = _Mesh.like(mesh, phi)
        more.all()
        columns.append((more.phi1, more.bl, more.clear, more.clear_points))

    seen = _approaches(mesh)
    if len(seen):
        sample(seen)
    for _ in range(REFINE_ROUNDS):
        phi, bl, cl = (np.concatenate([c[k] for c in columns]) for k in range(3))
        order = np.argsort(phi)
        p, b, c = phi[order], bl[order], cl[order]
        gap = np.diff(p, append=p[0] + 2 * math.pi)  # interval after each sample
        new = []
        for f in (b, -b, c):
            for i in _extremes(f):
                for j in ((i - 1) % len(p), i):  # the intervals before and after sample i
                    if gap[j] > REFINE_RAD and abs(f[(j + 1) % len(p)] - f[j]) > REFINE_MM:
                        new.append(p[j] + 0.5 * gap[j])
        if not new:
            break
        sample(np.unique(np.mod(new, 2 * math.pi)))
    phi, bl, cl, pts = (np.concatenate([c[k] for c in columns]) for k in range(4))
    n0 = len(mesh.phi1)
    return phi[n0:], bl[n0:], cl[n0:], pts[int(np.argmin(cl))]


class _Mesh:
    """The arrays of one :func:`mesh_check` and the stages that fill them, a chunk of steps at a time."""

    def __init__(self, pair, drv, drn, module, phi1, half, tol, sectors=None):
        self.pair, self.drv, self.drn, self.module, self.half, self.tol = pair, drv, drn, module, half, tol
        self.external = pair.ring is None
        self.centre = -pair.centre_distance if pair.ring == "driven" else pair.centre_distance
        self.turn = 1.0 if self.external else -1.0  # the driven gear's sense for a positive δ
        self.phi1 = np.asarray(phi1, dtype=float)
        steps = len(self.phi1)
        self.r1 = pair.driver.r(self.phi1)
        theta2 = pair.driven_rotation(self.phi1)
        self.r2 = np.abs(self.r1 - self.centre)
        self.psi1 = -self.phi1
        self.psi2 = (math.pi + theta2) if self.external else -theta2
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
    def like(cls, mesh: _Mesh, phi1) -> _Mesh:
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

    def all(self) -> None:
        """Fill every array, a chunk of steps at a time."""
        steps = len(self.phi1)
        for start in range(0, steps, MESH_CHUNK):
            ks = np.arange(start, min(steps, start + MESH_CHUNK))
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
