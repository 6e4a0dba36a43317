"""Seed 002's machine under load (issue 44): the designed motion at carrier 1's 60 r/min (seed 002
§5.1: its ADAMS run, 360 °/s), the masses of the made and bought parts, the cam on the roller.

The model (:func:`model`), read from :class:`~transplanter.machine.carriers.DoubleCarrierMachine`:

* **Moving links** — one per rigid body, the machine's links that are keyed or bolted together
  merged (:data:`RIGID`): carrier 1 (with its hub, front plate, drive tube and standoffs), gears
  3-4 on their shaft, gears 5-9 on theirs, the follower (lever, roller pin, sector 7), carrier 2
  (with sector 8 and its front plate), the idler 10, gear 11 with the arm and the claw. The sun and
  the cam are the frame's. The roller's own spin is left out (a 625 bearing: its mass moves with
  the lever; its outer ring's spin inertia, ~0.2 kg·mm², against the follower's ~200).
* **Motion** — the machine as designed (:attr:`DoubleCarrierMachineStudy.design`: the pairs' design
  motions and keys) with the follower's swing the cam's own law (a quintic periodic spline) instead
  of its sampled table: the five-point stencils of :mod:`~transplanter.machine.dynamics` need
  smooth poses (step :data:`STEP_RAD`); the made parts' micrometre errors are an excitation this
  rigid model leaves out.
* **Pins**, their two supports where the structure placed them (z: the middle of each body):
  carrier 1 in the frame — the drive tube's two wrapped bushes on the fixed shaft (the cover's
  61803 on the fixed shaft's front end is a third support, which makes the carrier's seat
  indeterminate: its share is given to the bushes, the conservative reading for them, and the
  61803 is not rated here); gears 3-4, gears 5-9 and the follower's shaft each in carrier 1 and
  its front plate; carrier 2 on gears 5-9's shaft (sector 8's and carrier 2's bearings); the idler
  and gear 11's shaft each in carrier 2 and its front plate (all 61801-2Z).
* **Meshes** — sun 2 and gear 3, gears 4 and 5 (non-circular: the relative instant centre), the
  sectors 7-8 and the spurs 9-10 and 10-11 (circular, ratio 1: the pitch point in the middle of
  the line of centres — the sectors stop turning against each other where the swing turns back),
  each in its gears' plane at its cutter's pressure angle.
* **The cam on the roller** — a :class:`~transplanter.machine.dynamics.Contact`: along the normal
  to the roller centre's path on the fixed cam (the cam's pitch curve), in the cam's plane; it
  must push (``min_n >= 0``) or the roller leaves the cam: the machine has no return spring.
* **External loads** — gravity along -y (the soil below). Seed 002's pushing spring (2 N/mm, free
  70 mm, 100 N at 25 mm) belongs to the "spring-cam mechanism designed in the planting arm" (§5.1):
  its push rod and spring ride in link 3. The machine here models no push rod (the claw is a plate
  bolted to the arm); read as seed 002 places it — spring, rod and their cam all borne by link 3 —
  the spring is internal to that link and loads no joint of the model. What the rod puts into the
  pot when released, and the seedling's pull-out force, seed 002 does not give: left out.

The record (:func:`study_loads`) is seed 004's (:func:`~transplanter.families.machines.planetary_loads.study_loads`)
with the cam's contact force and the roller bearing's life beside the supports, and the made teeth of
the non-circular meshes under these loads (:mod:`~transplanter.families.machines.carrier_teeth`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.families.machines import carrier_teeth
from transplanter.families.machines import loads as machine_loads_module
from transplanter.families.machines.cantilever import built_in_row
from transplanter.families.machines.loads import (
    POSITIONS,
    drive_rows,
    link_lumps,
    mass_record,
    mesh_rows,
    shaking_record,
    support_rows,
)
from transplanter.families.machines.planetary_loads import loads_picture
from transplanter.families.machines.shafts import KeyJoint, shafts_record
from transplanter.machine.carriers import DoubleCarrierMachine
from transplanter.machine.dynamics import (
    Contact,
    Drive,
    Loads,
    Machine,
    Mesh,
    Pin,
    equivalent_load,
    link_motion,
    solve,
)
from transplanter.proof.tooth_stress import STEEL, hertz_line_contact
from transplanter.shop.catalogue.bearings import LIFE_H, Bearing, rating_life_h

__all__ = ["RIGID", "CamLawMachine", "cam_contact_stress", "model", "study_loads"]

#: the machine's links that move as one body: link -> the link it is keyed or bolted to
RIGID = {
    "sun": "fixed",
    "cam": "fixed",
    "roller": "follower",
    "shaft3b": "shaft3",
    "gear9": "shaft5",
    "sector7": "follower",
    "sector8": "carrier2",
    "arm": "gear11",
}
#: carrier 1's speed (seed 002 §5.1: 60 r/min, 120 plants per minute per row), rad/s
SPEED = 2 * math.pi
#: the stencils' step in carrier 1's turn, rad: the truncation of Newton-Euler against virtual power
#: falls as its cube here (1.4e-5, 1.8e-6, 2.3e-7 of the largest power at 2, 1 and 0.5 mrad)
STEP_RAD = 5e-4


@dataclasses.dataclass(frozen=True)
class CamLawMachine(DoubleCarrierMachine):
    """The machine as designed with the follower's swing the cam's law itself (``law(θ)`` rad) —
    smooth to its fifth derivative, as the loads' stencils need."""

    law: Callable | None = dataclasses.field(default=None, repr=False)

    def _swing(self, theta) -> np.ndarray:
        return np.asarray(self.law(np.mod(theta, 2 * math.pi)), dtype=float)


