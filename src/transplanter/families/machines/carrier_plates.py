"""The plates of seed 002's structure (:mod:`~transplanter.families.machines.carrier_structure`) as a
designer draws them: the **frame** that holds the fixed shaft and the cam's posts, carrier 1's
**hub** keyed on the drive tube, the **front plates** of both carriers, and the bores, bosses and
screw holes the structure adds to carrier 1, carrier 2 and sector 8 — each as ``(section, holes,
features, notes)`` for :func:`~transplanter.families.builder.making.manufacture`.

A plate is the convex hull of round bosses (:func:`transplanter.machine.carrier_parts.plate`): one
``BEARING_WALL_MM`` round every bearing bore, one ``SCREW_BOSS_MM`` round every screw hole.
"""

from __future__ import annotations

import math

from transplanter.families.machines.carrier_structure import bores, post_positions, sector_bolts
from transplanter.machine import carrier_parts
from transplanter.shop import solids
from transplanter.shop.catalogue import circlip_for_shaft, fit

__all__ = ["BEARING_WALL_MM", "SCREW_BOSS_MM", "FRAME_TOP_MM", "structure_plates"]

#: the wall a plate keeps round a bearing's outer ring, and a boss round a screw hole (radius), mm
BEARING_WALL_MM, SCREW_BOSS_MM = 6.0, 8.0
#: the frame reaches this far above the carrier axis, where it is bolted to the transplanter, mm
FRAME_TOP_MM = 160.0


def _at(radius: float, angles_deg) -> list[tuple[float, float]]:
    return [(radius * math.cos(math.radians(a)), radius * math.sin(math.radians(a))) for a in angles_deg]


def _bearing_notes(holes) -> str:
    return "; ".join(f"Ø{d:g} {fit(d, 'H7').text.split(' ', 1)[1]} at ({x:.3f}, {y:.3f})" for x, y, d in holes)


