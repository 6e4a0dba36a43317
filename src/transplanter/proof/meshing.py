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
  outline meets an edge of the other (``transplanter.geometry.contact``; exact for the polygons, every
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

**Between the samples** (``refine=True``): every close pass of a tooth tip is found and
measured, then every local extreme of free play and clearance is bisected to ``REFINE_RAD`` /
``REFINE_MM`` (:mod:`transplanter.proof.mesh_refine`, where the method and what it still assumes are
written down); an extreme's figure is the extreme over the uniform and the refined samples.

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

>>> from transplanter.geometry.cutter import ShaperCutter
>>> from transplanter.geometry.pitch import GearPair, PitchCurve
>>> from transplanter.geometry.pair_gate import generate_pair
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

from transplanter.core.errors import GeometryError, SpecError
from transplanter.core.precision import significant
from transplanter.core.tolerances import AREA_ROUND_OFF_MM2, CONTACT_TOL_MM, PENETRATION_TOL
from transplanter.geometry import contact
from transplanter.proof.mesh_engine import CLEARANCE_CAP_MM, FOULING_PITCHES, MeshingPair, MeshSweep
from transplanter.proof.mesh_refine import refine as refine_extremes

__all__ = ["FOULING_PITCHES", "CLEARANCE_CAP_MM", "Extreme", "MeshReport", "MeshingPair", "mesh_check"]


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
        if values is None:
            raise GeometryError("this meshing report has no clearance: the check ran without it")
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


def mesh_check(
    pair: MeshingPair,
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
    (:mod:`transplanter.geometry.contact`), no root finding and no whole-outline Booleans:

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
    mesh = MeshSweep(pair, drv, drn, module, 2 * math.pi * np.arange(steps) / steps, half, contact_tol)
    mesh.all()
    arc = mesh.te * mesh.r2
    offset = float(arc.mean())
    refined = refine_extremes(mesh) if refine else None
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
