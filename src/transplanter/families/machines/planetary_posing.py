"""Seed 004's machine posed from the files of its family's earlier parts: the pair's assembly record
and the meshing its proof measured on the re-read DXFs (the train rebuilt from it, its start held to
the record), the seedling box and the soil as sections, every body re-read from its DXF in its
plane on its link, and where the planets sit at the start.

The functions take the :class:`~transplanter.families.machines.planetary_machine.PlanetaryMachineStudy`
(``study``) that states the machine.
"""

from __future__ import annotations

import json
import math

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.design.agronomy import transplanting_metrics
from transplanter.design.objectives import gearbox_radius
from transplanter.families.machines.record import BOUGHT, OBSTACLE, OUTLINE_TOL_MM, read_bodies
from transplanter.families.pairs.pair_assembly import read_meshing_csv
from transplanter.machine.bodies import Body, PlanetaryMachine
from transplanter.machine.hardware import read_turned
from transplanter.machine.play import turned
from transplanter.proof.clearance import posed_sections, reach
from transplanter.proof.train_rebuild import meshed_train

__all__ = [
    "START_POSE_DEG",
    "bodies",
    "bought_file",
    "box_planes",
    "inputs",
    "obstacles",
    "posed_machine",
    "planting_metrics",
    "span",
    "start_poses",
]

#: the start pose of each planet may differ from the assembly record by the measured meshing
#: error only; more than this is a wrong frame, deg
START_POSE_DEG = 1.0


def inputs(study, files: dict[str, bytes]) -> tuple[dict, dict[str, str], float | None]:
    """The pair's assembly record, the names of the files the machine is posed from, and how
    far each planet may turn off its driving-flank pose, rad: the bound the pair's proof states
    over its play (``meshing.dxf.train.objectives_under_play.turn_deg``; None without)."""
    p = study.pair.name
    names = {
        "ring": f"{p}.driver.dxf",
        "planet": f"{p}.driven.dxf",
        "carrier": f"{study.carrier}.carrier.dxf",
        "record": f"{p}.teeth.json",
        "meshing": f"{p}.dxf_meshing.csv",
    }
    missing = [n for n in names.values() if n not in files]
    if missing:
        raise GeometryError(f"{study.name}: the machine is posed from {missing}, which are not there")
    results = json.loads(files[names["record"]])["results"]
    record = results.get("assembly")
    if not record:
        raise GeometryError(f"{study.name}: {names['record']} has no assembly record")
    play = results.get("meshing", {}).get("dxf", {}).get("train", {}).get("objectives_under_play", {})
    return record, names, (math.radians(play["turn_deg"]) if "turn_deg" in play else None)


def posed_machine(study, files: dict[str, bytes], record: dict, names: dict[str, str]) -> tuple[PlanetaryMachine, dict]:
    """The machine's links from the pair's meshing on its re-read DXFs; their start against
    the assembly record."""
    ang, err = read_meshing_csv(files[names["meshing"]])
    made = meshed_train(study.train, ang, err)
    step = np.diff(np.append(ang, ang[0] + 2 * math.pi))
    slope = float(np.max(np.abs(np.diff(np.append(err, err[0])) / np.maximum(step, 1e-12))))
    machine = PlanetaryMachine(made, slope)
    links = machine.links
    start = study.train.carrier_start
    worst = 0.0
    for k, (c, b) in enumerate(
        zip(record["planet_carrier_angles_deg"], record["planet_body_angle_to_carrier_line_deg"], strict=True)
    ):
        _, _, angle = links[f"planet.{k + 1}"].pose(np.zeros(1))
        want = start + math.radians(c + b)
        worst = max(worst, abs(math.degrees(math.remainder(float(angle[0]) - want, 2 * math.pi))))
    if worst > START_POSE_DEG:
        raise GeometryError(
            f"{study.name}: the planets start {worst:.3g} deg from where the assembly record puts them "
            f"(limit {START_POSE_DEG:g} deg)"
        )
    return machine, {"start_vs_assembly_record_deg": rounded(worst, 6), "error_slope": rounded(slope, 6)}


