"""What every machine study writes and reads: its bodies re-read from their DXFs, the obstacles,
a judged pair as the record states it, the animation and slider, the 3MF at the start.

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
from transplanter.machine.bodies import MOTION_POSITIONS, Body, Judged
from transplanter.shop import formats, solids

__all__ = [
    "OBSTACLE",
    "OUTLINE_TOL_MM",
    "obstacle_file",
    "read_bodies",
    "clearance_row",
    "judged_again",
    "pictures",
    "start_assembly",
]

#: the suffix of an obstacle's section (the seedling box, the soil): a DXF that is not a part
OBSTACLE = ".obstacle.dxf"
#: the re-read DXF sections are judged simplified to within this, mm (a stated distance is then
#: within twice this plus ``clearance.CLEARANCE_TOL_MM`` of the files' own)
OUTLINE_TOL_MM = 1e-3


def obstacle_file(name: str, what: str, section: shapely.Polygon, span: tuple[float, float]) -> dict[str, bytes]:
    """``<name>.<what>.obstacle.dxf``: an obstacle's section in the machine frame (not a part)."""
    lo, hi = span
    part = formats.MadePart(
        f"{name}.{what}",
        section,
        None,
        hi - lo,
        (f"{what}: an obstacle in the machine frame (not a part), z {lo:g}..{hi:g} mm",),
    )
    return {f"{name}.{what}{OBSTACLE}": formats.DXF.write(part)}


def read_bodies(files: dict[str, bytes], specs) -> list[Body]:
    """Each body ``(name, file, z, link, mirrored)`` as re-read from its DXF (simplified to
    :data:`OUTLINE_TOL_MM`; mirrored about its x-axis when it is mounted face down)."""
    out = []
    cache: dict[str, shapely.Polygon] = {}
    for name, fname, z, link, mirrored in specs:
        if fname not in cache:
            cache[fname] = formats.section_of(fname, files[fname]).simplify(OUTLINE_TOL_MM)
        section = cache[fname]
        if mirrored:
            section = shapely.orient_polygons(shapely.transform(section, lambda xy: xy * [1.0, -1.0]))
        out.append(Body(name, section, z, link, fname, mirrored))
    return out


def clearance_row(j: Judged, clearance: float, played: Judged | None = None, depth: dict | None = None) -> dict:
    """A judged pair as the machine record states it (``clearance``: what it is judged against)."""
    row = {
        "bodies": [j.pair.a, j.pair.b],
        "min_mm": rounded(j.distance, 6),
        "at_driver_deg": round(j.at_deg, 4),
        "bound_mm": rounded(j.bound, 6),
    }
    if j.pair.working:
        row["working"] = j.pair.working
        if depth is not None:  # only the tool's free end enters its work
            row["enters_from_tip_mm"] = depth
    else:
        row["pass"] = bool(j.distance >= clearance)
    if played is not None and played.exact:
        row["under_play_mm"] = rounded(played.distance, 6)
        row["under_play_at_driver_deg"] = round(played.at_deg, 4)
    elif played is not None:  # settled by the bound: no point moves further than turn x reach
        row["under_play_at_least_mm"] = rounded(played.distance, 6)
    return row


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
    table = np.stack([j.sampled for j in checked])
    nearest = np.argmin(table, axis=0)
    clearance = [(float(table[k, i]), f"{checked[k].pair.a} - {checked[k].pair.b}") for i, k in enumerate(nearest)]
    script = animation.slider_script(
        bodies, poses(theta), tips(theta), np.degrees(theta), [p[::every] for p in phases], clearance, labels
    )
    return {f"{name}.animation.gif": gif, f"{name}.slider.js": script}


def start_assembly(name: str, bodies, links, at: dict) -> tuple[dict, dict[str, bytes]]:
    """``<name>.assembly.3mf``: each moving body's re-read section extruded on its layer where it
    sits at the start (its link's pose at 0, or ``at[link]``), re-read and verified."""
    placed, volumes = [], {}
    for b in bodies:
        if b.link == "fixed" and b.dxf.endswith(OBSTACLE):
            continue
        x, y, a = at.get(b.link) or (float(np.asarray(v).ravel()[0]) for v in links[b.link].pose(np.zeros(1)))
        width = b.z[1] - b.z[0]
        solid = solids.part_solid(b.section, shapely.Polygon(), solids.Features(), width)
        placed.append((b.name, solid, formats.placement(x, y, b.z[0], a)))
        volumes[b.name] = b.section.area * width
    data = formats.THREEMF.write(placed)
    res = formats.THREEMF.verify(data, list(volumes), volumes)
    return {"file": f"{name}.assembly.3mf", **res}, {f"{name}.assembly.3mf": data}


def judged_again(rows: list[dict], stated: bytes, required) -> tuple[list[str], dict]:
    """The clearance ``rows`` judged again from the files against the record ``stated`` (a
    ``<machine>.machine.json``): a problem for each that moved by more than 1e-6 mm or is not
    recorded; and the summary a check prints — the pair nearest its requirement
    (``required(row)``, mm)."""
    was = {tuple(r["bodies"]): r["min_mm"] for r in json.loads(stated)["clearances"]}
    problems = []
    for row in rows:
        before = was.get(tuple(row["bodies"]))
        if before is None or abs(before - row["min_mm"]) > 1e-6:
            problems.append(f"{' and '.join(row['bodies'])}: {row['min_mm']} mm now, {before} mm recorded")
    judged = [r for r in rows if "working" not in r]
    near = min(judged, key=lambda r: r["min_mm"] - required(r))
    summary = {
        "pairs_judged": len(judged),
        "smallest_mm": near["min_mm"],
        "between": " - ".join(near["bodies"]),
        "at_driver_deg": near["at_driver_deg"],
        "required_mm": required(near),
    }
    return problems, summary
