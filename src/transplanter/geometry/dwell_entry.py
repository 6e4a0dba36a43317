"""The entry of an incomplete pair: where each motion's first tooth meets the driven at rest.

The driven is held at its dwell angle while the driver turns on; the first driver angle at which
the driver touches it (bisection), and where on each gear, below its tip, that contact lies
(:func:`entry_contacts`, on the cut outlines or on the sections re-read). A contact within
``TIP_BAND`` modules of both tips is tip on tip, which the proof
(:mod:`transplanter.families.pairs.incomplete_pair`) refuses.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely import affinity, ops

from transplanter.geometry.incomplete import IncompleteGears
from transplanter.geometry.pitch import driven_axis, driven_turn

__all__ = ["TIP_BAND", "entry_contacts"]

#: an entry contact within this many modules of both gears' tips is tip-on-tip
TIP_BAND = 0.1


def entry_contacts(gears: IncompleteGears, driver: shapely.Polygon, driven: shapely.Polygon) -> list[dict]:
    """Where each motion's first tooth contact is: the driven held at its dwell angle while the
    driver turns on, the first driver angle (bisection to 1e-6 deg) at which the driver's teeth
    (not its locking arc) touch it, and the contact's radius on each gear below its tip."""
    pair, m = gears.pair, gears.driver.module
    centre = driven_axis(pair)
    out = []
    motions = pair.law.motions
    sectors = gears.driver.sectors_deg
    reach = float(np.linalg.norm(shapely.get_coordinates(driver), axis=1).max())
    segs = pair.law.segments
    for dwell, lock in zip(pair.law.dwells, gears.locks, strict=True):
        turn2 = float(driven_turn(pair, np.radians([dwell.start + 1e-9]))[0])
        held = affinity.translate(affinity.rotate(driven, turn2, origin=(0, 0), use_radians=True), centre, 0.0)
        # only the driven within the driver's reach can touch it (the same first contact, far fewer vertices)
        within = shapely.intersection(held, shapely.Point(0.0, 0.0).buffer(reach + 2 * m))
        held = held if within.is_empty else within
        shapely.prepare(held)  # touching or not is all the bisection asks: an indexed test
        after = motions.index(segs[(segs.index(dwell) + 1) % len(segs)])
        first_space = math.radians(sectors[after][0])

        def apart(phi: float, held=held) -> bool:  # whatever of the driver touches it: arc, relieved tooth, tooth
            return not shapely.intersects(held, affinity.rotate(driver, -phi, origin=(0, 0), use_radians=True))

        lo, hi = math.radians(dwell.start) + 1e-6, math.radians(dwell.end) + math.radians(30.0)
        if apart(hi):
            out.append({"dwell_deg": [dwell.start, dwell.end], "entry": "no tooth reaches the held driven gear"})
            continue
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if apart(mid) else (lo, mid)
        posed = affinity.rotate(driver, -hi, origin=(0, 0), use_radians=True)
        p1, p2 = ops.nearest_points(posed, held)
        r1 = math.hypot(p1.x, p1.y)
        r2 = math.hypot(p2.x - centre, p2.y)
        near = shapely.Point(p1.x, p1.y).buffer(2.5 * m)  # the teeth around the contact
        tip1 = float(np.linalg.norm(shapely.get_coordinates(shapely.intersection(posed, near)), axis=1).max())
        local = shapely.get_coordinates(shapely.intersection(held, near)) - (centre, 0.0)
        d2 = np.linalg.norm(local, axis=1)
        tip2 = float(d2.max()) if pair.mesh == "external" else float(d2.min())
        below1, below2 = (tip1 - r1) / m, abs(tip2 - r2) / m
        body = (math.atan2(p1.y, p1.x) + hi - first_space + math.pi) % (2 * math.pi) - math.pi
        out.append(
            {
                "dwell_deg": [dwell.start, dwell.end],
                "touching": "the locking arc" if body < 0 and abs(r1 - lock.radius) < 1e-3 else "a tooth of the sector",
                "first_contact_driver_deg": round(math.degrees(hi) % 360, 4),
                "after_dwell_end_deg": round(math.degrees(hi) - dwell.end, 4),
                "driver_radius_below_tip_m": round(below1, 4),
                "driven_radius_from_tip_m": round(below2, 4),
                "tip_on_tip": bool(below1 < TIP_BAND and below2 < TIP_BAND),
            }
        )
    return out
