"""Seed 002's machine judged: every two bodies that move against each other, in 3D over the cycle —
their axial gap, or the clearance stated in-plane; the declared joints (meshes, the roller, the
claw's bolts) recorded; the follower pivot's shaft end against the cam; the gearbox (carriers
and all they carry) against the soil by seed 002's requirement 7, the claw in the soil (only its
tines may enter), the claw at the synthesised four poses, the tip's envelope with every mesh
anywhere in its play; with ``shown`` the motion table, the animation and the slider, the claw's
phases named as seed 004's arms' are.

The functions take the :class:`~transplanter.families.machines.carrier_machine.DoubleCarrierMachineStudy`
(``study``) that states the machine.
"""

from __future__ import annotations

import json
import math

import numpy as np
import shapely

from transplanter.core.precision import rounded
from transplanter.families.machines import carrier_bodies, carrier_making, carrier_posing, carrier_structure
from transplanter.families.machines.judging import PHASES, body_rows, depth_row, motion_files
from transplanter.families.machines.record import clearance_row, pairs_record, read_bodies
from transplanter.machine import tray
from transplanter.machine.bodies import (
    IN_PLANE,
    MOTION_POSITIONS,
    WORKING,
    Body,
    Pair,
    pairs_to_judge,
    posed,
)
from transplanter.machine.carriers import DoubleCarrierMachine
from transplanter.proof.clearance import overlap_areas, posed_sections
from transplanter.proof.crossing import deepest_crossing

__all__ = [
    "JOINTS",
    "claw_phases",
    "judge",
    "judge_tray",
    "pivot_end",
    "plays",
    "poses_check",
    "structure_record",
    "tip_under_play",
]

#: what joins each pair :data:`~transplanter.families.machines.carrier_posing.JOINED` declares
JOINTS = {
    ("sun", "gear_3"): "mesh: stage 2-3",
    ("gear_4", "gear_5"): "mesh: stage 3-5",
    ("cam", "roller"): "rolling contact: the follower's roller on the cam",
    ("lever", "roller"): "bearing: the roller (a 625 ball bearing) on its pin in the lever",
    ("sector_7", "sector_8"): "mesh: the sector gears 7-8",
    ("gear_9", "gear_10"): "mesh: spur gears 9-10",
    ("gear_10", "gear_11"): "mesh: spur gears 10-11",
    ("arm", "claw"): "bolts: the claw on the arm plate",
}


def pivot_end(study, bodies: list[Body], links: dict, theta: np.ndarray) -> dict:
    """The follower pivot's shaft end (``layers.pivot_end`` out of the lever's back face towards the
    cam) against the cam: its axial gap to the cam's plane against the minimum, and on how many of
    the ``theta`` positions the lever's hub about the pivot (the lever's outline on -x: the largest
    anything on the shaft end can be) passes over the cam's outline."""
    L = study.layers
    lever = next(b for b in bodies if b.name == "lever")
    cam = next(b for b in bodies if b.name == "cam")
    hub = -float(lever.section.bounds[0])  # the lever runs along +x from the pivot to the roller
    x, y, _ = (np.broadcast_to(v, theta.shape) for v in links[lever.link].pose(theta))
    placed = posed_sections(cam.section, *(np.broadcast_to(v, theta.shape) for v in links[cam.link].pose(theta)))
    over = int(np.sum(shapely.distance(placed, shapely.points(np.stack([x, y], axis=1))) < hub))
    return {
        "shaft": "the follower pivot (the lever and sector 7 keyed on it)",
        "end_z_mm": [L.lever[0] - L.pivot_end, L.lever[0]],
        "hub_radius_mm": rounded(hub, 6),
        "over_the_cam_positions": over,
        "positions": len(theta),
        "axial_gap_mm": rounded(L.pivot_gap, 6),
        "minimum_mm": L.min_axial_gap,
        "pass": bool(L.pivot_gap >= L.min_axial_gap),
    }