def structure_plates(study, machine, hw, bolt_circle: float, sector8_turn: float) -> dict[str, tuple]:
    """Carrier 1, carrier 2 and sector 8 with the structure's bores and holes, and the plates the
    structure adds (module docstring): ``{part: (section, holes, features, notes)}``; ``hw`` the
    laid-out :class:`~transplanter.families.machines.carrier_structure.Hardware`, sector 8's screws on
    ``bolt_circle`` about A_c, its DXF frame ``sector8_turn`` rad from carrier 2's."""
    S = study.structure
    l1, l2, _ = study.chain.link_lengths
    seats = bores(hw)
    post, hub_screw, standoff, sector = (S.screws[w] for w in ("posts", "hub", "standoffs", "sector"))
    hub_bolts = _at(*S.hub_bolts)
    out = {}

    def bosses(holes):
        return [(x, y, d / 2 + BEARING_WALL_MM) for x, y, d in holes]

    def screws(points, dia):
        return [(x, y, dia) for x, y in points], [(x, y, SCREW_BOSS_MM) for x, y in points]

    # carrier 1: its bearings, a clearance bore round the fixed shaft, the hub's and standoffs' screws
    c1_b = seats["carrier_1"]
    hub_h, hub_bo = screws(hub_bolts, hub_screw[1])
    st_h, st_bo = screws(S.standoffs_1, standoff[1])
    # round the fixed shaft and the retaining ring beside carrier 1 (in front of it, holding the sun)
    ring = circlip_for_shaft(S.main_shaft)
    clear = max(S.main_shaft + 2 * study.clearance, ring.groove_diameter + 2 * ring.lug + 2 * S.hardware_clearance)
    clear = float(math.ceil(clear))
    c1_holes = ((0.0, 0.0, clear), *c1_b, *hub_h, *st_h)
    c1 = carrier_parts.plate([(0.0, 0.0, clear / 2 + BEARING_WALL_MM), *bosses(c1_b), *hub_bo, *st_bo])
    out["carrier_1"] = (
        c1,
        c1_holes,
        solids.Features(holes=c1_holes),
        (
            "first planetary carrier (link 1): turns clockwise about A0 (its origin), driven by its hub; +x to A_c "
            f"({l1:.4f}, 0)",
            f"bearing bores: {_bearing_notes(c1_b)}; a Ø{clear:g} clearance bore round the fixed shaft at A0",
            f"{len(hub_h)} x {hub_screw[0]} clearance Ø{hub_screw[1]:g} for the hub's screws (from the front); "
            f"{len(st_h)} x {standoff[0]} clearance Ø{standoff[1]:g} for the standoffs' screws (from the back)",
        ),
    )
    cov_b = seats["carrier_1_front"]
    st_t, _ = screws(S.standoffs_1, standoff[2])
    out["carrier_1_front"] = (
        carrier_parts.plate([*bosses(cov_b), *st_bo]),
        (*cov_b, *st_t),
        solids.Features(holes=(*cov_b, *st_t)),
        (
            "carrier 1's front plate: holds the shafts of gears 3-4, gears 5-9 and the follower at their front "
            "ends, and the fixed shaft's; on carrier 1's frame (origin A0)",
            f"bearing bores: {_bearing_notes(cov_b)}",
            f"{len(st_t)} x {standoff[0]} tapped for the standoffs' screws (op 20)",
            "timing: +x to A_c as carrier 1's; the standoffs' screws set it on carrier 1",
        ),
    )
    hub_t = tuple((x, y, hub_screw[2]) for x, y in hub_bolts)
    hub_r = S.hub_bolts[0] + SCREW_BOSS_MM
    out["hub"] = (
        solids.circle_polygon(0.0, 0.0, hub_r),
        hub_t,
        solids.Features(bore=S.tube, holes=hub_t),
        (
            f"carrier 1's hub: keyed on the drive tube (Ø{S.tube:g} H7, DIN 6885 hub keyway at +y) and screwed to "
            f"carrier 1 ({len(hub_t)} x {hub_screw[0]} tapped, op 20): carrier 1's input, "
            f"{S.speed_rpm:g} r/min",
            "timing: its keyway at +y on the drive tube's key; its screw holes follow carrier 1's",
        ),
    )
    # carrier 2: its bearings, the standoffs' screws and sector 8's
    c2_b = seats["carrier_2"]
    st2_h, st2_bo = screws(S.standoffs_2, standoff[1])
    sec_h, _ = screws(sector_bolts(bolt_circle), sector[1])
    c2_holes = (*c2_b, *st2_h, *sec_h)
    c2 = carrier_parts.plate([(0.0, 0.0, 20.0), *bosses(c2_b), *st2_bo])
    out["carrier_2"] = (
        c2,
        c2_holes,
        solids.Features(holes=c2_holes),
        (
            "second planetary carrier (link 2): turns about A_c (its origin) on gear 5-9's shaft; "
            f"+x to Q ({l2:.4f}, 0)",
            f"bearing bores: {_bearing_notes(c2_b)}",
            f"{len(st2_h)} x {standoff[0]} clearance Ø{standoff[1]:g} for the standoffs' screws (from the back); "
            f"{len(sec_h)} x {sector[0]} clearance Ø{sector[1]:g} for sector 8's screws (from the front)",
        ),
    )
    fr_b = seats["carrier_2_front"]
    st2_t, _ = screws(S.standoffs_2, standoff[2])
    out["carrier_2_front"] = (
        carrier_parts.plate([*bosses(fr_b), *st2_bo]),
        (*fr_b, *st2_t),
        solids.Features(holes=(*fr_b, *st2_t)),
        (
            "carrier 2's front plate: holds the shafts of the idler 10 and of gear 11 with the arm at their front "
            "ends; on carrier 2's frame (origin A_c)",
            f"bearing bores: {_bearing_notes(fr_b)}",
            f"{len(st2_t)} x {standoff[0]} tapped for the standoffs' screws (op 20)",
            "timing: +x to Q as carrier 2's; the standoffs' screws set it on carrier 2",
        ),
    )
    # after the wire (Making.operations): the tapped holes, cut at their tap drill
    out["operations"] = {
        "carrier_1_front": (f"tap the {len(st_t)} standoff holes {standoff[0]} through",),
        "carrier_2_front": (f"tap the {len(st2_t)} standoff holes {standoff[0]} through",),
        "hub": (f"tap the {len(hub_t)} holes {hub_screw[0]} through",),
    }
    c, s = math.cos(sector8_turn), math.sin(sector8_turn)
    out["sector_8_holes"] = (
        *seats["sector_8"],
        *((c * x - s * y, s * x + c * y, sector[2]) for x, y in sector_bolts(bolt_circle)),
    )
    # the frame: a plate round A0 up to where the transplanter holds it; the fixed shaft keyed in it
    posts = post_positions(study, machine)
    reach = S.posts[0] + 2 * SCREW_BOSS_MM
    corner = 20.0
    top = [(s * (reach - 2 * corner), FRAME_TOP_MM - corner, corner) for s in (-1.0, 1.0)]
    frame = carrier_parts.plate([(0.0, 0.0, reach), *top])
    mounts = tuple((x, y, 13.0) for x, y, _ in top)
    fr_holes = (*((x, y, post[1]) for x, y in posts), *mounts)
    out["frame"] = (
        frame.normalize(),
        fr_holes,
        solids.Features(bore=S.main_shaft, holes=fr_holes),
        (
            f"frame: holds the fixed shaft (Ø{S.main_shaft:g} H7, DIN 6885 keyway at +y; retaining rings both "
            f"sides) and the cam on {len(posts)} posts ({post[0]} clearance Ø{post[1]:g}); drawn in the machine "
            "frame (A0 at the origin, y up)",
            f"bolted to the transplanter's frame by 2 x M12 (Ø13) at y {FRAME_TOP_MM - corner:g}; the input chain "
            "leaves between two posts",
            "timing: its +y up (the soil below); the shaft's keyway at +y holds the fixed shaft, and the cam with it",
        ),
    )
    return out
