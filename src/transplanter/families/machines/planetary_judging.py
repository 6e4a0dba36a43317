"""Seed 004's machine judged: every two bodies that move against each other, in 3D over the
carrier's turn — their axial gap, or their in-plane clearance (and with each planet anywhere in its
play); the declared joints (meshes, keys, bolts) recorded — how deep each needle enters its work,
objectives i and ii on the bodies beside the needle-line figures, and what one plane for all arm bodies would do; with
``shown`` the motion table, the animation and the slider.

The functions take the :class:`~transplanter.families.machines.planetary_machine.PlanetaryMachineStudy`
(``study``) that states the machine and the clearance it must keep.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import shapely
import shapely.affinity

from transplanter.core.precision import rounded
from transplanter.design.objectives import BOX_CLEARANCE_MM, seed004_objectives
from transplanter.families.machines import planetary_posing
from transplanter.families.machines.judging import PHASES, body_rows, depth_row
from transplanter.families.machines.record import clearance_row, pairs_record, pictures
from transplanter.machine import animation
from transplanter.machine.bodies import (
    IN_PLANE,
    MOTION_POSITIONS,
    Body,
    Judged,
    Link,
    Pair,
    PlanetaryMachine,
    clearances,
    judge_pairs,
    motion_rows,
    pairs_to_judge,
    posed,
    tool_phases,
)
from transplanter.machine.hardware import TURN
from transplanter.machine.play import clearances_under_play
from transplanter.proof.clearance import Posed, out_of_round, posed_sections, reach, relative
from transplanter.shop.export import csv_bytes

__all__ = ["joints_of", "judge", "objectives", "required_of", "work_depths", "door_margins"]

#: the structure's bodies the animation and the slider show (the rest is in the motion table)
SHOWN = ("carrier_rear", "ring_spacer", "ring_flange", "frame_")


def joints_of(study, design=None) -> tuple[dict[frozenset, str], dict[frozenset, str]]:
    """The machine's declared joints (pair of bodies -> what joins them) and working pairs (pair
    -> what the tool does there): each planet meshes with the ring and carries its arm plate on
    its key and its needle on two bolts; each needle works in the box and in the soil; and the
    structure's (``design``: bearings on their shafts and in their plates, circlips, sleeves,
    thrust washers, keys)."""
    joints, working = dict(design.joints) if design is not None else {}, {}
    for k in range(1, study.train.planets + 1):
        if design is not None:
            joints[frozenset((f"planet_{k}", f"planet_shaft_{k}"))] = "key: the planet on its shaft"
            joints[frozenset((f"arm_{k}", f"planet_shaft_{k}"))] = "key: the arm plate on the planet shaft"
        joints[frozenset(("ring", f"planet_{k}"))] = "mesh: the ring's teeth and the planet's"
        joints[frozenset((f"planet_{k}", f"arm_{k}"))] = "key: the planet and the arm plate on one keyed shaft"
        joints[frozenset((f"arm_{k}", f"needle_{k}"))] = (
            "bolts: the needle on 2 x M4 through spacer washers on the plate's outer face"
        )
        working[frozenset((f"needle_{k}", "box"))] = "the needle takes seedlings from the box"
        working[frozenset((f"needle_{k}", "soil"))] = "the needle plants in the soil"
    return joints, working


def required_of(study, design):
    """The clearance a pair must keep in-plane, mm: a rigid pair judged anyway its own (the frame
    above the soil: objective x), two pieces of the structure's hardware the running clearance,
    any other the machine's clearance."""
    run = study.structure.running_clearance

    def required(p: Pair) -> float:
        key = frozenset((p.a, p.b))
        if key in design.keep:
            return design.keep[key]
        return run if {p.a, p.b} <= design.hardware else study.clearance

    return required


def _symmetric(design) -> set[str]:
    """The structure's bodies whose sections are circles or rings about their own origin: turning
    about it leaves them where they are (their speed is their origin's)."""
    out = {b for placed in design.turned for b, _, _ in placed.at}
    return out | {f.name for f in design.fitted if f.kind != "Nut" and f.judged() is not None}


