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
  teeth first touch the driver's (root finding on the signed gap — distance, or minus the
  overlap area^(2/3), ∝ depth — with scipy ``brentq`` to 1e-8 mm, in the window); that angle as arc length at the
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
See ``tests/test_validate.py``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy import optimize

from transplanter import cams
from transplanter.errors import GeometryError, SpecError
from transplanter.export import significant

__all__ = [
    "MeshReport",
    "mesh_check",
    "TrainReport",
    "train_check",
    "FollowerReport",
    "follower_check",
    "turned_by",
]

#: overlap area (mm²) that counts as interference: the outlines are exact to 0.25 µm chords,
#: so a zero-backlash pair overlaps by ~1e-4 mm² over a few teeth; real interference of a
#: module-0.4 tooth tip 10 µm deep is already ~3e-3 mm²
PENETRATION_TOL = 1e-3
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
            "max_penetration_mm2": significant(self.max_penetration) if self.max_penetration > 1e-12 else 0.0,
            "max_fouling_mm2": significant(self.max_fouling) if self.max_fouling > 1e-12 else 0.0,
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


def _place(poly, angle, shift):
    return shapely.affinity.translate(shapely.affinity.rotate(poly, angle, origin=(0, 0), use_radians=True), *shift)


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


def mesh_check(
    pair,
    driver_polygon,
    driven_polygon,
    module: float,
    steps: int = 120,
    window: float = 3.0,
    contact_tol: float = 2e-3,
    teeth: int | None = None,
) -> MeshReport:
    """Mesh ``driver_polygon`` and ``driven_polygon`` (body frames) per ``pair``'s design ratio.

    ``window`` (modules) is the half-size of the square around the pitch point where the
    contact is searched (the path of contact reaches ~2.5 modules either side);
    ``contact_tol`` (mm) the gap that counts as contact; ``teeth`` the driver's tooth count
    (``steps`` is raised until coprime with it).
    """
    if not isinstance(steps, int) or steps < 4:
        raise SpecError.out_of_range("steps", steps, "an integer >= 4")
    driver_polygon = _polygon("driver_polygon", driver_polygon)
    driven_polygon = _polygon("driven_polygon", driven_polygon)
    steps = _coprime(steps, teeth)
    a = pair.centre_distance
    external = pair.ring is None
    ring_drives = pair.ring == "driver"
    centre = -a if pair.ring == "driven" else a  # a driven ring's centre is beyond the planet's
    half = window * module
    phi1 = 2 * math.pi * np.arange(steps) / steps
    r1 = pair.driver.r(phi1)
    theta2 = pair.driven_rotation(phi1)
    r2 = np.abs(r1 - centre)
    pen, foul, dist, te, bl, nc = (np.zeros(steps) for _ in range(6))
    side = np.zeros(steps, dtype=np.int8)
    for k in range(steps):
        px = float(r1[k])
        box = shapely.box(px - half, -half, px + half, half)
        drv_full = _place(driver_polygon, -phi1[k], (0.0, 0.0))
        drv = shapely.intersection(drv_full, box)
        shapely.prepare(drv)

        ang0 = (math.pi + theta2[k]) if external else -theta2[k]
        whole = _place(driven_polygon, ang0, (centre, 0.0))
        span = 2 * module / max(float(r2[k]), module)  # about a tooth of free play
        # what can enter the window while the driven gear turns by up to ±span about (a, 0)
        reach = span * (abs(px - centre) + 2 * half) + module
        local = shapely.clip_by_rect(whole, px - half - reach, -half - reach, px + half + reach, half + reach)
        turn = 1.0 if external else -1.0

        def driven(delta, local=local, box=box, turn=turn):
            moved = shapely.affinity.rotate(local, turn * delta, origin=(centre, 0.0), use_radians=True)
            return shapely.intersection(moved, box)

        def gap(delta, drv=drv):
            # signed: the distance apart, or minus the overlap area^(2/3) — two curved flanks
            # pressed d into each other overlap by an area ∝ d^1.5, so this is ∝ d and keeps
            # brentq's interpolation useful, at a fraction of the cost of a penetration depth
            g = driven(delta)
            if not shapely.intersects(drv, g):
                return float(shapely.distance(drv, g))
            return -(max(shapely.intersection(drv, g).area, 1e-300) ** (2 / 3))

        # interference anywhere: the driver clipped to the driven gear's extent
        overlap = shapely.intersection(shapely.clip_by_rect(drv_full, *whole.bounds), whole)
        pieces = [g for g in getattr(overlap, "geoms", [overlap]) if g.area > 0]
        if pieces:
            pen[k] = overlap.area
            away = [
                g for g in pieces if math.hypot(g.centroid.x - px, g.centroid.y) > FOULING_PITCHES * math.pi * module
            ]
            foul[k] = sum(g.area for g in away)
            big = max(pieces, key=lambda g: g.area)
            cx, cy = big.centroid.x, big.centroid.y
            dist[k] = math.hypot(cx - px, cy)
            body = math.atan2(cy, cx) + phi1[k]  # polar angle in the driver body
            beyond = math.hypot(cx, cy) > float(pair.driver.r(body))
            side[k] = 1 if beyond != ring_drives else 2  # a gear's tips are beyond its pitch curve, a ring's inside
        found = []
        at_design = gap(0.0)
        rho = max(float(r2[k]), module)
        for sign in (-1.0, 1.0):  # first contact backwards (driving flanks) and forwards (coast)
            if at_design <= 0:  # already touching at the design angle
                found.append(0.0)
                continue
            # bracket from the design angle outwards: a step a little over the gap, then ×4
            lo, hi = 0.0, min(span, 1.5 * at_design / rho)
            g_hi = gap(sign * hi)
            while g_hi > 0 and hi < span:
                lo, hi = hi, min(span, 4 * hi)
                g_hi = gap(sign * hi)
            if g_hi > 0:
                found.append(sign * span)
            else:
                found.append(optimize.brentq(gap, sign * lo, sign * hi, xtol=1e-8 / rho))
        te[k] = found[0]
        bl[k] = (found[1] - found[0]) * float(r2[k])
        # tooth pairs in contact with the driving flanks closed up
        near = shapely.intersection(drv.buffer(contact_tol, quad_segs=2), driven(found[0]))
        nc[k] = len(getattr(near, "geoms", [near])) if not near.is_empty else 0
    arc = te * r2
    offset = float(arc.mean())
    return MeshReport(phi1, pen, arc - offset, bl, nc, foul, dist, side, te, offset)


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


