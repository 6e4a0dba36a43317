"""The parts seed 002's machine makes (:mod:`~transplanter.families.machines.carrier_machine`), as a
designer draws them (:mod:`transplanter.machine.carrier_parts`), with their shafts, bolts and shop notes:
carrier 1, carrier 2, the follower lever, the sector gears 7 and 8, the arm and its claw — and the
part that makes them (:class:`CarrierPartsStudy`)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.families.builder.making import check_shop_files, manufacture
from transplanter.families.builder.study import Built, Checked, StudyDefaults
from transplanter.machine import carrier_parts
from transplanter.machine.arm_parts import CLEARANCE_M4, TAP_DRILL_M4
from transplanter.machine.bodies import MOTION_POSITIONS
from transplanter.machine.carriers import DoubleCarrierMachine
from transplanter.shop import formats, solids

__all__ = [
    "CarrierPartsStudy",
    "BOUGHT",
    "parts_to_make",
    "claw_span",
    "sector8_in_carrier2",
    "shaft_keys",
    "MIRRORED",
    "roller_z",
    "SHAFT_MM",
    "ROLLER_WIDTH_MM",
]

#: the suffix of a bought part's section (drawn for the judge, not cut)
BOUGHT = ".bought.dxf"
#: the roller: a 625 deep-groove ball bearing (5 x 16 x 5 mm) on a 5 mm pin
ROLLER_PIN_MM = 5.0
ROLLER_WIDTH_MM = 5.0
#: shaft and bore diameters, mm: the gears' keyed shafts, the frame shaft through carrier 1
SHAFT_MM = 12.0
FRAME_SHAFT_MM = 30.0
#: sector 8's two bolts to carrier 2 sit on this radius about A_c (the hubs are 20 mm), mm
BOLT_CIRCLE_MM = 13.0


#: the arm's hub at Q and its boss where the claw is bolted, radii (mm)
ARM_HUB_MM, ARM_BOSS_MM = 16.0, 9.0
#: the claw's bolts sit this far inside its tab's ends, mm
CLAW_BOLT_INSET_MM = 5.0


def claw_span(study) -> tuple[float, float]:
    """Where the claw starts on the arm (its tab's end under the arm's boss) and how long its
    free tines are to the tip, mm, for the machine ``study``."""
    start = study.claw_at - ARM_BOSS_MM
    return start, study.chain.link_lengths[2] - (start + study.claw_tab)


def roller_z(layers) -> tuple[float, float]:
    """The roller (5 mm wide) in the middle of the cam's plane."""
    mid = 0.5 * sum(layers.cam)
    return mid - ROLLER_WIDTH_MM / 2, mid + ROLLER_WIDTH_MM / 2


