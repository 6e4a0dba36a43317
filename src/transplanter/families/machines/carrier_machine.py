"""The whole seed-002 machine: both carriers, the sector and spur gears, the arm with its claw,
posed from the made parts, every two bodies that could meet judged over the cycle, and the cycle
to watch.

:class:`DoubleCarrierMachineStudy` is built from the files of five earlier parts of its family
(``uses``): the two non-circular stages, the sector pair 7-8 and the spur pair 9-10 (each its
DXFs and the meshing its proof measured on them, ``<pair>.dxf_meshing.csv``) and the swing cam
(its DXF, on which the follower is run again). It

1. poses every member (:class:`transplanter.machine.carriers.DoubleCarrierMachine`) from those made
   meshes and the follower's swing on the re-read cam;
2. makes what the earlier parts do not: carrier 1 and carrier 2 (plates around their shafts),
   the follower lever (the roller is a bought 625 ball bearing, drawn for the judge), the sector
   gears 7 and 8 (the sector pair's gears kept over the swing they mesh in), the arm (link 3) and
   its claw — DXF, STL, STEP and notes each; what holds and drives them
   (:mod:`~transplanter.families.machines.carrier_structure`: the frame, the fixed shaft, the drive
   tube and carrier 1's hub, both carriers' front plates, every gear shaft turned and held in two
   bearings, spacers, standoffs and posts; the bearings, bushes, rings, keys and screws bought);
   and the soil and seed 002's pot tray (:mod:`transplanter.machine.tray`) as obstacles;
3. stacks the bodies in the planes the part script states
   (:class:`~transplanter.families.machines.layers.CarrierLayers`);
4. judges every two bodies that move against each other in 3D over the cycle
   (:func:`transplanter.machine.bodies.judge_pairs`): planes at least ``layers.min_axial_gap``
   apart pass on that gap, the others must keep the clearance stated in-plane, bounded between
   samples (:mod:`transplanter.proof.clearance`); the declared joints (meshes, the roller on the cam
   and on its pin, the claw's bolts) are recorded; every gearbox body (carriers and all they carry)
   is held above the soil by seed 002's requirement 7 (≥ 40 mm); the claw in the soil is its work
   (only its tines may enter); the follower pivot's shaft end keeps its axial gap to the cam; the
   structure's hardware keeps its running clearance in the bores it passes; every body against the
   pot tray, the claw's grip in the picked pot its work, seed 002's requirements 2 and 3 recorded
   with their margins (``results.machine.tray``; a requirement the design does not meet is a
   finding, ``results.machine.findings``, not a failed part: the tray is the seedling box's);
5. checks that the claw, posed from the made parts, passes the synthesised four poses (Table 1
   with link 3's attitudes) within the tolerance stated (``pose_tolerance``);
6. writes the motion table, an animated GIF, the report's slider, a 3MF of the made parts at the
   start; the bill of materials, the assembly STEP, the assembly drawing with balloons and its
   picture (:mod:`~transplanter.families.machines.assembly`, the bought parts:
   :func:`~transplanter.families.machines.carrier_bodies.assembly_inputs`); and ``results.machine`` (the
   data contract a judge re-poses the DXF bodies from).

**The soil** (the paper gives no soil line for its Table 1 frame): a rotary planter plants where
its tip reaches farthest from the carrier axis, so the machine frame is turned to put that
direction straight down, and the soil surface lies ``planting_depth`` above the deepest point —
the pot's 40 mm (seed 002 §2.2: the pot seedling is set to its rim).

Posed from the files in :mod:`~transplanter.families.machines.carrier_posing` (steps 1 and 3, and
the soil), judged in :mod:`~transplanter.families.machines.carrier_judging` (steps 4 and 5, and step
6's motion table and pictures); the parts of step 2 are made by
:mod:`~transplanter.families.machines.carrier_making`; this module states the study and writes the
record.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

from transplanter.core.errors import GeometryError, SpecError, check_number
from transplanter.design.linkage.open_chain import OpenChain3R
from transplanter.families.builder.making import Making, check_shop_files
from transplanter.families.builder.study import Built, Checked, StudyDefaults
from transplanter.families.machines import (
    carrier_bodies,
    carrier_judging,
    carrier_loads,
    carrier_making,
    carrier_posing,
    shafts,
)
from transplanter.families.machines.assembly import (
    AssemblyFiles,
    BoughtBody,
    check_documents,
    documents_and_assembly,
    start_pose,
    step_made,
)
from transplanter.families.machines.carrier_making import BOUGHT, CarrierPartsStudy
from transplanter.families.machines.carrier_structure import CarrierStructure
from transplanter.families.machines.layers import CarrierLayers
from transplanter.families.machines.loads import supports_short
from transplanter.families.machines.record import judged_again, obstacle_file
from transplanter.families.mechanisms.cams import CamStudy
from transplanter.families.pairs.toothed import ToothedPairStudy
from transplanter.machine.carriers import DoubleCarrierMachine
from transplanter.machine.tray import PotTray
from transplanter.shop.export import json_bytes

__all__ = ["CarrierLayers", "DoubleCarrierMachineStudy", "CarrierPartsStudy", "BOUGHT", "GEARBOX_ABOVE_SOIL_MM"]

#: seed 002 §2.2 requirement 7: the gearbox's lowest point at least this far above the soil, mm
GEARBOX_ABOVE_SOIL_MM = 40.0


@dataclass(frozen=True)
class DoubleCarrierMachineStudy(StudyDefaults):
    """Seed 002's machine (module docstring)."""

    cost = 8

    name: str
    chain: OpenChain3R
    stage23: ToothedPairStudy
    stage35: ToothedPairStudy
    #: the sector gears' pair (driver: the follower's sector 7) and the spur pair 9-10 (11 = 9)
    sectors: ToothedPairStudy
    spurs: ToothedPairStudy
    cam: CamStudy
    layers: CarrierLayers
    #: the clearance every two bodies that could meet must keep, mm
    clearance: float
    #: plates (carriers), the follower lever, sectors, arm and claw as made (width = thickness)
    plate: Making
    lever: Making
    sector: Making
    arm: Making
    claw: Making
    #: the claw's tip at the four poses: (position mm, attitude deg)
    pose_tolerance: tuple[float, float] = (1.1, 0.5)
    #: the soil surface above the tip's deepest point, mm
    planting_depth: float = 40.0
    gearbox_above_soil: float = GEARBOX_ABOVE_SOIL_MM
    #: the arm plate's boss where the claw is bolted (mm from Q), claw width and tab length, mm
    claw_at: float = 70.0
    claw_width: float = 10.0
    claw_tab: float = 20.0
    #: the name of the part that makes the carriers, lever, sectors, arm and claw
    #: (:meth:`parts_study`; the machine is posed and judged from its files)
    parts: str = "carriers"
    #: what holds and drives the machine (:mod:`~transplanter.families.machines.carrier_structure`)
    structure: CarrierStructure | None = None
    #: seed 002's pot tray the claw picks from (None: no tray judged), and how deep the claw must
    #: enter the picked pot (seed 002 requirement 3), mm
    tray: PotTray | None = None
    pot_depth: float = 30.0

    def __post_init__(self) -> None:
        if not isinstance(self.structure, CarrierStructure):
            raise SpecError(f"{self.name}: structure must be a CarrierStructure (what holds and drives the machine)")
        if self.tray is not None and not isinstance(self.tray, PotTray):
            raise SpecError(f"{self.name}: tray must be a PotTray or None")
        check_number("pot_depth", self.pot_depth, 0.0, 1000.0, low_open=True, unit="mm")
        check_number("clearance", self.clearance, 0.0, 1000.0, unit="mm")
        check_number("planting_depth", self.planting_depth, 0.0, 500.0, unit="mm")
        check_number("gearbox_above_soil", self.gearbox_above_soil, 0.0, 1000.0, unit="mm")
        for what in ("stage23", "stage35", "sectors", "spurs"):
            study = getattr(self, what)
            if not isinstance(study, ToothedPairStudy) or study.making is None:
                raise SpecError(
                    f"{self.name}: {what} must be a ToothedPairStudy with making (its files pose the machine)"
                )
        if not isinstance(self.cam, CamStudy) or self.cam.making is None:
            raise SpecError(f"{self.name}: cam must be a CamStudy with making (its DXF moves carrier 2)")
        for what in ("plate", "lever", "sector", "arm", "claw"):
            if not isinstance(getattr(self, what), Making):
                raise SpecError(f"{self.name}: {what} must be a Making")
        if len(self.pose_tolerance) != 2:
            raise SpecError.out_of_range("pose_tolerance", self.pose_tolerance, "(position mm, attitude deg)")
        check_number("pose_tolerance position", self.pose_tolerance[0], 0.0, 100.0, low_open=True, unit="mm")
        check_number("pose_tolerance attitude", self.pose_tolerance[1], 0.0, 45.0, low_open=True, unit="deg")
        for what, width in (
            ("stage23", self.stage23.making[0].width),
            ("stage35", self.stage35.making[0].width),
            ("sectors", self.sector.width),
            ("spurs", self.spurs.making[0].width),
            ("cam", self.cam.making.width),
            ("lever", self.lever.width),
            ("carrier1", self.plate.width),
            ("carrier2", self.plate.width),
            ("arm", self.arm.width),
            ("claw", self.claw.width),
        ):
            z = getattr(self.layers, what)
            if abs((z[1] - z[0]) - width) > 1e-9:
                raise SpecError.out_of_range(f"layers.{what}", z, f"as wide as what sits there ({width:g} mm)")

    @property
    def uses(self) -> tuple[str, ...]:
        return (self.stage23.name, self.stage35.name, self.sectors.name, self.spurs.name, self.cam.name, self.parts)

    def parts_study(self) -> CarrierPartsStudy:
        """The part that makes this machine's carriers, lever, sectors, arm and claw — list it in
        the family before the machine: a change to a gear's backlash re-poses the machine without
        making its plates again."""
        return CarrierPartsStudy(self.parts, self)

    # -- the machine as designed (posed from the files: carrier_posing) ------------------------

    @cached_property
    def design(self) -> DoubleCarrierMachine:
        """The machine as designed: the pairs' design motions, the cam's law — what the parts are
        drawn from and their keys are cut for (:func:`carrier_posing.design`)."""
        return carrier_posing.design(self)

    # -- build -------------------------------------------------------------------------------

    def build(self, out: Path) -> Built:
        raise GeometryError(f"{self.name} is built from the files of {list(self.uses)} (the builder gives them)")

    def build_using(self, out: Path, used: dict[str, bytes]) -> Built:
        with AssemblyFiles() as assembly:  # its processes forked now, while this one holds little
            return self._built(used, assembly)

    def _built(self, used: dict[str, bytes], assembly: AssemblyFiles) -> Built:
        machine, posed_from = carrier_posing.made_machine(self, used)
        files: dict[str, bytes] = {}
        results: dict = {}
        files.update(obstacle_file(self.name, "soil", carrier_posing.soil(self), carrier_posing.span(self)))
        if self.tray is not None:
            files.update(carrier_posing.tray_files(self))
        judged = carrier_judging.judge(self, {**used, **files}, machine)
        record = judged["record"]
        record["posed_from"] = {
            "meshing": [f"{getattr(self, w).name}.dxf_meshing.csv" for w in ("stage23", "stage35", "sectors", "spurs")],
            "cam": f"{self.cam.name}.cam.dxf (the follower run on it again)",
            **posed_from,
        }
        record["keys_deg"] = carrier_making.shaft_keys(self.design)
        results["machine"] = record
        files.update(judged["files"])
        # the 3MF of the made plates and gears; the bill of materials, the assembly STEP and drawing
        # with balloons, the picture (the structure's turned parts by their solids, its bought parts)
        shop = {**used, **files}
        shown, bought, made = carrier_bodies.assembly_inputs(self, judged, shop)
        assembly.start_assembly(self.name, shown, judged["links"], {})
        documents, more, bom, placed = documents_and_assembly(
            self.name, judged["bodies"], judged["links"], {}, shop, bought, made=made, step=assembly.step
        )
        results.update(documents)
        files.update(more)
        results["assembly"], more = assembly.start_assembly_made()
        files.update(more)
        # the machine under load: masses from the assembly's bodies, the designed motion (issue 44)
        links_of = {b.name: b.link for b in [*judged["bodies"], *made, *bought]}
        results["loads"], more = carrier_loads.study_loads(
            self,
            placed,
            bom,
            links_of,
            lambda link: start_pose(link, judged["links"], {}),
            [BoughtBody.like(b) for b in bought],
            teeth=(shop, carrier_posing.body_specs(self)),
        )
        files.update(more)
        step_made(assembly.step, self.name, results, files)  # the assembly STEP, written beside the loads
        cam = results["loads"]["cam"]
        if not cam["stays_on_the_cam"]:  # a finding: the machine as drawn has no force closure at the cam
            record.setdefault("findings", []).append(
                f"under load at {carrier_loads.SPEED * 30 / math.pi:g} r/min the follower's roller leaves the cam "
                f"(the cam would have to pull {-cam['min_n']:g} N at {cam['min_at_driver_deg']:g} deg): nothing holds "
                f"it on — a return spring on the follower lever giving at least {cam['return_torque_needed_nm']:g} N m "
                f"about its pivot (at {cam['return_torque_at_driver_deg']:g} deg), or a grooved cam"
            )
        short = shafts.finding(results["loads"]["keys_and_shafts"], "its inertia and weight at 60 r/min")
        if short:
            record.setdefault("findings", []).append(short)
        built_in = results["loads"]["built_in_shaft"]
        if not built_in["pass"]:  # the structure's own shaft: short of its rating fails the part
            judged["problems"].append(
                f"the fixed shaft built into the frame falls short ({', '.join(built_in['short'])}): clamp moment "
                f"{built_in['peak_moment_at_clamp_nm']:g} N m, seat {built_in['seat_pressure_mpa']:g} MPa "
                f"(allowable {built_in['seat_pressure_allowable_mpa']:g}), deflection at the sun "
                f"{built_in['deflection_at_gear_mm'] * 1e3:.1f} µm (limit {built_in['deflection_limit_mm'] * 1e3:g}): "
                "a thicker frame plate or a larger shaft"
            )
        short = supports_short(results["loads"]["supports"], f"{self.structure.load_n:g} N")
        if short:  # sized for the structure's stated load: a support the computed loads break fails the part
            judged["problems"].append(short)
        files[f"{self.name}.machine.json"] = json_bytes(record)
        if judged["problems"]:
            raise GeometryError(f"{self.name}: " + "; ".join(judged["problems"]))
        params = {
            "clearance_mm": self.clearance,
            "gearbox_above_soil_mm": self.gearbox_above_soil,
            "planting_depth_mm": self.planting_depth,
            "pose_tolerance": {"position_mm": self.pose_tolerance[0], "attitude_deg": self.pose_tolerance[1]},
            "layers_mm": self.layers.record(),
            "claw_mm": {"at": self.claw_at, "width": self.claw_width, "tab": self.claw_tab},
            "uses": list(self.uses),
        }
        return Built({"kind": "machine", "parameters": params, "results": results}, files)

    def check(self, files: dict[str, bytes]) -> Checked:
        """The machine posed again from the files as found and every clearance judged again; each
        must be the recorded one."""
        machine, _ = carrier_posing.made_machine(self, files)
        judged = carrier_judging.judge(self, files, machine, shown=False)
        again, summary = judged_again(
            judged["record"]["clearances"], files[f"{self.name}.machine.json"], lambda r: r["required_mm"]
        )
        problems = list(judged["problems"]) + again
        # (the parts' STEPs are the parts study's to re-read; the machine's 3MF is this one's)
        shown, bought, turned = carrier_bodies.assembly_inputs(self, judged, files)
        made, more = check_shop_files(files, {}, (f"{self.name}.assembly.3mf", [b.name for b in shown]))
        problems += more
        # the bill of materials against the made files, the assembly STEP re-read
        documents, more = check_documents(self.name, judged["bodies"], judged["links"], {}, files, bought, made=turned)
        problems += more
        return Checked({"clearances": summary, "made": {**made, **documents}}, problems)