def judge(study, files: dict[str, bytes], machine: DoubleCarrierMachine, shown: bool = True) -> dict:
    """The machine ``study`` states, posed as ``machine``: bodies, pairs, clearances (the gearbox
    against the soil by requirement 7), the claw in the soil, the four poses and the tip under
    play; with ``shown`` the motion table, the animation and the slider too."""
    base = read_bodies(files, carrier_posing.body_specs(study))
    hw = carrier_structure.hardware(study, study.design)
    more, links, screwed = carrier_bodies.bodies(study, hw, files, carrier_posing.links(study, machine), base)
    bodies = base + more
    ready = posed(bodies, links)
    joints = {frozenset(p): JOINTS.get(p, "declared in carrier_posing.JOINED") for p in carrier_posing.JOINED}
    joints.update(hw.joints)
    working = {frozenset(("claw", "soil")): "the claw plants in the soil"}
    gearbox = {b.name for b in bodies if b.name not in carrier_posing.NOT_GEARBOX and b.link != "arm"}
    gearbox -= {b.name for b in screwed if b.link == "arm"}  # the claw's screws go with the claw
    # requirement 7 holds every gearbox body above the soil, the fixed ones too
    keep = frozenset(frozenset((g, "soil")) for g in gearbox)
    grid = 2 * math.pi * np.arange(360) / 360
    pairs = pairs_to_judge(bodies, links, joints, working, grid, keep)

    def above_soil(p: Pair) -> str | None:  # requirement 7's pairs, stated by their nearest
        return "gearbox above the soil" if "soil" in (p.a, p.b) and ({p.a, p.b} & gearbox) else None

    def required(p: Pair) -> float:
        if above_soil(p):
            return study.gearbox_above_soil
        if frozenset((p.a, p.b)) in hw.concentric:
            return study.structure.hardware_clearance
        return study.clearance

    gap = study.layers.min_axial_gap
    verdicts = carrier_bodies.judge(bodies, links, ready, pairs, grid, gap, required, joints, above_soil)
    judged = [v.judged for v in verdicts if v.kind == IN_PLANE]
    problems = [v.problem for v in verdicts if v.problem]
    # (the layers hold its axial gap to the minimum when stated: CarrierLayers)
    pivot = pivot_end(study, bodies, links, grid)
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    claw = next(b for b in bodies if b.name == "claw")
    soil = next(b for b in bodies if b.name == "soil")
    l3 = study.chain.link_lengths[2]
    depth = depth_row(claw, soil, links["arm"], theta, (l3, 0.0), (0.0, 0.0))
    _, tines = carrier_making.claw_span(study)
    if depth["at_most_mm"] > tines:
        problems.append(
            f"the claw enters the soil {depth['at_most_mm']:.4g} mm from its tip, beyond its {tines:.4g} mm tines"
        )
    box = [j for j in judged if above_soil(j.pair)]
    low = min(box, key=lambda j: j.distance)
    poses = poses_check(study, machine)
    problems += poses["problems"]
    record = {
        "driver": "carrier 1, deg of clockwise turn from the chain's pose 1 (seed 002's tau)",
        "frame": (
            "A0 (the carrier axis) at the origin, y up: seed 002's Table 1 frame turned "
            f"{math.degrees(machine.frame[2]):.1f} deg about A0 so that the tip's farthest reach points down"
        ),
        "bodies": body_rows(bodies),
        "mirrored": "a mirrored body is mounted face down: its DXF mirrored about the DXF's x-axis, then posed",
        "joined": {" + ".join(sorted(p)): what for p, what in joints.items()},
        "motion": f"{study.name}.motion.csv",
        "positions": MOTION_POSITIONS,
        "clearance_required_mm": study.clearance,
        "gearbox_above_soil_required_mm": study.gearbox_above_soil,
        "min_axial_gap_mm": gap,
        "clearances": [
            {
                **clearance_row(v, None, depth if v.kind == WORKING else None),
                **({"required_mm": v.minimum} if v.kind == IN_PLANE else {}),
            }
            for v in verdicts
        ],
        "pairs": pairs_record(bodies, verdicts, gap),
        "pivot_end": pivot,
        "gearbox_above_soil": {
            "min_mm": rounded(low.distance, 6),
            "body": low.pair.a if low.pair.b == "soil" else low.pair.b,
            "at_driver_deg": round(low.at_deg, 4),
            "required_mm": study.gearbox_above_soil,
            "margin_mm": rounded(low.distance - study.gearbox_above_soil, 6),
        },
        "soil_level_mm": rounded(float(soil.section.bounds[3]), 6),
        "poses": poses["rows"],
        "tip_under_play": tip_under_play(study, machine, files, float(soil.section.bounds[3])),
        "animation": f"{study.name}.animation.gif",
        "slider": f"{study.name}.slider.js",
    }
    turned = {p.body for _, placed in hw.turned for p in placed}
    for name in turned:
        record["bodies"][name]["layer"] = "TURN"  # a turned part's drawing: its side view (hardware.TURN)
    record["structure"] = structure_record(study, hw, screwed)
    shown_bodies = list(bodies)
    if study.tray is not None:
        record["tray"], tray_bodies = judge_tray(study, files, bodies, links, ready, grid)
        shown_bodies += tray_bodies
        record["findings"] = [r["finding"] for r in record["tray"]["requirements"].values() if not r["pass"]]
    out_files = {}
    if shown:
        tip = machine.tip(theta)
        phases = [claw_phases(study, tip, float(soil.section.bounds[3]))]

        def tips(t):  # the one tool's path, as the pictures take the tools'
            return [machine.tip(t)]

        out_files.update(motion_files(study.name, shown_bodies, links, theta, tips, judged, phases, ["arm"]))
    return {
        "record": record,
        "files": out_files,
        "problems": problems,
        "bodies": bodies,
        "links": links,
        "hardware": hw,
        "screws": screwed,
    }


