"""The whole seed-002 machine: both carriers, the sector and spur gears, the arm with its claw,
posed from the made parts, every two bodies that could meet judged over the cycle, and the cycle
to watch.

:class:`DoubleCarrierMachineStudy` is built from the files of five earlier parts of its family
(``uses``): the two non-circular stages, the sector pair 7-8 and the spur pair 9-10 (each its
DXFs and the meshing its proof measured on them, ``<pair>.dxf_meshing.csv``) and the swing cam
(its DXF, on which the follower is run again). It

1. poses every member (:class:`transplanter.carriers.DoubleCarrierMachine`) from those made
   meshes and the follower's swing on the re-read cam;
2. makes what the earlier parts do not: carrier 1 and carrier 2 (plates around their shafts),
   the follower lever (the roller is a bought 625 ball bearing, drawn for the judge), the sector
   gears 7 and 8 (the sector pair's gears kept over the swing they mesh in), the arm (link 3) and
   its claw — DXF, STL, STEP and notes each; and the soil as an obstacle;
3. stacks the bodies in the planes the part script states (:class:`CarrierLayers`);
4. judges every two bodies whose planes overlap and that no mesh, joint or bolt joins, over the
   cycle, bounded between samples (:mod:`transplanter.clearance`): against the clearance stated,
   and every gearbox body (carriers and all they carry) against the soil by seed 002's
   requirement 7 (≥ 40 mm); the claw in the soil is its work (only its tines may enter);
5. checks that the claw, posed from the made parts, passes the synthesised four poses (Table 1
   with link 3's attitudes) within the tolerance stated (``pose_tolerance``);
6. writes the motion table, an animated GIF, the report's slider, a 3MF of the made parts at the
   start and ``results.machine`` (the data contract a judge re-poses the DXF bodies from).

**The soil** (the paper gives no soil line for its Table 1 frame): a rotary planter plants where
its tip reaches farthest from the carrier axis, so the machine frame is turned to put that
direction straight down, and the soil surface lies ``planting_depth`` above the deepest point —
the pot's 40 mm (seed 002 §2.2: the pot seedling is set to its rim).
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import shapely

from transplanter import follower, formats
from transplanter.carriers import CarrierLayout, DoubleCarrierMachine, MadeMesh
from transplanter.errors import GeometryError, SpecError, check_number
from transplanter.export import csv_bytes, json_bytes
from transplanter.families import carrier_making
from transplanter.families.cams import CamStudy
from transplanter.families.carrier_making import BOUGHT, CarrierPartsStudy
from transplanter.families.gears import ToothedPairStudy
from transplanter.families.machine import PHASES  # the claw's: picking between poses 1 and 2
from transplanter.families.machine_record import (
    OBSTACLE,
    clearance_row,
    judged_again,
    obstacle_file,
    pictures,
    read_bodies,
    start_assembly,
)
from transplanter.families.making import Making, check_shop_files
from transplanter.families.pair_assembly import read_meshing_csv
from transplanter.families.study import Built, Checked, StudyDefaults
from transplanter.linkage.open_chain import OpenChain3R
from transplanter.machine import (
    MOTION_POSITIONS,
    Body,
    Judged,
    clearances,
    motion_rows,
    pairs_to_judge,
    posed,
    work_depth,
)
from transplanter.precision import rounded

__all__ = ["CarrierLayers", "DoubleCarrierMachineStudy", "CarrierPartsStudy", "BOUGHT", "GEARBOX_ABOVE_SOIL_MM"]

#: seed 002 §2.2 requirement 7: the gearbox's lowest point at least this far above the soil, mm
GEARBOX_ABOVE_SOIL_MM = 40.0


@dataclass(frozen=True)
class CarrierLayers:
    """Where each plane of bodies sits across the machine, z-ranges in mm (0 at the cam's back
    face): the designer's choice, stated in the part script."""

    cam: tuple[float, float]
    #: the follower lever beside the cam (its roller rides in the cam's plane)
    lever: tuple[float, float]
    carrier1: tuple[float, float]
    stage23: tuple[float, float]
    stage35: tuple[float, float]
    sectors: tuple[float, float]
    carrier2: tuple[float, float]
    spurs: tuple[float, float]
    arm: tuple[float, float]
    claw: tuple[float, float]

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            z = getattr(self, f.name)
            if not (len(z) == 2 and z[0] < z[1]):
                raise SpecError.out_of_range(f"layers.{f.name}", z, "(z0, z1) mm with z0 < z1")

    @property
    def span(self) -> tuple[float, float]:
        zs = [z for f in dataclasses.fields(self) for z in getattr(self, f.name)]
        return min(zs) - 10.0, max(zs) + 10.0


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

    def __post_init__(self) -> None:
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

    # -- the machine from the files ------------------------------------------------------------

    def _meshes(self, files: dict[str, bytes]) -> dict[str, MadeMesh]:
        out = {}
        for what in ("stage23", "stage35", "sectors", "spurs"):
            study = getattr(self, what)
            table = f"{study.name}.dxf_meshing.csv"
            if table not in files:
                raise GeometryError(f"{self.name}: the machine is posed from {table}, which is not there")
            angle, error = read_meshing_csv(files[table])
            out[what] = MadeMesh(study.sized.pair, angle, error)
        return out

    def _layout(self) -> CarrierLayout:
        l1, l2, _ = self.chain.link_lengths
        return CarrierLayout.solve(
            l1,
            l2,
            self.stage23.sized.pair.centre_distance,
            self.stage35.sized.pair.centre_distance,
            self.cam.follower.pivot_distance,
            self.sectors.sized.pair.centre_distance,
            self.spurs.sized.pair.centre_distance,
        )

    @cached_property
    def design(self) -> DoubleCarrierMachine:
        """The machine as designed: the pairs' design motions, the cam's law — what the parts are
        drawn from and their keys are cut for."""
        theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
        return DoubleCarrierMachine(
            self.chain,
            self._layout(),
            *(MadeMesh(getattr(self, w).sized.pair) for w in ("stage23", "stage35", "sectors", "spurs")),
            self.cam.follower,
            theta,
            np.asarray(self.cam.motion(theta), dtype=float),
        )

    def _machine(self, files: dict[str, bytes]) -> tuple[DoubleCarrierMachine, dict]:
        """The machine posed from the made meshes and the follower run on the re-read cam, keyed
        as the parts are cut (the design's keys)."""
        meshes = self._meshes(files)
        cam = f"{self.cam.name}.cam.dxf"
        if cam not in files:
            raise GeometryError(f"{self.name}: the machine is posed from {cam}, which is not there")
        contour = formats.section_of(cam, files[cam])
        theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
        run = follower.follower_check(contour, self.cam.motion, self.cam.follower, MOTION_POSITIONS)
        machine = DoubleCarrierMachine(
            self.chain,
            self.design.layout,
            meshes["stage23"],
            meshes["stage35"],
            meshes["sectors"],
            meshes["spurs"],
            self.cam.follower,
            theta,
            run.actual,
            self.design.cut_keys,
        )
        return machine, {"follower_on_the_cam_dxf_max_error_mm": rounded(run.max_error, 6)}

    def _soil(self) -> shapely.Polygon:
        """The soil below its surface, ``planting_depth`` above the design tip's deepest point."""
        theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
        deepest = float(self.design.tip(theta)[:, 1].min())
        level = deepest + self.planting_depth
        reach = 400.0
        return shapely.box(-reach, level - 150.0, reach, level)

    # -- bodies and judging ---------------------------------------------------------------------

    def _specs(self) -> list[tuple[str, str, tuple[float, float], str, bool]]:
        L, n = self.layers, self.parts
        s23, s35, sp = self.stage23.name, self.stage35.name, self.spurs.name
        specs = [
            ("carrier_1", f"{n}.carrier_1.dxf", L.carrier1, "carrier1", False),
            ("cam", f"{self.cam.name}.cam.dxf", L.cam, "cam", False),
            ("lever", f"{n}.lever.dxf", L.lever, "follower", False),
            ("roller", f"{n}.roller{BOUGHT}", carrier_making.roller_z(self.layers), "roller", False),
            ("sun", f"{s23}.driver.dxf", L.stage23, "sun", False),
            ("gear_3", f"{s23}.driven.dxf", L.stage23, "shaft3", False),
            ("gear_4", f"{s35}.driver.dxf", L.stage35, "shaft3b", False),
            ("gear_5", f"{s35}.driven.dxf", L.stage35, "shaft5", False),
            ("sector_7", f"{n}.sector_7.dxf", L.sectors, "sector7", False),
            ("sector_8", f"{n}.sector_8.dxf", L.sectors, "sector8", False),
            ("carrier_2", f"{n}.carrier_2.dxf", L.carrier2, "carrier2", False),
            ("gear_9", f"{sp}.driver.dxf", L.spurs, "gear9", False),
            ("gear_10", f"{sp}.driven.dxf", L.spurs, "idler", False),
            ("gear_11", f"{sp}.driver.dxf", L.spurs, "gear11", False),
            ("arm", f"{n}.arm.dxf", L.arm, "arm", False),
            ("claw", f"{n}.claw.dxf", L.claw, "arm", False),
            ("soil", f"{self.name}.soil{OBSTACLE}", L.span, "fixed", False),
        ]
        # mounted face down: the pairs seen from their backs (carriers module docstring)
        return [(*spec[:4], spec[3] in carrier_making.MIRRORED) for spec in specs]

    #: bodies joined by a mesh, a contact, a shaft, a key or bolts (not judged against each other)
    JOINED = (
        ("sun", "gear_3"),
        ("gear_4", "gear_5"),
        ("cam", "roller"),
        ("lever", "roller"),
        ("sector_7", "sector_8"),
        ("gear_9", "gear_10"),
        ("gear_10", "gear_11"),
        ("arm", "claw"),
    )
    #: the gearbox: what must keep ``gearbox_above_soil`` from the soil (all but the arm and claw)
    NOT_GEARBOX = ("arm", "claw", "soil")

    def _links(self, machine: DoubleCarrierMachine) -> dict:
        links = dict(machine.links)
        # the cam is fixed to the frame at its own angle; the roller turns on the lever's pin
        # (a circle: only its centre's path matters, posed on the lever's frame)
        cam_angle = self._cam_angle(machine)
        links["cam"] = dataclasses.replace(
            links["carrier1"], name="cam", pose=lambda t: _still(t, cam_angle), turn_rate=0.0
        )
        links["roller"] = links["follower"]
        return links

    def _cam_angle(self, machine: DoubleCarrierMachine) -> float:
        """The cam's DXF frame in the machine frame: its follower frame (pivot on +x) where carrier
        1 puts the pivot at the start, turned by the cam angle there (0)."""
        p = machine.poses(np.zeros(1))
        x, y, _ = p["follower"]
        return float(math.atan2(float(y[0]), float(x[0])))

    def _judge(self, files: dict[str, bytes], machine: DoubleCarrierMachine, shown: bool = True) -> dict:
        bodies = read_bodies(files, self._specs())
        links = self._links(machine)
        ready = posed(bodies, links)
        joined = {frozenset(p) for p in self.JOINED}
        working = {frozenset(("claw", "soil")): "the claw plants in the soil"}
        pairs = pairs_to_judge(bodies, joined, working)
        grid = 2 * math.pi * np.arange(360) / 360
        judged = clearances(ready, pairs, grid)
        gearbox = {b.name for b in bodies if b.name not in self.NOT_GEARBOX}

        def required(j: Judged) -> float:
            if "soil" in (j.pair.a, j.pair.b) and ({j.pair.a, j.pair.b} & gearbox):
                return self.gearbox_above_soil
            return self.clearance

        problems = [
            f"{j.pair.a} and {j.pair.b} come {j.distance:.4g} mm apart at driver {j.at_deg:.2f} deg "
            f"(required {required(j):g} mm)"
            for j in judged
            if not j.pair.working and j.distance < required(j)
        ]
        theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
        claw = next(b for b in bodies if b.name == "claw")
        soil = next(b for b in bodies if b.name == "soil")
        depth = self._claw_depth(claw, soil, links["arm"], theta)
        _, tines = carrier_making.claw_span(self)
        if depth["at_most_mm"] > tines:
            problems.append(
                f"the claw enters the soil {depth['at_most_mm']:.4g} mm from its tip, beyond its {tines:.4g} mm tines"
            )
        box = [j for j in judged if required(j) == self.gearbox_above_soil]
        low = min(box, key=lambda j: j.distance)
        poses = self._poses_check(machine)
        problems += poses["problems"]
        record = {
            "driver": "carrier 1, deg of clockwise turn from the chain's pose 1 (seed 002's tau)",
            "frame": (
                "A0 (the carrier axis) at the origin, y up: seed 002's Table 1 frame turned "
                f"{math.degrees(machine.frame[2]):.1f} deg about A0 so that the tip's farthest reach points down"
            ),
            "bodies": {
                b.name: {
                    "dxf": b.dxf,
                    "z_mm": [b.z[0], b.z[1]],
                    "link": b.link,
                    **({"mirrored": True} if b.mirrored else {}),
                }
                for b in bodies
            },
            "mirrored": "a mirrored body is mounted face down: its DXF mirrored about the DXF's x-axis, then posed",
            "joined": sorted(" + ".join(sorted(p)) for p in joined),
            "motion": f"{self.name}.motion.csv",
            "positions": MOTION_POSITIONS,
            "clearance_required_mm": self.clearance,
            "gearbox_above_soil_required_mm": self.gearbox_above_soil,
            "clearances": [
                {**clearance_row(j, required(j), None, depth if j.pair.working else None), "required_mm": required(j)}
                for j in judged
            ],
            "gearbox_above_soil": {
                "min_mm": rounded(low.distance, 6),
                "body": low.pair.a if low.pair.b == "soil" else low.pair.b,
                "at_driver_deg": round(low.at_deg, 4),
                "required_mm": self.gearbox_above_soil,
                "margin_mm": rounded(low.distance - self.gearbox_above_soil, 6),
            },
            "soil_level_mm": rounded(float(soil.section.bounds[3]), 6),
            "poses": poses["rows"],
            "tip_under_play": self._tip_under_play(machine, files, float(soil.section.bounds[3])),
            "animation": f"{self.name}.animation.gif",
            "slider": f"{self.name}.slider.js",
        }
        out_files = {}
        if shown:
            tip = machine.tip(theta)
            phases = [self._phases(machine, tip, float(soil.section.bounds[3]))]
            header, rows = motion_rows(bodies, links, theta)
            out_files[f"{self.name}.motion.csv"] = csv_bytes(header, rows)
            out_files.update(pictures(self.name, bodies, links, lambda t: [machine.tip(t)], judged, phases, ["arm"]))
        return {"record": record, "files": out_files, "problems": problems, "bodies": bodies, "links": links}

    def _claw_depth(self, claw: Body, soil: Body, link, theta: np.ndarray) -> dict:
        l3 = self.chain.link_lengths[2]
        deepest, at, most = work_depth(claw, soil, link, theta, (l3, 0.0), (0.0, 0.0))
        return {
            "deepest_from_tip_mm": rounded(deepest, 6),
            "at_driver_deg": round(math.degrees(at), 4),
            "at_most_mm": rounded(most, 6),
        }

    def _poses_check(self, machine: DoubleCarrierMachine) -> dict:
        """The claw at the chain's four poses against Table 1 (Q + L3 at link 3's attitude)."""
        ch = self.chain
        tau = np.asarray(ch.pose_tau, dtype=float)
        tip = machine.tip(tau)
        _, _, arm = machine.poses(tau)["arm"]
        l3 = ch.link_lengths[2]
        rows, problems = [], []
        rot = machine.frame[2]
        for k, (pose, att) in enumerate(zip(ch.poses.poses, ch.arm_attitudes, strict=True)):
            want = machine.to_machine(np.array([pose.x + l3 * math.cos(att), pose.y + l3 * math.sin(att)]))
            off = float(np.linalg.norm(tip[k] - want))
            turn = math.degrees(math.remainder(float(arm[k]) - rot - att, 2 * math.pi))
            ok = off <= self.pose_tolerance[0] and abs(turn) <= self.pose_tolerance[1]
            rows.append(
                {
                    "pose": k + 1,
                    "at_driver_deg": round(math.degrees(tau[k]), 4),
                    "tip_off_mm": rounded(off, 6),
                    "attitude_off_deg": rounded(turn, 6),
                    "tolerance": [self.pose_tolerance[0], self.pose_tolerance[1]],
                    "pass": bool(ok),
                }
            )
            if not ok:
                problems.append(
                    f"the claw misses pose {k + 1} by {off:.3g} mm and {turn:.3g} deg (tolerance "
                    f"{self.pose_tolerance[0]:g} mm, {self.pose_tolerance[1]:g} deg)"
                )
        return {"rows": rows, "problems": problems}

    def _plays(self, files: dict[str, bytes]) -> dict[str, float]:
        """Each mesh's play as a turn of its driven gear (rad): the largest free play its proof
        measured on the re-read DXFs (``assembly.backlash_mm.max``, circumferential at the pitch
        point) over the driven gear's smallest pitch radius — a bound, not a sample."""
        out = {}
        for what in ("stage23", "stage35", "sectors", "spurs"):
            study = getattr(self, what)
            record = json.loads(files[f"{study.name}.teeth.json"])["results"]["assembly"]
            out[what] = float(record["backlash_mm"]["max"]) / study.sized.pair.driven.min_radius().value
        return out

    def _tip_under_play(self, machine: DoubleCarrierMachine, files: dict[str, bytes], soil: float) -> dict:
        """The claw tip's envelope when every mesh sits anywhere within its play (:meth:`_plays`)
        and the follower within its error on the cam DXF: carrier 2 turns by up to the sectors'
        play plus the follower's error over its arm, the arm by up to stage 2-3's play carried
        through stage 4-5's ratio plus stage 4-5's and both spur meshes' (9-10, 10-11); the tip's
        largest distance from its made path over the four sign combinations, at 1440 positions."""
        play = self._plays(files)
        theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
        t3 = machine.stage23.driven(theta)
        ratio35 = np.abs(np.asarray(machine.stage35.pair.ratio(t3), dtype=float))
        follower_err = float(np.max(np.abs(machine.swing - self.cam.motion(machine.swing_at))))
        carrier2 = play["sectors"] + follower_err
        arm = play["stage23"] * ratio35 + play["stage35"] + 2 * play["spurs"]
        p = machine.poses(theta)
        ax, ay, c2 = p["carrier2"]
        _, _, a3 = p["arm"]
        l2, l3 = self.chain.link_lengths[1:]
        tip = np.stack([ax + l2 * np.cos(c2) + l3 * np.cos(a3), ay + l2 * np.sin(c2) + l3 * np.sin(a3)], axis=1)
        envelope = np.zeros(len(theta))
        for s2 in (-1.0, 1.0):
            for s3 in (-1.0, 1.0):
                b2, b3 = c2 + s2 * carrier2, a3 + s3 * arm
                moved = np.stack([ax + l2 * np.cos(b2) + l3 * np.cos(b3), ay + l2 * np.sin(b2) + l3 * np.sin(b3)], 1)
                envelope = np.maximum(envelope, np.linalg.norm(moved - tip, axis=1))
        at = int(np.argmax(envelope))
        t1, t2, t3p = (float(v) for v in self.chain.pose_tau[:3])
        picking = (theta >= t1) & (theta <= t2)
        planting = tip[:, 1] < soil
        return {
            "plays_deg": {k: rounded(math.degrees(v), 6) for k, v in play.items()},
            "carrier_2_turn_deg": rounded(math.degrees(carrier2), 6),
            "arm_turn_max_deg": rounded(math.degrees(float(arm.max())), 6),
            "max_mm": rounded(float(envelope[at]), 6),
            "at_driver_deg": round(math.degrees(theta[at]), 4),
            "picking_max_mm": rounded(float(envelope[picking].max()), 6),
            "planting_max_mm": rounded(float(envelope[planting].max()), 6) if planting.any() else None,
            "at_pose_3_mm": rounded(float(envelope[int(np.argmin(np.abs(theta - t3p)))]), 6),
        }

    def _phases(self, machine: DoubleCarrierMachine, tip: np.ndarray, soil: float) -> list[str]:
        """The claw's phase at each motion-table position: picking from pose 1 to pose 2, planting
        in the soil, conveying between, return after."""
        theta = 2 * math.pi * np.arange(len(tip)) / len(tip)
        t1, t2 = (float(v) for v in self.chain.pose_tau[:2])
        planted = False
        order = np.argsort(np.mod(theta - t1, 2 * math.pi))
        names = [""] * len(tip)
        for k in order:  # from pose 1 round the cycle
            if t1 <= theta[k] <= t2:
                names[k] = PHASES[0]
            elif tip[k, 1] < soil:
                names[k], planted = PHASES[2], True
            else:
                names[k] = PHASES[3] if planted else PHASES[1]
        return names

    # -- build -------------------------------------------------------------------------------

    def build(self, out: Path) -> Built:
        raise GeometryError(f"{self.name} is built from the files of {list(self.uses)} (the builder gives them)")

    def build_using(self, out: Path, used: dict[str, bytes]) -> Built:
        machine, posed_from = self._machine(used)
        files: dict[str, bytes] = {}
        results: dict = {}
        files.update(obstacle_file(self.name, "soil", self._soil(), self.layers.span))
        judged = self._judge({**used, **files}, machine)
        record = judged["record"]
        record["posed_from"] = {
            "meshing": [f"{getattr(self, w).name}.dxf_meshing.csv" for w in ("stage23", "stage35", "sectors", "spurs")],
            "cam": f"{self.cam.name}.cam.dxf (the follower run on it again)",
            **posed_from,
        }
        record["keys_deg"] = carrier_making.shaft_keys(self.design)
        results["machine"] = record
        files.update(judged["files"])
        results["assembly"], more = start_assembly(self.name, judged["bodies"], judged["links"], {})
        files.update(more)
        files[f"{self.name}.machine.json"] = json_bytes(record)
        if judged["problems"]:
            raise GeometryError(f"{self.name}: " + "; ".join(judged["problems"]))
        params = {
            "clearance_mm": self.clearance,
            "gearbox_above_soil_mm": self.gearbox_above_soil,
            "planting_depth_mm": self.planting_depth,
            "pose_tolerance": {"position_mm": self.pose_tolerance[0], "attitude_deg": self.pose_tolerance[1]},
            "layers_mm": {k: list(v) for k, v in dataclasses.asdict(self.layers).items()},
            "claw_mm": {"at": self.claw_at, "width": self.claw_width, "tab": self.claw_tab},
            "uses": list(self.uses),
        }
        return Built({"kind": "machine", "parameters": params, "results": results}, files)

    def check(self, files: dict[str, bytes]) -> Checked:
        """The machine posed again from the files as found and every clearance judged again; each
        must be the recorded one."""
        machine, _ = self._machine(files)
        judged = self._judge(files, machine, shown=False)
        again, summary = judged_again(
            judged["record"]["clearances"], files[f"{self.name}.machine.json"], lambda r: r["required_mm"]
        )
        problems = list(judged["problems"]) + again
        # (the parts' STEPs are the parts study's to re-read; the machine's 3MF is this one's)
        made, more = check_shop_files(
            files, {}, (f"{self.name}.assembly.3mf", [b.name for b in judged["bodies"] if not b.dxf.endswith(OBSTACLE)])
        )
        problems += more
        return Checked({"clearances": summary, "made": made}, problems)


def _still(theta, angle: float):
    z = np.zeros_like(np.asarray(theta, dtype=float))
    return z, z, z + angle
