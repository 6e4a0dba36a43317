"""Seed 004's structure as files and records: the made plates with their drawings' notes, the
turned parts' drawings, the bought parts drawn for the judge, the seedling box and the soil, and the
record of loads, speeds, bearings, planes and drives (:mod:`planetary_structure` designs it).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.families.builder.making import Making, manufacture
from transplanter.families.machines import planetary_posing
from transplanter.families.machines.assembly import MadeBody
from transplanter.families.machines.planetary_axis import main_axis
from transplanter.families.machines.planetary_structure import (
    CLEARANCE_HOLE,
    TAP_DRILL,
    Collected,
    Design,
    Plate,
    planet_shafts,
)
from transplanter.families.machines.record import BOUGHT, OBSTACLE, obstacle_file
from transplanter.machine.hardware import bought_drawing, read_turned
from transplanter.shop import formats
from transplanter.shop.catalogue import fit
from transplanter.shop.solids import Features, circle_polygon

__all__ = ["designed", "drawn", "plates", "record", "make", "made_bodies", "planes_of_3mf", "turned_problems"]


def designed(study, machine_links, files: dict[str, bytes], names: dict[str, str]) -> Design:
    """The structure of ``study`` (:mod:`planetary_structure`, :mod:`planetary_axis`) with its plates
    and its record."""
    out = Collected()
    dims, hardware, keep = main_axis(study, machine_links, files, names, out, planet_shafts(study, machine_links, out))
    d = Design((), tuple(out.turned), tuple(out.fitted), out.links, out.joints, keep, hardware, dims)
    d = dataclasses.replace(d, plates=plates(study, d))
    return dataclasses.replace(d, record=record(study, d))


def plates(study, d: Design) -> tuple[Plate, ...]:
    """The structure's made plates: the two carrier plates, the ring spacer and flange, the frame."""
    s, g = study.structure, d.dims
    a, n, bp, cbp, bq, cbq, cc, fc = (g[k] for k in ("a", "n", "bp", "cbp", "bq", "cbq", "cc", "fc"))
    size, tie, tie_angles, F, R, G, fl, FF, RF = (
        g[k] for k in ("size", "tie", "tie_angles", "F", "R", "G", "fl", "FF", "RF")
    )
    d_c, d_r, key_f, holes, between = (g[k] for k in ("d_c", "d_r", "key_f", "holes", "between"))
    r_out, r_in, ring_screw, flange_screw = (g[k] for k in ("r_out", "r_in", "ring_screw", "flange_screw"))
    frame_angles, r_tube, r_frame, frame_screw = (g[k] for k in ("frame_angles", "r_tube", "r_frame", "frame_screw"))
    plate_mat, light = s.plate_material, s.light_material
    seats = [(a * math.cos(2 * math.pi * k / n), a * math.sin(2 * math.pi * k / n), bp.D) for k in range(n)]
    ties = [(s.tie_radius * math.cos(t), s.tie_radius * math.sin(t)) for t in tie_angles]
    r_c = a + bp.D / 2 + s.margin
    mounts = [(r_tube * math.cos(t), r_tube * math.sin(t)) for t in (math.pi / 4 + k * math.pi / 2 for k in range(4))]
    seat_note = (
        f"{n} bearing seats {fit(bp.D, 'H7').text} on R{a:.4f}, {360 / n:g} deg apart from +x, each with a "
        f"{cbp.designation} groove (op 20)"
    )
    return (
        Plate(
            "carrier",
            circle_polygon(0.0, 0.0, r_c),
            shapely.Polygon(),
            Features(bore=d_c, holes=(*seats, *((x, y, TAP_DRILL[size]) for x, y in ties))),
            F,
            "carrier",
            "carrier",
            plate_mat,
            (
                "front carrier plate: mates with the planet shafts' front bearings (" + bp.designation + ") in its "
                "seats, the carrier shaft on its key and the tie tubes on its back face",
                seat_note,
                f"bore {fit(d_c, 'H7').text} with the DIN 6885 hub keyway: the carrier shaft ({fit(d_c, 'k6').text})",
                f"{n} x {size} tapped on R{s.tie_radius:g} between the planets: the tie screws from the back",
                "timing: the seat on +x carries arm I",
            ),
            (
                f"in each bearing seat turn the {cbp.designation} groove {cbp.groove_size}, its near edge "
                f"{cbp.n_min:g} from the back face (the ring's side)",
                f"tap {n} x {size} through on R{s.tie_radius:g}",
            ),
        ),
        Plate(
            "carrier_rear",
            circle_polygon(0.0, 0.0, r_c),
            shapely.Polygon(),
            Features(bore=d_c, holes=(*seats, *((x, y, CLEARANCE_HOLE[size]) for x, y in ties))),
            R,
            "carrier",
            "carrier_rear",
            plate_mat,
            (
                "rear carrier plate, in the ring's back cavity: mates with the planet shafts' rear bearings in its "
                "seats, the carrier shaft on its key and the tie tubes on its front face",
                seat_note,
                f"bore {fit(d_c, 'H7').text} with the DIN 6885 hub keyway: the carrier shaft, between two "
                f"{cc.designation}",
                f"{n} x {CLEARANCE_HOLE[size]:g} on R{s.tie_radius:g} for the tie screws ({tie.designation}, heads "
                "behind)",
                "timing: the seat on +x carries arm I",
            ),
            (
                f"in each bearing seat turn the {cbp.designation} groove {cbp.groove_size}, its near edge "
                f"{cbp.n_min:g} from the front face (the ring's side)",
            ),
        ),
        Plate(
            "ring_spacer",
            circle_polygon(0.0, 0.0, r_out),
            circle_polygon(0.0, 0.0, r_in),
            Features(
                holes=(*((x, y, TAP_DRILL["M3"]) for x, y, _ in holes), *((x, y, TAP_DRILL["M3"]) for x, y in between))
            ),
            (fl[1], G[0]),
            "ring",
            "ring_spacer",
            light,
            (
                "ring spacer: behind the ring, on its bolt circle, leaving the cavity the rear carrier plate turns in; "
                "mates with the ring's back face and the ring flange's front face",
                f"{len(holes)} x M3 tapped (the ring's screws {ring_screw.designation} from the front) and "
                f"{len(holes)} x M3 tapped between them (the flange's {flange_screw.designation} from the back)",
                "timing: the ring's holes lie half a pitch off +x",
            ),
            (f"tap all {2 * len(holes)} holes M3 through",),
        ),
        Plate(
            "ring_flange",
            circle_polygon(0.0, 0.0, r_out),
            shapely.Polygon(),
            Features(bore=d_r, holes=tuple((x, y, CLEARANCE_HOLE["M3"]) for x, y in between)),
            fl,
            "ring",
            "ring_flange",
            s.flange_material,
            (
                "ring flange: drives the ring through the spacer from the hollow ring shaft; mates with the spacer "
                "and the ring shaft's key",
                f"bore {fit(d_r, 'H7').text} with the DIN 6885 hub keyway ({key_f.designation}); held by a "
                f"{fc.designation} in front and the flange sleeve behind",
                f"{len(between)} x {CLEARANCE_HOLE['M3']:g} for {flange_screw.designation} into the spacer",
                "timing: its holes lie between the ring's (a whole pitch of 8 off +x, half of 16)",
            ),
        ),
        Plate(
            "frame_front",
            circle_polygon(0.0, 0.0, r_frame),
            shapely.Polygon(),
            Features(
                bore=bq.D,
                keyway=False,
                holes=tuple((r_tube * math.cos(t), r_tube * math.sin(t), TAP_DRILL[size]) for t in frame_angles),
            ),
            FF,
            "fixed",
            "frame_front",
            plate_mat,
            (
                "front frame plate: mates with the ring shaft's front bearing (" + bq.designation + ") and the frame "
                "tubes",
                f"bearing seat {fit(bq.D, 'H7').text} with a {cbq.designation} groove",
                f"3 x {size} tapped on R{r_tube:g}: the frame's tie screws",
                "timing: a tube hole on +y, as the rear plate's",
            ),
            (
                f"in the bearing seat turn the {cbq.designation} groove {cbq.groove_size}, its near edge "
                f"{cbq.n_min:g} from the back face",
                f"tap 3 x {size} through on R{r_tube:g}",
            ),
        ),
        Plate(
            "frame_rear",
            circle_polygon(0.0, 0.0, r_frame),
            shapely.Polygon(),
            Features(
                bore=bq.D,
                keyway=False,
                holes=(
                    *((r_tube * math.cos(t), r_tube * math.sin(t), CLEARANCE_HOLE[size]) for t in frame_angles),
                    *((x, y, TAP_DRILL["M6"]) for x, y in mounts),
                ),
            ),
            RF,
            "fixed",
            "frame_rear",
            plate_mat,
            (
                "rear frame plate: mates with the ring shaft's rear bearing and the frame tubes; bolted to the "
                "transplanter's drive case",
                f"bearing seat {fit(bq.D, 'H7').text} with a {cbq.designation} groove",
                f"3 x {CLEARANCE_HOLE[size]:g} on R{r_tube:g} for {frame_screw.designation} (heads behind); "
                f"4 x M6 tapped on R{r_tube:g} at 45 deg + k 90 deg: the mounting to the transplanter",
                "timing: a tube hole on +y (the frame has no angle of its own to keep)",
            ),
            (
                f"in the bearing seat turn the {cbq.designation} groove {cbq.groove_size}, its near edge "
                f"{cbq.n_min:g} from the front face",
                f"tap 4 x M6 through on R{r_tube:g} at 45 deg + k 90 deg",
            ),
        ),
    )


