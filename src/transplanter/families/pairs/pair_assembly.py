"""The make and assemble stations of a gear pair: shop files with timing marks, then what a shop
needs to put the two gears together.

:func:`make` gives each cut gear a timing mark (a hole facing its mate, or a notch in a ring's
rim) at the start contact and its notes (mate, centre distance, backlash, how it is turned at
assembly), and writes its shop files (:func:`making.manufacture`). :func:`assemble` then takes
the backlash and clearance the proof measured on the re-read DXF and writes the assembly record,
the 3MF of the gears where they sit at the start (each planet on its carrier line when the pair
drives a train), each gear's STEP, the assembly drawing and the design motion.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.families.builder.making import Making, assembly_file, manufacture, step_file
from transplanter.families.pairs.pair_cut import ROLES, CutPair
from transplanter.families.pairs.pair_proof import TrainHook
from transplanter.geometry.backlash import tolerance_budget
from transplanter.geometry.pitch import driven_axis
from transplanter.geometry.teeth import ToothedGear
from transplanter.proof.meshing import MeshReport
from transplanter.shop import formats, solids
from transplanter.shop.export import csv_bytes

__all__ = [
    "MESHING_COLUMNS",
    "meshing_csv",
    "read_meshing_csv",
    "MARK_DIAMETER",
    "MARK_WALL",
    "MOTION_ROWS",
    "Made",
    "assemble",
    "bodies",
    "make",
    "steps",
    "timing_mark",
]

#: timing-mark hole (external gears) or rim notch (rings): largest diameter, mm, and the
#: smallest wall left to the root, the bore and other holes, mm
MARK_DIAMETER = 2.0
MARK_WALL = 1.0
#: rows per driver turn of the design motion a shop receives (``<part>.motion.csv``)
MOTION_ROWS = 720


def timing_mark(gear: ToothedGear, features: solids.Features) -> tuple[float, float, float]:
    """(x, y, diameter) of a timing mark at body angle 0, where the gear meets its mate at the
    start: a through hole between bore and roots on an external gear, a notch in a ring's rim.
    GeometryError when there is no room for it."""
    contour = gear.toothed_contour
    if gear.internal:
        r_rim = float(gear.blank.bounds[2])
        wall = r_rim - float(np.linalg.norm(contour, axis=1).max())
        d = min(MARK_DIAMETER, 0.8 * wall)
        x = r_rim
    else:
        r_root = float(np.linalg.norm(contour, axis=1).min())
        r_in = features.bore / 2 if features.bore else 0.0
        room = r_root - r_in - 2 * MARK_WALL
        d = min(MARK_DIAMETER, room)
        x = r_in + MARK_WALL + room / 2 + (0.0 if features.bore else 0.25 * room)
    if d < 0.5:
        raise GeometryError(
            f"no room for a timing mark on the {'ring' if gear.internal else 'gear'}: {d:.3g} mm (limit 0.5 mm) "
            f"between {'the teeth and the rim' if gear.internal else 'the bore and the roots'}"
        )
    mark = shapely.Point(x, 0.0).buffer(d / 2 + MARK_WALL)
    for hx, hy, hd in features.holes:
        if mark.intersects(shapely.Point(hx, hy).buffer(hd / 2)):
            raise GeometryError(f"the timing mark at ({x:.2f}, 0) mm meets the hole at ({hx:g}, {hy:g}) mm")
    return float(x), 0.0, float(d)


@dataclass(frozen=True)
class Made:
    """Both gears made: their timing marks, results, shop files and parts (for the assembly)."""

    #: role -> (x, y, diameter) of its timing mark, mm
    marks: dict
    #: role -> the manufacturing results
    results: dict
    files: dict
    #: role -> formats.MadePart
    parts: dict
    #: (driver, driven) Making as made (marks, tolerance and quantity in)
    making: tuple[Making, Making]


def _notes(cut: CutPair, k: int, making: Making, mark, train: TrainHook | None, extra=()) -> tuple[str, ...]:
    role, other = ROLES[k], ROLES[1 - k]
    gear, mate, pair = cut.gears[k], cut.gears[1 - k], cut.pair
    external = pair.ring is None
    turn = (
        "the driven gear is turned 180 deg from its DXF frame at assembly"
        if external
        else "both gears keep their DXF orientation at assembly"
    )
    j = cut.sized.backlash
    notes = [
        f"{gear.teeth} teeth, module {gear.module:.6g} mm, face width {making.width:g} mm",
        f"mates with {cut.name}.{other} ({mate.teeth} teeth), {'external' if external else 'internal'} mesh, "
        f"centre distance {pair.centre_distance:.4f} mm",
        f"backlash {j:.4f} mm circumferential by design",
        f"timing mark: {'notch' if gear.internal else 'hole'} dia {mark[2]:.2f} mm at +x meets the mate's mark "
        f"at the start; {turn}",
    ]
    if train is not None and role == "driven":
        notes.append(f"one planet per arm, {360 / train.planets:g} deg apart on the carrier")
    if j == 0:
        notes.append(
            "ZERO BACKLASH by request: no play for the cutting tolerance - the pair binds unless the centre "
            "distance is opened"
        )
    return (*notes, *extra)


def make(cut: CutPair, making: tuple[Making, Making], train: TrainHook | None, notes: tuple[str, ...] = ()) -> Made:
    """Each gear with its timing mark and notes (``notes``: more for both), through
    :func:`making.manufacture` (its STEP is written later, by :func:`assemble`, after the 3MF's
    re-read)."""
    marks, results, files, parts, made = {}, {}, {}, {}, []
    for k, (role, gear) in enumerate(zip(ROLES, cut.gears, strict=True)):
        m = making[k]
        mark = timing_mark(gear, m.features)
        marks[role] = mark
        m = dataclasses.replace(
            m,
            features=dataclasses.replace(m.features, notches=(mark,))
            if gear.internal
            else dataclasses.replace(m.features, holes=(*m.features.holes, mark)),
            tolerance=cut.tolerance,
            quantity=train.planets if train is not None and role == "driven" else m.quantity,
        )
        res, shop, part = manufacture(
            f"{cut.name}.{role}",
            gear.blank,
            gear.cut,
            dataclasses.replace(m, step=False),
            _notes(cut, k, m, mark, train, notes),
            lambda pt, g=gear: f"tooth space {g.nearest_space(pt)}",
            marks=((mark[0], mark[1], "TIMING"),),
        )
        res["timing_mark_mm"] = {"x": rounded(mark[0], 6), "y": 0.0, "diameter": rounded(mark[2], 6)}
        results[role], parts[role] = res, part
        files.update(shop)
        made.append(m)
    return Made(marks, results, files, parts, tuple(made))


def bodies(name: str, train: TrainHook | None) -> list[str]:
    """The bodies of ``<name>.assembly.3mf``: driver and driven, or the ring and each planet."""
    if train is None:
        return [f"{name}.driver", f"{name}.driven"]
    return [f"{name}.driver", *(f"{name}.driven.{k + 1}" for k in range(train.planets))]


def _record(cut: CutPair, made: Made, dxf: MeshReport, min_clearance, train: TrainHook | None) -> dict:
    pair, sizing, name = cut.pair, cut.sized.sizing, cut.name
    external = pair.ring is None
    centre = driven_axis(pair)
    lo, hi = dxf.backlash_min.value, dxf.backlash_max.value
    return {
        "kind": "external" if external else "internal",
        "ring": pair.ring,
        "driver": f"{name}.driver",
        "driven": f"{name}.driven",
        "teeth": [int(z) for z in sizing.teeth],
        "module_mm": rounded(sizing.module, 9),
        "centre_distance_mm": rounded(pair.centre_distance, 9),
        "driven_centre_mm": [rounded(centre, 9), 0.0],
        "driven_angle_at_start_deg": 180.0 if external else 0.0,
        "driver_turns": "clockwise",
        "driven_turns": "counter-clockwise" if external else "clockwise",
        "timing_marks_mm": {role: [rounded(x, 6), rounded(y, 6)] for role, (x, y, _) in made.marks.items()},
        "backlash_mm": {"min": rounded(lo, 6), "max": rounded(hi, 6)},
        "backlash_at_driver_deg": {"min": round(dxf.backlash_min.at_deg, 4), "max": round(dxf.backlash_max.at_deg, 4)},
        "clearance_mm": {
            "min": rounded(dxf.clearance_min.value, 6),
            "at_driver_deg": round(dxf.clearance_min.at_deg, 4),
            "required": None if min_clearance is None else rounded(min_clearance, 6),
        },
        "backlash_target_mm": rounded(cut.sized.backlash, 6),
        "tolerance_mm": cut.tolerance,
        "tolerance_budget_mm": rounded(tolerance_budget(cut.tolerance), 6),
        "motion": f"{name}.motion.csv",
        "drawing": f"{name}.assembly.dxf",
    } | (train.carrier() if train is not None else {})


def _placed(a: dict, parts: dict, names: list[str], train: TrainHook | None) -> list:
    """The made gears where they sit at the start, from the assembly record a shop gets: the
    driven gear at its centre and start angle, or each planet on its carrier line."""
    turn = math.radians(a["driven_angle_at_start_deg"])
    if train is None:
        x, y = a["driven_centre_mm"]
        driven = [(a["driven"], parts["driven"], formats.placement(x, y, 0.0, turn))]
    else:
        r = a["centre_distance_mm"]
        driven = []
        for name, carrier, body in zip(
            names[1:], a["planet_carrier_angles_deg"], a["planet_body_angle_to_carrier_line_deg"], strict=True
        ):
            c = math.radians(carrier)
            driven.append(
                (
                    name,
                    parts["driven"],
                    formats.placement(r * math.cos(c), r * math.sin(c), 0.0, c + math.radians(body)),
                )
            )
    return [(a["driver"], parts["driver"], formats.placement()), *driven]


def _motion_csv(pair) -> bytes:
    phi = 2 * math.pi * np.arange(MOTION_ROWS + 1) / MOTION_ROWS
    sense = 1.0 if pair.ring is None else -1.0  # counter-clockwise positive
    driven = sense * pair.driven_rotation(phi)
    rows = [[f"{math.degrees(a):.4f}", f"{math.degrees(b):.9f}"] for a, b in zip(phi, driven, strict=True)]
    return csv_bytes(["driver_clockwise_deg", "driven_counterclockwise_deg"], rows)


#: a meshing table read back may differ from a fresh meshing by this, rad (CSV round-off)
MESHING_TABLE_RAD = 1e-9
#: columns of ``<pair>.dxf_meshing.csv``
MESHING_COLUMNS = ("driver_clockwise_deg", "driven_error_deg")


def meshing_csv(report: MeshReport) -> bytes:
    """The meshing measured on the re-read DXFs, per step of the proof: the driver's angle and
    the driven gear's rotation beyond its design angle at driving-flank contact (deg)."""
    order = np.argsort(report.driver_angle, kind="stable")
    rows = [
        [math.degrees(float(a)), math.degrees(float(e))]
        for a, e in zip(np.asarray(report.driver_angle)[order], np.asarray(report.driven_error)[order], strict=True)
    ]
    return csv_bytes(list(MESHING_COLUMNS), rows)


