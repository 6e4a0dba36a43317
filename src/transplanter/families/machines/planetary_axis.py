"""Seed 004's main axis as a shop assembles it (:mod:`planetary_structure` states the design): the
carrier plates tied by spacer tubes, the carrier shaft, the ring's spacer, flange and hollow shaft,
the wrapped bushes and thrust washers between the two shafts, the frame and both drives.
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.errors import SpecError
from transplanter.design.objectives import GEARBOX_CLEARANCE_MM
from transplanter.families.machines.planetary_structure import (
    CLEARANCE_HOLE,
    MIN_WALL,
    MIN_WEB,
    TAP_DRILL,
    Collected,
    Placed,
    _hub_key,
    _quantity,
    _ring_holes,
    _screw,
    _sleeve_od,
)
from transplanter.machine.bodies import Link
from transplanter.machine.hardware import Fitted, Turned, mounted
from transplanter.proof.clearance import reach
from transplanter.shop import formats
from transplanter.shop.catalogue import (
    bearing_for,
    bearings,
    bush_for,
    circlip_for_bore,
    circlip_for_shaft,
    fit,
    key_for,
    washer,
)

__all__ = ["main_axis"]


def main_axis(
    study, machine_links: dict[str, Link], files: dict[str, bytes], names: dict[str, str], out: Collected, dims: dict
) -> tuple[dict, frozenset, dict]:
    """The main axis into ``out`` (module docstring), from the planet shafts' ``dims`` and the ring's
    DXF among ``files``: the figures the plates and the record are drawn from, the hardware's body
    names and the rigid pairs judged anyway (the frame above the soil)."""
    s, L = study.structure, study.layers
    gap, run, name = L.min_axial_gap, s.running_clearance, study.name
    steel, plate_mat = s.shaft_material, s.plate_material
    a, n, load, bp, F, R, G, T = (dims[k] for k in ("a", "n", "load", "bp", "F", "R", "G", "T"))
    sp = dims["speeds"]
    carrier_rpm, ring_rpm, relative_rpm = sp["carrier"], sp["ring"], sp["relative"]
    links, turned, fitted, joint = out.links, out.turned, out.fitted, out.joint
    # -- the carrier: rear plate, tie tubes, carrier shaft ----------------------------------------
    d_c = s.carrier_shaft
    size = s.tie_screw
    tie = _screw(size, T + (F[0] - R[1]), T)
    tie_angles = [math.pi / n + 2 * math.pi * j / n for j in range(n)]
    tube = Turned(
        f"{name}.carrier_tube",
        s.tube_outer,
        F[0] - R[1],
        bore=CLEARANCE_HOLE[size],
        material=plate_mat,
        quantity=n,
        notes=("mates: between the carrier plates, on a tie screw", "timing: none (round)"),
    )
    tube_at = []
    for j, t in enumerate(tie_angles, 1):
        m = mounted(
            machine_links["carrier"], f"carrier@tie_{j}", s.tie_radius * math.cos(t), s.tie_radius * math.sin(t)
        )
        links[m.name] = m
        tube_at.append((f"carrier_tube_{j}", m.name, R[1]))
        fitted.append(Fitted(f"tie_screw_{j}", tie, m.name, R[0]))
    turned.append(Placed(tube, tuple(tube_at)))
    cc, tw = circlip_for_shaft(d_c), washer(f"M{d_c:g}")
    key_c = key_for(d_c, T)
    bush = bush_for(d_c, 2 * d_c, load, relative_rpm)
    # the hollow ring shaft: the smallest bearing bore keeping MIN_WALL under the flange key
    d_r = next(
        d
        for d in sorted({b.d for b in bearings()})
        if d > bush.bush.D and (d - bush.bush.D) / 2 - key_for(d, 1e6).t1 >= MIN_WALL
    )
    fc = circlip_for_shaft(d_r)
    front_end = R[0] - cc.s - tw.thickness  # the ring shaft's front end, on the thrust washer
    fl1 = front_end - fc.n_min - fc.groove_width  # the flange's front face, on its circlip
    key_f = _hub_key(d_r, 0.0)
    fl = (fl1 - key_f.length, fl1)
    if fl1 > R[0] - tie.head_height - gap:
        raise SpecError(f"the ring cavity is too shallow: the flange at {fl1:g} mm meets the tie screw heads")
    bq = bearing_for(d_r, ring_rpm, load, life_h=s.life_h)
    cbq, csq = circlip_for_bore(bq.D), circlip_for_shaft(d_r)
    Tf = bq.B + cbq.groove_width + cbq.n_min
    FF = (fl[0] - gap - Tf, fl[0] - gap)
    RF = (FF[0] - s.frame_gap - Tf, FF[0] - s.frame_gap)
    qf, qr = (FF[1] - bq.B, FF[1]), (RF[0], RF[0] + bq.B)
    hub_r = (qr[0] - csq.s - s.drive_hub, qr[0] - csq.s)
    key_rd = key_for(d_r, s.drive_hub - 2 * csq.groove_width)
    rear_end = hub_r[0] - csq.groove_width - csq.n_min
    flange_sleeve = (qf[1], fl[0])
    ring_shaft = Turned(
        f"{name}.ring_shaft",
        d_r,
        front_end - rear_end,
        bore=bush.bush.D,
        keyways=(
            (
                fl[0] + (fl[1] - fl[0] - key_f.length) / 2 - rear_end,
                key_f.length,
                key_f.b,
                key_f.t1,
                key_f.shaft_note(d_r),
            ),
            (
                hub_r[0] + (s.drive_hub - key_rd.length) / 2 - rear_end,
                key_rd.length,
                key_rd.b,
                key_rd.t1,
                key_rd.shaft_note(d_r) + ": the ring drive's hub",
            ),
        ),
        grooves=tuple(
            (z - rear_end, fc.groove_width, fc.groove_diameter, fc.groove_note)
            for z in (fl[1], qr[0] - csq.groove_width, hub_r[0] - csq.groove_width)
        ),
        fits=(
            *((z0 - rear_end, z1 - rear_end, f"{fit(d_r, 'k6').text}: {bq.designation} seat") for z0, z1 in (qr, qf)),
            (
                0.0,
                front_end - rear_end,
                f"bore {fit(bush.bush.D, 'H7').text}: {bush.designation} pressed in, one each end",
            ),
        ),
        material=steel,
        notes=(
            f"the ring's drive: hub seat z {hub_r[0] - rear_end:g}..{hub_r[1] - rear_end:g} for the ring's "
            f"prime mover ({ring_rpm:.4g} r/min), the hub held by the end circlip",
            "mates: the ring flange on its key (held by the front circlip and the flange sleeve), the frame's "
            "bearings on the k6 seats, the carrier shaft's bushes pressed into its bore",
            "timing: none (the flange's key sets nothing the ring's bolts do not)",
        ),
    )
    c_hub = (rear_end - tw.thickness - cc.s - s.drive_hub, rear_end - tw.thickness - cc.s)
    c_end = c_hub[0] - cc.groove_width - cc.n_min
    key_cd = key_for(d_c, s.drive_hub - 2 * cc.groove_width)
    carrier_grooves = (
        R[1],
        R[0] - cc.groove_width,
        rear_end - tw.thickness - cc.groove_width,
        c_hub[0] - cc.groove_width,
    )
    carrier_shaft = Turned(
        f"{name}.carrier_shaft",
        d_c,
        F[1] - c_end,
        keyways=tuple(
            (z0 + (width - k.length) / 2 - c_end, k.length, k.b, k.t1, note)
            for z0, width, k, note in (
                (F[0], T, key_c, key_c.shaft_note(d_c) + ": front carrier plate"),
                (R[0], T, key_c, key_c.shaft_note(d_c) + ": rear carrier plate"),
                (c_hub[0], s.drive_hub, key_cd, key_cd.shaft_note(d_c) + ": the carrier drive's hub"),
            )
        ),
        grooves=tuple((z - c_end, cc.groove_width, cc.groove_diameter, cc.groove_note) for z in carrier_grooves),
        fits=(
            *((z0 - c_end, z0 + T - c_end, f"{fit(d_c, 'k6').text}: carrier plate hub") for z0 in (R[0], F[0])),
            *(
                (z0 - c_end, z0 + bush.bush.B - c_end, f"{fit(d_c, 'h6').text}: in {bush.designation}")
                for z0 in (front_end - bush.bush.B, rear_end)
            ),
        ),
        material=steel,
        notes=(
            f"the carrier's drive: hub seat z {c_hub[0] - c_end:g}..{c_hub[1] - c_end:g} for the carrier's "
            f"prime mover ({carrier_rpm:.4g} r/min); its front end flush with the front carrier plate",
            "mates: both carrier plates on their keys, the rear one between two circlips; the bushes in the ring "
            "shaft on its h6 seats, a thrust washer and a circlip at each end of the ring shaft",
            "timing: its two plate keyways in line (the plates' seats are in line through them)",
        ),
    )
    turned += [
        Placed(carrier_shaft, (("carrier_shaft", "carrier", c_end),)),
        Placed(ring_shaft, (("ring_shaft", "ring", rear_end),)),
        Placed(
            Turned(
                f"{name}.flange_sleeve",
                _sleeve_od(bq.bearing, bq.D / 2, run),
                flange_sleeve[1] - flange_sleeve[0],
                bore=d_r,
                material=steel,
                notes=(
                    "mates: on the ring shaft, between the ring flange and the frame's front bearing's inner ring",
                    "timing: none (round)",
                ),
            ),
            (("flange_sleeve", "ring", flange_sleeve[0]),),
        ),
    ]
    fitted += [
        Fitted("carrier_circlip_front", cc, "carrier", R[1]),
        Fitted("carrier_circlip_back", cc, "carrier", R[0] - cc.s),
        Fitted("thrust_washer_front", tw, "carrier", front_end),
        Fitted("thrust_washer_rear", tw, "carrier", rear_end - tw.thickness),
        Fitted("carrier_circlip_drive", cc, "carrier", rear_end - tw.thickness - cc.s),
        Fitted("carrier_circlip_end", cc, "carrier", c_hub[0] - cc.s),
        Fitted("carrier_drive_key", key_cd, "carrier", c_hub[0] + (s.drive_hub - key_cd.length) / 2),
        Fitted("bush_front", bush, "ring", front_end - bush.bush.B),
        Fitted("bush_rear", bush, "ring", rear_end),
        Fitted("flange_circlip", fc, "ring", fl[1]),
        Fitted("ring_circlip_bearing", csq, "ring", qr[0] - csq.s),
        Fitted("ring_circlip_end", csq, "ring", hub_r[0] - csq.s),
        Fitted("ring_drive_key", key_rd, "ring", hub_r[0] + (s.drive_hub - key_rd.length) / 2),
        Fitted("frame_bearing_front", bq, "fixed", qf[0]),
        Fitted("frame_bearing_rear", bq, "fixed", qr[0]),
        Fitted("frame_circlip_front", cbq, "fixed", qf[0] - cbq.s),
        Fitted("frame_circlip_rear", cbq, "fixed", qr[1]),
    ]
    for end in ("front", "rear"):
        joint(f"bush_{end}", "carrier_shaft", f"wrapped bush on the carrier shaft ({fit(d_c, 'h6').text})")
        joint(f"thrust_washer_{end}", "ring_shaft", "thrust washer: the ring shaft's end face runs on it")
        joint(f"thrust_washer_{end}", f"bush_{end}", "thrust washer: the bush's end runs on it")
        joint(f"frame_bearing_{end}", "ring_shaft", f"bearing on the ring shaft: {fit(d_r, 'k6').text}")
        joint(f"frame_bearing_{end}", f"frame_{end}", f"bearing in the frame: {fit(bq.D, 'H7').text}")
        joint(f"frame_bearing_{end}", f"frame_circlip_{end}", "the DIN 472 circlip holds the outer ring")
    joint("flange_sleeve", "frame_bearing_front", "the sleeve bears on the inner ring (turns with it)")
    joint("ring_circlip_bearing", "frame_bearing_rear", "the DIN 471 circlip holds the rear inner ring")

    # -- the ring spacer, the flange and their screws: on the ring's bolt circle, as its DXF has it --
    ring_data = files[names["ring"]]
    ring_section = formats.section_of(names["ring"], ring_data, layer=formats.CUT)
    r_out = float(np.hypot(*np.asarray(ring_section.exterior.coords).T).max())
    holes = [h for h in _ring_holes(ring_data) if abs(h[2] - CLEARANCE_HOLE["M3"]) < 1e-3]
    if not holes:
        raise SpecError(f"{names['ring']} has no M3 clearance holes for the ring spacer's screws")
    r_bolt = float(np.mean([math.hypot(x, y) for x, y, _ in holes]))
    # the spacer's bore keeps the clearance from the planets' tips (they pass in the plane it touches)
    planet = formats.section_of(names["planet"], files[names["planet"]], layer=formats.CUT)
    r_in = float(math.ceil(a + reach(planet) + study.clearance))
    web = r_bolt - TAP_DRILL["M3"] / 2 - r_in
    if web < MIN_WEB:
        raise SpecError(
            f"the ring spacer's bore (R{r_in:g}, {study.clearance:g} mm beyond the planets' tips) leaves {web:.3g} mm "
            f"under the ring's tapped holes on R{r_bolt:.4g} (at least {MIN_WEB:g})"
        )
    S = -fl[1] + G[0]
    ring_screw = _screw("M3", G[1] - G[0], S, "aluminium")
    flange_screw = _screw("M3", fl[1] - fl[0], S, "aluminium")
    between = [
        (
            r_bolt * math.cos(math.atan2(y, x) + math.pi / len(holes)),
            r_bolt * math.sin(math.atan2(y, x) + math.pi / len(holes)),
        )
        for x, y, _ in holes
    ]
    for j, (x, y, _) in enumerate(holes, 1):
        m = mounted(machine_links["ring"], f"ring@bolt_{j}", x, y)
        links[m.name] = m
        fitted.append(Fitted(f"ring_screw_{j}", ring_screw, m.name, G[1], flip=True))
        m = mounted(machine_links["ring"], f"ring@flange_bolt_{j}", *between[j - 1])
        links[m.name] = m
        fitted.append(Fitted(f"flange_screw_{j}", flange_screw, m.name, fl[0]))

    # -- the frame ----------------------------------------------------------------------------------
    r_tube = bq.D / 2 + s.margin + s.tube_outer / 2
    r_frame = r_tube + s.tube_outer / 2 + s.margin
    frame_screw = _screw(size, Tf + s.frame_gap, Tf)
    ftube = Turned(
        f"{name}.frame_tube",
        s.tube_outer,
        s.frame_gap,
        bore=CLEARANCE_HOLE[size],
        material=plate_mat,
        quantity=n,
        notes=("mates: between the frame plates, on a tie screw", "timing: none (round)"),
    )
    ftube_at = []
    frame_angles = [math.pi / 2 + 2 * math.pi * j / 3 for j in range(3)]
    for j, t in enumerate(frame_angles, 1):
        m = mounted(machine_links["fixed"], f"fixed@frame_tie_{j}", r_tube * math.cos(t), r_tube * math.sin(t))
        links[m.name] = m
        ftube_at.append((f"frame_tube_{j}", m.name, FF[0] - s.frame_gap))
        fitted.append(Fitted(f"frame_screw_{j}", frame_screw, m.name, RF[0]))
    turned.append(Placed(_quantity(ftube, 3), tuple(ftube_at)))

    plate_bodies = {"carrier_rear", "ring_spacer", "ring_flange", "frame_front", "frame_rear"}
    hardware = frozenset(plate_bodies | {b for placed in turned for b, _, _ in placed.at} | {f.name for f in fitted})
    keep = {frozenset((f, "soil")): GEARBOX_CLEARANCE_MM for f in ("frame_front", "frame_rear")}
    dims = dict(
        dims,
        bq=bq,
        cbq=cbq,
        cc=cc,
        fc=fc,
        bush=bush,
        size=size,
        tie=tie,
        tie_angles=tie_angles,
        F=F,
        R=R,
        G=G,
        fl=fl,
        FF=FF,
        RF=RF,
        d_c=d_c,
        d_r=d_r,
        key_f=key_f,
        key_cd=key_cd,
        key_rd=key_rd,
        holes=holes,
        between=between,
        r_out=r_out,
        r_in=r_in,
        r_bolt=r_bolt,
        ring_screw=ring_screw,
        flange_screw=flange_screw,
        frame_angles=frame_angles,
        r_tube=r_tube,
        frame_screw=frame_screw,
        r_frame=r_frame,
        c_hub=c_hub,
        hub_r=hub_r,
        c_end=c_end,
        rear_end=rear_end,
        front_end=front_end,
    )
    return dims, hardware, keep