def loads_machine(study) -> CamLawMachine:
    """:class:`CamLawMachine` of ``study``'s design (module docstring)."""
    design = study.design
    kept = {f.name: getattr(design, f.name) for f in dataclasses.fields(design) if f.init}
    return CamLawMachine(**{**kept, "keys": design.cut_keys}, law=study.cam.motion)


def _rigid(link: str) -> str:
    base = link.split("@", 1)[0]
    return RIGID.get(base, base)


def _mid(placed, name: str) -> float:
    return sum(machine_loads_module.z_span(placed, name)) / 2


def model(study, machine: DoubleCarrierMachine, lumps, placed, bought: dict) -> tuple[Machine, dict]:
    """The machine's dynamic model (module docstring) and each pin's two supports' parts."""
    L = study.layers
    links = {k: machine.links[k] for k in ("fixed", "carrier1", "shaft3", "shaft5", "follower", "carrier2")}
    links.update({k: machine.links[k] for k in ("idler", "gear11")})
    seats = (  # (joint, link a, link b, the supports' bodies)
        ("carrier 1 on the fixed shaft", "fixed", "carrier1", ("bush_tube_1", "bush_tube_2")),
        ("gears 3-4 in carrier 1", "carrier1", "shaft3", ("bearing_carrier_1_3", "bearing_carrier_1_front_3")),
        (
            "the follower in carrier 1",
            "carrier1",
            "follower",
            ("bearing_carrier_1_pivot", "bearing_carrier_1_front_pivot"),
        ),
        ("gears 5-9 in carrier 1", "carrier1", "shaft5", ("bearing_carrier_1_5", "bearing_carrier_1_front_5")),
        ("carrier 2 on gears 5-9's shaft", "shaft5", "carrier2", ("bearing_sector_8_5", "bearing_carrier_2_5")),
        ("the idler in carrier 2", "carrier2", "idler", ("bearing_carrier_2_idler", "bearing_carrier_2_front_idler")),
        (
            "gear 11 and the arm in carrier 2",
            "carrier2",
            "gear11",
            ("bearing_carrier_2_q", "bearing_carrier_2_front_q"),
        ),
    )
    pins, parts = [], {}
    for name, a, b, bodies in seats:
        z = tuple(_mid(placed, body) for body in bodies)
        order = (0, 1) if z[0] <= z[1] else (1, 0)
        pins.append(Pin(name, a, b, (z[order[0]], z[order[1]])))
        parts[name] = tuple(bought[bodies[k]] for k in order)

    def mid(z):
        return (z[0] + z[1]) / 2

    def alpha(what):
        return getattr(study, what).cutter.pressure_angle

    for what in ("sectors", "spurs"):  # circular, ratio 1: the pitch point halfway
        turn = float(getattr(study, what).sized.pair.driven_rotation(np.array([1.0]))[0])
        if abs(turn - 1.0) > 1e-9:
            raise GeometryError(f"{study.name}: the {what} pair is read as ratio 1; it turns {turn:.9g} per rad")
    meshes = (
        Mesh("sun 2 and gear 3", "fixed", "shaft3", mid(L.stage23), alpha("stage23")),
        Mesh("gears 4 and 5", "shaft3", "shaft5", mid(L.stage35), alpha("stage35")),
        Mesh("sectors 7 and 8", "follower", "carrier2", mid(L.sectors), alpha("sectors"), fraction=0.5),
        Mesh("gears 9 and 10", "shaft5", "idler", mid(L.spurs), alpha("spurs"), fraction=0.5),
        Mesh("gears 10 and 11", "idler", "gear11", mid(L.spurs), alpha("spurs"), fraction=0.5),
    )
    cam = Contact("the cam on the roller", "fixed", "follower", mid(L.cam), (study.cam.follower.arm_length, 0.0))
    drives = (Drive("carrier 1's drive tube", "carrier1"),)
    return Machine(links, lumps, tuple(pins), meshes, drives, contacts=(cam,)), parts