def record(study, d: Design) -> dict:
    """What the machine record states of the structure: loads, speeds, bearings, planes, drives."""
    s, tr, g = study.structure, study.train, d.dims
    load, r_min, bp, bq, bush, n = (g[k] for k in ("load", "r_min", "bp", "bq", "bush", "n"))
    R, G, fl, FF, RF, F = (g[k] for k in ("R", "G", "fl", "FF", "RF", "F"))
    c_hub, hub_r, c_end, rear_end, front_end = (g[k] for k in ("c_hub", "hub_r", "c_end", "rear_end", "front_end"))
    key_cd, key_rd, r_in, r_out, r_bolt, r_frame = (
        g[k] for k in ("key_cd", "key_rd", "r_in", "r_out", "r_bolt", "r_frame")
    )
    shaft_back, shaft_front = g["shaft"]
    sp = g["speeds"]
    carrier_rpm, ring_rpm, planet_rpm, planet_max, relative_rpm = (
        sp[k] for k in ("carrier", "ring", "planet", "planet_max", "relative")
    )
    name = study.name
    r_c = g["a"] + bp.D / 2 + s.margin
    return {
        "loads": {
            "needle_force_n": s.needle_force_n,
            "design_radial_n": rounded(load, 4),
            "reading": (
                f"F (1 + S / r_min): {s.needle_force_n:g} N at the needle tip (S = {tr.arm.tip:.4g} mm) and the "
                f"mesh reacting its moment at the planet's least pitch radius {r_min:.4g} mm, whole on every "
                "support; no axial load (spur teeth); the design figure the supports are sized for — the machine's "
                "computed loads (results.loads) check each of them"
            ),
        },
        "speeds_rpm": {
            "carrier": rounded(carrier_rpm, 6),
            "ring": rounded(ring_rpm, 6),
            "planet_in_carrier_mean": rounded(planet_rpm, 6),
            "planet_in_carrier_max": rounded(planet_max, 6),
            "carrier_in_ring": rounded(relative_rpm, 6),
        },
        "bearings": [
            _bearing_row(bp, 2 * n, "planet shafts in the carrier plates", planet_rpm),
            _bearing_row(bq, 2, "ring shaft in the frame", ring_rpm),
            {
                "designation": bush.designation,
                "standard": "ISO 3547-1",
                "count": 2,
                "where": "carrier shaft in the ring shaft",
                "speed_rpm": rounded(relative_rpm, 6),
                "radial_n": rounded(load, 4),
                "pressure_n_mm2": rounded(bush.pressure_n_mm2, 4),
                "sliding_m_s": rounded(bush.sliding_m_s, 6),
            },
        ],
        "planes_mm": {
            "carrier_rear": list(R),
            "ring_spacer": [rounded(fl[1], 6), G[0]],
            "ring_flange": [rounded(v, 6) for v in fl],
            "frame_front": [rounded(v, 6) for v in FF],
            "frame_rear": [rounded(v, 6) for v in RF],
            "planet_shaft": [rounded(shaft_back, 6), rounded(shaft_front, 6)],
            "carrier_shaft": [rounded(c_end, 6), F[1]],
            "ring_shaft": [rounded(rear_end, 6), rounded(front_end, 6)],
        },
        "drives": {
            "carrier": {
                "shaft": f"{name}.carrier_shaft",
                "speed_rpm": rounded(carrier_rpm, 6),
                "turning": "clockwise seen from the front",
                "hub_seat_mm": [rounded(c_hub[0], 6), rounded(c_hub[1], 6)],
                "key": key_cd.designation,
            },
            "ring": {
                "shaft": f"{name}.ring_shaft",
                "speed_rpm": rounded(ring_rpm, 6),
                "turning": "clockwise seen from the front",
                "hub_seat_mm": [rounded(hub_r[0], 6), rounded(hub_r[1], 6)],
                "key": key_rd.designation,
            },
            "planting": {
                "plants_per_min": rounded(n * carrier_rpm, 6),
                "reading": (
                    f"the train's carrier speed ({carrier_rpm:.4g} r/min) — the speed its planting metrics "
                    f"(forward speed, hole width) are computed at: {n} plants per carrier turn"
                ),
            },
        },
        "plates_mm": {
            "carrier_radius": rounded(r_c, 6),
            "ring_spacer": [rounded(r_in, 6), rounded(r_out, 6)],
            "frame_radius": rounded(r_frame, 6),
            "ring_bolt_circle": rounded(r_bolt, 6),
        },
    }


