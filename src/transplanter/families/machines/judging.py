"""What both machine studies judge and record alike over the cycle: a tool's phases, how deep it
enters its work, the bodies as the machine record states them, and the motion table with the
animation and slider (:func:`~transplanter.families.machines.record.pictures`) when shown.

Shared by :mod:`~transplanter.families.machines.planetary_judging` (seed 004) and
:mod:`~transplanter.families.machines.carrier_judging` (seed 002).
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.precision import rounded
from transplanter.families.machines.record import outline_layer, pictures
from transplanter.machine.bodies import Body, motion_rows, work_depth
from transplanter.shop.export import csv_bytes

__all__ = ["PHASES", "body_rows", "depth_row", "motion_files"]

#: an arm's phases over the cycle, in order (the tip in the box, then on to the soil, in it, back)
PHASES = ("picking", "conveying", "planting", "return")


def depth_row(tool: Body, work: Body, link, theta: np.ndarray, tip, knee) -> dict:
    """How far from its tip ``tool`` enters its ``work`` (the box or the soil) over ``theta``, as
    the record states it (:func:`transplanter.machine.bodies.work_depth`)."""
    deepest, at, most = work_depth(tool, work, link, theta, tip, knee)
    return {
        "deepest_from_tip_mm": rounded(deepest, 6),
        "at_driver_deg": round(math.degrees(at), 4),
        "at_most_mm": rounded(most, 6),
    }


def body_rows(bodies: list[Body]) -> dict:
    """Each body as the machine record states it: its DXF and the layer its outline is on there
    (CUT for a made part, REFERENCE for an obstacle, BOUGHT for a bought part), plane, link (and
    whether it is mounted face down)."""
    return {
        b.name: {
            "dxf": b.dxf,
            "layer": outline_layer(b.dxf),
            "z_mm": [b.z[0], b.z[1]],
            "link": b.link,
            **({"mirrored": True} if b.mirrored else {}),
        }
        for b in bodies
    }


def motion_files(name: str, bodies, links, theta: np.ndarray, tips, judged, phases, labels) -> dict[str, bytes]:
    """``<name>.motion.csv`` (each body's pose at ``theta``), then the animation and the slider
    (:func:`~transplanter.families.machines.record.pictures`, same arguments)."""
    header, rows = motion_rows(bodies, links, theta)
    files = {f"{name}.motion.csv": csv_bytes(header, rows)}
    files.update(pictures(name, bodies, links, tips, judged, phases, labels))
    return files