def cam_contact_stress(path, theta, force, axis, roller_radius: float, width: float) -> dict:
    """The largest Hertz stress (line contact, both steel) between a fixed disc cam and a roller
    outside it over the positions ``theta`` (rad) where the cam pushes with ``force`` (N, per
    position): ``path`` is the roller centre's position, velocity and acceleration ((n, 2) each,
    :meth:`~transplanter.machine.dynamics.Motion.point`) — its path is the cam's pitch curve, whose
    radius of curvature ``|v|³ / (v × a)`` less the roller's is the profile's at the contact, + where
    it curves round the cam (its centre of curvature on the side of the cam's ``axis``), − where it
    is hollow; ``width`` mm the contact's length.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 6, 7)  # a round cam R35, roller 8: the centre on R43 at 1 rad/s
    >>> e, n = np.stack([np.cos(t), np.sin(t)], axis=1), np.stack([-np.sin(t), np.cos(t)], axis=1)
    >>> row = cam_contact_stress((43 * e, 43 * n, -43 * e), t, np.full(7, 100.0), (0.0, 0.0), 8.0, 5.0)
    >>> row["profile_radius_mm"], round(row["value_mpa"], 1)  # sqrt(F/(pi b) (1/8+1/35) / (2 (1-0.3²)/206 GPa))
    (35.0, 332.7)
    """
    t = np.asarray(theta, dtype=float)
    c0, d1, d2 = (np.asarray(v, dtype=float) for v in path)
    speed = np.linalg.norm(d1, axis=1)
    kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed**3  # + turning left
    left = np.stack([-d1[:, 1], d1[:, 0]], axis=1) / speed[:, None]
    cam_side = np.sign(np.einsum("ij,ij->i", left, np.asarray(axis, dtype=float)[None, :] - c0))
    with np.errstate(divide="ignore"):
        pitch = np.where(kappa != 0.0, cam_side * np.sign(kappa) / np.abs(kappa), np.inf)
    profile = pitch - roller_radius
    best = None
    for k in np.flatnonzero(np.asarray(force) > 0.0):
        c = hertz_line_contact(float(force[k]), width, roller_radius, float(profile[k]), STEEL, STEEL)
        if best is None or c.sigma_h > best[0]:
            best = (c.sigma_h, k)
    if best is None:
        return {"value_mpa": 0.0, "reading": "the cam never pushes"}
    k = best[1]
    return {
        "value_mpa": rounded(best[0], 4),
        "at_driver_deg": round(float(np.degrees(t[k])), 4),
        "force_n": rounded(float(force[k]), 4),
        "profile_radius_mm": rounded(float(profile[k]), 4),
        "least_convex_profile_radius_mm": rounded(float(np.min(np.where(profile > 0, profile, np.inf))), 4),
    }


