"""Seed 004's machine as a shop assembles it: what holds and drives the train (plates, shafts,
bearings, fasteners, a frame, both drives), derived from the train, the made parts' files and the
catalogue (:mod:`transplanter.shop.catalogue`), with every choice stated.

**Loads and speeds (stated).** Until the forces are computed (issue 44) the design load is the
part script's ``needle_force_n`` at the needle tip, in the plane; the mesh reacts the moment it puts
on the planet at the planet's smallest pitch radius, so every support of a planet shaft is sized for
``F (1 + S / r_min)`` radially (each taking all of it, not shared) and so is every support of the
main axis (the one loaded arm's forces reach the carrier and the ring whole); no axial load (spur
teeth). Speeds are the train's: carrier ``carrier_speed``, ring ``ω1/ω2`` of it, the planets turning
``(1 - ω1/ω2) dψ/dφ`` against the carrier (its mean for the life, its largest for the speed limit),
the carrier ``1 - ω1/ω2`` of a turn per turn against the ring.

**Planet shafts, supported at both ends.** Each planet shaft (``d`` = the planet's bore) runs in a
deep-groove ball bearing (:func:`~transplanter.shop.catalogue.bearing_for`: the thinnest that carries
the load and leaves its sleeves a wall past the bore circlip) in the front carrier plate
(the plane the part script states) and one in a rear carrier plate as thick, ``min_axial_gap`` behind
the gears, inside the ring's back cavity. Cross-located ("X"): each bearing's outer ring stops
against a DIN 472 circlip at its plate's inner face, the inner rings are held by a DIN 471 circlip
behind the rear one and by the arm plate, which a DIN 471 circlip holds in front; spacer sleeves fill
the gaps between the inner rings, the planet and the arm plate (within the inner ring's face,
``SHOULDER``). Seats ``k6`` on the shaft, ``H7`` in the plates (the load stands still on the outer
ring). The plates are tied by spacer tubes between the planets at ``tie_radius``, with socket head
screws from the back into the front plate's tapped holes; the carrier shaft is keyed in both plates,
held by DIN 471 circlips either side of the rear plate, and ends flush with the front plate.

**The ring's drive.** A ring spacer (an annulus on the ring's bolt circle, tapped for the ring's M3
screws from the front and for M4 screws from the back) sets the ring flange behind the cavity; the
flange is keyed to a hollow ring shaft — the smallest deep-groove bore whose wall under the flange
key keeps ``MIN_WALL`` over the wrapped bushes (:func:`~transplanter.shop.catalogue.bush_for`) the
carrier shaft runs in — held in front by a DIN 471 circlip and behind by a sleeve on the frame's
front bearing. The carrier shaft is located on the ring shaft by ISO 7089 thrust washers and
circlips at both of its ends.

**The frame.** Two plates (``frame_gap`` apart, tied like the carrier) hold the ring shaft's two
bearings, cross-located as the planets'; a circlip behind the rear bearing and the ring drive's hub
seat behind it. Within the gearbox radius objective x assumes, above the soil (judged).

**The drives.** Each shaft ends in a keyed hub seat (``drive_hub`` mm, the hub held by an end
circlip) for its prime mover's sprocket or coupling: the ring shaft's at the ring's speed, the
carrier shaft's — behind it — at the carrier's (seed 004's two prime movers).

This module states the figures (:class:`Structure`), the loads, speeds and planet shafts
(:func:`planet_shafts`); :mod:`~transplanter.families.machines.planetary_axis` adds the main axis,
the ring's drive and the frame; :mod:`~transplanter.families.machines.planetary_parts` the plates,
the files and the record.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import shapely

from transplanter.core.errors import SpecError, check_number, finite_positive
from transplanter.core.precision import rounded
from transplanter.machine.bodies import Link
from transplanter.machine.hardware import Fitted, Turned, mounted
from transplanter.shop import formats
from transplanter.shop.catalogue import (
    bearing_for,
    circlip_for_bore,
    circlip_for_shaft,
    fit,
    key_for,
    screw,
)
from transplanter.shop.catalogue.bearings import SERIES
from transplanter.shop.catalogue.fasteners import key_lengths, screw_lengths
from transplanter.shop.solids import Features

__all__ = ["Structure", "Plate", "Placed", "Design", "Collected", "planet_shafts", "TAP_DRILL", "CLEARANCE_HOLE"]

#: tap drill (ISO 2306, 6H) and medium clearance hole (ISO 273) of each thread, mm
TAP_DRILL = {"M3": 2.5, "M4": 3.3, "M5": 4.2, "M6": 5.0, "M8": 6.8}
CLEARANCE_HOLE = {"M3": 3.4, "M4": 4.5, "M5": 5.5, "M6": 6.6, "M8": 9.0}
#: a screw engages at least this many diameters of thread in steel, and in aluminium
ENGAGEMENT = {"steel": 1.5, "aluminium": 2.0}
#: a sleeve against a bearing's inner ring keeps within d + SHOULDER (D - d): inside the inner
#: ring's face (ISO 15 rings' shoulders lie near d + 0.3 to 0.4 (D - d))
SHOULDER = 0.3
#: the least wall of the hollow ring shaft under its flange key, mm
MIN_WALL = 3.0
#: the least radial wall of a spacer sleeve on a planet shaft, mm
SLEEVE_WALL = 1.0
#: the least web between a tapped hole and a plate's edge, mm
MIN_WEB = 1.5


@dataclass(frozen=True)
class Structure:
    """What the part script states for the structure (module docstring); mm, N, h."""

    needle_force_n: float = 100.0
    #: radial clearance between two pieces of hardware turning against each other, mm
    running_clearance: float = 1.0
    #: material left round a bearing seat or a screw hole, mm
    margin: float = 8.0
    carrier_shaft: float = 20.0
    tie_radius: float = 70.0
    tube_outer: float = 12.0
    tie_screw: str = "M5"
    frame_gap: float = 20.0
    drive_hub: float = 25.0
    life_h: float = 3000.0
    #: the seedling box: its width across the machine (the mat's, centred on the needles' plane), the
    #: sheet its floor, walls and door are made of, and the door's lip up from the floor (the mat's
    #: soil block, 20 mm in seed 004, and 5 mm over it), mm
    box_width: float = 280.0
    sheet: float = 2.0
    door_lip: float = 25.0
    plate_material: str = "S235JR"
    #: the ring's spacer (tapped for the ring's and the flange's screws)
    light_material: str = "6061-T6"
    #: the ring flange: the hub of the ring drive's key
    flange_material: str = "6061-T6"
    shaft_material: str = "C45"

    def __post_init__(self) -> None:
        finite_positive("needle_force_n", self.needle_force_n)
        check_number("running_clearance", self.running_clearance, 0.1, 10.0, unit="mm")
        for name in (
            "margin",
            "carrier_shaft",
            "tie_radius",
            "tube_outer",
            "frame_gap",
            "drive_hub",
            "life_h",
            "box_width",
            "sheet",
            "door_lip",
        ):
            finite_positive(name, getattr(self, name))
        if self.tie_screw not in TAP_DRILL:
            raise SpecError.out_of_range("tie_screw", self.tie_screw, ", ".join(TAP_DRILL))


@dataclass(frozen=True)
class Plate:
    """A made plate: its file's stem part (``<machine>.<part>``), outline less ``cut``, features,
    plane, link and body name, material, the drawing's notes and the operations after the wire."""

    part: str
    blank: shapely.Polygon
    cut: shapely.Polygon
    features: Features
    z: tuple[float, float]
    link: str
    body: str
    material: str
    notes: tuple[str, ...]
    #: after the wire, in order (``Making.operations``)
    operations: tuple[str, ...] = ()