def _in_carrier(links: dict[str, Link], planets: set[str]) -> dict[str, Link]:
    """Every link seen from the carrier, with its speed bounds there: the carrier and what is fixed
    on it stand still, the ring turns about the axis at 1 - ω1/ω2 of the carrier's rate, the
    ground at the carrier's, each planet about its own fixed centre at its turn rate plus the
    carrier's; a mounted link as its base turns, its origin moving at that rate times its offset."""
    carrier = links["carrier"]
    rate = {"carrier": 0.0, "ring": abs(links["ring"].turn_rate - 1.0), "fixed": 1.0}
    rate.update({k: links[k].turn_rate + 1.0 for k in planets})
    out = {}
    for name, link in links.items():
        base, (x, y) = (link.origin_in[0][0], link.origin_in[0][1:]) if link.origin_in else (name, (0.0, 0.0))
        turn = rate[base]

        def pose(theta, link=link):
            t = np.asarray(theta, dtype=float)
            mine = tuple(np.broadcast_to(np.asarray(v, dtype=float), t.shape) for v in link.pose(t))
            ref = tuple(np.broadcast_to(np.asarray(v, dtype=float), t.shape) for v in carrier.pose(t))
            return relative(mine, ref)

        out[name] = Link(name, pose, turn * math.hypot(x, y), turn, link.origin_in)
    return out


def _posed_in(bodies, links: dict[str, Link], about_origin: set[str], symmetric: set[str]) -> dict:
    """:func:`posed` with the bounds this machine knows: the radii a body's points keep from the
    frame's origin — exact for a body on a link turning about that origin, or for a symmetric body
    whose link's origin stands still (a shaft seen from its carrier); the origin's distance less and
    plus the body's reach for any other body on such a link; none otherwise — and a symmetric body
    moving no faster than its origin, posed without its turn and so uncertain by how far it is out
    of round (``Posed.wobble``: a flattened circle's chords, ~1 µm)."""
    ready = posed(bodies, links)
    zero = np.zeros(1)
    for b in bodies:
        link = links[b.link]
        base, (x, y) = (link.origin_in[0][0], link.origin_in[0][1:]) if link.origin_in else (b.link, (0.0, 0.0))
        radii = None
        if base in about_origin or (link.speed == 0.0 and b.name in symmetric):
            if base not in about_origin:
                x, y = (float(np.asarray(v, dtype=float).ravel()[0]) for v in link.pose(zero)[:2])
            placed = shapely.affinity.translate(b.section, x, y)
            radii = (float(shapely.distance(shapely.Point(0.0, 0.0), placed)), reach(placed))
        elif link.speed == 0.0:
            c, r = (
                math.hypot(*(float(np.asarray(v, dtype=float).ravel()[0]) for v in link.pose(zero)[:2])),
                reach(b.section),
            )
            radii = (max(0.0, c - r), c + r)
        if b.name in symmetric:  # posed without its turn: as uncertain as it is out of round
            wobble = out_of_round(b.section)
            radii = None if radii is None else (max(0.0, radii[0] - wobble), radii[1] + wobble)
            ready[b.name] = dataclasses.replace(ready[b.name], radii=radii, speed=link.speed, wobble=wobble)
        else:
            ready[b.name] = dataclasses.replace(ready[b.name], radii=radii)
    return ready


def _not_periodic(bodies, links) -> set[str]:
    """The bodies not back where they started after one carrier turn: the ring turns ω1/ω2 of a
    turn per carrier turn (3/4), so a body on it comes back only if its section looks the same
    turned by that much (the spacer's bolt circle does; a single screw, a keyway, a timing notch do
    not)."""
    ends = np.array([0.0, 2 * math.pi])
    out = set()
    for b in bodies:
        x, y, a = (np.broadcast_to(np.asarray(v, dtype=float), ends.shape) for v in links[b.link].pose(ends))
        if (
            abs(x[1] - x[0]) < 1e-9
            and abs(y[1] - y[0]) < 1e-9
            and abs(math.remainder(a[1] - a[0], 2 * math.pi)) < 1e-12
        ):
            continue
        start, end = posed_sections(b.section, x, y, a)
        if shapely.symmetric_difference(start, end).area > 1e-9 * max(b.section.area, 1.0):
            out.add(b.name)
    return out


