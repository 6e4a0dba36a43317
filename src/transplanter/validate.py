"""Kinematic validation of generated gear profiles: do the parts themselves mesh?

The driver is turned through a full turn in ``steps`` positions; the driven gear is placed
where the *design* ratio puts it (``GearPair.driven_rotation``); and the actual tooth
outlines are compared near the pitch point (a window of a few modules, so each step costs a
few small polygon operations):

- **penetration**: overlap area of the two outlines (mm²) — must stay below a tolerance;
- **transmission error**: the driven gear is turned back from its design angle until its
  teeth first touch the driver's (root finding on the signed gap — distance, or minus the
  penetration depth — with scipy ``brentq``); that angle as arc length at the pitch point (mm)
  minus its cycle mean (the constant share of the backlash) is the geometric transmission
  error, reported as max and rms;
- **backlash**: the same search forwards; backlash is the arc between the two contacts;
- **contact**: with the driving flanks closed up, the number of separate places where the
  outlines are within ``contact_tol`` — never zero for a working pair; its mean over the
  cycle is the geometric contact ratio (both flanks count when there is no backlash).

Placement follows the ``pitch.pair`` conventions: the driver turns clockwise about the
origin, the driven centre is at (a, 0); an external driven gear's body frame is turned by π
at the start and turns counter-clockwise; an internal one turns clockwise with the driver.

Examples
--------
See ``tests/test_validate.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy import optimize

from transplanter.errors import SpecError

__all__ = ["MeshReport", "mesh_check"]


@dataclass(frozen=True)
class MeshReport:
    """Meshing figures over a cycle (arrays per step, summaries as properties)."""

    driver_angle: np.ndarray = field(repr=False)
    penetration: np.ndarray = field(repr=False)
    transmission_error: np.ndarray = field(repr=False)
    backlash: np.ndarray = field(repr=False)
    contacts: np.ndarray = field(repr=False)
    #: mean driving-flank contact offset (mm at the driven pitch point): half the backlash
    #: for symmetric tooth thinning; the transmission error is measured from it
    offset: float = 0.0

    @property
    def max_penetration(self) -> float:
        return float(self.penetration.max())

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

    def problems(self, max_penetration: float = 1e-3, backlash: tuple[float, float] | None = None) -> list[str]:
        """What a designer must fix, in words (empty when the pair meshes).

        ``max_penetration`` is the overlap-area tolerance (mm²); ``backlash`` the design band
        (mm at the driven pitch point).
        """
        out = []
        deg = np.degrees(self.driver_angle)
        k = int(np.argmax(self.penetration))
        if self.penetration[k] > max_penetration:
            out.append(
                f"the teeth interfere: {self.penetration[k]:.3g} mm² of overlap at driver angle {deg[k]:.1f} deg "
                f"(limit {max_penetration:g} mm²) — the centre distance, the tooth counts or the cutter do not "
                "match the pitch curves"
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
                    f"{lo:g}..{hi:g} mm (at driver angles {deg[k]:.1f} and {deg[j]:.1f} deg)"
                )
        return out


def _depth(p, q) -> float:
    """Penetration depth of two overlapping polygons: the deepest vertex of either inside the other."""
    worst = 0.0
    for inner, outer in ((q, p), (p, q)):
        for ring in getattr(inner, "geoms", [inner]):
            if ring.is_empty:
                continue
            pts = shapely.get_coordinates(ring.boundary)
            inside = shapely.contains_xy(outer, pts[:, 0], pts[:, 1])
            if inside.any():
                worst = max(worst, float(shapely.distance(outer.boundary, shapely.points(pts[inside])).max()))
    return worst


def _place(poly, angle, shift):
    return shapely.affinity.translate(shapely.affinity.rotate(poly, angle, origin=(0, 0), use_radians=True), *shift)


def mesh_check(
    pair,
    driver_polygon,
    driven_polygon,
    module: float,
    steps: int = 120,
    window: float = 4.0,
    contact_tol: float = 2e-3,
) -> MeshReport:
    """Mesh ``driver_polygon`` and ``driven_polygon`` (body frames) per ``pair``'s design ratio.

    ``window`` (modules) is the half-size of the square around the pitch point that is
    examined; ``contact_tol`` (mm) the gap that counts as contact.
    """
    if not isinstance(steps, int) or steps < 4:
        raise SpecError.out_of_range("steps", steps, "an integer >= 4")
    a = pair.centre_distance
    external = pair.mesh.value == "external"
    half = window * module
    phi1 = 2 * math.pi * np.arange(steps) / steps
    r1 = pair.driver.r(phi1)
    theta2 = pair.driven_rotation(phi1)
    r2 = np.where(external, a - r1, r1 - a)
    pen, te, bl, nc = (np.zeros(steps) for _ in range(4))
    for k in range(steps):
        px = float(r1[k])
        box = shapely.box(px - half, -half, px + half, half)
        drv = shapely.intersection(_place(driver_polygon, -phi1[k], (0.0, 0.0)), box)
        shapely.prepare(drv)

        def driven(delta, k=k, box=box):
            ang = (math.pi + theta2[k] + delta) if external else (-theta2[k] - delta)
            return shapely.intersection(_place(driven_polygon, ang, (a, 0.0)), box)

        def gap(delta, drv=drv):
            g = driven(delta)
            if not shapely.intersects(drv, g):
                return float(shapely.distance(drv, g))
            return -_depth(drv, g)

        pen[k] = shapely.intersection(drv, driven(0.0)).area
        span = 2 * module / max(float(r2[k]), module)  # about a tooth of free play
        found = []
        for sign in (-1.0, 1.0):  # first contact backwards (driving flanks) and forwards (coast)
            if gap(0.0) <= 0:  # already touching at the design angle
                found.append(0.0)
            elif gap(sign * span) > 0:
                found.append(sign * span)
            else:
                found.append(optimize.brentq(gap, 0.0, sign * span, xtol=1e-12))
        te[k] = found[0] * float(r2[k])
        bl[k] = (found[1] - found[0]) * float(r2[k])
        # tooth pairs in contact with the driving flanks closed up
        near = shapely.intersection(drv.buffer(contact_tol, quad_segs=2), driven(found[0]))
        nc[k] = len(getattr(near, "geoms", [near])) if not near.is_empty else 0
    offset = float(te.mean())
    te = te - offset
    return MeshReport(phi1, pen, te, bl, nc, offset)
