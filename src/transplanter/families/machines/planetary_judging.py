"""Seed 004's machine judged: every two bodies that could meet over the carrier's turn (and with
each planet anywhere in its play), how deep each needle enters its work, objectives i and ii on the
bodies beside the needle-line figures, and what one plane for all arm bodies would do; with
``shown`` the motion table, the animation and the slider.

The functions take the :class:`~transplanter.families.machines.planetary_machine.PlanetaryMachineStudy`
(``study``) that states the machine and the clearance it must keep.
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.precision import rounded
from transplanter.design.objectives import BOX_CLEARANCE_MM, seed004_objectives
from transplanter.families.machines import planetary_posing
from transplanter.families.machines.judging import PHASES, body_rows, depth_row, motion_files
from transplanter.families.machines.record import clearance_row
from transplanter.machine import animation
from transplanter.machine.bodies import (
    MOTION_POSITIONS,
    Body,
    Judged,
    Pair,
    PlanetaryMachine,
    clearances,
    clearances_under_play,
    pairs_to_judge,
    posed,
    tool_phases,
)

__all__ = ["judge", "objectives", "work_depths"]


def judge(
    study, files, names, machine: PlanetaryMachine, module: float, turn: float | None, shown: bool = True
) -> dict:
    """The machine ``study`` states, posed as ``machine``: bodies, pairs, clearances (and with
    ``turn``, rad, each planet at either end of its play), objectives on bodies and the one-plane
    finding; with ``shown`` the motion table, the animation and the slider too."""
    n = study.train.planets
    bodies = planetary_posing.bodies(study, files, names)
    links = machine.links
    ready = posed(bodies, links)
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    # the clearances start from a coarser grid (the bound refines between its samples): the
    # slider's positions, so each position's smallest clearance is one of its samples
    grid = 2 * math.pi * np.arange(animation.SLIDER_POSITIONS) / animation.SLIDER_POSITIONS
    joined = set()
    working = {}
    for k in range(1, n + 1):
        joined |= {
            frozenset(("ring", f"planet_{k}")),  # the mesh
            frozenset(("carrier", f"planet_{k}")),  # the planet shaft
            frozenset((f"planet_{k}", f"arm_{k}")),  # the key
            frozenset((f"arm_{k}", f"needle_{k}")),  # the bolts
        }
        working[frozenset((f"needle_{k}", "box"))] = "the needle takes seedlings from the box"
        working[frozenset((f"needle_{k}", "soil"))] = "the needle plants in the soil"
    pairs = pairs_to_judge(bodies, joined, working)
    judged = clearances(ready, pairs, grid)
    played = {}
    if turn is not None:  # the planets anywhere in their play, each independently
        planets = {f"planet.{k}" for k in range(1, n + 1)}
        checked = [p for p in pairs if not p.working]
        nominal = {frozenset((j.pair.a, j.pair.b)): j for j in judged}
        settle = max(study.clearance, BOX_CLEARANCE_MM)  # what the pairs are judged against
        played = {
            frozenset((j.pair.a, j.pair.b)): j
            for j in clearances_under_play(bodies, ready, links, checked, grid, turn, planets, nominal, settle)
        }
    depths = work_depths(study, bodies, links, theta, [j.pair for j in judged if j.pair.working])
    arm = study.arm
    problems = [
        f"{p.a} enters {p.b} {d['at_most_mm']:.4g} mm from its tip, beyond its {arm.bar:.4g} mm bar "
        f"(at driver {d['at_driver_deg']:.1f} deg): more than the needle meets its work"
        for p, d in depths.items()
        if d["at_most_mm"] > arm.bar
    ]
    problems += [
        f"{j.pair.a} and {j.pair.b} come {j.distance:.4g} mm apart at driver {j.at_deg:.2f} deg "
        f"(clearance required {study.clearance:g} mm)"
        for j in judged
        if not j.pair.working and j.distance < study.clearance
    ]
    # what one plane for all arm bodies would do: each arm plate against the other arms' needles
    cross = [Pair(f"arm_{k}", f"needle_{j}") for k in range(1, n + 1) for j in range(1, n + 1) if j != k]
    single = clearances(ready, cross, grid)
    worst_single = min(single, key=lambda j: j.distance)
    one_plane = {
        "min_mm": rounded(worst_single.distance, 6),
        "bodies": [worst_single.pair.a, worst_single.pair.b],
        "at_driver_deg": round(worst_single.at_deg, 4),
        "finding": (
            f"in one plane the arms would not clear: {worst_single.pair.a}'s plate comes "
            f"{worst_single.distance:.3g} mm from {worst_single.pair.b} at driver {worst_single.at_deg:.1f} deg "
            f"(clearance {study.clearance:g} mm) — so the plates and the needles sit in two planes "
            f"(z {study.layers.plates[0]:g}..{study.layers.plates[1]:g} and "
            f"{study.layers.needles[0]:g}..{study.layers.needles[1]:g} mm)"
            if worst_single.distance < study.clearance
            else f"the arms would clear in one plane too ({worst_single.distance:.3g} mm)"
        ),
    }
    found = objectives(study, machine, judged, module, played)
    if turn is not None:
        worst = min(played.values(), key=lambda j: j.distance)
        under = [j for j in played.values() if j.distance < study.clearance]
        record_play = {
            "turn_deg": rounded(math.degrees(turn), 6),
            "measured": sum(j.exact for j in played.values()),
            "settled_by_the_bound": sum(not j.exact for j in played.values()),
            "smallest_mm": rounded(worst.distance, 6),
            "bodies": [worst.pair.a, worst.pair.b],
            "at_driver_deg": round(worst.at_deg, 4),
            "below_clearance": sorted(f"{j.pair.a} - {j.pair.b}: {j.distance:.4g} mm" for j in under),
        }
    record = {
        "driver": "the carrier, deg of clockwise turn from the start",
        "frame": "the train's: carrier axis at the origin, y up, the soil below (seed 004 eqs 3-10)",
        "bodies": body_rows(bodies),
        "joined": sorted(" + ".join(sorted(p)) for p in joined),
        "motion": f"{study.name}.motion.csv",
        "positions": MOTION_POSITIONS,
        "clearance_required_mm": study.clearance,
        "clearances": [
            clearance_row(j, study.clearance, played.get(frozenset((j.pair.a, j.pair.b))), depths.get(j.pair))
            for j in judged
        ],
        "animation": f"{study.name}.animation.gif",
        "slider": f"{study.name}.slider.js",
    }
    if turn is not None:
        # each planet anywhere within its play (± the turn the pair's proof bounds), independently
        record["under_play"] = record_play
    files_out = {}
    if shown:
        box, soil = (next(b.section for b in bodies if b.name == w) for w in ("box", "soil"))
        phases = [tool_phases(t, box, soil, PHASES) for t in machine.tips(theta)]
        labels = [f"arm {k + 1}" for k in range(n)]
        files_out.update(motion_files(study.name, bodies, links, theta, machine.tips, judged, phases, labels))
    return {
        "record": record,
        "objectives": found,
        "one_plane": one_plane,
        "files": files_out,
        "problems": problems + [o for o in found.get("missed", [])],
        "bodies": bodies,
    }


def work_depths(study, bodies: list[Body], links, theta: np.ndarray, pairs: list[Pair]) -> dict:
    """How far from its tip each needle enters its work (box or soil): :func:`judging.depth_row`."""
    by_name = {b.name: b for b in bodies}
    arm = study.arm
    out = {}
    for p in pairs:
        needle, work = (by_name[p.a], by_name[p.b]) if p.a.startswith("needle") else (by_name[p.b], by_name[p.a])
        out[p] = depth_row(needle, work, links[needle.link], theta, arm.tip, arm.knee)
    return out


def objectives(study, machine: PlanetaryMachine, judged: list[Judged], module: float, played: dict) -> dict:
    """Objectives i and ii on the bodies (and with the planets anywhere in their play), beside
    the needle-line figures."""
    line = {o.number: o for o in seed004_objectives(machine.made, study.site, module)}

    def arm_of(name: str) -> str | None:
        return name.split("_")[1] if name.startswith(("arm_", "needle_")) else None

    between_arms = [j for j in judged if arm_of(j.pair.a) and arm_of(j.pair.b) and arm_of(j.pair.a) != arm_of(j.pair.b)]
    at_box = [j for j in judged if "box" in (j.pair.a, j.pair.b) and not j.pair.working]
    i = min(between_arms, key=lambda j: j.distance)
    ii = min(at_box, key=lambda j: j.distance)
    rows = {
        "i arms do not interfere": {
            "bodies": [i.pair.a, i.pair.b],
            "min_mm": rounded(i.distance, 6),
            "limit_mm": study.clearance,
            "margin_mm": rounded(i.distance - study.clearance, 6),
            "at_driver_deg": round(i.at_deg, 4),
            **_played(played, between_arms),
            "needle_lines_mm": rounded(line["i"].value, 6),
            "needle_lines_limit_mm": line["i"].low,
        },
        "ii arms clear the seedling box": {
            "bodies": [ii.pair.a, ii.pair.b],
            "min_mm": rounded(ii.distance, 6),
            "limit_mm": BOX_CLEARANCE_MM,
            "margin_mm": rounded(ii.distance - BOX_CLEARANCE_MM, 6),
            "at_driver_deg": round(ii.at_deg, 4),
            **_played(played, at_box),
            "knee_to_box_face_mm": rounded(line["ii"].value, 6),
            "knee_limit_mm": line["ii"].low,
        },
    }
    missed = []
    if i.distance < study.clearance:
        missed.append(f"objective i on the bodies: {i.pair.a} and {i.pair.b} {i.distance:.4g} mm apart")
    if ii.distance < BOX_CLEARANCE_MM:
        missed.append(
            f"objective ii on the bodies: {ii.pair.a} {ii.distance:.4g} mm from the box (limit {BOX_CLEARANCE_MM:g})"
        )
    return {**rows, "all_met": not missed, **({"missed": missed} if missed else {})}


def _played(played: dict, among: list[Judged]) -> dict:
    """The smallest of ``among`` with the planets anywhere in their play (nothing without)."""
    found = [played[k] for k in (frozenset((j.pair.a, j.pair.b)) for j in among) if k in played]
    if not found:
        return {}
    worst = min(found, key=lambda j: j.distance)
    key = "under_play_mm" if worst.exact else "under_play_at_least_mm"
    return {key: rounded(worst.distance, 6), "under_play_bodies": [worst.pair.a, worst.pair.b]}
