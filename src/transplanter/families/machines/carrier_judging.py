"""Seed 002's machine judged: every two bodies that could meet over the cycle against the clearance
stated, the gearbox (carriers and all they carry) against the soil by seed 002's requirement 7, the
claw in the soil (only its tines may enter), the claw at the synthesised four poses, the tip's
envelope with every mesh anywhere in its play; with ``shown`` the motion table, the animation and
the slider, the claw's phases named as seed 004's arms' are.

The functions take the :class:`~transplanter.families.machines.carrier_machine.DoubleCarrierMachineStudy`
(``study``) that states the machine.
"""

from __future__ import annotations

import json
import math

import numpy as np

from transplanter.core.precision import rounded
from transplanter.families.machines import carrier_making, carrier_posing
from transplanter.families.machines.judging import PHASES, body_rows, depth_row, motion_files
from transplanter.families.machines.record import clearance_row, read_bodies
from transplanter.machine.bodies import MOTION_POSITIONS, Judged, clearances, pairs_to_judge, posed
from transplanter.machine.carriers import DoubleCarrierMachine

__all__ = ["claw_phases", "judge", "plays", "poses_check", "tip_under_play"]


def judge(study, files: dict[str, bytes], machine: DoubleCarrierMachine, shown: bool = True) -> dict:
    """The machine ``study`` states, posed as ``machine``: bodies, pairs, clearances (the gearbox
    against the soil by requirement 7), the claw in the soil, the four poses and the tip under
    play; with ``shown`` the motion table, the animation and the slider too."""
    bodies = read_bodies(files, carrier_posing.body_specs(study))
    links = carrier_posing.links(study, machine)
    ready = posed(bodies, links)
    joined = {frozenset(p) for p in carrier_posing.JOINED}
    working = {frozenset(("claw", "soil")): "the claw plants in the soil"}
    pairs = pairs_to_judge(bodies, joined, working)
    grid = 2 * math.pi * np.arange(360) / 360
    judged = clearances(ready, pairs, grid)
    gearbox = {b.name for b in bodies if b.name not in carrier_posing.NOT_GEARBOX}

    def required(j: Judged) -> float:
        if "soil" in (j.pair.a, j.pair.b) and ({j.pair.a, j.pair.b} & gearbox):
            return study.gearbox_above_soil
        return study.clearance

    problems = [
        f"{j.pair.a} and {j.pair.b} come {j.distance:.4g} mm apart at driver {j.at_deg:.2f} deg "
        f"(required {required(j):g} mm)"
        for j in judged
        if not j.pair.working and j.distance < required(j)
    ]
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
    box = [j for j in judged if required(j) == study.gearbox_above_soil]
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
        "joined": sorted(" + ".join(sorted(p)) for p in joined),
        "motion": f"{study.name}.motion.csv",
        "positions": MOTION_POSITIONS,
        "clearance_required_mm": study.clearance,
        "gearbox_above_soil_required_mm": study.gearbox_above_soil,
        "clearances": [
            {**clearance_row(j, required(j), None, depth if j.pair.working else None), "required_mm": required(j)}
            for j in judged
        ],
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
    out_files = {}
    if shown:
        tip = machine.tip(theta)
        phases = [claw_phases(study, tip, float(soil.section.bounds[3]))]

        def tips(t):  # the one tool's path, as the pictures take the tools'
            return [machine.tip(t)]

        out_files.update(motion_files(study.name, bodies, links, theta, tips, judged, phases, ["arm"]))
    return {"record": record, "files": out_files, "problems": problems, "bodies": bodies, "links": links}


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