def parts_to_make(study, machine: DoubleCarrierMachine, used: dict[str, bytes]) -> dict[str, tuple]:
    """Each part of the machine ``study`` (a ``DoubleCarrierMachineStudy``) drawn from ``machine``
    (as designed) and the sector pair's DXFs in ``used``: ``{part: (section, holes, making,
    notes)}``."""
    lay = machine.layout
    l1, l2, l3 = study.chain.link_lengths
    f = study.cam.follower
    L = study.layers
    shaft = (SHAFT_MM / 2) + 8.0  # boss radius around a 12 mm shaft
    c1 = carrier_parts.plate([(0.0, 0.0, 26.0), (*lay.s3, shaft), (l1, 0.0, shaft), (*lay.pivot, shaft)])
    c1_holes = ((0.0, 0.0, FRAME_SHAFT_MM), (*lay.s3, SHAFT_MM), (l1, 0.0, SHAFT_MM), (*lay.pivot, SHAFT_MM))
    # carrier 2 carries sector 8, bolted: two M4 on a circle about A_c
    bolts = tuple(
        (BOLT_CIRCLE_MM * math.cos(a), BOLT_CIRCLE_MM * math.sin(a)) for a in (0.25 * math.pi, 1.25 * math.pi)
    )
    c2 = carrier_parts.plate([(0.0, 0.0, 20.0), (*lay.idler, shaft), (l2, 0.0, shaft)])
    c2_holes = (
        (0.0, 0.0, SHAFT_MM),
        (*lay.idler, SHAFT_MM),
        (l2, 0.0, SHAFT_MM),
        *((x, y, TAP_DRILL_M4) for x, y in bolts),
    )
    lever = carrier_parts.lever(f.arm_length, shaft, 7.0)
    lever_holes = ((f.arm_length, 0.0, ROLLER_PIN_MM),)
    # the sectors: the pair's gears kept over the contacts the swing uses
    lo, hi = swing_range(study.cam.motion)
    pair = study.sectors.sized
    pitch = 2 * math.pi / int(pair.sizing.teeth[0])
    g7 = formats.section_of(f"{study.sectors.name}.driver.dxf", used[f"{study.sectors.name}.driver.dxf"])
    g8 = formats.section_of(f"{study.sectors.name}.driven.dxf", used[f"{study.sectors.name}.driven.dxf"])
    s7 = carrier_parts.sector(g7, lo, hi, pitch, 20.0)
    s8 = carrier_parts.sector(g8, -hi, -lo, pitch, 20.0)
    # sector 8's bolts where carrier 2's tapped holes are (carrier 2's frame -> sector 8's)
    turn = -sector8_in_carrier2(machine)
    c, s = math.cos(turn), math.sin(turn)
    s8_holes = tuple((c * x - s * y, s * x + c * y, CLEARANCE_M4) for x, y in bolts)
    arm = carrier_parts.arm(l3, ARM_HUB_MM, ARM_BOSS_MM, study.claw_at)
    start, tines = claw_span(study)
    claw = carrier_parts.claw(l3, start, study.claw_width, study.claw_tab)
    claw_bolts = ((start + CLAW_BOLT_INSET_MM, 0.0), (start + study.claw_tab - CLAW_BOLT_INSET_MM, 0.0))
    where = "layer z {:g}..{:g} mm from the cam's back face"
    keys = shaft_keys(machine)
    return {
        "carrier_1": (
            c1,
            c1_holes,
            dataclasses.replace(study.plate, features=solids.Features(holes=c1_holes)),
            (
                "first planetary carrier (link 1): turns clockwise on the frame shaft (bore "
                f"{FRAME_SHAFT_MM:g} mm at A0, its origin); +x to A_c",
                f"shafts ({SHAFT_MM:g} mm): gears 3/4 at ({lay.s3[0]:.3f}, {lay.s3[1]:.3f}), gear 5/9 and "
                f"carrier 2 at A_c ({l1:.4f}, 0), the follower at ({lay.pivot[0]:.3f}, {lay.pivot[1]:.3f}) mm",
                "mates with the frame shaft (a bearing at A0) and carries gears 3/4, gear 5/9, the follower and "
                "carrier 2 on their shafts",
                "timing: its +x line through A_c at the chain's pose 1 (see the machine record)",
                where.format(*L.carrier1),
            ),
        ),
        "carrier_2": (
            c2,
            c2_holes,
            dataclasses.replace(study.plate, features=solids.Features(holes=c2_holes)),
            (
                f"second planetary carrier (link 2): turns about A_c (its origin) on gear 5/9's shaft; +x to Q "
                f"({l2:.4f}, 0)",
                f"shafts ({SHAFT_MM:g} mm): the idler 10 at ({lay.idler[0]:.3f}, {lay.idler[1]:.3f}), gear 11 and "
                "the arm at Q",
                "mates with sector 8: 2 x M4 tapped (tap drill 3.3 mm) about A_c",
                f"timing: sector 8's DXF frame sits {keys['sector_8_frame_from_carrier_2s']:g} deg from this one's "
                "(counter-clockwise, seen from the arm's side); its bolts set it",
                where.format(*L.carrier2),
            ),
        ),
        "lever": (
            lever,
            lever_holes,
            dataclasses.replace(study.lever, features=solids.Features(bore=SHAFT_MM, holes=lever_holes)),
            (
                f"cam follower lever (7): pivot at its origin on carrier 1, keyed with sector 7 on one shaft; "
                f"roller pin ({ROLLER_PIN_MM:g} mm, a 625 bearing, 16 mm) at ({f.arm_length:g}, 0) mm",
                "mates with the cam (its roller on the cam's profile) and sector 7 (keyed on one shaft)",
                f"timing: sector 7's keyway sits {keys['sector_7_keyway_from_the_levers']:g} deg from this one's "
                "on the shaft (counter-clockwise, seen from the arm's side)",
                where.format(*L.lever) + "; its roller in the cam's plane",
            ),
        ),
        "sector_7": (
            s7,
            (),
            dataclasses.replace(study.sector, features=solids.Features()),
            (
                f"sector gear 7 (the follower's): {study.sectors.name}.driver's teeth kept over the swing "
                f"({math.degrees(hi - lo):.1f} deg) and 3 pitches each side; keyed on the lever's shaft",
                f"mates with sector 8, centre distance {pair.pair.centre_distance:.4f} mm, ratio 1",
                "timing: its timing hole meets sector 8's at the swing's start (the follower on the cam's base circle)",
                where.format(*L.sectors),
            ),
        ),
        "sector_8": (
            s8,
            s8_holes,
            dataclasses.replace(study.sector, features=solids.Features(holes=s8_holes)),
            (
                f"sector gear 8 (carrier 2's): {study.sectors.name}.driven's teeth kept over the swing; turns on "
                "gear 5/9's shaft, bolted to carrier 2 (2 x M4 clearance 4.5 mm)",
                f"mates with sector 7, centre distance {pair.pair.centre_distance:.4f} mm",
                "timing: its timing hole meets sector 7's at the swing's start; its bolts set it on carrier 2",
                where.format(*L.sectors),
            ),
        ),
        "arm": (
            arm,
            (),
            dataclasses.replace(
                study.arm,
                features=solids.Features(bore=SHAFT_MM, holes=tuple((x, y, TAP_DRILL_M4) for x, y in claw_bolts)),
            ),
            (
                f"transplanting arm (link 3): keyed to gear 11's shaft at Q (its origin); the claw tip at "
                f"({l3:g}, 0) mm",
                "mates with gear 11 (keyed on one shaft at Q) and the claw (bolted)",
                f"timing: this keyway sits {keys['arm_keyway_from_gear_11s']:g} deg from gear 11's on the shaft "
                "(counter-clockwise, seen from the arm's side; gear 11 is mounted face down)",
                "2 x M4 tapped (tap drill 3.3 mm) for the claw",
                where.format(*L.arm),
            ),
        ),
        "claw": (
            claw,
            tuple((x, y, CLEARANCE_M4) for x, y in claw_bolts),
            dataclasses.replace(
                study.claw, features=solids.Features(holes=tuple((x, y, CLEARANCE_M4) for x, y in claw_bolts))
            ),
            (
                f"clamping claw: its tines' section in the arm's frame, {tines:.0f} mm free to enter the pot "
                "(seed 002 requirement 3: >= 30 mm); bolted on the arm (2 x M4)",
                f"tip (point R{carrier_parts.TIP_RADIUS_MM:g}) at ({l3:g}, 0) mm",
                "mates with the arm: timing by its two bolt holes on the arm's tapped holes",
                where.format(*L.claw),
            ),
        ),
    }