@dataclass(frozen=True)
class Placed:
    """A turned part and where each of its bodies sits: ``(body, link, z of its back end)``."""

    part: Turned
    at: tuple[tuple[str, str, float], ...]


@dataclass(frozen=True)
class Design:
    """The structure: plates, turned parts, bought parts, the links they are mounted on, the
    declared joints, the rigid pairs judged anyway (``keep``: pair -> clearance, mm), the bodies
    judged against each other at the running clearance, and the record."""

    plates: tuple[Plate, ...]
    turned: tuple[Placed, ...]
    fitted: tuple[Fitted, ...]
    links: dict[str, Link] = field(repr=False)
    joints: dict[frozenset, str]
    keep: dict[frozenset, float]
    hardware: frozenset
    #: the figures the plates and the record are drawn from (:mod:`planetary_parts`)
    dims: dict = field(repr=False)
    record: dict = field(default_factory=dict)


def _ring_holes(data: bytes) -> list[tuple[float, float, float]]:
    """The round holes of a made part's DXF (CUT): ``(x, y, diameter)``."""
    out = []
    for arcs in formats.DXF.arc_centres(data, layer=formats.CUT)[1:]:
        if len(arcs) and np.ptp(arcs[:, :3], axis=0).max() < 1e-6 and abs(arcs[:, 3].sum() - 2 * math.pi) < 1e-6:
            out.append((float(arcs[0, 0]), float(arcs[0, 1]), float(2 * arcs[0, 2])))
    return out


