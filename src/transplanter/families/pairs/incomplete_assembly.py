"""The make and assemble station of an incomplete pair: shop files, timing marks and the assembly.

:func:`make` makes each gear of the cut pair (``<name>.driver|driven.dxf/.stl``, a timing mark —
a hole, or a notch in a ring's rim — at the start contact, notes naming the mate, the law, the
backlash and the locking arcs); :func:`assemble` places them in mesh: ``<name>.assembly.3mf`` and
the STEP files, ``<name>.motion.csv`` (the law, phase per row), ``<name>.dxf_meshing.csv`` and
``<name>.assembly.dxf``, and returns the assembly record.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from transplanter.core.precision import rounded
from transplanter.families.builder.making import Making, assembly_file, manufacture, step_file
from transplanter.families.pairs import pair_assembly
from transplanter.families.pairs.incomplete_proof import ROLES
from transplanter.geometry.incomplete import IncompleteGears
from transplanter.geometry.pitch import driven_axis, driven_turn
from transplanter.geometry.pitch.intermittent import IncompletePair
from transplanter.shop import formats
from transplanter.shop.export import csv_bytes

__all__ = ["assemble", "make"]


def make(
    name: str,
    gears: IncompleteGears,
    pair: IncompletePair,
    module: float,
    backlash: float,
    making: tuple[Making, Making],
    tolerance: float,
) -> tuple[dict[str, bytes], dict, dict]:
    """Make both gears of ``gears`` (cut from ``pair`` at ``module``, mm, for ``backlash``, mm) as
    ``making`` says, to ``tolerance`` (± mm): (files, part per role, timing mark ``(x, y, dia)``
    per role)."""
    g = gears
    files, parts, marks = {}, {}, {}
    for k, (role, gear) in enumerate(zip(ROLES, g.gears, strict=True)):
        m = making[k]
        mark = pair_assembly.timing_mark(gear, m.features)
        features = (
            dataclasses.replace(m.features, notches=(mark,))
            if gear.internal
            else dataclasses.replace(m.features, holes=(*m.features.holes, mark))
        )
        m = dataclasses.replace(m, features=features, tolerance=tolerance, step=False)
        notes = (
            f"incomplete {'ring' if gear.internal else 'gear'}: {gear.teeth} teeth on toothed sectors, module "
            f"{module:.6g} mm, face width {m.width:g} mm",
            f"mates with {name}.{ROLES[1 - k]}, {pair.mesh} mesh, centre distance "
            f"{pair.centre_distance:.4f} mm; law: {pair.law.describe()}",
            f"backlash {backlash:.4f} mm on the teeth; locking arcs {g.locks[0].radius:.4f} / "
            f"{g.locks[0].radius + g.locks[0].clearance:.4f} mm about the driver's axis",
            f"timing mark: {'notch' if gear.internal else 'hole'} dia {mark[2]:.2f} mm at +x meets the mate's "
            "at the start",
        )
        res, shop, part = manufacture(
            f"{name}.{role}",
            gear.blank,
            gear.cut,
            m,
            notes,
            lambda pt, gg=gear: f"tooth space {gg.nearest_space(pt)}",
            marks=((mark[0], mark[1], "TIMING"),),
        )
        files.update(shop)
        parts[role] = part
        marks[role] = mark
    return files, parts, marks


def assemble(
    name: str, pair: IncompletePair, parts: dict, marks: dict, dxf_report, made: dict[str, bytes]
) -> tuple[dict, dict[str, bytes]]:
    """The pair ``name`` in mesh from its ``parts`` and timing ``marks`` (per role, from
    :func:`make`), ``dxf_report`` the meshing of its re-read DXF and ``made`` its shop files:
    (the assembly record, the assembly's files)."""
    external = pair.mesh == "external"
    centre = driven_axis(pair)
    turn = round(math.degrees(float(driven_turn(pair, np.zeros(1))[0])) % 360.0, 9)  # at driver angle 0
    placed = [
        (f"{name}.driver", parts["driver"], formats.placement()),
        (f"{name}.driven", parts["driven"], formats.placement(centre, 0.0, 0.0, math.radians(turn))),
    ]
    record, files = assembly_file(name, placed)
    steps = {role: step_file(parts[role], files) for role in ROLES}
    phi = 2 * math.pi * np.arange(pair_assembly.MOTION_ROWS + 1) / pair_assembly.MOTION_ROWS
    sense = 1.0 if external else -1.0
    rows = [
        [f"{math.degrees(a):.4f}", f"{math.degrees(b):.9f}", "dwell" if not mv else "motion"]
        for a, b, mv in zip(phi, sense * pair.law.psi(phi), pair.moving(phi), strict=True)
    ]
    files[f"{name}.motion.csv"] = csv_bytes(["driver_clockwise_deg", "driven_counterclockwise_deg", "phase"], rows)
    files[f"{name}.dxf_meshing.csv"] = pair_assembly.meshing_csv(dxf_report)
    files[f"{name}.assembly.dxf"] = formats.DXF.assembly(
        name,
        [
            (f"{name}.driver", made[f"{name}.driver.dxf"], (0.0, 0.0, 0.0)),
            (f"{name}.driven", made[f"{name}.driven.dxf"], (centre, 0.0, math.radians(turn))),
        ],
        (f"centre distance {pair.centre_distance:.4f} mm; driver turns clockwise", f"law: {pair.law.describe()}"),
    )
    return {
        "kind": pair.mesh,
        "driver": f"{name}.driver",
        "driven": f"{name}.driven",
        "centre_distance_mm": rounded(pair.centre_distance, 9),
        "driven_centre_mm": [rounded(centre, 9), 0.0],
        "driven_angle_at_start_deg": turn,
        "driver_turns": "clockwise",
        "driven_turns": "counter-clockwise" if external else "clockwise",
        "timing_marks_mm": {role: [rounded(x, 6), rounded(y, 6)] for role, (x, y, _) in marks.items()},
        "model": record,
        "step": steps,
        "motion": f"{name}.motion.csv",
        "drawing": f"{name}.assembly.dxf",
    }, files
