"""Seed 002's machine posed from the files of its family's earlier parts: each pair's made mesh (the
meshing its proof measured on the re-read DXFs), the follower run again on the re-read cam, the
machine as designed (what the parts are drawn from and keyed for), the soil, and the bodies in their
planes on their links with what joins them.

The functions take the :class:`~transplanter.families.machines.carrier_machine.DoubleCarrierMachineStudy`
(``study``) that states the machine.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.families.machines import carrier_making
from transplanter.families.machines.carrier_making import BOUGHT
from transplanter.families.machines.carrier_structure import cam_angle
from transplanter.families.machines.record import OBSTACLE, obstacle_file
from transplanter.families.pairs.pair_assembly import read_meshing_csv
from transplanter.machine import tray
from transplanter.machine.bodies import MOTION_POSITIONS
from transplanter.machine.carriers import CarrierLayout, DoubleCarrierMachine, MadeMesh
from transplanter.proof import follower
from transplanter.shop import formats

__all__ = [
    "JOINED",
    "NOT_GEARBOX",
    "body_specs",
    "design",
    "layout",
    "links",
    "made_machine",
    "meshes",
    "soil",
    "span",
    "tray_files",
    "tray_place",
    "tray_specs",
    "tray_z",
]


def meshes(study, files: dict[str, bytes]) -> dict[str, MadeMesh]:
    """Each pair's made mesh: its design pair turned by the meshing its proof measured on the
    re-read DXFs (``<pair>.dxf_meshing.csv``)."""
    out = {}
    for what in ("stage23", "stage35", "sectors", "spurs"):
        pair = getattr(study, what)
        table = f"{pair.name}.dxf_meshing.csv"
        if table not in files:
            raise GeometryError(f"{study.name}: the machine is posed from {table}, which is not there")
        angle, error = read_meshing_csv(files[table])
        out[what] = MadeMesh(pair.sized.pair, angle, error)
    return out


def layout(study) -> CarrierLayout:
    """Where the shafts sit: the chain's link lengths and the pairs' and the cam's centre distances."""
    l1, l2, _ = study.chain.link_lengths
    return CarrierLayout.solve(
        l1,
        l2,
        study.stage23.sized.pair.centre_distance,
        study.stage35.sized.pair.centre_distance,
        study.cam.follower.pivot_distance,
        study.sectors.sized.pair.centre_distance,
        study.spurs.sized.pair.centre_distance,
    )


def design(study) -> DoubleCarrierMachine:
    """The machine as designed: the pairs' design motions, the cam's law — what the parts are
    drawn from and their keys are cut for."""
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    return DoubleCarrierMachine(
        study.chain,
        layout(study),
        *(MadeMesh(getattr(study, w).sized.pair) for w in ("stage23", "stage35", "sectors", "spurs")),
        study.cam.follower,
        theta,
        np.asarray(study.cam.motion(theta), dtype=float),
    )


def made_machine(study, files: dict[str, bytes]) -> tuple[DoubleCarrierMachine, dict]:
    """The machine posed from the made meshes and the follower run on the re-read cam, keyed
    as the parts are cut (the design's keys)."""
    made = meshes(study, files)
    cam = f"{study.cam.name}.cam.dxf"
    if cam not in files:
        raise GeometryError(f"{study.name}: the machine is posed from {cam}, which is not there")
    contour = formats.section_of(cam, files[cam])
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    run = follower.follower_check(contour, study.cam.motion, study.cam.follower, MOTION_POSITIONS)
    machine = DoubleCarrierMachine(
        study.chain,
        study.design.layout,
        made["stage23"],
        made["stage35"],
        made["sectors"],
        made["spurs"],
        study.cam.follower,
        theta,
        run.actual,
        study.design.cut_keys,
    )
    return machine, {"follower_on_the_cam_dxf_max_error_mm": rounded(run.max_error, 6)}


def span(study) -> tuple[float, float]:
    """Across the whole machine, the structure too (the soil lies across it), mm: 10 mm beyond the
    outermost planes."""
    S = study.structure
    zs = [*study.layers.span, S.frame[0] - 10.0, S.front[1] + 10.0]
    return min(zs), max(zs)


def soil(study) -> shapely.Polygon:
    """The soil below its surface, ``planting_depth`` above the design tip's deepest point."""
    theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    deepest = float(study.design.tip(theta)[:, 1].min())
    level = deepest + study.planting_depth
    reach = 400.0
    return shapely.box(-reach, level - 150.0, reach, level)