def _screw(size: str, grip: float, depth: float, metal: str = "steel"):
    """The shortest ISO 4762 screw through ``grip`` mm that engages ``ENGAGEMENT`` diameters of a
    tapped part ``depth`` mm thick without coming out of it."""
    d = float(size[1:])
    need = grip + ENGAGEMENT[metal] * d
    fits = [x for x in screw_lengths() if need <= x <= grip + depth]
    try:
        return screw(size, min(fits))
    except ValueError:
        raise SpecError(
            f"no standard ISO 4762 {size} length from {need:g} to {grip + depth:g} mm (grip {grip:g} mm)"
        ) from None


def _hub_key(d: float, hub: float):
    """The key of a hub ``hub`` long on a shaft ``d``: the catalogue's, or the shortest standard
    one when the hub is shorter than every key of that width (the hub is then made that long)."""
    b = key_for(d, 1e6).b
    return key_for(d, max(hub, min(x for x in key_lengths() if x > b)))


def _planet_bearing(d: float, rpm: float, load: float, s: Structure):
    """The smallest bearing (series by series, thinnest first) that carries the planet's load and
    leaves a sleeve against its inner ring, passing its bore circlip's lugs, a wall of
    :data:`SLEEVE_WALL`: a thin-section bearing under a light load does not."""
    sleeveless = []
    for series in SERIES:
        try:
            b = bearing_for(d, rpm, load, life_h=s.life_h, series=(series,))
        except SpecError:
            continue
        c = circlip_for_bore(b.D)
        if _sleeve_od(b.bearing, c.groove_diameter / 2 - c.lug, s.running_clearance) >= d + 2 * SLEEVE_WALL:
            return b
        sleeveless.append(f"{b.designation}'s bore circlip leaves no {SLEEVE_WALL:g} mm sleeve wall")
    why = "; ".join(sleeveless)
    if not sleeveless:  # none carries it: the catalogue's own reason
        try:
            bearing_for(d, rpm, load, life_h=s.life_h)
        except SpecError as e:
            why = str(e)
    raise SpecError(f"no planet bearing for Ø{d:g} at needle_force_n = {s.needle_force_n:g} N: {why}")


def _sleeve_od(bearing, clear_to: float, running: float) -> float:
    """A sleeve's outer diameter against ``bearing``'s inner ring: within its face and
    ``running`` clear of a radius ``clear_to`` it passes (a bore circlip), whole mm down."""
    d, D = bearing.d, bearing.D
    return float(math.floor(min(d + SHOULDER * (D - d), 2 * (clear_to - running))))


@dataclass
class Collected:
    """What the structure's designers add up: mounted links, turned parts, bought parts, joints."""

    links: dict[str, Link] = field(default_factory=dict)
    turned: list[Placed] = field(default_factory=list)
    fitted: list[Fitted] = field(default_factory=list)
    joints: dict[frozenset, str] = field(default_factory=dict)

    def joint(self, x: str, y: str, why: str) -> None:
        self.joints[frozenset((x, y))] = why


