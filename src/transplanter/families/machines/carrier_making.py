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
from transplanter.families.machines import carrier_bodies, carrier_plates, carrier_structure
from transplanter.families.machines.record import BOUGHT
from transplanter.machine import carrier_parts
from transplanter.machine.arm_parts import CLEARANCE_M4, TAP_DRILL_M4
from transplanter.machine.bodies import MOTION_POSITIONS
from transplanter.machine.carriers import DoubleCarrierMachine
from transplanter.machine.hardware import read_turned
from transplanter.shop import formats, solids
from transplanter.shop.export import json_bytes

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

#: the roller: a 625 deep-groove ball bearing (5 x 16 x 5 mm) on a 5 mm pin
ROLLER_PIN_MM = 5.0
ROLLER_WIDTH_MM = 5.0
#: the gears' keyed shafts, mm
SHAFT_MM = 12.0


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


def parts_to_make(study, machine: DoubleCarrierMachine, used: dict[str, bytes], hw=None) -> dict[str, tuple]:
    """Each part of the machine ``study`` (a ``DoubleCarrierMachineStudy``) drawn from ``machine``
    (as designed) and the sector pair's DXFs in ``used``, with the structure ``hw`` laid out
    (:func:`~transplanter.families.machines.carrier_structure.hardware`; default: laid out here):
    ``{part: (section, holes, making, notes)}``."""
    l3 = study.chain.link_lengths[2]
    f = study.cam.follower
    L, S = study.layers, study.structure
    hw = hw if hw is not None else carrier_structure.hardware(study, machine)
    shaft = (SHAFT_MM / 2) + 8.0  # boss radius around a 12 mm shaft
    plates = carrier_plates.structure_plates(study, machine, hw, S.sector_bolt_circle, -sector8_in_carrier2(machine))
    c1, c1_holes, c1_features, c1_notes = plates["carrier_1"]
    c2, c2_holes, c2_features, c2_notes = plates["carrier_2"]
    lever = carrier_parts.lever(f.arm_length, shaft, 7.0)
    lever_holes = ((f.arm_length, 0.0, ROLLER_PIN_MM),)
    # the sectors: the pair's gears kept over the contacts the swing uses
    lo, hi = swing_range(study.cam.motion)
    pair = study.sectors.sized
    pitch = 2 * math.pi / int(pair.sizing.teeth[0])
    g7 = formats.section_of(f"{study.sectors.name}.driver.dxf", used[f"{study.sectors.name}.driver.dxf"])
    g8 = formats.section_of(f"{study.sectors.name}.driven.dxf", used[f"{study.sectors.name}.driven.dxf"])
    s7 = carrier_parts.sector(g7, lo, hi, pitch, 20.0)
    # sector 8 turns on gear 5-9's shaft in a bearing: the gear's keyed bore filled, the bearing's bored
    s8 = shapely.Polygon(carrier_parts.sector(g8, -hi, -lo, pitch, 20.0).exterior)
    # sector 8 turns on gear 5-9's shaft in a bearing, screwed to carrier 2 from carrier 2's front
    s8_holes = plates["sector_8_holes"]
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
            dataclasses.replace(study.plate, features=c1_features),
            (
                *c1_notes,
                "carries gears 3-4, gear 5-9 and the follower on their shafts (bearings here and in its front plate) "
                "and carrier 2 on gear 5-9's shaft",
                "timing: its +x line through A_c at the chain's pose 1 (see the machine record)",
                where.format(*L.carrier1),
            ),
        ),
        "carrier_2": (
            c2,
            c2_holes,
            dataclasses.replace(study.plate, features=c2_features),
            (
                *c2_notes,
                f"timing: sector 8's DXF frame sits {keys['sector_8_frame_from_carrier_2s']:g} deg from this one's "
                "(counter-clockwise, seen from the arm's side); its screws set it",
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
            dataclasses.replace(
                study.sector,
                features=solids.Features(holes=s8_holes),
                operations=(f"tap the 2 holes {S.screws['sector'][0]} through",),
            ),
            (
                f"sector gear 8 (carrier 2's): {study.sectors.name}.driven's teeth kept over the swing; turns on "
                f"gear 5-9's shaft in a bearing (bore Ø{s8_holes[0][2]:g} H7), screwed to carrier 2 "
                f"(2 x {S.screws['sector'][0]} tapped (op 20), across two spacers)",
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
                operations=("tap the 2 holes M4 through",),
            ),
            (
                f"transplanting arm (link 3): keyed to gear 11's shaft at Q (its origin); the claw tip at "
                f"({l3:g}, 0) mm",
                "mates with gear 11 (keyed on one shaft at Q) and the claw (bolted)",
                f"timing: this keyway sits {keys['arm_keyway_from_gear_11s']:g} deg from gear 11's on the shaft "
                "(counter-clockwise, seen from the arm's side; gear 11 is mounted face down)",
                "2 x M4 tapped for the claw (op 20)",
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
        **{
            part: (
                plates[part][0],
                plates[part][1],
                dataclasses.replace(making, features=plates[part][2], operations=plates["operations"].get(part, ())),
                (*plates[part][3], where.format(*z)),
            )
            for part, making, z in (
                ("carrier_1_front", study.plate, S.cover),
                ("carrier_2_front", study.plate, S.front),
                ("hub", dataclasses.replace(study.plate, width=S.hub[1] - S.hub[0], material="C45"), S.hub),
                ("frame", dataclasses.replace(study.plate, width=S.frame[1] - S.frame[0]), S.frame),
            )
        },
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
        # the cam: its holes place the screws that hold it on its posts
        return (self.machine.sectors.name, self.machine.cam.name)

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
        hw = carrier_structure.hardware(spec, design)
        sections = {}
        for part, (section, _holes, making, notes) in parts_to_make(spec, design, used, hw).items():
            res, shop, made = manufacture(
                f"{self.name}.{part}",
                section,
                shapely.Polygon(),
                making,
                notes,
                lambda pt: f"({pt[0]:.1f}, {pt[1]:.1f})",
            )
            results[part] = res
            files.update(shop)
            sections[part] = made.section
        for turned, _ in hw.turned:
            res, shop = turned.files()  # its drawing re-read as the part it shows, or an error
            res["dxf_R2000"] = {"layer": "TURN", "re_read_as_made": True}
            results[turned.name.removeprefix(f"{self.name}.")] = res
            files.update(shop)
        # the bought parts' drawings, for the judge: the structure's and the screws' heads
        screwed = carrier_bodies.screws(spec, _screwed_bodies(spec, design, hw, sections, self.name), {**used, **files})
        files.update(carrier_bodies.bought_files(self.name, [*hw.fitted, *(_fitted(b) for b in screwed)]))
        results["structure"] = {**spec.structure.record(), "bearings": list(hw.bearings), "shafts": hw.shafts}
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
                layer=formats.BOUGHT,
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
        # the parts' records beside their files, for the machine's bill of materials (bill.made_records)
        files[f"{self.name}.parts.json"] = json_bytes({"parameters": params, "results": results})
        return Built({"kind": "carrier_parts", "parameters": params, "results": results}, files)

    def check(self, files: dict[str, bytes]) -> Checked:
        """Each part's STEP against its DXF, re-read; each turned part's drawing re-read as made."""
        S = self.machine.structure
        widths = {f"{self.name}.{p}": getattr(self.machine, m).width for p, m in self.WIDTHS}
        for part, z in (("carrier_1_front", S.cover), ("carrier_2_front", S.front), ("hub", S.hub), ("frame", S.frame)):
            widths[f"{self.name}.{part}"] = z[1] - z[0]
        made, problems = check_shop_files(files, widths)
        for turned, _ in carrier_structure.hardware(self.machine, self.machine.design).turned:
            again = read_turned(files[f"{turned.name}.dxf"], turned.name)
            if not again.same_as(turned):
                problems.append(f"{turned.name}.dxf re-reads as {again}, not as made")
        return Checked({"made": made}, problems)


def _fitted(b):
    from transplanter.machine.hardware import Fitted

    return Fitted(b.name, b.part, b.link, b.z, b.flip)


def _screwed_bodies(study, machine, hw, sections: dict, stem: str) -> dict:
    """The bodies the screwed joints name, as :func:`carrier_bodies.screws` reads them: the plates
    made here, the cam, the claw and arm, and one post."""
    from transplanter.machine.bodies import Body

    L, S = study.layers, study.structure
    z = {
        "carrier_1": L.carrier1,
        "carrier_2": L.carrier2,
        "carrier_1_front": S.cover,
        "carrier_2_front": S.front,
        "hub": S.hub,
        "frame": S.frame,
        "sector_8": L.sectors,
        "arm": L.arm,
        "claw": L.claw,
    }
    out = {name: Body(name, sections[name], zr, "x", f"{stem}.{name}.dxf") for name, zr in z.items()}
    out["cam"] = Body("cam", shapely.box(0, 0, 1, 1), L.cam, "fixed", f"{study.cam.name}.cam.dxf")
    post = next(p for t, ps in hw.turned for p in ps if p.body == "post_1")
    out["post_1"] = Body("post_1", shapely.box(0, 0, 1, 1), post.z, post.link, "")
    return out