def structure_record(study, hw, screwed) -> dict:
    """What holds and drives the machine as the record states it: the structure's figures, each
    shaft and what holds it, the bearings chosen with their lives, the screws by joint."""
    count: dict[str, int] = {}
    for b in screwed:
        count[b.part.designation] = count.get(b.part.designation, 0) + 1
    return {
        **study.structure.record(),
        "input": (
            f"carrier 1 turns at {study.structure.speed_rpm:g} r/min (seed 002 §5.1), driven through the drive tube's "
            "rear end (keyed for the input sprocket) between the frame and the cam"
        ),
        "shafts": hw.shafts,
        "bearings": list(hw.bearings),
        "screws": count,
        "bodies": sum(len(p) for _, p in hw.turned) + len(hw.fitted) + len(screwed),
    }


def judge_tray(study, files, bodies, links, ready, grid) -> tuple[dict, list]:
    """Seed 002's requirements 2 and 3 on the pot tray: every body against the tray's walls and
    the picked pot in 3D over the cycle (the claw's grip in the pot its work), how far the claw
    enters the pot along its axis, and the figures a reader needs — recorded, with a finding for
    each requirement the design does not meet (the tray is the seedling box's, not the machine's: a
    finding, not a failed part)."""
    tb = read_bodies(files, carrier_posing.tray_specs(study))
    everything = [*bodies, *tb]
    ready = {**ready, **posed(tb, links)}
    working = {frozenset(("claw", "pot")): "the claw grips the picked pot's soil"}
    pairs = [p for p in pairs_to_judge(everything, links, {}, working, grid) if {p.a, p.b} & {"tray", "pot"}]
    gap = study.layers.min_axial_gap
    verdicts = carrier_bodies.judge(everything, links, ready, pairs, grid, gap, lambda p: study.clearance, {})
    mouth, axis = carrier_posing.tray_place(study, study.design)
    claw = next(b for b in bodies if b.name == "claw")
    pot = next(b for b in tb if b.name == "pot")
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    poses = tuple(np.broadcast_to(v, theta.shape) for v in links["arm"].pose(theta))
    depth, at = tray.depth_in(claw.section, poses, pot.section, mouth, axis)
    walls = [v for v in verdicts if not v.pair.working]
    worst = min(walls, key=lambda v: v.figure - (v.minimum or 0.0))
    overlap, deepest = {}, None
    for v in walls:
        if not v.passed:
            area = overlap_areas(ready[v.pair.a], ready[v.pair.b], grid)
            # how deep the moving body's deepest point lies inside the tray or the pot, over the cycle
            body, fixed = (v.pair.a, v.pair.b) if v.pair.b in ("tray", "pot") else (v.pair.b, v.pair.a)
            cross = deepest_crossing(ready[body], ready[fixed], grid)
            overlap[" + ".join((v.pair.a, v.pair.b))] = {
                "max_mm2": rounded(float(area.max()), 6),
                "positions": int(np.sum(area > 0.0)),
                "of": len(grid),
                "deepest_mm": rounded(cross.depth, 6),
                "deepest_at_most_mm": rounded(cross.bound, 6),
                "at_driver_deg": round(math.degrees(cross.theta), 4),
            }
            if deepest is None or cross.depth > deepest[0].depth:
                deepest = (cross, body, fixed)
    tz, pz = carrier_posing.tray_z(study)
    claw_z = study.layers.claw
    centre = (pz[0] + pz[1]) / 2
    # the signed figure: the least clearance when every pair clears, minus the deepest crossing else
    signed = worst.figure if deepest is None else -deepest[0].depth
    req2 = {
        "text": "seed 002 requirement 2: the seedling clip should not interfere with the plastic pot tray",
        "smallest_clearance_mm": rounded(worst.figure, 6),
        "between": [worst.pair.a, worst.pair.b] if deepest is None else [deepest[1], deepest[2]],
        "required_mm": study.clearance,
        "signed_clearance_mm": rounded(signed, 6),
        "margin_mm": rounded(signed - study.clearance, 6),
        "overlaps": overlap,
        "pass": all(v.passed for v in walls),
    }
    if deepest is not None:
        cross, body, fixed = deepest
        req2["deepest_crossing"] = {
            "body": body,
            "into": fixed,
            "depth_mm": rounded(cross.depth, 6),
            "at_most_mm": rounded(cross.bound, 6),
            "at_driver_deg": round(math.degrees(cross.theta), 4),
            "deepest_possible_mm": rounded(cross.inradius, 6),
            "measure": (
                "the deepest point of the body inside the tray (its plastic and other cells) or the picked pot, "
                "from their outline (mm): the least the body would have to move to leave it; the true deepest over "
                "the continuous cycle, between depth_mm and at_most_mm (proof.crossing); deepest_possible_mm is "
                "the most any point can be (half the tray's thickness: a body reaching it is buried to its mid-plane)"
            ),
        }
        how = (
            f"crosses {cross.depth:.3g} mm into the {fixed}"
            if cross.depth > 0.0
            else f"comes within {-cross.depth:.3g} mm of the {fixed}"
        )
        if cross.depth >= cross.inradius - 0.05:  # as deep as a point can be inside it
            how += f" (to its middle: no point can lie deeper in it than {cross.inradius:.3g} mm)"
        req2["finding"] = (
            f"requirement 2 not met: {len(overlap)} pairs of the arm's bodies and the tray fail; the {body} {how} "
            f"at {math.degrees(cross.theta):.1f} deg of the driver (margin {signed - study.clearance:.3g} mm to the "
            f"{study.clearance:g} mm clearance), the claw picking at Table 1's pose 2"
        )
    req3 = {
        "text": f"seed 002 requirement 3: the seedling clip enters the soil pot at least {study.pot_depth:g} mm",
        "depth_mm": rounded(depth, 6),
        "at_driver_deg": round(math.degrees(theta[at]), 4),
        "required_mm": study.pot_depth,
        "margin_mm": rounded(depth - study.pot_depth, 6),
        "pass": bool(depth >= study.pot_depth),
    }
    if not req3["pass"]:
        req3["finding"] = (
            f"requirement 3 not met: the claw enters the pot {depth:.3g} mm ({study.pot_depth:g} mm asked)"
        )
    record = {
        **study.tray.record(),
        "placed": (
            f"the picked pot's axis through the claw's tip at Table 1's pose 2 (seed 002's end of picking), "
            f"{study.pot_depth:g} mm down it; the tray's normal {study.tray.inclination_deg:g} deg from "
            "straight down, on the side the claw points to there"
        ),
        "mouth_mm": [rounded(float(v), 6) for v in mouth],
        "axis_deg": rounded(math.degrees(axis), 6),
        "z_mm": {"tray": list(tz), "pot": list(pz)},
        "claw_from_the_cell_walls_across_mm": rounded(
            min(claw_z[0] - (centre - study.tray.bottom / 2), centre + study.tray.bottom / 2 - claw_z[1]), 6
        ),
        "bodies": body_rows(tb),
        "clearances": [clearance_row(v) | ({"required_mm": v.minimum} if v.kind == IN_PLANE else {}) for v in verdicts],
        "requirements": {"2": req2, "3": req3},
    }
    return record, tb