def sector8_in_carrier2(machine: DoubleCarrierMachine) -> float:
    """Sector 8's DXF frame angle in carrier 2's frame (fixed: it is bolted there)."""
    p = machine.poses(np.zeros(1))
    return float(p["sector8"][2][0] - p["carrier2"][2][0])


#: the members whose parts are mounted face down (their DXF mirrored about its x-axis)
MIRRORED = ("sun", "shaft3", "gear9", "idler", "gear11")


def shaft_keys(machine: DoubleCarrierMachine) -> dict[str, float]:
    """How the parts on one shaft turn from each other at the start, deg counter-clockwise seen
    from the arm's side: the angle from one part's keyway to its shaft-mate's (each part's keyway
    is at +y of its DXF, which a part mounted face down shows at -y) — what a shop sets when it
    cuts the shaft's keyways; and for sector 8, bolted, the angle of its DXF frame from carrier 2's."""
    p = machine.poses(np.zeros(1))

    def key(a: str) -> float:
        return float(p[a][2][0]) + (-0.5 if a in MIRRORED else 0.5) * math.pi

    def diff(x: float) -> float:
        return round(math.degrees(math.remainder(x, 2 * math.pi)), 4)

    return {
        "gear_4_keyway_from_gear_3s": diff(key("shaft3b") - key("shaft3")),
        "gear_9_keyway_from_gear_5s": diff(key("gear9") - key("shaft5")),
        "sector_7_keyway_from_the_levers": diff(key("sector7") - key("follower")),
        "arm_keyway_from_gear_11s": diff(key("arm") - key("gear11")),
        "sector_8_frame_from_carrier_2s": diff(sector8_in_carrier2(machine)),
    }