def _roller_row(study, m: Machine, loads, roller, life_h: float) -> dict:
    """The cam's force on the roller over the cycle and the roller bearing's ISO 281 life (its outer
    ring rolling on the cam: turning at the roller centre's speed along the cam over its radius,
    relative to the lever)."""
    f = loads.contact[:, 0]
    k, j = int(np.argmax(f)), int(np.argmin(f))
    cam = m.contacts[0]
    # the roller centre's path and its derivatives: the follower's motion at the roller's axle
    lever = link_motion(m.links["follower"], loads.theta, loads.speed)
    path = lever.point(np.asarray(cam.point, dtype=float))
    centre, velocity = path[0], path[1]
    v, w = np.linalg.norm(velocity, axis=1), lever.w
    line = loads.contact_line[:, 0]
    sense = np.sign(np.einsum("ij,ij->i", velocity, np.stack([line[:, 1], -line[:, 0]], axis=1)))
    rpm = np.abs(sense * v / study.cam.follower.roller_radius - w) * 60 / (2 * math.pi)
    bearing = getattr(roller, "bearing", roller)
    row = {
        "contact": cam.name,
        "max_n": rounded(float(f[k]), 4),
        "at_driver_deg": round(float(np.degrees(loads.theta[k])), 4),
        "min_n": rounded(float(f[j]), 4),
        "min_at_driver_deg": round(float(np.degrees(loads.theta[j])), 4),
        "stays_on_the_cam": bool(f[j] >= 0.0),
    }
    if f[j] < 0.0:  # nothing holds the roller on: what a return spring on the lever must give
        d = centre - lever.o  # from the lever's pivot
        arm = np.abs(d[:, 0] * line[:, 1] - d[:, 1] * line[:, 0])  # the contact line's lever about the pivot, mm
        need = np.maximum(-f, 0.0) * arm * 1e-3
        i = int(np.argmax(need))
        row["return_torque_needed_nm"] = rounded(float(need[i]), 4)
        row["return_torque_at_driver_deg"] = round(float(np.degrees(loads.theta[i])), 4)
    if isinstance(bearing, Bearing):  # the Hertz stress of the roller on the cam, over the roller's width
        axis = np.asarray([float(np.ravel(v)[0]) for v in m.links[cam.a].pose(np.zeros(1))[:2]])
        width = min(float(bearing.B), float(study.layers.cam[1] - study.layers.cam[0]))
        row["contact_stress"] = {
            **cam_contact_stress(path, loads.theta, f, axis, study.cam.follower.roller_radius, width),
            "width_mm": width,
            "method": "Hertz line contact, steel on steel (E 206 GPa, nu 0.3), nominal; no allowable stated",
        }
        p = equivalent_load(np.maximum(f, 0.0), rpm)
        life = rating_life_h(bearing.C_n, p, float(np.mean(rpm))) if p > 0 else math.inf
        row.update(
            {
                "roller": bearing.designation,
                "roller_mean_rpm": rounded(float(np.mean(rpm)), 4),
                "roller_equivalent_load_n": rounded(p, 4),
                "roller_life_h": rounded(life, 4) if math.isfinite(life) else "inf",
                "required_life_h": life_h,
                "pass": bool(f[j] >= 0.0 and life >= life_h),
            }
        )
    return row


def machine_loads(m: Machine) -> Loads:
    """:func:`~transplanter.families.machines.loads.machine_loads` at :data:`STEP_RAD`: the loads
    over carrier 1's turn at :data:`SPEED`, Newton-Euler held to virtual power."""
    loads = solve(m, 2 * math.pi * np.arange(POSITIONS) / POSITIONS, SPEED, STEP_RAD)
    if loads.power_error > machine_loads_module.POWER_AGREEMENT:
        raise GeometryError(
            f"the drive's power by Newton-Euler and the energy rate by virtual power differ by {loads.power_error:.3g} "
            f"of the largest power (> {machine_loads_module.POWER_AGREEMENT:g}): a joint does work"
        )
    return loads


