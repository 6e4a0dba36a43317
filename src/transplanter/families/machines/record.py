"""What every machine study writes and reads: its bodies re-read from their DXFs, the obstacles,
a pair judged in 3D as the record states it (and how the record accounts for every two bodies),
the animation and slider, the 3MF at the start.

Shared by :mod:`~transplanter.families.machines.planetary_machine` (seed 004) and
:mod:`~transplanter.families.machines.carrier_machine` (seed 002).
"""

from __future__ import annotations

import json
import math

import numpy as np
import shapely

from transplanter.core.precision import rounded
from transplanter.machine import animation
from transplanter.machine.bodies import (
    AXIAL,
    IN_PLANE,
    JOINT,
    MOTION_POSITIONS,
    WORKING,
    Body,
    Judged,
    Verdict,
    rigid_pairs,
)
from transplanter.proof.clearance import least_of
from transplanter.shop import formats, solids

__all__ = [
    "OBSTACLE",
    "BOUGHT",
    "OUTLINE_TOL_MM",
    "outline_layer",
    "obstacle_file",
    "read_bodies",
    "clearance_row",
    "pairs_record",
    "judged_again",
    "pictures",
    "start_assembly",
    "start_pose",
]

#: the suffix of an obstacle's section (the seedling box, the soil): a DXF that is not a part
OBSTACLE = ".obstacle.dxf"
#: the suffix of a bought part's section (drawn for the judge and the assembly, not cut)
BOUGHT = ".bought.dxf"
#: the re-read DXF sections are judged simplified to within this, mm (a stated distance is then
#: within twice this plus ``clearance.CLEARANCE_TOL_MM`` of the files' own)
OUTLINE_TOL_MM = 1e-3


def outline_layer(fname: str) -> str:
    """The DXF layer a body's file has its outline on, by what the file is: an obstacle's
    (:data:`OBSTACLE`) on REFERENCE, a bought part's (:data:`BOUGHT`) on BOUGHT, a made part's on
    CUT (``shop.dxf.OUTLINES``) — where the judges read it from."""
    if fname.endswith(OBSTACLE):
        return formats.REFERENCE
    return formats.BOUGHT if fname.endswith(BOUGHT) else formats.CUT


def obstacle_file(name: str, what: str, section: shapely.Polygon, span: tuple[float, float]) -> dict[str, bytes]:
    """``<name>.<what>.obstacle.dxf``: an obstacle's section in the machine frame (not a part: its
    outline on layer REFERENCE, nothing on CUT)."""
    lo, hi = span
    part = formats.MadePart(
        f"{name}.{what}",
        section,
        None,
        hi - lo,
        (f"{what}: an obstacle in the machine frame (not a part), z {lo:g}..{hi:g} mm",),
        layer=formats.REFERENCE,
    )
    return {f"{name}.{what}{OBSTACLE}": formats.DXF.write(part)}


def read_bodies(files: dict[str, bytes], specs) -> list[Body]:
    """Each body ``(name, file, z, link, mirrored)`` as re-read from its DXF — from the layer its
    file has its outline on (:func:`outline_layer`) — simplified to :data:`OUTLINE_TOL_MM`, and
    mirrored about its x-axis when it is mounted face down."""
    out = []
    cache: dict[str, shapely.Polygon] = {}
    for name, fname, z, link, mirrored in specs:
        if fname not in cache:
            section = formats.section_of(fname, files[fname], layer=outline_layer(fname))
            cache[fname] = section.simplify(OUTLINE_TOL_MM)
        section = cache[fname]
        if mirrored:
            section = shapely.orient_polygons(shapely.transform(section, lambda xy: xy * [1.0, -1.0]))
        out.append(Body(name, section, z, link, fname, mirrored))
    return out