def swing_range(motion) -> tuple[float, float]:
    """The follower's swing, smallest and largest over a cam turn (rad), at the motion table's
    positions."""
    t = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    s = np.asarray(motion(t), dtype=float)
    return float(s.min()), float(s.max())


@dataclass(frozen=True)
class CarrierPartsStudy(StudyDefaults):
    """The parts seed 002's machine makes (this module's :func:`parts_to_make`): carrier
    1, carrier 2, the follower lever, the sector gears 7 and 8 (trimmed from the sector pair's
    DXFs, the one file they use), the arm and its claw — drawn from the machine as designed
    (``machine.design``) with its keys, DXF, STL and STEP each; and the bought roller's section
    for the judge. ``machine`` is the :class:`DoubleCarrierMachineStudy` that states them."""

    cost = 5

    name: str
    #: the ``carrier_machine.DoubleCarrierMachineStudy`` that states the parts (it makes this
    #: study: ``parts_study()``; not imported here, the machine module imports this one)
    machine: StudyDefaults

    @property
    def uses(self) -> tuple[str, ...]:
        return (self.machine.sectors.name,)

    WIDTHS = (
        ("carrier_1", "plate"),
        ("carrier_2", "plate"),
        ("lever", "lever"),
        ("sector_7", "sector"),
        ("sector_8", "sector"),
        ("arm", "arm"),
        ("claw", "claw"),
    )

    def build(self, out: Path) -> Built:
        raise GeometryError(f"{self.name} is built from the files of {list(self.uses)} (the builder gives them)")

    def build_using(self, out: Path, used: dict[str, bytes]) -> Built:
        spec = self.machine
        design = spec.design
        files: dict[str, bytes] = {}
        results: dict = {}
        for part, (section, _holes, making, notes) in parts_to_make(spec, design, used).items():
            res, shop, _ = manufacture(
                f"{self.name}.{part}",
                section,
                shapely.Polygon(),
                making,
                notes,
                lambda pt: f"({pt[0]:.1f}, {pt[1]:.1f})",
            )
            results[part] = res
            files.update(shop)
        f = spec.cam.follower
        roller = solids.circle_polygon(f.arm_length, 0.0, f.roller_radius)
        files[f"{self.name}.roller{BOUGHT}"] = formats.DXF.write(
            formats.MadePart(
                f"{self.name}.roller",
                roller,
                None,
                5.0,
                (
                    f"bought: 625 ball bearing (5 x {2 * f.roller_radius:g} x 5 mm) on the lever's pin, "
                    "in the lever's frame",
                ),
            )
        )
        lay = design.layout
        results["keys_deg"] = shaft_keys(design)
        results["shafts_mm"] = {
            "gear_3_4_on_carrier_1": [rounded(v, 6) for v in lay.s3],
            "follower_pivot_on_carrier_1": [rounded(v, 6) for v in lay.pivot],
            "idler_on_carrier_2": [rounded(v, 6) for v in lay.idler],
        }
        params = {
            "claw_mm": {"at": spec.claw_at, "width": spec.claw_width, "tab": spec.claw_tab},
            "machine": spec.name,
            "uses": list(self.uses),
        }
        return Built({"kind": "carrier_parts", "parameters": params, "results": results}, files)

    def check(self, files: dict[str, bytes]) -> Checked:
        """Each part's STEP against its DXF, re-read."""
        made, problems = check_shop_files(
            files, {f"{self.name}.{p}": getattr(self.machine, m).width for p, m in self.WIDTHS}
        )
        return Checked({"made": made}, problems)