def _there_and_back(ready: Posed, end: float) -> Posed:
    """``ready`` driven to ``end`` (rad: the motion table's last position) and back — θ = end t/π,
    then end (2 - t/π), over t in one period — periodic in t whether or not the body is back at its
    start after the turn, end/π times as fast."""

    def pose(t, pose=ready.pose):
        t = np.mod(np.asarray(t, dtype=float), 2 * math.pi)
        return pose(end * np.where(t < math.pi, t / math.pi, 2.0 - t / math.pi))

    return dataclasses.replace(ready, pose=pose, speed=ready.speed * end / math.pi)


@dataclasses.dataclass(frozen=True)
class _Frames:
    """Where each pair is measured (:func:`_judged_in_frames`): the bodies posed in the machine's
    frame and in the carrier's, with those frames' links; the motion table's last position ``end``
    (rad) and the positions ``fine`` a there-and-back measure samples; and each pair's (in the
    carrier's frame, there and back)."""

    machine: dict
    carrier: dict
    links: dict
    carrier_links: dict
    end: float
    fine: np.ndarray
    of: dict

    def groups(self, pairs) -> dict[tuple[bool, bool], list]:
        out: dict[tuple[bool, bool], list] = {}
        for p in pairs:
            out.setdefault(self.of[frozenset((p.a, p.b))], []).append(p)
        return out

    def unwound(self, j: Judged, grid) -> Judged:
        """A there-and-back figure's angle as the driver's, its samples on ``grid``."""
        t = math.radians(j.at_deg) % (2 * math.pi)
        at = math.degrees(self.end * (t / math.pi if t < math.pi else 2.0 - t / math.pi))
        return dataclasses.replace(j, at_deg=at, samples=j.samples[: len(grid)])


def _judged_in_frames(bodies, links, pairs, grid, gap, required, symmetric, planets) -> tuple[list, _Frames]:
    """:func:`judge_pairs`, each pair measured in the machine's frame or the carrier's, whichever
    bounds their relative speed tighter (distances are the same in both): the carrier's settles a
    shaft turning in its bore at once. A pair with a body not back at its start after the turn
    (:func:`_not_periodic`) is measured to the motion table's last position and back
    (:func:`_there_and_back`, on twice the positions): its figure is over the positions the table
    poses and between them, not across the turn's end, where such a body jumps."""
    carrier_links = _in_carrier(links, planets)
    machine = _posed_in(bodies, links, {"ring", "carrier", "fixed"}, symmetric)
    carrier = _posed_in(bodies, carrier_links, {"ring", "carrier", "fixed"}, symmetric)
    unwound = _not_periodic(bodies, links)
    end = 2 * math.pi * (MOTION_POSITIONS - 1) / MOTION_POSITIONS
    there = math.pi * np.asarray(grid, dtype=float) / end  # t of each grid angle, then back through `end`
    fine = np.concatenate([there, [math.pi], 2 * math.pi - there[:0:-1]])
    of = {
        frozenset((p.a, p.b)): (
            carrier[p.a].speed + carrier[p.b].speed < machine[p.a].speed + machine[p.b].speed,
            bool({p.a, p.b} & unwound),
        )
        for p in pairs
    }
    frames = _Frames(machine, carrier, links, carrier_links, end, fine, of)
    found = {}
    for (in_carrier, back), some in frames.groups(pairs).items():
        ready = carrier if in_carrier else machine
        if back:
            names = {n for p in some for n in (p.a, p.b)}
            ready = {n: _there_and_back(ready[n], end) for n in names}
        for v in judge_pairs(ready, some, fine if back else grid, gap, required, stated=stated_as):
            if back and v.judged is not None:  # t back to the driver's angle, the samples on the grid
                v = dataclasses.replace(v, judged=frames.unwound(v.judged, grid))
            found[(v.pair.a, v.pair.b)] = v
    return [found[(p.a, p.b)] for p in pairs], frames