def span(study, design) -> tuple[float, float]:
    """Across the whole machine, mm: 10 mm beyond its outermost bodies (the soil lies across it)."""
    zs = [*study.layers.span]
    zs += [z for p in design.plates for z in p.z]
    zs += [z + dz for placed in design.turned for _, _, z in placed.at for dz in (0.0, placed.part.length)]
    return min(zs) - 10.0, max(zs) + 10.0


def box_planes(study) -> dict[str, tuple[str, tuple[float, float]]]:
    """The seedling box's bodies: name -> (the obstacle's section it is, its z-range mm). The box is
    ``box_width`` wide across the machine, centred on the needles' plane; the door's slot runs
    ``clearance`` either side of the needles."""
    st, needles = study.structure, study.layers.needles
    mid = (needles[0] + needles[1]) / 2
    z0, z1 = mid - st.box_width / 2, mid + st.box_width / 2
    slot = (needles[0] - study.clearance, needles[1] + study.clearance)
    return {
        "box": ("box", (z0, z1)),
        "box_floor": ("box_floor", (z0, z1)),
        "box_door_back": ("box_door", (z0, slot[0])),
        "box_door_front": ("box_door", (slot[1], z1)),
        "box_wall_back": ("box_wall", (z0 - st.sheet, z0)),
        "box_wall_front": ("box_wall", (z1, z1 + st.sheet)),
    }


def planting_metrics(study, module: float):
    """The train's planting metrics at its site (the soil surface's height in the machine frame, the
    machine's travel): :func:`transplanter.design.agronomy.transplanting_metrics`."""
    tr, site = study.train, study.site
    return transplanting_metrics(
        tr,
        site.seedling_box,
        site.plant_spacing,
        site.planting_depth,
        gearbox_radius(tr.pair.driver.max_radius().value, module),
    )


def obstacles(
    study, module: float, needle_link, needle: shapely.Polygon, turn: float | None = None
) -> tuple[dict[str, shapely.Polygon], dict]:
    """The seedling box's sections (the seedlings — the needle's work — its floor, its side walls and
    the seedling door: an L of sheet at the box's end, slotted where the needles pass) and the soil,
    in the machine frame; and the door as the record states it. The floor stops short of the
    needle's path by the clearance (its reach into the floor's plane over the cycle, ``needle`` on
    ``needle_link`` — and turned either way by the planet's play ``turn``, rad — 1440 positions, and
    what it can gain between them, rounded up to the mm); the door's shelf carries the seedlings'
    end from there to its lip."""
    tr, site, st = study.train, study.site, study.structure
    soil = planting_metrics(study, module).soil_level
    u = np.array([math.cos(site.box_slope), math.sin(site.box_slope)])
    n = np.array([-u[1], u[0]])
    p = np.asarray(site.seedling_box, dtype=float)
    length, height = study.box
    h, t = height / 2, st.sheet

    def outline(points) -> shapely.Polygon:
        return shapely.orient_polygons(shapely.Polygon([p + u * a + n * b for a, b in points]))

    def box(s0: float, s1: float, t0: float, t1: float) -> shapely.Polygon:
        return outline([(s0, t0), (s1, t0), (s1, t1), (s0, t1)])

    theta = 2 * math.pi * np.arange(1440) / 1440
    sweeps = []
    for played in (needle_link,) if not turn else (turned(needle_link, -turn), needle_link, turned(needle_link, turn)):
        x, y, a = (np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in played.pose(theta))
        sweeps += list(posed_sections(needle, x, y, a))
    swept = shapely.union_all(sweeps)
    between = (needle_link.speed + needle_link.turn_rate * reach(needle)) * math.pi / len(theta)
    local = shapely.transform(swept, lambda xy: np.stack([(xy - p) @ u, (xy - p) @ n], axis=1))
    reach_in = local.intersection(shapely.box(-length, -h - t, length, -h))
    s_floor = math.ceil((reach_in.bounds[2] if not reach_in.is_empty else 0.0) + between + study.clearance)
    lip = -h + st.door_lip
    door = outline([(-t, -h - t), (s_floor, -h - t), (s_floor, -h), (0.0, -h), (0.0, lip), (-t, lip)])
    reach_mm = reach_in.bounds[2] if not reach_in.is_empty else None
    reach_all = reach_mm if reach_mm is None else rounded(reach_mm, 6)
    planes = box_planes(study)
    record = {
        "slot_z_mm": [planes["box_door_back"][1][1], planes["box_door_front"][1][0]],
        "opening_along_the_slope_mm": [-t, s_floor],
        "needle_reach_into_the_floor_plane_mm": reach_all,
        "between_positions_mm": rounded(between, 6),
        "reading": (
            f"the seedling door: an L of {t:g} mm sheet at the box's end — a lip {st.door_lip:g} mm up from the "
            f"floor (the mat's soil block) and a shelf to {s_floor:g} mm up the slope, where the floor begins — "
            f"slotted {study.clearance:g} mm either side of the needles' plane; the needle passes through the slot and "
            f"the floor's gap, never through the floor (its reach into the floor's plane over the cycle, the planet "
            f"anywhere in its play, {reach_all} mm, what it may gain between the positions and the clearance); the "
            f"box {st.box_width:g} mm wide is shown mid-traverse (its sideways feed, the transplanter's, moves it "
            "along z only)"
        ),
    }
    reach_xy = tr.pair.centre_distance + tr.arm.tip + 100.0
    return {
        "box": box(0.0, length, -h, h),
        "box_floor": box(s_floor, length, -h - t, -h),
        "box_door": door,
        "box_wall": box(-t, length, -h - t, h),
        "soil": shapely.box(-2 * reach_xy, soil - 150.0, 2 * reach_xy, soil),
    }, record