def study_loads(study, placed, bom, links_of: dict, pose_of, bought_bodies, teeth=None):
    """The record of seed 002's machine under load and its picture's files: ``placed``/``bom`` the
    assembly's bodies and bill, ``links_of`` body -> link, ``pose_of(link)`` its pose at the start
    (x, y, angle), ``bought_bodies`` the :class:`~transplanter.families.machines.assembly.BoughtBody` s;
    ``teeth`` (the family's files, the bodies naming them: :func:`carrier_posing.body_specs`): the
    made teeth of the non-circular meshes rated too (:func:`carrier_teeth.teeth_records`)."""
    rigid = {body: _rigid(link) for body, link in links_of.items()}
    lumps = link_lumps(placed, bom, rigid, pose_of)
    bought = {b.name: b.part for b in bought_bodies}
    machine = loads_machine(study)
    m, parts = model(study, machine, lumps, placed, bought)
    loads = machine_loads(m)
    life_h = getattr(study.structure, "life_h", LIFE_H)
    supports = support_rows(m, loads, parts, life_h)
    cam = _roller_row(study, m, loads, bought.get("roller"), life_h)
    record = {
        "reading": (
            f"the designed motion (the cam's law as the swing) at carrier 1's {SPEED * 30 / math.pi:g} r/min (seed "
            "002 §5.1), the masses of the made and bought parts, gravity; seed 002's pushing spring works inside the "
            "planting arm (its push rod, not modelled): internal to link 3, it loads no joint here; no pull-out or "
            "pushing force given by the seed; carrier 1's seat: the drive tube's two bushes (the cover's bearing on "
            "the fixed shaft's end taking no share: the bushes' conservative reading); planar: no axial load"
        ),
        "positions": int(loads.theta.size),
        "power_agreement": {
            "newton_euler_vs_virtual_power_rel": float(f"{loads.power_error:.3e}"),
            "required": machine_loads_module.POWER_AGREEMENT,
        },
        "mass": mass_record(lumps),
        "drives": drive_rows(m, loads),
        "meshes": mesh_rows(m, loads),
        "cam": cam,
        "supports": supports,
        "shaking": shaking_record(loads),
    }
    if teeth is not None:
        record["teeth"] = carrier_teeth.teeth_records(study, machine, m, loads, *teeth)
    keys, shafts = _key_joints()
    record["keys_and_shafts"] = shafts_record(m, loads, placed, bom, bought, rigid, pose_of, keys, shafts)
    # the fixed central shaft: built into the frame, rated as a cantilever (cantilever module docstring)
    record["built_in_shaft"] = built_in_row(
        m,
        loads,
        placed,
        bom,
        "shaft_main",
        "frame",
        ("carrier 1 on the fixed shaft", "sun 2 and gear 3"),
        ("sun 2 and gear 3", float(study.stage23.sized.sizing.module)),
        keys=("key_frame", "key_sun"),
        why=(
            "built in, not held at both ends: carrier 1 turns round the shaft through the whole circle in every "
            "plane in front of the frame, so nothing of the frame reaches its front end (the front plate's bearing "
            "there is a seat of carrier 1)"
        ),
    )
    return record, loads_picture(study.name, m, loads)


def _key_joints() -> tuple[list[KeyJoint], list[str]]:
    """Seed 002's keys — what each joins, what its torque is — and the turned shafts that turn (the
    fixed main shaft, built into the frame, is rated as a cantilever: :func:`built_in_row`)."""
    k = KeyJoint
    keys = [
        k("key_sun", "shaft_main", "sun", joints=("sun 2 and gear 3",)),
        k("key_frame", "shaft_main", "frame", hub_bodies=("sun",), joints=("sun 2 and gear 3",)),
        k("key_input", "drive_tube", None, drive="carrier 1's drive tube"),
        k("key_hub", "drive_tube", "hub", drive="carrier 1's drive tube"),
        k("key_gear_3", "shaft_3", "gear_3", joints=("sun 2 and gear 3",)),
        k("key_gear_4", "shaft_3", "gear_4", joints=("gears 4 and 5",)),
        k("key_gear_5", "shaft_5", "gear_5", joints=("gears 4 and 5",)),
        k("key_gear_9", "shaft_5", "gear_9", joints=("gears 9 and 10",)),
        k("key_gear_10", "shaft_idler", "gear_10", joints=("gears 9 and 10", "gears 10 and 11")),
        k("key_gear_11", "shaft_q", "gear_11", joints=("gears 10 and 11",)),
        k("key_arm", "shaft_q", "arm", hub_bodies=("arm", "claw")),
        k(
            "key_lever",
            "shaft_pivot",
            "lever",
            hub_bodies=("lever", "roller_pin", "spacer_roller", "roller", "ring_roller"),
            joints=("the cam on the roller",),
        ),
        k("key_sector_7", "shaft_pivot", "sector_7", joints=("sectors 7 and 8",)),
    ]
    return keys, ["shaft_3", "shaft_5", "shaft_idler", "shaft_q", "shaft_pivot", "drive_tube"]