def clearance_row(v: Verdict, played: Judged | None = None, depth: dict | None = None) -> dict:
    """A pair judged in 3D as the machine record states it: its ``kind`` (axial gap, in-plane,
    joint, working), the ``figure_mm`` it is judged by, the ``minimum_mm`` it must keep (None: not
    judged), ``pass``, its ``axial_gap_mm`` (negative: the planes overlap); with an in-plane
    approach, where it lies and its bound (a pair found only to a share of its margin over its
    minimum states that bound as ``min_mm``, ``exact`` False, and the nearest the search found, at
    ``at_driver_deg`` (an upper bound), as ``nearest_measured_mm``: the true minimum lies between
    the two); a joint's or a working pair's reason."""
    j = v.judged
    row = {
        "bodies": [v.pair.a, v.pair.b],
        "kind": v.kind,
        "figure_mm": rounded(v.figure, 6),
        "minimum_mm": v.minimum,
        "pass": bool(v.passed),
        "axial_gap_mm": rounded(v.pair.axial_gap, 6),
    }
    if v.kind == JOINT:
        row["joint"] = v.pair.joint
    if j is not None:
        row.update(min_mm=rounded(j.distance, 6), at_driver_deg=round(j.at_deg, 4), bound_mm=rounded(j.bound, 6))
        if not j.exact and j.nearest is not None:  # far from its minimum: found to a share of the margin
            row.update(exact=False, nearest_measured_mm=rounded(j.nearest, 6))
    if v.kind == WORKING:
        row["working"] = v.pair.working
        if depth is not None:  # only the tool's free end enters its work
            row["enters_from_tip_mm"] = depth
    if played is not None and played.exact:
        row["under_play_mm"] = rounded(played.distance, 6)
        row["under_play_at_driver_deg"] = round(played.at_deg, 4)
    elif played is not None:  # a lower bound: settled by the bound (no point moves further than
        # turn x reach), or kept by symmetry from a nominal figure that is a lower bound
        row["under_play_at_least_mm"] = rounded(played.distance, 6)
    return row


def pairs_record(bodies: list[Body], verdicts: list[Verdict], min_axial_gap: float) -> dict:
    """How the record accounts for every two bodies: how many pairs of each kind were judged, the
    smallest axial gap and in-plane clearance among the judged, and the pairs rigid to each
    other (one link, or links that never move against each other: not judged)."""
    kinds = {k: sum(v.kind == k for v in verdicts) for k in (AXIAL, IN_PLANE, JOINT, WORKING)}
    axial = [v for v in verdicts if v.kind == AXIAL]
    plane = [v for v in verdicts if v.kind == IN_PLANE]
    out: dict = {"judged": len(verdicts), **kinds, "min_axial_gap_mm": min_axial_gap}
    if axial:
        low = min(axial, key=lambda v: v.figure)
        out["smallest_axial_gap"] = {"mm": rounded(low.figure, 6), "bodies": [low.pair.a, low.pair.b]}
    if plane:
        low = min(plane, key=lambda v: v.figure - (v.minimum or 0.0))
        out["nearest_in_plane"] = {
            "mm": rounded(low.figure, 6),
            "minimum_mm": low.minimum,
            "bodies": [low.pair.a, low.pair.b],
        }
    out["failed"] = sum(not v.passed for v in verdicts)
    out["rigid"] = sorted(" + ".join(p) for p in rigid_pairs(bodies, [v.pair for v in verdicts]))
    return out


def pictures(name: str, bodies, links, tips, judged, phases, labels) -> dict[str, bytes]:
    """The animated GIF and the report slider's script of the machine: ``tips(theta)`` the tools'
    tip paths, ``phases`` each tool's phase at the motion table's positions, ``labels`` their
    names; each slider position shows the smallest clearance of the ``judged`` pairs there."""

    def poses(theta):
        return {
            b.name: tuple(np.broadcast_to(v, theta.shape).copy() for v in links[b.link].pose(theta)) for b in bodies
        }

    frames = 2 * math.pi * np.arange(animation.GIF_FRAMES) / animation.GIF_FRAMES
    gif = animation.gif_bytes(bodies, poses(frames), tips(frames))
    every = MOTION_POSITIONS // animation.SLIDER_POSITIONS
    theta = 2 * math.pi * np.arange(0, MOTION_POSITIONS, every) / MOTION_POSITIONS
    checked = [j for j in judged if not j.pair.working]
    least, nearest = least_of([j.samples for j in checked])  # each pair measured only where it may be the nearest
    clearance = [(float(d), f"{checked[k].pair.a} - {checked[k].pair.b}") for d, k in zip(least, nearest, strict=True)]
    script = animation.slider_script(
        bodies, poses(theta), tips(theta), np.degrees(theta), [p[::every] for p in phases], clearance, labels
    )
    return {f"{name}.animation.gif": gif, f"{name}.slider.js": script}


