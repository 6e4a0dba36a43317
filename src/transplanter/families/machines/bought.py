"""The bought parts a machine's made parts call for, read from the parts' DXFs as a fitter reads
them, and placed as :class:`~transplanter.families.machines.assembly.BoughtBody` items.

* :func:`keys` — a **parallel key** (DIN 6885-1, :func:`~transplanter.shop.catalogue.key_for`)
  in every hub whose bore at the part's origin has a keyway (a bore contour reaching past its
  circle towards +y): the key of the bore's diameter, the longest standard length the hub takes,
  sitting in the shaft's keyseat (its underside ``t1`` below the shaft's surface) in the middle
  of the hub's width — turned over with a part mounted face down;
* :func:`screws` — an ISO 4762 **cap screw** through every clearance hole of a part into the
  tapped hole of the part it is bolted to: its head on the clamped part's far face, its length
  the longest standard one that does not come out of the tapped part, engaging at least
  ``ENGAGEMENT`` × its diameter of it.

What the machine studies' drawings name beside them is placed here too: seed 004's keys and needle
screws (:func:`planetary_bought`), seed 002's roller bearing, retaining ring, keys and screws
(:func:`carrier_bought`). Not yet placed, for want of a part to hold them or a catalogue row: seed
004's spacer washers (ISO 7093-1, not in the catalogue), its ring's M3 bolts (the ring flange is
not modelled) and planet-shaft end screws, seed 002's roller pin (ISO 8734, not in the catalogue).
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.families.machines.assembly import BoughtBody
from transplanter.families.machines.record import outline_layer
from transplanter.shop import formats
from transplanter.shop.arcs import bulge_points
from transplanter.shop.catalogue import bearing, circlip_for_shaft, key_for, screw
from transplanter.shop.catalogue.fasteners import screw_lengths

__all__ = ["ENGAGEMENT", "keys", "screws", "round_holes", "planetary_bought", "carrier_bought"]

#: a screw engages at least this many diameters of thread in a tapped steel part (steel screw in a
#: steel part of like strength: about one diameter, VDI 2230 / the usual tapped-hole rule)
ENGAGEMENT = 1.0
#: a bore's keyway reaches at least this far past its circle, mm (a plain bore re-reads within µm)
KEYWAY_MM = 0.1


def round_holes(data: bytes, fname: str) -> list[tuple[float, float, float]]:
    """The round holes of a part's DXF (``fname`` says its outline layer): ``(x, y, diameter)`` of
    every hole contour made of arcs about one centre, mm, in the DXF's frame; the diameter to 0.01
    mm (the re-read arcs lie up to 0.55 µm outside the nominal hole)."""
    out = []
    for arcs in formats.DXF.arc_centres(data, layer=outline_layer(fname))[1:]:
        if len(arcs) and np.ptp(arcs[:, 0]) < 1e-6 and np.ptp(arcs[:, 1]) < 1e-6 and np.ptp(arcs[:, 2]) < 1e-6:
            if abs(arcs[:, 3].sum() - 2 * math.pi) < 1e-6:  # the whole circle
                out.append((float(arcs[0, 0]), float(arcs[0, 1]), round(float(2 * arcs[0, 2]), 2)))
    return out


def _keyed_bore(data: bytes, fname: str) -> float | None:
    """The diameter of the keyed bore at the DXF's origin, or None (no bore there, or no keyway):
    the hole that holds the origin, with arcs about it, reaching past their circle towards +y."""
    layer = outline_layer(fname)
    contours = formats.DXF.arcs(data, layer=layer)  # the outline first, then the holes
    for (verts, _), arcs in list(zip(contours, formats.DXF.arc_centres(data, layer=layer), strict=True))[1:]:
        points = bulge_points(verts, 1e-3)
        if not len(arcs) or not shapely.Polygon(points).contains(shapely.Point(0.0, 0.0)):
            continue
        # the bore's arcs are those about the origin (an arc fit may close a keyway's flank with a
        # wide arc about some other point: not the bore)
        about = arcs[np.hypot(arcs[:, 0], arcs[:, 1]) < 1e-6]
        if not len(about):
            return None
        r = float(about[:, 2].max())
        # the arcs lie up to 0.55 µm off the bore (one-sided: a hole grows): its nominal diameter is
        # the re-read one to 0.01 mm — 12.0006 mm is a 12 mm bore, which takes a 4 x 4 key, not 5 x 5
        return round(2 * r, 2) if points[:, 1].max() > r + KEYWAY_MM else None
    return None


def keys(bodies, files: dict[str, bytes]) -> list[BoughtBody]:
    """A parallel key in the keyed bore of every body whose DXF has one (module docstring), named
    ``key_<body>``."""
    out = []
    for b in bodies:
        if not b.dxf.endswith(".dxf") or outline_layer(b.dxf) != "CUT":
            continue
        d = _keyed_bore(files[b.dxf], b.dxf)
        if d is None:
            continue
        width = b.z[1] - b.z[0]
        key = key_for(d, width)
        seat = d / 2 - key.t1  # the key's underside in the shaft's keyseat
        z = b.z[0] + (width - key.length) / 2
        if b.mirrored:  # face down: the keyway points along -y of the link's frame
            out.append(BoughtBody(f"key_{b.name}", key, b.link, 0.0, -seat, z, math.pi))
        else:
            out.append(BoughtBody(f"key_{b.name}", key, b.link, 0.0, seat, z))
    return out


def screws(clamped, tapped, files: dict[str, bytes], size: str = "M4", clearance: float = 4.5) -> list[BoughtBody]:
    """A cap screw of ``size`` through each ``clearance`` mm hole of the body ``clamped`` into the
    body ``tapped`` (module docstring), named ``screw_<clamped>_<k>``; GeometryError when the
    clamped part has no such hole or no standard length fits."""
    holes = [(x, y) for x, y, dia in round_holes(files[clamped.dxf], clamped.dxf) if abs(dia - clearance) < 1e-3]
    if not holes:
        raise GeometryError(f"{clamped.name} has no {clearance:g} mm clearance hole for its {size} screws")
    front = clamped.z[0] >= tapped.z[1]  # the clamped part in front: screwed in from the front
    gap = clamped.z[0] - tapped.z[1] if front else tapped.z[0] - clamped.z[1]
    grip = clamped.z[1] - clamped.z[0] + gap
    depth = tapped.z[1] - tapped.z[0]
    d = float(size[1:])
    fits = [x for x in screw_lengths() if grip + ENGAGEMENT * d <= x <= grip + depth]
    if not fits:
        raise GeometryError(
            f"no standard ISO 4762 {size} length bolts {clamped.name} ({grip:g} mm grip) into {tapped.name} "
            f"({depth:g} mm of thread, {ENGAGEMENT:g} d engaged)"
        )
    part = screw(size, max(fits))
    sign = -1.0 if clamped.mirrored else 1.0
    z = clamped.z[1] if front else clamped.z[0]
    return [
        BoughtBody(f"screw_{clamped.name}_{k}", part, clamped.link, x, sign * y, z, flip=front)
        for k, (x, y) in enumerate(sorted(holes), 1)
    ]


def planetary_bought(bodies, files: dict[str, bytes]) -> list[BoughtBody]:
    """Seed 004's bought parts its drawings name: a key in every keyed bore (the carrier's, each
    planet's and each arm plate's) and the two M4 screws that bolt each needle to its arm plate."""
    by = {b.name: b for b in bodies}
    out = keys(bodies, files)
    for name in sorted(by):
        if name.startswith("needle_"):
            out += screws(by[name], by["arm_" + name.removeprefix("needle_")], files)
    return out


def carrier_bought(bodies, files: dict[str, bytes]) -> list[BoughtBody]:
    """Seed 002's bought parts its drawings name: the follower's roller, a 625 deep groove ball
    bearing where its drawing (``.bought.dxf``) puts it; the DIN 471 retaining ring on the
    follower pivot against the lever's back face; a key in every keyed bore; the M4 screws of
    sector 8 (into carrier 2) and of the claw (into the arm)."""
    by = {b.name: b for b in bodies}
    roller, lever = by["roller"], by["lever"]
    x, y = shapely.centroid(roller.section).coords[0]
    wheel = bearing("625")
    across = math.sqrt(4 * roller.section.area / math.pi)
    if abs(across - wheel.D) > 0.01 or abs(roller.z[1] - roller.z[0] - wheel.B) > 1e-9:
        raise GeometryError(
            f"the roller's drawing is {across:.3f} mm across, not a 625 bearing's {wheel.D:g} x {wheel.B:g}"
        )
    pivot = _keyed_bore(files[lever.dxf], lever.dxf)
    if pivot is None:
        raise GeometryError(f"the lever ({lever.dxf}) has no keyed bore for its pivot shaft")
    ring = circlip_for_shaft(pivot)
    return [
        BoughtBody("roller", wheel, roller.link, x, y, roller.z[0]),
        BoughtBody("retaining_ring_pivot", ring, lever.link, 0.0, 0.0, lever.z[0] - ring.s),
        *keys(bodies, files),
        *screws(by["sector_8"], by["carrier_2"], files),
        *screws(by["claw"], by["arm"], files),
    ]
