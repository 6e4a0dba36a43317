"""Seed 002's structure as bodies the judge poses and items the bill of materials lists: the turned
parts re-read from their drawings, the bought parts from the drawings made for the judge, the
screws where the plates' holes put them.

* :func:`bought_files` — ``<stem>.<designation>.bought.dxf``: one drawing per catalogue part the
  structure buys (a bearing's or a ring's section, a screw's head), on layer ``BOUGHT``;
* :data:`SCREWED` and :func:`screws` — the screwed joints, each a cap screw through every clearance
  hole of the clamped part into the tapped one (:func:`~transplanter.families.machines.bought.screws`);
* :func:`bodies` — every body of the structure on its link (a mounted link where it sits off its
  carrier's origin), with the links it adds;
* :func:`bought` — the bought parts as :class:`~transplanter.families.machines.assembly.BoughtBody`
  items for the bill of materials and the assembly.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import shapely

from transplanter.families.machines import bought as bought_parts
from transplanter.families.machines.assembly import BoughtBody
from transplanter.families.machines.record import BOUGHT, OUTLINE_TOL_MM, read_bodies
from transplanter.machine.bodies import IN_PLANE, Body, Judged, Verdict, judge_pairs
from transplanter.machine.hardware import Fitted, bought_drawing, mounted, read_turned
from transplanter.proof.clearance import Samples, out_of_round, reach, relative

__all__ = ["SCREWED", "assembly_inputs", "bought", "bought_files", "bodies", "drawing_name", "judge", "screws"]

#: the screwed joints: (clamped body, tapped body, the structure's screw entry)
SCREWED = (
    ("frame", "post_1", "posts"),
    ("cam", "post_1", "posts"),
    ("carrier_1", "hub", "hub"),
    ("carrier_1", "carrier_1_front", "standoffs"),
    ("carrier_2", "carrier_2_front", "standoffs"),
    ("carrier_2", "sector_8", "sector"),
)


def drawing_name(stem: str, part) -> str:
    """The drawing a bought part is judged from: ``<stem>.<its designation, lower case>.bought.dxf``."""
    return f"{stem}.{re.sub(r'[^0-9a-z]+', '_', part.designation.lower()).strip('_')}{BOUGHT}"


def bought_files(stem: str, fitted) -> dict[str, bytes]:
    """One drawing per catalogue part of the :class:`~transplanter.machine.hardware.Fitted` items
    (keys, inside their hubs, have none)."""
    out = {}
    for f in fitted:
        judged = f.judged()
        name = drawing_name(stem, f.part)
        if judged is None or name in out:
            continue
        section, (z0, z1) = judged
        note = f"bought: {f.part.designation} ({f.part.standard}), drawn for the judge and the assembly; not cut"
        out[name] = bought_drawing(name.removesuffix(BOUGHT), section, z1 - z0, (note,))
    return out


def screws(study, by_name: dict[str, Body], files: dict[str, bytes]) -> list[BoughtBody]:
    """The cap screws of every screwed joint of :data:`SCREWED` and the claw's on the arm (M4)."""
    out = []
    post = by_name["post_1"]
    mid = (post.z[0] + post.z[1]) / 2
    # a post is tapped from both ends: each screw has the half of it on its side
    halves = {
        "frame": dataclasses.replace(post, z=(post.z[0], mid)),
        "cam": dataclasses.replace(post, z=(mid, post.z[1])),
    }
    for clamped, tapped, what in (*SCREWED, ("claw", "arm", None)):
        size, clearance, _ = study.structure.screws[what] if what else ("M4", 4.5, 3.3)
        into = halves[clamped] if tapped == "post_1" else by_name[tapped]
        found = bought_parts.screws(by_name[clamped], into, files, size, clearance)
        # named by both parts: a part clamped in two joints (carrier 1: the hub's and the standoffs')
        out += [dataclasses.replace(b, name=f"screw_{clamped}_{tapped}_{k}") for k, b in enumerate(found, 1)]
    return out