def body_specs(study) -> list[tuple[str, str, tuple[float, float], str, bool]]:
    """Every body the machine is judged on: ``(name, DXF, plane, link, mirrored)``
    (:func:`~transplanter.families.machines.record.read_bodies`)."""
    L, S, n = study.layers, study.structure, study.parts
    s23, s35, sp = study.stage23.name, study.stage35.name, study.spurs.name
    specs = [
        ("carrier_1", f"{n}.carrier_1.dxf", L.carrier1, "carrier1", False),
        ("cam", f"{study.cam.name}.cam.dxf", L.cam, "cam", False),
        ("lever", f"{n}.lever.dxf", L.lever, "follower", False),
        ("roller", f"{n}.roller{BOUGHT}", carrier_making.roller_z(study.layers), "roller", False),
        ("sun", f"{s23}.driver.dxf", L.stage23, "sun", False),
        ("gear_3", f"{s23}.driven.dxf", L.stage23, "shaft3", False),
        ("gear_4", f"{s35}.driver.dxf", L.stage35, "shaft3b", False),
        ("gear_5", f"{s35}.driven.dxf", L.stage35, "shaft5", False),
        ("sector_7", f"{n}.sector_7.dxf", L.sectors, "sector7", False),
        ("sector_8", f"{n}.sector_8.dxf", L.sectors, "sector8", False),
        ("carrier_2", f"{n}.carrier_2.dxf", L.carrier2, "carrier2", False),
        ("gear_9", f"{sp}.driver.dxf", L.spurs, "gear9", False),
        ("gear_10", f"{sp}.driven.dxf", L.spurs, "idler", False),
        ("gear_11", f"{sp}.driver.dxf", L.spurs, "gear11", False),
        ("arm", f"{n}.arm.dxf", L.arm, "arm", False),
        ("claw", f"{n}.claw.dxf", L.claw, "arm", False),
        # the structure's plates (carrier_structure): the frame, carrier 1's hub and both front plates
        ("frame", f"{n}.frame.dxf", S.frame, "fixed", False),
        ("hub", f"{n}.hub.dxf", S.hub, "carrier1", False),
        ("carrier_1_front", f"{n}.carrier_1_front.dxf", S.cover, "carrier1", False),
        ("carrier_2_front", f"{n}.carrier_2_front.dxf", S.front, "carrier2", False),
        ("soil", f"{study.name}.soil{OBSTACLE}", span(study), "fixed", False),
    ]
    # mounted face down: the pairs seen from their backs (carriers module docstring)
    return [(*spec[:4], spec[3] in carrier_making.MIRRORED) for spec in specs]


#: bodies joined by a mesh, a contact, a shaft, a key or bolts (not judged against each other)
JOINED = (
    ("sun", "gear_3"),
    ("gear_4", "gear_5"),
    ("cam", "roller"),
    ("sector_7", "sector_8"),
    ("gear_9", "gear_10"),
    ("gear_10", "gear_11"),
    ("arm", "claw"),
)
#: the gearbox: what must keep ``gearbox_above_soil`` from the soil (all but the arm and claw)
NOT_GEARBOX = ("arm", "claw", "soil")


def links(study, machine: DoubleCarrierMachine) -> dict:
    """The links the bodies ride on: the machine's, with the cam fixed at its angle and the roller
    on the lever."""
    out = dict(machine.links)
    # the cam is fixed to the frame at its own angle; the roller turns on the lever's pin
    # (a circle: only its centre's path matters, posed on the lever's frame)
    angle = cam_angle(machine)
    out["cam"] = dataclasses.replace(out["carrier1"], name="cam", pose=lambda t: _still(t, angle), turn_rate=0.0)
    out["roller"] = out["follower"]
    return out


def tray_place(study, machine: DoubleCarrierMachine) -> tuple[np.ndarray, float]:
    """The picked pot's mouth (x, y mm) and axis (rad, into the pot): the claw grips its seedling at
    Table 1's pose 2 (seed 002's end of picking seedling), so the pot is where the claw's tip is
    then, ``pot_depth`` (seed 002 requirement 3: 30 mm) down its axis; the axis is the tray's normal at
    its inclination, on the side the claw points to there."""
    tau = np.array([float(study.chain.pose_tau[1])])
    tip = machine.tip(tau)[0]
    att = float(machine.poses(tau)["arm"][2][0])
    return tray.pot_place(study.tray.inclination_deg, tip, att, study.pot_depth)


def tray_z(study) -> tuple[tuple[float, float], tuple[float, float]]:
    """The tray's z-range and its picked pot's: in front of the gearbox by the minimum axial gap, the
    picked column first, the claw's plane inside it (mm). The tray is as wide as 8 columns (the
    128-cell tray's 8 across); its picked cell is cut through its middle (``tray`` docstring)."""
    t = study.tray
    back = study.structure.front[1] + study.layers.min_axial_gap
    return (back, back + 8 * t.pitch), (back, back + t.top)


def tray_files(study) -> dict[str, bytes]:
    """The tray's walls and the picked pot's soil as obstacles in the machine frame."""
    mouth, axis = tray_place(study, study.design)
    (tz, pz) = tray_z(study)
    out = obstacle_file(study.name, "tray", study.tray.walls(mouth, axis), tz)
    out.update(obstacle_file(study.name, "pot", study.tray.pot(mouth, axis), pz))
    return out


def tray_specs(study) -> list[tuple[str, str, tuple[float, float], str, bool]]:
    """The tray's bodies as :func:`body_specs` states bodies."""
    tz, pz = tray_z(study)
    return [
        ("tray", f"{study.name}.tray{OBSTACLE}", tz, "fixed", False),
        ("pot", f"{study.name}.pot{OBSTACLE}", pz, "fixed", False),
    ]


def _still(theta, angle: float):
    z = np.zeros_like(np.asarray(theta, dtype=float))
    return z, z, z + angle
