"""Seed 004's machine under load (issue 44): its designed motion at the carrier's speed, the
masses of its made and bought parts, the needle's work.

The model (:func:`model`): the ring, the carrier and each planet as moving links (the designed
train: :class:`~transplanter.machine.bodies.PlanetaryMachine` of the study's train); the ring in
the frame's two bearings, the carrier's shaft in the ring shaft's two bushes, each planet's shaft in
its two carrier plates' bearings (:class:`~transplanter.machine.dynamics.Pin`, the supports' z from
the assembly); the ring's teeth on each planet's in the gears' plane at the cutter's pressure angle
(:class:`~transplanter.machine.dynamics.Mesh`); two motors, the ring's and the carrier's. The ring
turns at ``ω1/ω2`` of the carrier; the carrier at the train's ``carrier_speed`` (60 r/min: the
speed its planting metrics are computed at, 3 plants per turn).

External load — **a stated assumption** (seed 004 gives no force): the structure's
``needle_force_n`` at each needle tip, against the tip's motion, while the tip is below the soil
surface (planting); gravity along -y. Picking from the mat and the seedling's own weight are left
out (a seedling of a few grams).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import optimize

from transplanter.core.precision import rounded
from transplanter.families.machines import loads as machine_loads_module
from transplanter.families.machines.loads import (
    drive_rows,
    link_lumps,
    link_of,
    machine_loads,
    mass_record,
    mesh_rows,
    shaking_record,
    support_rows,
    z_span,
)
from transplanter.families.machines.shafts import KEY_SAFETY, SHAFT_SAFETY, KeyJoint, shafts_record
from transplanter.machine.bodies import PlanetaryMachine
from transplanter.machine.dynamics import Drive, Loads, Machine, Mesh, Pin, PointLoad
from transplanter.proof.mesh_cycle import mesh_cycle_load
from transplanter.report.figure import figure_files, plt, size, styled
from transplanter.shop import formats

__all__ = [
    "CAPACITY_TOL_N",
    "model",
    "study_loads",
    "teeth_record",
    "keys_and_shafts",
    "needle_capacity",
    "loads_picture",
]

#: the needle force capacity is found to this, N
CAPACITY_TOL_N = 0.5


def _work(force_n: float, soil: float, travel: float):
    """The needle's work: ``force_n`` against the tip's motion through the soil (its velocity in the
    machine frame plus the machine's travel, ``travel`` mm/s along x) while it is below ``soil``."""

    def force(theta, pos, vel):
        through = vel + np.array([travel, 0.0])
        speed = np.linalg.norm(through, axis=1)
        inside = (pos[:, 1] < soil) & (speed > 0)
        unit = np.divide(through, speed[:, None], out=np.zeros_like(through), where=speed[:, None] > 0)
        return -force_n * unit * inside[:, None]

    return force


def model(study, lumps, placed, bought: dict, metrics, needle_force: float | None = None) -> tuple[Machine, dict]:
    """The machine's dynamic model (module docstring) and each pin's two supports' parts; the
    needle's work force ``needle_force`` N (None: the structure's stated one)."""
    work = study.structure.needle_force_n if needle_force is None else needle_force
    tr = study.train
    links = PlanetaryMachine(tr).links
    mid = {name: sum(z_span(placed, name)) / 2 for name in bought}
    pins = [Pin("ring in the frame", "fixed", "ring", (mid["frame_bearing_rear"], mid["frame_bearing_front"]))]
    parts = {pins[0].name: (bought["frame_bearing_rear"], bought["frame_bearing_front"])}
    pins.append(Pin("carrier in the ring shaft", "ring", "carrier", (mid["bush_rear"], mid["bush_front"])))
    parts[pins[1].name] = (bought["bush_rear"], bought["bush_front"])
    meshes, loads = [], []
    z_gear = sum(study.layers.gears) / 2
    alpha = study.pair.cutter.pressure_angle
    tip = tuple(float(v) for v in study.arm.tip)
    for k in range(1, tr.planets + 1):
        planet = f"planet.{k}"
        z = (mid[f"bearing_rear_{k}"], mid[f"bearing_front_{k}"])
        pin = Pin(f"planet {k} in the carrier", "carrier", planet, z)
        pins.append(pin)
        parts[pin.name] = (bought[f"bearing_rear_{k}"], bought[f"bearing_front_{k}"])
        meshes.append(Mesh(f"ring and planet {k}", "ring", planet, z_gear, alpha, ring="a"))
        force = _work(work, metrics.soil_level, metrics.travel_direction * metrics.forward_speed)
        loads.append(PointLoad(f"needle {k} in the soil", planet, tip, sum(study.layers.needles) / 2, force))
    drives = (Drive("ring motor", "ring"), Drive("carrier motor", "carrier"))
    return Machine(links, lumps, tuple(pins), tuple(meshes), drives, tuple(loads)), parts


def teeth_record(study, m: Machine, loads: Loads, files: dict[str, bytes], names: dict, module: float) -> dict:
    """The made teeth under the mesh's load over the cycle (:func:`transplanter.proof.mesh_cycle.mesh_cycle_load`):
    the ring and planet 1 re-read from their DXFs, the planet turned from its designed angle until
    its flank closes on the ring's against the torque the mesh puts on it (the pitch-point force
    times its lever about the planet's centre), every contact rated — the force there (that torque
    over the contact normal's lever), Hertz with both flanks' radii, the ISO 6336-3 30° root stress
    of both loaded teeth. Planets 2 and 3 are planet 1 turned by 120° of carrier (the train's
    arms are copies: ``phase_error``). Nominal stresses: every ISO factor 1; two pairs in contact
    each carry the whole load. The gears are C45 (the bill of materials): the catalogue has no ISO
    6336-5 allowable for it that can be cited, so no safety factor is stated — the record says
    what the material must allow."""
    ring_section = formats.section_of(names["ring"], files[names["ring"]], layer=formats.CUT)
    planet_section = formats.section_of(names["planet"], files[names["planet"]], layer=formats.CUT)
    ring = np.asarray(max(ring_section.interiors, key=lambda r: len(r.coords)).coords)  # the toothed hole
    planet = np.asarray(planet_section.exterior.coords)
    j = 0
    line, pitch = loads.mesh_line[:, j], loads.pitch_point[:, j]
    x, y, a = (
        np.broadcast_to(np.asarray(v, dtype=float), loads.theta.shape) for v in m.links["planet.1"].pose(loads.theta)
    )
    centre = np.stack([x, y], axis=1)
    arm = pitch - centre
    torque = loads.mesh[:, j] * (arm[:, 0] * line[:, 1] - arm[:, 1] * line[:, 0])  # N mm, counter-clockwise +
    a_ring = np.broadcast_to(np.asarray(m.links["ring"].pose(loads.theta)[2], dtype=float), loads.theta.shape)
    res = mesh_cycle_load(
        (ring, planet),
        ((np.zeros_like(centre), a_ring), (centre, a)),
        torque,
        width=study.pair.making[0].width,
        module=module,
        pressure_angle=math.degrees(study.pair.cutter.pressure_angle),
        theta=loads.theta,
    )
    out: dict = {
        "mesh": m.meshes[j].name,
        "reading": (
            "the made teeth closed against the mesh torque at each position, every contact rated: the force "
            "there (torque over the contact normal's lever), Hertz with both flanks' local radii, ISO 6336-3's 30° "
            "tangent root section on each loaded tooth's actual outline (Y_F, Y_S measured on it); nominal "
            "(every ISO factor 1), two pairs in contact each taking the whole load; planets 2 and 3 are planet 1 "
            "turned by 120° of carrier"
        ),
        "positions_with_two_contacts": int(np.sum(res.contacts >= 2)),
        "closing_turn_deg": [round(float(np.degrees(res.turn.min())), 4), round(float(np.degrees(res.turn.max())), 4)],
        "max_force_n": rounded(float(np.nanmax(res.force)), 4),
        "note": res.note,
    }
    if res.max_sigma_h is not None:
        out["max_contact_stress_mpa"] = _peak(res.max_sigma_h)
    for name, peak in zip(("max_root_stress_ring_mpa", "max_root_stress_planet_mpa"), res.max_sigma_f, strict=True):
        if peak is not None:
            out[name] = _peak(peak)
    need_h = out.get("max_contact_stress_mpa", {}).get("value")
    need_f = max(
        (out[k]["value"] for k in ("max_root_stress_ring_mpa", "max_root_stress_planet_mpa") if k in out), default=None
    )
    out["material"] = {
        "gears": "C45 (the bill of materials)",
        "allowables": None,
        "why": (
            "no ISO 6336-5 allowable for C45 (through-hardened carbon steel) could be read from a source that "
            "can be cited"
        ),
        "needs_sigma_hlim_mpa_at_least": need_h,
        "needs_sigma_fe_mpa_at_least": need_f,
    }
    return out


def _peak(p) -> dict:
    pl = p.place
    return {
        "value": rounded(float(p.value), 4),
        "at_driver_deg": round(float(p.theta), 4),
        "force_n": rounded(float(pl.load.force), 4),
        "ring_tooth_deg": round(float(pl.teeth[0]), 4),
        "ring_flank": pl.flanks[0],
        "planet_tooth_deg": round(float(pl.teeth[1]), 4),
        "planet_flank": pl.flanks[1],
    }


def study_loads(study, placed, bom, links_of: dict, pose_of, bought_bodies, metrics, teeth=None):
    """The record of seed 004's machine under load and its picture's files; ``teeth`` (the family's
    files, the names of its ring's and planet's DXFs, the module): the made teeth rated too."""
    lumps = link_lumps(placed, bom, links_of, pose_of)
    bought = {b.name: b.part for b in bought_bodies}
    m, parts = model(study, lumps, placed, bought, metrics)
    speed = study.train.carrier_speed
    loads = machine_loads(m, speed)
    idle = machine_loads(dataclasses.replace(m, loads=()), speed)  # inertia and gravity alone
    record = {
        "reading": (
            f"the designed motion at the carrier's {speed * 30 / math.pi:g} r/min (the ring at "
            f"{abs(study.train.omega_ratio) * speed * 30 / math.pi:g} r/min), the masses of the made and bought "
            f"parts, gravity and a stated needle force of {study.structure.needle_force_n:g} N against the tip's "
            "motion through the soil (below its surface, the machine travelling) — seed 004 gives none; "
            "planar: no axial load (spur teeth, gravity in the plane); the supports' shares from the moments "
            "about x and y"
        ),
        "positions": int(loads.theta.size),
        "power_agreement": {
            "newton_euler_vs_virtual_power_rel": float(f"{loads.power_error:.3e}"),
            "required": machine_loads_module.POWER_AGREEMENT,
        },
        "mass": mass_record(lumps),
        "drives": drive_rows(m, loads, idle),
        "meshes": mesh_rows(m, loads),
        "supports": support_rows(m, loads, parts, study.structure.life_h),
        "shaking": shaking_record(loads),
    }
    if teeth is not None:
        record["teeth"] = teeth_record(study, m, loads, *teeth)
    ks = (placed, bom, bought, links_of, pose_of)
    record["keys_and_shafts"] = keys_and_shafts(study, m, loads, *ks)
    if not record["keys_and_shafts"]["pass"]:
        record["keys_and_shafts"]["needle_force_capacity"] = needle_capacity(
            study, lumps, metrics, ks, record["keys_and_shafts"]
        )
    return record, loads_picture(study.name, m, loads)


def _key_joints(study, m: Machine, placed, links_of) -> tuple[list[KeyJoint], list[str]]:
    """Seed 004's keys — what each joins and what its torque is — and its turned shafts."""
    names = {p.name for p in placed}
    keys = []
    for k in range(1, study.train.planets + 1):
        keys.append(KeyJoint(f"key_planet_{k}", f"planet_shaft_{k}", f"planet_{k}", joints=(f"ring and planet {k}",)))
        arm = tuple(
            n
            for n in sorted(names)
            if n in (f"arm_{k}", f"needle_{k}") or n.startswith((f"needle_spacer_{k}_", f"screw_needle_{k}_"))
        )
        keys.append(
            KeyJoint(
                f"key_arm_{k}", f"planet_shaft_{k}", f"arm_{k}", hub_bodies=arm, joints=(f"needle {k} in the soil",)
            )
        )
    carrier = ("carrier", "carrier_rear")
    plates = tuple(
        n
        for n in sorted(names)
        if link_of(links_of[n]) == "carrier"
        and (n in carrier or n.startswith(("carrier_tube", "tie_screw", "bearing_", "bore_circlip")))
    )
    pins = tuple(p.name for p in m.pins if p.a == "carrier")
    keys += [KeyJoint(f"key_{c}", "carrier_shaft", c, hub_bodies=plates, joints=pins) for c in carrier]
    keys.append(KeyJoint("carrier_drive_key", "carrier_shaft", None, drive="carrier motor"))
    ring = tuple(
        n
        for n in sorted(names)
        if n in ("ring", "ring_spacer", "ring_flange") or n.startswith(("ring_screw", "flange_screw"))
    )
    meshes = tuple(x.name for x in m.meshes)
    keys.append(KeyJoint("key_ring_flange", "ring_shaft", "ring_flange", hub_bodies=ring, joints=meshes))
    keys.append(KeyJoint("ring_drive_key", "ring_shaft", None, drive="ring motor"))
    shafts = [f"planet_shaft_{k}" for k in range(1, study.train.planets + 1)] + ["carrier_shaft", "ring_shaft"]
    return keys, shafts


def keys_and_shafts(study, m: Machine, loads: Loads, placed, bom, bought, links_of, pose_of) -> dict:
    """Every key and turned shaft of seed 004 under ``loads``
    (:func:`~transplanter.families.machines.shafts.shafts_record`)."""
    keys, shafts = _key_joints(study, m, placed, links_of)
    return shafts_record(m, loads, placed, bom, bought, links_of, pose_of, keys, shafts)


def _margin(rec: dict) -> tuple[float, str]:
    """The least safety over the required one, less 1 (>= 0: every key and shaft passes), and where."""
    rows = [(float(r["safety"]) / KEY_SAFETY, r["key"]) for r in rec["keys"]]
    rows += [
        (min(float(r["fatigue_safety"]), float(r["yield_safety"])) / SHAFT_SAFETY, f"{r['shaft']} ({r['section']})")
        for r in rec["shafts"]
    ]
    low = min(rows)
    return low[0] - 1.0, low[1]


def needle_capacity(study, lumps, metrics, ks, at_stated: dict | None = None) -> dict:
    """The largest needle force (N) every key and shaft carries (Brent's method, to
    :data:`CAPACITY_TOL_N`, on the required safety over the least one, less 1 — nearly linear in the
    force, as a key's pressure is: a few solves): what the machine as drawn carries when the stated
    force is more than that. ``at_stated``: the keys and shafts record at the stated force, if known."""
    placed, bom, bought, links_of, pose_of = ks
    speed = study.train.carrier_speed
    stated = study.structure.needle_force_n
    known: dict[float, tuple[float, str]] = {}
    if at_stated is not None:
        known[stated] = _margin(at_stated)

    def margin(force: float) -> tuple[float, str]:
        if force not in known:
            m, _ = model(study, lumps, placed, bought, metrics, needle_force=force)
            known[force] = _margin(keys_and_shafts(study, m, machine_loads(m, speed), *ks))
        return known[force]

    low, where = margin(0.0)
    if low < 0.0:
        return {"n": 0.0, "limited_by": where, "reading": "short under the links' inertia and weight alone"}
    found = optimize.brentq(lambda f: 1.0 - 1.0 / (1.0 + margin(f)[0]), 0.0, stated, xtol=CAPACITY_TOL_N)
    carried = math.floor(found / CAPACITY_TOL_N) * CAPACITY_TOL_N
    left, where = margin(carried)
    return {
        "n": carried,
        "limited_by": where,  # the least safety there: the first to fall short above it
        "least_margin_there": rounded(left, 4),
        "stated_n": stated,
        "reading": (
            f"the largest needle force (to {CAPACITY_TOL_N:g} N) at which every key and shaft keeps its required "
            "safety, by Brent's method on the least safety (checked there)"
        ),
    }


@styled
def loads_picture(name: str, m: Machine, loads: Loads) -> dict[str, bytes]:
    """``<name>.loads.png`` (and ``.svg``): the drives' torque over the carrier's turn and the
    frame's shaking force, polar (its tip over the turn)."""
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=size(3.4))
    deg = np.degrees(loads.theta)
    for i, d in enumerate(m.drives):
        ax.plot(deg, loads.torque[:, i], lw=1.0, label=d.name)
    ax.set_xlabel("carrier turn (deg)")
    ax.set_ylabel("drive torque (N m)")
    ax.set_xticks([0, 90, 180, 270, 360])
    ax.grid(True, lw=0.3)
    ax.legend(loc="best")
    f = loads.shaking_force
    ax2.plot(np.append(f[:, 0], f[0, 0]), np.append(f[:, 1], f[0, 1]), lw=1.0)
    ax2.plot([0.0], [0.0], "k+")
    ax2.set_aspect("equal", adjustable="datalim")
    ax2.set_xlabel("shaking force x (N)")
    ax2.set_ylabel("y (N)")
    ax2.grid(True, lw=0.3)
    ax2.set_title("shaking force on the frame")
    fig.tight_layout()
    return figure_files(fig, f"{name}.loads")