def start_pose(link: str, links, at: dict) -> tuple[float, float, float]:
    """Where ``link`` sits at the start: ``at[link]`` or its pose at driver angle 0, (x, y mm, angle rad)."""
    if at.get(link) is not None:
        return tuple(float(v) for v in at[link])
    return tuple(float(np.asarray(v).ravel()[0]) for v in links[link].pose(np.zeros(1)))


def start_assembly(name: str, bodies, links, at: dict) -> tuple[dict, dict[str, bytes]]:
    """``<name>.assembly.3mf``: each moving body's re-read section extruded on its layer where it
    sits at the start (its link's pose at 0, or ``at[link]``), re-read and verified."""
    placed, volumes = [], {}
    for b in bodies:
        if b.link == "fixed" and b.dxf.endswith(OBSTACLE):
            continue
        x, y, a = start_pose(b.link, links, at)
        width = b.z[1] - b.z[0]
        solid = solids.part_solid(b.section, shapely.Polygon(), solids.Features(), width)
        placed.append((b.name, solid, formats.placement(x, y, b.z[0], a)))
        volumes[b.name] = b.section.area * width
    data = formats.THREEMF.write(placed)
    res = formats.THREEMF.verify(data, list(volumes), volumes)
    return {"file": f"{name}.assembly.3mf", **res}, {f"{name}.assembly.3mf": data}


def judged_again(rows: list[dict], stated: bytes, required=None) -> tuple[list[str], dict]:
    """The clearance ``rows`` judged again from the files against the record ``stated`` (a
    ``<machine>.machine.json``): a problem for each whose kind or verdict changed, whose figure
    moved by more than 1e-6 mm, or that is not recorded (or is recorded and no longer judged);
    and the summary a check prints — how many pairs of each kind, the smallest axial gap and the
    in-plane pair nearest its minimum (``required(row)``, mm; default its ``minimum_mm``)."""
    required = required or (lambda r: r["minimum_mm"])
    was = {tuple(r["bodies"]): r for r in json.loads(stated)["clearances"]}
    problems = []
    for row in rows:
        before = was.pop(tuple(row["bodies"]), None)
        name = " and ".join(row["bodies"])
        if before is None:
            problems.append(f"{name}: judged now ({row['kind']}), not in the record")
        elif (before.get("kind"), before.get("pass")) != (row["kind"], row["pass"]):
            problems.append(
                f"{name}: {row['kind']} pass={row['pass']} now, {before.get('kind')} pass={before.get('pass')} recorded"
            )
        elif abs(before["figure_mm"] - row["figure_mm"]) > 1e-6:
            problems.append(f"{name}: {row['figure_mm']} mm now, {before['figure_mm']} mm recorded")
    problems += [f"{' and '.join(k)}: recorded, no longer judged" for k in was]
    plane = [r for r in rows if r["kind"] == IN_PLANE]
    axial = [r for r in rows if r["kind"] == AXIAL]
    kinds = {k: sum(r["kind"] == k for r in rows) for k in (AXIAL, IN_PLANE, JOINT, WORKING)}
    summary: dict = {"pairs_judged": len(rows), **kinds}
    if axial:
        low = min(axial, key=lambda r: r["figure_mm"])
        summary["smallest_axial_gap_mm"] = low["figure_mm"]
        summary["axial_between"] = " - ".join(low["bodies"])
    if plane:
        near = min(plane, key=lambda r: r["min_mm"] - required(r))
        summary.update(
            smallest_mm=near["min_mm"],
            between=" - ".join(near["bodies"]),
            at_driver_deg=near["at_driver_deg"],
            required_mm=required(near),
        )
    return problems, summary
