"""The meshing check as it was before the vectorised one (transplanter <= 0.13): the reference.

``validate.mesh_check`` now finds first contact in closed form (vertex-edge angular clearance,
all pairs at once) and computes overlap only where vertices lie inside the other gear. This is
the implementation it replaced, kept verbatim: polygons rotated and intersected at every
evaluation, ``brentq`` on the signed gap (distance, or minus overlap area^(2/3)) to 1e-8 mm.
``tests/test_validate.py`` compares the two; ``benchmarks/meshing.py`` times them.
"""

import math

import numpy as np
import shapely
from scipy import optimize

from transplanter.core.errors import SpecError
from transplanter.proof.meshing import FOULING_PITCHES, MeshReport, _coprime, _polygon


def _place(poly, angle, shift):
    return shapely.affinity.translate(shapely.affinity.rotate(poly, angle, origin=(0, 0), use_radians=True), *shift)


def mesh_check_reference(
    pair,
    driver_polygon,
    driven_polygon,
    module: float,
    steps: int = 120,
    window: float = 3.0,
    contact_tol: float = 2e-3,
    teeth: int | None = None,
) -> MeshReport:
    """``validate.mesh_check`` as it was: the same arguments, the same report."""
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
