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
from transplanter.families.machines.record import OBSTACLE, read_bodies
from transplanter.families.pairs.pair_assembly import read_meshing_csv
from transplanter.machine.bodies import Body, PlanetaryMachine
from transplanter.proof.train_rebuild import meshed_train

__all__ = ["START_POSE_DEG", "bodies", "inputs", "obstacles", "posed_machine", "start_poses"]

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


def obstacles(study, module: float) -> dict[str, shapely.Polygon]:
    """The seedling box and the soil as sections in the machine frame."""
    tr, site = study.train, study.site
    soil = transplanting_metrics(
        tr,
        site.seedling_box,
        site.plant_spacing,
        site.planting_depth,
        gearbox_radius(tr.pair.driver.max_radius().value, module),
    ).soil_level
    u = np.array([math.cos(site.box_slope), math.sin(site.box_slope)])
    n = np.array([-u[1], u[0]])
    p = np.asarray(site.seedling_box, dtype=float)
    length, height = study.box
    box = shapely.Polygon(
        [p - n * height / 2, p + u * length - n * height / 2, p + u * length + n * height / 2, p + n * height / 2]
    )
    reach = tr.pair.centre_distance + tr.arm.tip + 100.0
    ground = shapely.box(-2 * reach, soil - 150.0, 2 * reach, soil)
    return {"box": shapely.orient_polygons(box), "soil": ground}


def bodies(study, files: dict[str, bytes], names: dict[str, str]) -> list[Body]:
    """Every body as re-read from its DXF, in its plane, on its link."""
    L, n = study.layers, study.train.planets
    plate, needle = f"{study.name}.arm_plate.dxf", f"{study.name}.needle.dxf"
    specs = [
        ("ring", names["ring"], L.gears, "ring", False),
        ("carrier", names["carrier"], L.carrier, "carrier", False),
    ]
    for k in range(1, n + 1):
        specs += [
            (f"planet_{k}", names["planet"], L.gears, f"planet.{k}", False),
            (f"arm_{k}", plate, L.plates, f"planet.{k}", False),
            (f"needle_{k}", needle, L.needles, f"planet.{k}", False),
        ]
    specs += [(w, f"{study.name}.{w}{OBSTACLE}", L.span, "fixed", False) for w in ("box", "soil")]
    return read_bodies(files, specs)


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