def follower_check(contour, motion, follower, n: int = 720) -> FollowerReport:
    """Press ``follower`` onto the made cam ``contour`` (shapely polygon, cam frame) at ``n``
    cam angles and compare its position with ``motion`` (the law the cam was designed for).

    Roller followers: the follower coordinate s at which the roller just touches the contour
    (signed roller-centre distance minus roller radius = 0, ``brentq`` within ±10 % of the
    stroke plus 1 mm of the law). Flat-faced: the contour's support height minus the base
    radius. The cam turns counter-clockwise by θ (``cams`` conventions).
    """
    contour = _polygon("contour", contour)
    if not isinstance(n, int) or n < 8:
        raise SpecError.out_of_range("n", n, "an integer >= 8")
    theta = 2 * math.pi * np.arange(n) / n
    law = np.asarray(motion(theta), dtype=float)
    boundary = contour.exterior
    shapely.prepare(boundary)
    if isinstance(follower, cams.FlatFacedFollower):
        pts = shapely.get_coordinates(boundary)
        # support height along the follower's +y, which is (sin θ, cos θ) in the cam frame
        actual = np.max(pts @ np.stack([np.sin(theta), np.cos(theta)]), axis=0) - follower.base_radius
        return FollowerReport(theta, law, actual, actual - law)
    if not isinstance(follower, cams.OscillatingRollerFollower | cams.TranslatingRollerFollower):
        raise SpecError(f"unknown follower type {type(follower).__name__}")
    rr = follower.roller_radius
    actual = np.empty(n)
    span = 0.1 * float(np.ptp(law)) + (1.0 / follower.arm_length if hasattr(follower, "arm_length") else 1.0)

    def gap(s, t):
        x, y = cams.roller_centre(follower, s, t)[0]
        d = float(shapely.distance(boundary, shapely.Point(x, y)))
        return (d if not shapely.contains_xy(contour, x, y) else -d) - rr

    for k, t in enumerate(theta):
        lo, hi = law[k] - span, law[k] + span
        if gap(lo, t) > 0 or gap(hi, t) < 0:
            raise GeometryError(
                f"the follower does not reach the cam contour near θ = {math.degrees(t):.1f} deg within ±{span:.3g} "
                "of the law — the contour is not this cam's"
            )
        actual[k] = optimize.brentq(gap, lo, hi, args=(t,), xtol=1e-12)
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