def bodies(study, hw, files: dict[str, bytes], links: dict, base: list[Body]) -> tuple[list[Body], dict, list]:
    """The structure's bodies — turned parts re-read from their drawings, bought ones from theirs,
    the screws' heads where the plates' holes put them (:func:`screws`, the ``base`` bodies naming
    the plates) — the links they add to ``links`` (mounted where they sit), and the screws."""
    more = dict(links)
    for name, on, x, y in hw.mounts:
        more[name] = mounted(links[on], name, x, y)
    turned = []
    for part, placements in hw.turned:
        section = read_turned(files[f"{part.name}.dxf"], part.name).section()
        turned += [Body(p.body, section, p.z, p.link, f"{part.name}.dxf") for p in placements]
    screwed = screws(study, {b.name: b for b in [*base, *turned]}, files)
    fitted = list(hw.fitted)
    for b in screwed:
        more[b.name] = mounted(more[b.link], b.name, b.x, b.y, b.angle)
        fitted.append(Fitted(b.name, b.part, b.name, b.z, b.flip))
    specs = [
        (f.name, drawing_name(study.parts, f.part), judged[1], f.link, False)
        for f in fitted
        if (judged := f.judged()) is not None
    ]
    return turned + read_bodies(files, specs), more, screwed


def bought(hw, screwed: list[BoughtBody], keys: list[BoughtBody], extra: list[BoughtBody]) -> list[BoughtBody]:
    """Every bought part of the structure, placed, for the bill of materials and the assembly: its
    bearings, bushes and rings, the screws, the keys and the ``extra`` ones (the input key)."""
    placed = [BoughtBody(f.name, f.part, f.link, 0.0, 0.0, f.z, 0.0, f.flip) for f in hw.fitted]
    return placed + list(screwed) + list(keys) + list(extra)


def assembly_inputs(study, judged: dict, files: dict[str, bytes]) -> tuple[list[Body], list, tuple]:
    """What the machine's 3MF, bill of materials and assembly STEP take from the judged machine:
    the bodies made as plates and gears (and the roller) for the 3MF; every bought part placed — the
    roller and the keys in the keyed bores (:func:`bought_parts.carrier_bought`), the structure's
    bearings, bushes, rings and screws, the input sprocket's key; and the turned parts placed by
    their own solids (:class:`~transplanter.families.machines.assembly.MadeBody`)."""
    from transplanter.families.machines.assembly import MadeBody
    from transplanter.families.machines.record import OBSTACLE
    from transplanter.shop.catalogue import bearing, circlip_for_shaft, key_for

    hw, screwed, bodies = judged["hardware"], judged["screws"], judged["bodies"]
    turned = {p.body for _, placed in hw.turned for p in placed}
    fitted = {f.name for f in hw.fitted} | {b.name for b in screwed}
    base = [b for b in bodies if b.name not in turned | fitted]
    roller = next(b for b in base if b.name == "roller")
    x, y = shapely.centroid(roller.section).coords[0]
    theirs = [BoughtBody("roller", bearing("625"), roller.link, x, y, roller.z[0]), *bought_parts.keys(base, files)]
    keyed = {b.name for b in theirs}
    hubs = {b.name: b for b in base}
    for body, _, d, (a, b) in hw.keyed:  # a hub whose drawing's keyway the reader does not find (a sector)
        if f"key_{body}" not in keyed:
            k, hub = key_for(d, b - a), hubs[body]
            sign = -1.0 if hub.mirrored else 1.0  # its keyway at +y of its drawing
            seat = BoughtBody(f"key_{body}", k, hub.link, 0.0, sign * (d / 2 - k.t1), a + (b - a - k.length) / 2)
            theirs.append(dataclasses.replace(seat, angle=math.pi) if hub.mirrored else seat)
    S, gap = study.structure, study.layers.min_axial_gap
    z0 = S.frame[1] + circlip_for_shaft(S.main_shaft).s + gap  # the drive tube's rear end
    key = key_for(S.tube, study.layers.cam[0] - gap - z0)
    sprocket = BoughtBody("key_input", key, "carrier1", 0.0, S.tube / 2 - key.t1, z0)
    made = tuple(
        MadeBody(p.body, part.name, part.solid(), p.link, z=p.z[0]) for part, placed in hw.turned for p in placed
    )
    shown = [b for b in base if not b.dxf.endswith(OBSTACLE)]
    return shown, bought(hw, screwed, theirs, [sprocket]), made


def _round(section) -> bool:
    """Whether ``section`` is a disc or a ring about its frame's origin: every vertex of each of its
    rings at one distance from the origin, within the outlines' tolerance (``OUTLINE_TOL_MM``)."""
    rings = [section.exterior, *section.interiors] if section.geom_type == "Polygon" else []
    for ring in rings:
        r = np.hypot(*shapely.get_coordinates(ring).T)
        if not len(r) or np.ptp(r) > OUTLINE_TOL_MM:
            return False
    return bool(rings)