def poses_check(study, machine: DoubleCarrierMachine) -> dict:
    """The claw at the chain's four poses against Table 1 (Q + L3 at link 3's attitude)."""
    ch = study.chain
    tau = np.asarray(ch.pose_tau, dtype=float)
    tip = machine.tip(tau)
    _, _, arm = machine.poses(tau)["arm"]
    l3 = ch.link_lengths[2]
    rows, problems = [], []
    rot = machine.frame[2]
    for k, (pose, att) in enumerate(zip(ch.poses.poses, ch.arm_attitudes, strict=True)):
        want = machine.to_machine(np.array([pose.x + l3 * math.cos(att), pose.y + l3 * math.sin(att)]))
        off = float(np.linalg.norm(tip[k] - want))
        turn = math.degrees(math.remainder(float(arm[k]) - rot - att, 2 * math.pi))
        ok = off <= study.pose_tolerance[0] and abs(turn) <= study.pose_tolerance[1]
        rows.append(
            {
                "pose": k + 1,
                "at_driver_deg": round(math.degrees(tau[k]), 4),
                "tip_off_mm": rounded(off, 6),
                "attitude_off_deg": rounded(turn, 6),
                "tolerance": [study.pose_tolerance[0], study.pose_tolerance[1]],
                "pass": bool(ok),
            }
        )
        if not ok:
            problems.append(
                f"the claw misses pose {k + 1} by {off:.3g} mm and {turn:.3g} deg (tolerance "
                f"{study.pose_tolerance[0]:g} mm, {study.pose_tolerance[1]:g} deg)"
            )
    return {"rows": rows, "problems": problems}