def _bearing_row(b, count: int, where: str, speed: float) -> dict:
    return {
        "designation": b.designation,
        "standard": b.standard,
        "count": count,
        "where": where,
        "d_D_B_mm": [b.d, b.D, b.B],
        "speed_rpm": rounded(speed, 6),
        "radial_n": rounded(b.radial_n, 4),
        "life_h": rounded(b.life_h, 4),
        "static_safety": rounded(b.static_safety, 4),
    }


def _seats(data: bytes, diameter: float) -> list[tuple[float, float]]:
    """The centres of the round holes of ``diameter`` (mm) in a DXF, on the layer its outline is on."""
    out = []
    for arcs in formats.DXF.arc_centres(data)[1:]:
        if len(arcs) and np.ptp(arcs[:, :3], axis=0).max() < 1e-6 and abs(2 * arcs[0, 2] - diameter) < 0.01:
            out.append((float(arcs[0, 0]), float(arcs[0, 1])))
    return out


def make(
    study, d: Design, used: dict[str, bytes], names: dict[str, str], machine_links, module: float, turn=None
) -> tuple[list[dict], dict, dict]:
    """The structure's files: each plate made (:func:`manufacture`), each turned part's drawing, STL
    and STEP, each judged bought part's section (one ``.bought.dxf`` per designation), the box and
    the soil. Returns the made parts' records, the files and the seedling door's record. The front
    carrier plate's seats must lie where the train's carrier drawing has its planet holes."""
    records, files = [], {}
    for p in d.plates:
        making = Making(width=p.z[1] - p.z[0], features=p.features, material=p.material, operations=p.operations)
        where = f"z {p.z[0]:g}..{p.z[1]:g} mm across the machine (0 at the ring's back face)"
        res, shop, _ = manufacture(
            f"{study.name}.{p.part}",
            p.blank,
            p.cut,
            making,
            (*p.notes, where),
            lambda pt: f"({pt[0]:.1f}, {pt[1]:.1f})",
        )
        records.append(res)
        files.update(shop)
    train_holes = _seats(used[names["carrier"]], study.pair.making[1].features.bore)
    ours = _seats(files[f"{study.name}.carrier.dxf"], d.dims["bp"].D)
    off = max((min(math.dist(h, o) for o in ours) for h in train_holes), default=math.inf)
    if len(ours) != len(train_holes) or off > 1e-3:
        raise GeometryError(
            f"{study.name}: the carrier's bearing seats lie {off:.3g} mm from the planet holes of {names['carrier']}"
        )
    for placed in d.turned:
        res, shop = placed.part.files()
        records.append(res)
        files.update(shop)
    drawn = set()
    for f in d.fitted:
        judged = f.judged()
        fname = planetary_posing.bought_file(study.name, f)
        if judged is None or fname in drawn:
            continue
        drawn.add(fname)
        section, z = judged
        notes = (f"bought: {f.part.designation} ({f.part.standard}), drawn for the judge in its own frame",)
        files[fname] = bought_drawing(fname.removesuffix(".bought.dxf"), section, z[1] - z[0], notes)
    sections, door = planetary_posing.obstacles(study, module, machine_links["planet.1"], study.arm.needle, turn)
    span = planetary_posing.span(study, d)
    planes = planetary_posing.box_planes(study)
    for what, section in sections.items():
        zs = [z for w, z in planes.values() if w == what] or [span]
        z = (min(z[0] for z in zs), max(z[1] for z in zs))
        files.update(obstacle_file(study.name, what, section, z))
    return records, files, door