def planet_shafts(study, machine_links: dict[str, Link], out: Collected) -> dict:
    """The loads, the speeds and the planet shafts of ``study`` (a ``PlanetaryMachineStudy`` with
    ``structure``, its train posed on ``machine_links``): their bearings in the two carrier plates,
    circlips, sleeves and the needle spacers, into ``out``; the figures the rest is drawn from."""
    s: Structure = study.structure
    tr, L = study.train, study.layers
    gap, run = L.min_axial_gap, s.running_clearance
    a, n = tr.pair.centre_distance, tr.planets
    name = study.name
    steel = s.shaft_material

    # -- loads and speeds (module docstring) ------------------------------------------------
    r_min = tr.pair.driven.min_radius().value
    load = s.needle_force_n * (1.0 + tr.arm.tip / r_min)
    carrier_rpm = tr.carrier_speed * 60.0 / (2 * math.pi)
    w = tr.omega_ratio
    ratio = np.asarray(tr.pair.ratio(np.linspace(0.0, 2 * math.pi, 4096, endpoint=False)), dtype=float)
    planet_rpm = abs(1.0 - w) * carrier_rpm * float(np.mean(np.abs(ratio)))
    planet_max = abs(1.0 - w) * carrier_rpm * float(np.max(np.abs(ratio)))
    ring_rpm, relative_rpm = abs(w) * carrier_rpm, abs(1.0 - w) * carrier_rpm

    # -- planet shafts --------------------------------------------------------------------------
    d_p = study.pair.making[1].features.bore
    bp = _planet_bearing(d_p, planet_rpm, load, s)
    if planet_max > bp.limiting_speed_rpm:
        raise SpecError(f"planet bearing {bp.designation}: {planet_max:.4g} r/min over its limiting speed")
    cbp, csp = circlip_for_bore(bp.D), circlip_for_shaft(d_p)
    F = L.carrier
    T = F[1] - F[0]
    R = (L.gears[0] - gap - T, L.gears[0] - gap)
    if T < bp.B + cbp.groove_width + cbp.n_min:
        raise SpecError.out_of_range(
            "layers.carrier", F, f"at least {bp.B + cbp.groove_width + cbp.n_min:g} mm thick (bearing + circlip groove)"
        )
    fb0 = F[0] + cbp.n_min + cbp.groove_width  # the front bearing, against its circlip
    fb = (fb0, fb0 + bp.B)
    rb1 = R[1] - cbp.n_min - cbp.groove_width
    rb = (rb1 - bp.B, rb1)
    G, A = L.gears, L.plates
    shaft_back = rb[0] - csp.groove_width - csp.n_min
    shaft_front = A[1] + csp.groove_width + csp.n_min
    if L.needles[0] - shaft_front < gap:
        raise SpecError.out_of_range(
            "layers.needles",
            L.needles,
            f"from {shaft_front + gap:g} mm: the planet shaft's end and its circlip "
            f"stand {shaft_front - A[1]:g} mm out of the arm plate",
        )
    key_g, key_a = key_for(d_p, G[1] - G[0]), key_for(d_p, A[1] - A[0])
    planet_shaft = Turned(
        f"{name}.planet_shaft",
        d_p,
        shaft_front - shaft_back,
        keyways=(
            (
                G[0] + (G[1] - G[0] - key_g.length) / 2 - shaft_back,
                key_g.length,
                key_g.b,
                key_g.t1,
                key_g.shaft_note(d_p),
            ),
            (
                A[0] + (A[1] - A[0] - key_a.length) / 2 - shaft_back,
                key_a.length,
                key_a.b,
                key_a.t1,
                key_a.shaft_note(d_p),
            ),
        ),
        grooves=(
            (rb[0] - csp.groove_width - shaft_back, csp.groove_width, csp.groove_diameter, csp.groove_note),
            (A[1] - shaft_back, csp.groove_width, csp.groove_diameter, csp.groove_note),
        ),
        fits=tuple(
            (z0 - shaft_back, z1 - shaft_back, f"{fit(d_p, 'k6').text}: {bp.designation} seat") for z0, z1 in (rb, fb)
        ),
        material=steel,
        quantity=n,
        notes=(
            "one per planet, a bearing each side of the planet",
            "mates: the planet and the arm plate on their keys, the bearings' inner rings on the k6 seats, a DIN 471 "
            "circlip in each groove",
            "timing: its two keyways in line (the planet's key and the arm plate's set the arm's angle)",
        ),
    )
    od = _sleeve_od(bp.bearing, cbp.groove_diameter / 2 - cbp.lug, run)
    sleeves = {  # spacer sleeves: rear inner ring to planet, planet to front inner ring, to the arm plate
        "rear": (rb[1], G[0]),
        "front": (G[1], fb[0]),
        "arm": (fb[1], A[0]),
    }
    spacer = (A[1], L.needles[0])  # under each needle's two bolts, over the circlip's plane
    links, turned, fitted, joint = out.links, out.turned, out.fitted, out.joint

    sleeve_parts: dict[float, tuple[Turned, list]] = {}
    for where, (z0, z1) in sleeves.items():
        length = rounded(z1 - z0, 9)
        if length not in sleeve_parts:
            sleeve_parts[length] = (
                Turned(
                    f"{name}.planet_sleeve_{len(sleeve_parts) + 1}",
                    od,
                    length,
                    bore=d_p,
                    material=steel,
                    quantity=0,
                    notes=(
                        "spacer sleeve on a planet shaft, slide fit",
                        "mates: between a bearing's inner ring and the planet or the arm plate (turns with them)",
                        "timing: none (round)",
                    ),
                ),
                [],
            )
        for k in range(1, n + 1):
            sleeve_parts[length][1].append((f"sleeve_{where}_{k}", f"planet.{k}", z0))
    hole = study.arm.needle_holes
    spacer_part = Turned(
        f"{name}.needle_spacer",
        2 * hole[0][2] + 1.0,
        spacer[1] - spacer[0],
        bore=hole[0][2],
        material=steel,
        quantity=2 * n,
        notes=(
            "mates: under each needle bolt, between the arm plate and the needle",
            "timing: none (round)",
        ),
    )
    spacer_at = []
    for k in range(1, n + 1):
        plink = f"planet.{k}"
        angle = -2 * math.pi * (k - 1) / n  # planet k on the carrier (its DXF frame has planet 1 on +x)
        seat = mounted(machine_links["carrier"], f"carrier@planet_{k}", a * math.cos(angle), a * math.sin(angle))
        links[seat.name] = seat
        for end, (z0, _), zc, flip in (("front", fb, fb[0] - cbp.s, False), ("rear", rb, rb[1], False)):
            fitted += [
                Fitted(f"bearing_{end}_{k}", bp, seat.name, z0),
                Fitted(f"bore_circlip_{end}_{k}", cbp, seat.name, zc, flip),
            ]
            joint(
                f"bearing_{end}_{k}", f"planet_shaft_{k}", f"bearing on its shaft: inner ring on {fit(d_p, 'k6').text}"
            )
            joint(
                f"bearing_{end}_{k}",
                "carrier" if end == "front" else "carrier_rear",
                f"bearing in its plate: outer ring in {fit(bp.D, 'H7').text}",
            )
            joint(f"bearing_{end}_{k}", f"bore_circlip_{end}_{k}", "the DIN 472 circlip holds the outer ring")
        fitted += [
            Fitted(f"shaft_circlip_rear_{k}", csp, plink, rb[0] - csp.s),
            Fitted(f"shaft_circlip_front_{k}", csp, plink, A[1]),
        ]
        joint(f"shaft_circlip_rear_{k}", f"bearing_rear_{k}", "the DIN 471 circlip holds the rear inner ring")
        for where, (z0, z1) in sleeves.items():
            for end, b in (("rear", rb), ("front", fb)):
                if abs(z0 - b[1]) < 1e-9 or abs(z1 - b[0]) < 1e-9:
                    joint(
                        f"sleeve_{where}_{k}",
                        f"bearing_{end}_{k}",
                        "the sleeve bears on the inner ring (turns with it)",
                    )
        for j, (x, y, _) in enumerate(hole, 1):
            m = mounted(machine_links[plink], f"{plink}@needle_bolt_{j}", x, y)
            links[m.name] = m
            spacer_at.append((f"needle_spacer_{k}_{j}", m.name, spacer[0]))
    turned.append(
        Placed(planet_shaft, tuple((f"planet_shaft_{k}", f"planet.{k}", shaft_back) for k in range(1, n + 1)))
    )
    for part, at in sleeve_parts.values():
        turned.append(Placed(_quantity(part, len(at)), tuple(at)))
    turned.append(Placed(spacer_part, tuple(spacer_at)))

    return dict(
        a=a,
        n=n,
        load=load,
        r_min=r_min,
        bp=bp,
        cbp=cbp,
        F=F,
        R=R,
        G=G,
        T=T,
        shaft=(shaft_back, shaft_front),
        speeds=dict(
            carrier=carrier_rpm, ring=ring_rpm, planet=planet_rpm, planet_max=planet_max, relative=relative_rpm
        ),
    )


def _quantity(part: Turned, count: int) -> Turned:
    return dataclasses.replace(part, quantity=count)