def plays(study, files: dict[str, bytes]) -> dict[str, float]:
    """Each mesh's play as a turn of its driven gear (rad): the largest free play its proof
    measured on the re-read DXFs (``assembly.backlash_mm.max``, circumferential at the pitch
    point) over the driven gear's smallest pitch radius — a bound, not a sample."""
    out = {}
    for what in ("stage23", "stage35", "sectors", "spurs"):
        pair = getattr(study, what)
        record = json.loads(files[f"{pair.name}.teeth.json"])["results"]["assembly"]
        out[what] = float(record["backlash_mm"]["max"]) / pair.sized.pair.driven.min_radius().value
    return out


def tip_under_play(study, machine: DoubleCarrierMachine, files: dict[str, bytes], soil: float) -> dict:
    """The claw tip's envelope when every mesh sits anywhere within its play (:func:`plays`)
    and the follower within its error on the cam DXF: carrier 2 turns by up to the sectors'
    play plus the follower's error over its arm, the arm by up to stage 2-3's play carried
    through stage 4-5's ratio plus stage 4-5's and both spur meshes' (9-10, 10-11); the tip's
    largest distance from its made path over the four sign combinations, at 1440 positions."""
    play = plays(study, files)
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    t3 = machine.stage23.driven(theta)
    ratio35 = np.abs(np.asarray(machine.stage35.pair.ratio(t3), dtype=float))
    follower_err = float(np.max(np.abs(machine.swing - study.cam.motion(machine.swing_at))))
    carrier2 = play["sectors"] + follower_err
    arm = play["stage23"] * ratio35 + play["stage35"] + 2 * play["spurs"]
    p = machine.poses(theta)
    ax, ay, c2 = p["carrier2"]
    _, _, a3 = p["arm"]
    l2, l3 = study.chain.link_lengths[1:]
    tip = np.stack([ax + l2 * np.cos(c2) + l3 * np.cos(a3), ay + l2 * np.sin(c2) + l3 * np.sin(a3)], axis=1)
    envelope = np.zeros(len(theta))
    for s2 in (-1.0, 1.0):
        for s3 in (-1.0, 1.0):
            b2, b3 = c2 + s2 * carrier2, a3 + s3 * arm
            moved = np.stack([ax + l2 * np.cos(b2) + l3 * np.cos(b3), ay + l2 * np.sin(b2) + l3 * np.sin(b3)], 1)
            envelope = np.maximum(envelope, np.linalg.norm(moved - tip, axis=1))
    at = int(np.argmax(envelope))
    t1, t2, t3p = (float(v) for v in study.chain.pose_tau[:3])
    picking = (theta >= t1) & (theta <= t2)
    planting = tip[:, 1] < soil
    return {
        "plays_deg": {k: rounded(math.degrees(v), 6) for k, v in play.items()},
        "carrier_2_turn_deg": rounded(math.degrees(carrier2), 6),
        "arm_turn_max_deg": rounded(math.degrees(float(arm.max())), 6),
        "max_mm": rounded(float(envelope[at]), 6),
        "at_driver_deg": round(math.degrees(theta[at]), 4),
        "picking_max_mm": rounded(float(envelope[picking].max()), 6),
        "planting_max_mm": rounded(float(envelope[planting].max()), 6) if planting.any() else None,
        "at_pose_3_mm": rounded(float(envelope[int(np.argmin(np.abs(theta - t3p)))]), 6),
    }


def claw_phases(study, tip: np.ndarray, soil: float) -> list[str]:
    """The claw's phase at each motion-table position: picking from pose 1 to pose 2, planting
    in the soil, conveying between, return after."""
    theta = 2 * math.pi * np.arange(len(tip)) / len(tip)
    t1, t2 = (float(v) for v in study.chain.pose_tau[:2])
    planted = False
    order = np.argsort(np.mod(theta - t1, 2 * math.pi))
    names = [""] * len(tip)
    for k in order:  # from pose 1 round the cycle
        if t1 <= theta[k] <= t2:
            names[k] = PHASES[0]
        elif tip[k, 1] < soil:
            names[k], planted = PHASES[2], True
        else:
            names[k] = PHASES[3] if planted else PHASES[1]
    return names