def made_bodies(d: Design) -> tuple[MadeBody, ...]:
    """The turned parts placed by their own solids in the assembly STEP."""
    return tuple(
        MadeBody(body, placed.part.name, placed.part.solid(), link, z=z)
        for placed in d.turned
        for body, link, z in placed.at
    )


def planes_of_3mf(bodies, d: Design) -> list:
    """The bodies the 3MF of the made parts at the start holds: the train's and the arms' (gears,
    front carrier plate, arm plates, needles), which no other made body touches; the structure —
    the ring's spacer flush on the ring, the turned and bought parts — is in the assembly STEP, as
    exact solids (a 3MF's meshes overlap where two faces touch)."""
    return [b for b in bodies if not b.dxf.endswith((OBSTACLE, BOUGHT)) and b.name not in d.hardware]


def drawn(bodies, d: Design) -> list:
    """The bodies a fitter reads from a cut part's drawing (a keyed bore, a clearance hole): all but
    the turned parts, whose drawings are side views."""
    turned = {b for placed in d.turned for b, _, _ in placed.at}
    return [b for b in bodies if b.name not in turned]


def turned_problems(d: Design, files: dict[str, bytes]) -> list[str]:
    """Each turned part's drawing as found, re-read against the part the design makes."""
    out = []
    for placed in d.turned:
        fname = f"{placed.part.name}.dxf"
        try:
            again = read_turned(files[fname], placed.part.name)
        except (KeyError, GeometryError) as exc:
            out.append(f"{fname}: {exc}")
            continue
        if not again.same_as(placed.part):
            out.append(f"{fname} re-reads as {again}, not as the structure makes it")
    return out