def read_meshing_csv(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """(driver angle, driven error), rad, from :func:`meshing_csv`'s bytes."""
    text = data.decode().splitlines()
    if not text or tuple(text[0].split(",")) != MESHING_COLUMNS:
        raise GeometryError(f"not a meshing table: its header must be {','.join(MESHING_COLUMNS)}")
    values = np.array([[float(v) for v in line.split(",")] for line in text[1:] if line], dtype=float)
    return np.radians(values[:, 0]), np.radians(values[:, 1])


def meshing_table_problems(files: dict[str, bytes], name: str, report) -> list[str]:
    """The meshing table ``name`` (when in ``files``) against the meshing of the DXFs as found
    (``report``): what a machine posed from it would get wrong, or nothing."""
    if name not in files or report is None or isinstance(report, str):
        return []
    try:
        angle, error = read_meshing_csv(files[name])
    except (ValueError, GeometryError) as exc:
        return [f"{name} cannot be read: {exc}"]
    order = np.argsort(report.driver_angle, kind="stable")
    if len(angle) != len(order):
        return [f"{name} has {len(angle)} rows, the meshing of the DXFs {len(order)} steps"]
    off = max(
        float(np.max(np.abs(angle - np.asarray(report.driver_angle)[order]))),
        float(np.max(np.abs(error - np.asarray(report.driven_error)[order]))),
    )
    return [f"{name} is not the meshing of the DXFs as found ({off:.3g} rad off)"] if off > MESHING_TABLE_RAD else []


def steps(made: Made) -> dict[str, tuple[dict[str, bytes], dict]]:
    """Each role's STEP (when its making asks for one): ``{role: ({file name: bytes}, results)}``
    — written from the made parts alone, so it may run beside the meshing proof
    (:class:`~transplanter.families.builder.workers.Beside`)."""
    out = {}
    for role, making in zip(ROLES, made.making, strict=True):
        if making.step:
            files: dict[str, bytes] = {}
            out[role] = (files, step_file(made.parts[role], files))
    return out


def assemble(
    cut: CutPair,
    made: Made,
    dxf: MeshReport,
    min_clearance: float | None,
    train: TrainHook | None,
    written: Callable[[], dict[str, tuple[dict[str, bytes], dict]]] | None = None,
) -> tuple[dict, dict[str, bytes], dict]:
    """The assembly record (``dxf``: the proof on the re-read DXFs), its files (3MF, STEP,
    motion, drawing) and each role's STEP results (``written``: asked last, for the STEPs
    :func:`steps` wrote beside — the assembly is made while they are written —, or None to
    write them here)."""
    record = _record(cut, made, dxf, min_clearance, train)
    record["model"], model = assembly_file(cut.name, _placed(record, made.parts, bodies(cut.name, train), train))
    out = {f"{cut.name}.motion.csv": _motion_csv(cut.pair)}
    # what poses a machine built on the pair: the meshing measured on the re-read DXFs
    out[f"{cut.name}.dxf_meshing.csv"] = meshing_csv(dxf)
    a = record
    out[f"{cut.name}.assembly.dxf"] = formats.DXF.assembly(
        cut.name,
        [
            (a["driver"], made.files[f"{a['driver']}.dxf"], (0.0, 0.0, 0.0)),
            (
                a["driven"],
                made.files[f"{a['driven']}.dxf"],
                (*a["driven_centre_mm"], math.radians(a["driven_angle_at_start_deg"])),
            ),
        ],
        (
            f"centre distance {cut.pair.centre_distance:.4f} mm; driver turns clockwise",
            f"backlash measured on the DXF {a['backlash_mm']['min']:.4f}..{a['backlash_mm']['max']:.4f} mm "
            f"(target {a['backlash_target_mm']:.4f}, tolerance +/-{cut.tolerance:g} mm)",
            "timing marks meet at the start contact",
        ),
    )
    done = steps(made) if written is None else written()
    step_files = {name: data for files, _ in done.values() for name, data in files.items()}
    return record, model | step_files | out, {role: res for role, (_, res) in done.items()}
