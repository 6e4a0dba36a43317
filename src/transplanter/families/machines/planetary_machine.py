"""The whole seed-004 machine: planting arms as parts, every body posed over the cycle from the
made gears, the clearance between every two that could meet, and the cycle to watch.

:class:`PlanetaryMachineStudy` is built from the files of two earlier parts of its family
(``uses``): the ring/planet pair (its DXFs and assembly record) and the part that made the
carrier plate. It

1. takes the meshing the pair's proof measured on its ring and planet **as re-read from their
   DXFs** (``<pair>.dxf_meshing.csv``) and rebuilds the train from it — so every planet turns as
   the shop's parts let it — checked at the start against the assembly record (the pair's
   ``check`` meshes the DXFs again and holds the table to them);
2. makes the planting arm of each planet as two parts (:mod:`transplanter.machine.arm_parts`): the arm
   plate keyed to the planet shaft, and the needle bolted to it — DXF, STL, STEP, one of each per
   planet — and what holds and drives them (:mod:`~transplanter.families.machines.planetary_structure`,
   ``structure``: two carrier plates, the planet shafts in bearings at both ends, the carrier shaft,
   the ring's spacer, flange and hollow shaft, the frame, both drives; made plates, turned parts,
   bought parts) and the obstacles as DXF sections in the machine frame: the seedling box (its
   seedlings, a block ``box`` long up its slope from the end face and as high across it, its floor,
   side walls and seedling door) and the soil (below the soil level the train's metrics find);
3. stacks the bodies in the planes the part script states
   (:class:`~transplanter.families.machines.layers.Layers`): gears, carrier, arm plates, needles,
   and the structure's in the planes it derives from them; the soil across all of them;
4. judges every two bodies that move against each other in 3D over the carrier's turn
   (:func:`machine.judge_pairs`): planes at least ``layers.min_axial_gap`` apart pass on that gap,
   the others must keep the clearance stated (``clearance``) in-plane, bounded between the samples
   (:mod:`transplanter.proof.clearance`); a declared joint (the meshes, the keys, the bolts) is
   recorded, and a needle in the box or the soil is its work, recorded, not judged;
5. judges seed 004's objectives i (arms do not interfere) and ii (arms clear the box) on these
   bodies, beside the needle-line figures of :mod:`transplanter.design.objectives`, and says what one
   plane for all arm bodies would do (the reason for the layers);
6. writes the motion table (``driver_deg`` and each body's pose), an animated GIF, the slider's
   script for the report, and a 3MF of the made parts at the start; the bill of materials, the
   assembly STEP, the assembly drawing with balloons and its picture
   (:mod:`~transplanter.families.machines.assembly`, the bought parts its drawings name:
   :func:`~transplanter.families.machines.bought.planetary_bought`); and records
   ``results.machine`` (the data contract a judge re-poses the DXF bodies from).

Posed from the files in :mod:`~transplanter.families.machines.planetary_posing` (steps 1 and 3,
and step 2's obstacles), judged in :mod:`~transplanter.families.machines.planetary_judging` (steps 4
and 5, and step 6's motion table and pictures); this module states the study, makes the arm parts
and writes the record.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import shapely

from transplanter.core.errors import GeometryError, SpecError, check_number
from transplanter.core.forwarding import forward
from transplanter.design.objectives import Site
from transplanter.design.planetary import DifferentialTrain
from transplanter.families.builder.making import Making, check_shop_files, manufacture
from transplanter.families.builder.study import Built, Checked, StudyDefaults
from transplanter.families.machines import planetary_judging, planetary_loads, planetary_parts, planetary_posing, shafts
from transplanter.families.machines.assembly import (
    AssemblyFiles,
    BoughtBody,
    check_documents,
    documents_and_assembly,
    start_pose,
    step_made,
)
from transplanter.families.machines.bought import planetary_bought
from transplanter.families.machines.judging import PHASES
from transplanter.families.machines.layers import Layers
from transplanter.families.machines.loads import supports_short
from transplanter.families.machines.planetary_structure import Structure
from transplanter.families.machines.record import judged_again
from transplanter.families.pairs.toothed import ToothedPairStudy
from transplanter.machine.arm_parts import ArmParts, arm_parts
from transplanter.shop import solids
from transplanter.shop.export import json_bytes

__all__ = ["Layers", "PlanetaryMachineStudy", "PHASES", "Structure"]

#: names this module gave before issue 41 moved them to modules of their own, still found here
__getattr__ = forward(
    __name__,
    {
        "START_POSE_DEG": "transplanter.families.machines.planetary_posing",
    },
)


@dataclass(frozen=True)
class PlanetaryMachineStudy(StudyDefaults):
    """Seed 004's machine (module docstring): arms as parts, bodies posed from the made gears,
    clearances, objectives i and ii on bodies, motion, animation."""

    cost = 8

    name: str
    #: the train as designed (its pair must be ``pair``'s)
    train: DifferentialTrain
    #: the ring/planet pair study whose files pose the planets
    pair: ToothedPairStudy
    #: the part whose ``<carrier>.carrier.dxf`` is the carrier plate
    carrier: str
    site: Site
    layers: Layers
    #: the clearance every two bodies that could meet must keep, mm
    clearance: float
    #: arm plate and needle as made (width = plate thickness; features are set here)
    plate: Making
    needle: Making
    #: arm shape, mm: hub and knee-boss radii, bolting tab, needle width, needle point
    hub: float = 16.0
    boss: float = 9.0
    tab: float = 20.0
    needle_width: float = 6.0
    point: float = 12.0
    #: the seedling box section: length up the slope from its end face, height across it, mm
    box: tuple[float, float] = (300.0, 60.0)
    #: what holds and drives the train, and the box's sheet (:mod:`planetary_structure`)
    structure: Structure = Structure()

    def __post_init__(self) -> None:
        check_number("clearance", self.clearance, 0.0, 1000.0, unit="mm")
        if not isinstance(self.pair, ToothedPairStudy) or self.pair.making is None:
            raise SpecError(f"{self.name}: pair must be a ToothedPairStudy with making (its files pose the machine)")
        for what in ("plate", "needle"):
            if not isinstance(getattr(self, what), Making):
                raise SpecError(f"{self.name}: {what} must be a Making")
        check_number("box length", self.box[0], 1.0, 10_000.0, unit="mm")
        check_number("box height", self.box[1], 1.0, 10_000.0, unit="mm")
        width = self.pair.making[0].width
        if abs((self.layers.gears[1] - self.layers.gears[0]) - width) > 1e-9:
            raise SpecError.out_of_range("layers.gears", self.layers.gears, f"as wide as the gears ({width:g} mm)")

    @property
    def uses(self) -> tuple[str, ...]:
        return (self.pair.name, self.carrier)

    # -- the arm parts ----------------------------------------------------------------------

    @cached_property
    def arm(self) -> ArmParts:
        """The arm plate and the needle in the planet's frame (:func:`arm_parts.arm_parts`)."""
        return arm_parts(self.train.arm, self.hub, self.boss, self.tab, self.needle_width, self.point)

    # -- build ------------------------------------------------------------------------------

    def build(self, out: Path) -> Built:
        raise GeometryError(f"{self.name} is built from the files of {list(self.uses)} (the builder gives them)")

    def build_using(self, out: Path, used: dict[str, bytes]) -> Built:
        with AssemblyFiles() as assembly:  # its processes forked now, while this one holds little
            return self._built(used, assembly)

    def _built(self, used: dict[str, bytes], assembly: AssemblyFiles) -> Built:
        record, names, turn = planetary_posing.inputs(self, used)
        module = float(record["module_mm"])
        n = self.train.planets
        files: dict[str, bytes] = {}
        results: dict = {}
        arm = self.arm
        bore = self.pair.making[1].features.bore
        for role, section, holes, making, z in (
            ("arm_plate", arm.plate, arm.plate_holes, self.plate, self.layers.plates),
            ("needle", arm.needle, arm.needle_holes, self.needle, self.layers.needles),
        ):
            features = solids.Features(bore=bore if role == "arm_plate" else None, holes=holes)
            ops = (
                ("tap the 2 holes M4 through",)
                if role == "arm_plate"
                else (f"grind the point over its last {self.point:g} mm",)
            )
            making = dataclasses.replace(making, features=features, quantity=n, operations=ops)
            res, shop, _ = manufacture(
                f"{self.name}.{role}",
                section,
                shapely.Polygon(),
                making,
                self._notes(role, arm, z, bore),
                lambda pt: f"({pt[0]:.1f}, {pt[1]:.1f}) in the planet's frame",
            )
            results[role] = res
            files.update(shop)
        machine, start = planetary_posing.posed_machine(self, used, record, names)
        design = planetary_parts.designed(self, machine.links, used, names)
        made, more, door = planetary_parts.make(self, design, used, names, machine.links, module, turn)
        files.update(more)
        judged = planetary_judging.judge(self, {**used, **files}, names, machine, module, turn, design)
        results["machine"] = judged["record"]
        results["machine"]["posed_from"] = {
            "meshing": f"{names['meshing']} ({names['ring']} and {names['planet']} meshed by the pair's proof)",
            "assembly_record": names["record"],
            **start,
        }
        results["machine"]["structure"] = {**design.record, "door": {**door, **judged["record"]["door"]}}
        results["structure_parts"] = {r["stem"]: r for r in made}
        results["objectives_on_bodies"] = judged["objectives"]
        results["one_plane"] = judged["one_plane"]
        files.update(judged["files"])
        at = planetary_posing.start_poses(self, record)  # the planets in the middle of their play
        links = {**machine.links, **design.links}
        shown = planetary_parts.planes_of_3mf(judged["bodies"], design)
        assembly.start_assembly(self.name, shown, links, at)
        # the bill of materials, the assembly STEP and drawing with balloons, the picture
        shop, own = {**used, **files}, (results["arm_plate"], results["needle"], *made)
        bought = [*planetary_bought(planetary_parts.drawn(judged["bodies"], design), shop), *design.fitted]
        made_bodies = planetary_parts.made_bodies(design)
        documents, more, bom, placed = documents_and_assembly(
            self.name, judged["bodies"], links, at, shop, bought, own, made=made_bodies, step=assembly.step
        )
        results.update(documents)
        files.update(more)
        results["assembly"], more = assembly.start_assembly_made()
        files.update(more)
        # the machine under load: masses from the assembly's bodies, the designed motion (issue 44)
        links_of = {b.name: b.link for b in [*judged["bodies"], *made_bodies, *bought]}
        results["loads"], more = planetary_loads.study_loads(
            self,
            placed,
            bom,
            links_of,
            lambda link: start_pose(link, links, at),
            [BoughtBody.like(b) for b in bought],
            planetary_posing.planting_metrics(self, module),
            teeth=(used, names, module),
        )
        files.update(more)
        step_made(assembly.step, self.name, results, files)  # the assembly STEP, written beside the loads
        short = shafts.finding(
            results["loads"]["keys_and_shafts"], f"the stated {self.structure.needle_force_n:g} N at each needle"
        )
        if short:  # a finding: what the machine as drawn carries, and what would carry the stated load
            results["machine"].setdefault("findings", []).append(short)
        files[f"{self.name}.machine.json"] = json_bytes(results["machine"])
        sized = f"{results['machine']['structure']['loads']['design_radial_n']} N"
        short = supports_short(results["loads"]["supports"], sized)
        if short:  # sized for the structure's stated load: a support the computed loads break fails the part
            judged["problems"].append(short)
        if judged["problems"]:
            raise GeometryError(f"{self.name}: " + "; ".join(judged["problems"]))
        params = {
            "clearance_mm": self.clearance,
            "layers_mm": self.layers.record(),
            "arm_plate_mm": {"hub_radius": self.hub, "knee_boss_radius": self.boss, "bolting_tab": self.tab},
            "needle_mm": {"width": self.needle_width, "point": self.point},
            "seedling_box_section_mm": {"length_up_the_slope": self.box[0], "height_across": self.box[1]},
            "structure": dataclasses.asdict(self.structure),
            "uses": list(self.uses),
        }
        return Built({"kind": "machine", "parameters": params, "results": results}, files)

    def _notes(self, role: str, arm, z, bore) -> tuple[str, ...]:
        g = self.train.arm
        where = f"layer z {z[0]:g}..{z[1]:g} mm from the ring's back face"
        if role == "arm_plate":
            return (
                f"planting arm plate, one per planet: mates with the planet on its shaft (bore {bore:g} mm, "
                f"the planet's DIN 6885 key at +y), drawn in the planet's frame",
                "timing: the key sets the arm's angle to the planet (its timing mark on +x)",
                f"knee A at ({arm.knee[0]:.3f}, {arm.knee[1]:.3f}) mm (H1 = {g.knee:g} mm); needle tip at "
                f"S = {g.tip:g} mm, beta = {math.degrees(g.mount):.3f} deg",
                "2 x M4 tapped for the needle (op 20)",
                f"{where}; held on the planet shaft by a DIN 471 circlip on its outer face",
            )
        spacer = self.layers.needles[0] - self.layers.plates[1]
        over = f" over {spacer:g} mm spacers ({self.name}.needle_spacer)" if spacer > 0 else ""
        return (
            f"planting needle, one per arm: mates with the arm plate, bolted on its outer face (2 x M4){over}; tip at "
            f"({arm.tip[0]:.3f}, {arm.tip[1]:.3f}) mm in the planet's frame",
            "timing: its two bolt holes on the plate's tapped holes set its direction",
            f"{self.needle_width:g} mm wide, its point ground (op 20)",
            where,
        )

    def check(self, files: dict[str, bytes]) -> Checked:
        """The machine posed again from the files as found (the bodies re-read, the planets turned
        by the meshing table — which the pair's own check holds to its DXFs) and every clearance
        judged again; each must be the recorded one."""
        record, names, turn = planetary_posing.inputs(self, files)
        machine, _ = planetary_posing.posed_machine(self, files, record, names)
        design = planetary_parts.designed(self, machine.links, files, names)
        module = float(record["module_mm"])
        judged = planetary_judging.judge(self, files, names, machine, module, turn, design, shown=False)
        required = planetary_judging.required_of(self, design)
        again, summary = judged_again(
            judged["record"]["clearances"],
            files[f"{self.name}.machine.json"],
            lambda r: required(planetary_judging.Pair(*r["bodies"])),
        )
        problems = list(judged["problems"]) + again
        # the made parts' STEP against their DXF and the machine's 3MF, re-read as the other parts' are
        widths = {f"{self.name}.arm_plate": self.plate.width, f"{self.name}.needle": self.needle.width}
        widths.update({f"{self.name}.{p.part}": p.z[1] - p.z[0] for p in design.plates})
        shown = planetary_parts.planes_of_3mf(judged["bodies"], design)
        made, more = check_shop_files(files, widths, (f"{self.name}.assembly.3mf", [b.name for b in shown]))
        problems += more
        problems += planetary_parts.turned_problems(design, files)
        # the bill of materials against the made files, the assembly STEP re-read
        at = planetary_posing.start_poses(self, record)
        links = {**machine.links, **design.links}
        bought = [*planetary_bought(planetary_parts.drawn(judged["bodies"], design), files), *design.fitted]
        documents, more = check_documents(
            self.name, judged["bodies"], links, at, files, bought, made=planetary_parts.made_bodies(design)
        )
        problems += more
        return Checked({"clearances": summary, "made": {**made, **documents}}, problems)