def _under_play(bodies, frames: _Frames, checked, grid, turn, planets, nominal, settle) -> dict:
    """:func:`clearances_under_play` of the ``checked`` pairs, each in the frame and over the
    positions its nominal figure was measured on (:func:`_judged_in_frames`): the same bound on
    its relative speed, and a body not back at its start driven there and back, not across the
    turn's end."""
    out = {}
    for (in_carrier, back), some in frames.groups(checked).items():
        ready, links = (frames.carrier, frames.carrier_links) if in_carrier else (frames.machine, frames.links)
        wrap = (lambda p: _there_and_back(p, frames.end)) if back else None
        for j in clearances_under_play(
            bodies, ready, links, some, frames.fine if back else grid, turn, planets, nominal, settle, wrap=wrap
        ):
            if back and j.exact:
                j = frames.unwound(j, grid)
            out[frozenset((j.pair.a, j.pair.b))] = j
    return out


def judge(
    study, files, names, machine: PlanetaryMachine, module: float, turn: float | None, design, shown: bool = True
) -> dict:
    """The machine ``study`` states, posed as ``machine`` with its structure ``design``: bodies,
    pairs, clearances (and with ``turn``, rad, each planet at either end of its play), objectives on
    bodies, the seedling door's margins and the one-plane finding; with ``shown`` the motion table,
    the animation and the slider too."""
    n = study.train.planets
    bodies = planetary_posing.bodies(study, files, names, design)
    links = {**machine.links, **design.links}
    planets = {f"planet.{k}" for k in range(1, n + 1)}
    symmetric = _symmetric(design)
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    # the clearances start from a coarser grid (the bound refines between its samples): the
    # slider's positions, so each position's smallest clearance is one of its samples
    grid = 2 * math.pi * np.arange(animation.SLIDER_POSITIONS) / animation.SLIDER_POSITIONS
    joints, working = joints_of(study, design)
    pairs = pairs_to_judge(bodies, links, joints, working, grid, frozenset(design.keep))
    gap = study.layers.min_axial_gap
    required = required_of(study, design)
    verdicts, frames = _judged_in_frames(bodies, links, pairs, grid, gap, required, symmetric, planets)
    ready = frames.machine
    judged = [v.judged for v in verdicts if v.judged is not None]  # measured in-plane: working or not
    in_plane = [v.judged for v in verdicts if v.kind == IN_PLANE]
    played = {}
    if turn is not None:  # the planets anywhere in their play, each independently
        # a symmetric body turning about its own centre with its planet is where it was: such a pair
        # keeps its figure in the play; the others are measured there
        on_planet = {b.name for b in bodies if b.link in planets and b.name not in symmetric}
        checked = [j.pair for j in in_plane if {j.pair.a, j.pair.b} & on_planet]
        nominal = {frozenset((j.pair.a, j.pair.b)): j for j in in_plane}
        settle = max(study.clearance, BOX_CLEARANCE_MM)  # what the pairs are judged against
        played = _under_play(bodies, frames, checked, grid, turn, planets, nominal, settle)
        settled = sum(not j.exact for j in played.values())  # by the bound, without measuring
        measured = len(played) - settled
        link_of = {b.name: b.link for b in bodies}
        played.update(
            {k: j for k, j in nominal.items() if k not in played and {link_of[j.pair.a], link_of[j.pair.b]} & planets}
        )
    depths = work_depths(study, bodies, links, theta, [j.pair for j in judged if j.pair.working])
    arm = study.arm
    problems = [
        f"{p.a} enters {p.b} {d['at_most_mm']:.4g} mm from its tip, beyond its {arm.bar:.4g} mm bar "
        f"(at driver {d['at_driver_deg']:.1f} deg): more than the needle meets its work"
        for p, d in depths.items()
        if d["at_most_mm"] > arm.bar
    ]
    problems += [v.problem for v in verdicts if v.problem]
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
    found = objectives(study, machine, in_plane, module, played)
    if turn is not None:
        worst = min(played.values(), key=lambda j: j.distance)
        under = [j for j in played.values() if j.distance < required(j.pair)]
        record_play = {
            "turn_deg": rounded(math.degrees(turn), 6),
            "measured": measured,
            "settled_by_the_bound": settled,
            "kept_by_symmetry": len(played) - measured - settled,
            "smallest_mm": rounded(worst.distance, 6),
            "bodies": [worst.pair.a, worst.pair.b],
            "at_driver_deg": round(worst.at_deg, 4),
            "below_clearance": sorted(f"{j.pair.a} - {j.pair.b}: {j.distance:.4g} mm" for j in under),
        }
    record = {
        "driver": "the carrier, deg of clockwise turn from the start",
        "frame": "the train's: carrier axis at the origin, y up, the soil below (seed 004 eqs 3-10)",
        "bodies": _body_rows(bodies, design),
        "joined": {" + ".join(sorted(p)): what for p, what in joints.items()},
        "motion": f"{study.name}.motion.csv",
        "positions": MOTION_POSITIONS,
        "clearance_required_mm": study.clearance,
        "running_clearance_mm": study.structure.running_clearance,
        "door": door_margins(verdicts),
        "min_axial_gap_mm": gap,
        "clearances": [
            clearance_row(v, played.get(frozenset((v.pair.a, v.pair.b))), depths.get(v.pair)) for v in verdicts
        ],
        "pairs": pairs_record(bodies, verdicts, gap),
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
        header, rows = motion_rows(bodies, links, theta)  # every body: the judge re-poses each from it
        files_out[f"{study.name}.motion.csv"] = csv_bytes(header, rows)
        shown_bodies = [b for b in bodies if b.name not in design.hardware or b.name.startswith(SHOWN)]
        files_out.update(pictures(study.name, shown_bodies, links, machine.tips, in_plane, phases, labels))
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
    between_arms = [j for j in judged if stated_as(j.pair) == "i"]
    at_box = [j for j in judged if stated_as(j.pair) == "ii"]
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


def _arm_of(name: str) -> str | None:
    found = re.fullmatch(r"(arm|needle)_(\d+)", name)
    return found.group(2) if found else None


def _needle(name: str) -> bool:
    return re.fullmatch(r"needle_\d+", name) is not None


#: the parts of the seedling box a needle passes (:func:`door_margins`)
DOOR = ("box_door_back", "box_door_front", "box_floor", "box_wall_back", "box_wall_front")


def stated_as(p: Pair) -> str | None:
    """The figure the record states a pair's group by, its nearest (``judge_pairs``' ``stated``):
    objective ``i`` (two arms' bodies), ``ii`` (any body but a needle against a part of the box,
    not at its work: the needle enters it through the door), or a door part and a needle
    (:func:`door_margins`)."""
    a, b = _arm_of(p.a), _arm_of(p.b)
    if a and b and a != b:
        return "i"
    box = [n == "box" or n.startswith("box_") for n in (p.a, p.b)]
    needle = _needle(p.a) or _needle(p.b)
    if box[0] != box[1] and not p.working and not needle:
        return "ii"
    door = [part for part in DOOR if part in (p.a, p.b)]
    return f"door {door[0]}" if door and needle else None


def _played(played: dict, among: list[Judged]) -> dict:
    """The smallest of ``among`` with the planets anywhere in their play (nothing without)."""
    found = [played[k] for k in (frozenset((j.pair.a, j.pair.b)) for j in among) if k in played]
    if not found:
        return {}
    worst = min(found, key=lambda j: j.distance)
    key = "under_play_mm" if worst.exact else "under_play_at_least_mm"
    return {key: rounded(worst.distance, 6), "under_play_bodies": [worst.pair.a, worst.pair.b]}


def _body_rows(bodies, design) -> dict:
    """:func:`body_rows`, a turned part's with where its section is: the circle of its side view's
    diameter (layer ``TURN``), less its bore (``HIDDEN``) — its envelope across the machine."""
    rows = body_rows(bodies)
    for placed in design.turned:
        for body, _, _ in placed.at:
            rows[body]["layer"] = TURN
            rows[body]["section"] = (
                "turned: the circle of the side view's diameter less the bore (HIDDEN), its envelope"
            )
    return rows


def door_margins(verdicts) -> dict:
    """How the needles pass the seedling box: through the door's slot (their axial gap to the door
    either side of it), clear of the floor (in-plane) and of the side walls (axial gap), mm — the
    smallest over the needles."""
    out = {}
    for part in DOOR:
        found = [v for v in verdicts if stated_as(v.pair) == f"door {part}"]
        if found:
            low = min(found, key=lambda v: v.figure)
            out[part] = {"kind": low.kind, "mm": rounded(low.figure, 6), "minimum_mm": low.minimum, "pass": low.passed}
    return out