def judge(bodies: list[Body], links: dict, ready: dict, pairs, theta, gap: float, required, joints: dict, stated=None):
    """:func:`~transplanter.machine.bodies.judge_pairs` for every pair (``stated`` names the groups
    stated by their nearest), except the pairs it would bisect without end and that need none,
    whose in-plane distance is one figure all round:

    * a round body (a shaft, a ring, a spacer, a hub disc) whose centre stays at one point of the
      other body's frame keeps one distance from it — from that point's disc to the other's section,
      measured once (a shaft in a plate's bore, a ring beside it, the hub past the cam's screw heads);
    * a round body and another whose centres keep one distance, clear of each other, are that
      distance less their reaches apart when the other is round too or turns a whole turn against
      their line of centres (a ring on a gear shaft orbiting the fixed shaft's ring; a gear passing
      the fixed shaft);
    * a round body inside a roller that rolls on the other body (a joint, ``joints``: "rolling
      contact") is the roller's radius less its own from it at the contact, and no nearer anywhere
      (the roller's pin, its spacer and its ring against the cam).

    Verdicts in the order of ``pairs``."""
    by = {b.name: b for b in bodies}
    theta = np.asarray(theta, dtype=float)

    def centre_in(inner: Body, outer: Body):
        """Where ``inner``'s centre stays in ``outer``'s frame, if it stays at one point."""
        pa = tuple(np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in links[inner.link].pose(theta))
        pb = tuple(np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in links[outer.link].pose(theta))
        x, y, _ = relative(pa, pb)
        return (float(x[0]), float(y[0])) if max(np.ptp(x), np.ptp(y)) <= 1e-6 else None

    def one_figure(inner: Body, outer: Body) -> tuple[float, float] | None:
        """The one distance and how far below it the truth may lie, or None."""
        if not _round(inner.section):
            return None
        at = centre_in(inner, outer)
        if at is not None:  # measured with the round body unturned: as uncertain as it is out of round
            d = float(shapely.distance(shapely.affinity.translate(inner.section, *at), outer.section))
            return d, out_of_round(inner.section)
        # the other about its own centre at one distance from this one's, clear of it: round too, or
        # turning a whole turn against the line of centres (its farthest point faces this one's centre)
        pa, pb = (
            tuple(np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in links[b.link].pose(theta))
            for b in (inner, outer)
        )
        apart = np.hypot(pa[0] - pb[0], pa[1] - pb[1])
        gap = float(apart[0]) - reach(inner.section) - reach(outer.section)
        if np.ptp(apart) <= 1e-6 and gap > 0.0:
            line = np.arctan2(pa[1] - pb[1], pa[0] - pb[0])
            turn = np.unwrap(pb[2] - line)  # (sampled: the step back to the start closes the turn)
            if _round(outer.section) or np.ptp(turn) + np.abs(np.diff(turn)).max() >= 2 * np.pi:
                return gap, 0.0
        rolling = [r for r in by.values() if "rolling contact" in joints.get(frozenset((r.name, outer.name)), "")]
        for roller in rolling:
            at = centre_in(inner, roller)
            if at is not None:
                own = shapely.affinity.translate(roller.section, -at[0], -at[1])
                if _round(own) and reach(own) >= reach(inner.section):
                    return reach(own) - reach(inner.section), 0.0
        return None

    exact, rest = {}, []
    for p in pairs:
        one = None
        if not p.joint and not p.working and p.axial_gap < gap:
            one = one_figure(by[p.a], by[p.b]) or one_figure(by[p.b], by[p.a])
        if one is None:
            rest.append(p)
            continue
        d, below = one
        need = required(p)
        problem = ""
        if d < need:
            problem = (
                f"{p.a} and {p.b} keep {d:.4g} mm apart all round (clearance required {need:g} mm; "
                f"axial gap {p.axial_gap:g} mm)"
            )
        exact[(p.a, p.b)] = Verdict(
            p, IN_PLANE, d, need, not problem, Judged(p, d, 0.0, max(0.0, d - below), Samples.steady(theta, d)), problem
        )
    found = {(v.pair.a, v.pair.b): v for v in judge_pairs(ready, rest, theta, gap, required, stated=stated)}
    return [exact.get((p.a, p.b)) or found[(p.a, p.b)] for p in pairs]