def bodies(study, files: dict[str, bytes], names: dict[str, str], design) -> list[Body]:
    """Every body as re-read from its file, in its plane, on its link: the made plates from their
    DXFs, the turned parts from their drawings (:func:`hardware.read_turned`: the envelope), the
    judged bought parts from their ``.bought.dxf`` sections, the box and the soil."""
    L, n = study.layers, study.train.planets
    plate, needle = f"{study.name}.arm_plate.dxf", f"{study.name}.needle.dxf"
    specs = [("ring", names["ring"], L.gears, "ring", False)]
    for k in range(1, n + 1):
        specs += [
            (f"planet_{k}", names["planet"], L.gears, f"planet.{k}", False),
            (f"arm_{k}", plate, L.plates, f"planet.{k}", False),
            (f"needle_{k}", needle, L.needles, f"planet.{k}", False),
        ]
    specs += [(p.body, f"{study.name}.{p.part}.dxf", p.z, p.link, False) for p in design.plates]
    for f in design.fitted:
        judged = f.judged()
        if judged is not None:
            specs.append((f.name, bought_file(study.name, f), judged[1], f.link, False))
    for body, (what, z) in box_planes(study).items():
        specs.append((body, f"{study.name}.{what}{OBSTACLE}", z, "fixed", False))
    specs.append(("soil", f"{study.name}.soil{OBSTACLE}", span(study, design), "fixed", False))
    out = read_bodies(files, specs)
    for placed in design.turned:
        fname = f"{placed.part.name}.dxf"
        part = read_turned(files[fname], placed.part.name)
        section = part.section().simplify(OUTLINE_TOL_MM)
        out += [Body(body, section, (z, z + part.length), link, fname) for body, link, z in placed.at]
    return out


def bought_file(machine: str, fitted) -> str:
    """The ``.bought.dxf`` a judged bought part's section is read from (one per designation)."""
    slug = "".join(c if c.isalnum() or c in "-" else "_" for c in fitted.part.designation)
    return f"{machine}.{slug}{BOUGHT}"


def start_poses(study, record: dict) -> dict[str, tuple[float, float, float]]:
    """Where each planet sits at the start, ``(x, y, angle)`` mm and rad per link: where the assembly
    ``record`` puts it (the middle of its play), for the 3MF of the made parts."""
    start = study.train.carrier_start
    r = study.train.pair.centre_distance
    at = {}
    for k, (c, body) in enumerate(
        zip(record["planet_carrier_angles_deg"], record["planet_body_angle_to_carrier_line_deg"], strict=True)
    ):
        line = start + math.radians(c)
        at[f"planet.{k + 1}"] = (r * math.cos(line), r * math.sin(line), line + math.radians(body))
    return at
