"""The whole seed-004 machine: planting arms as parts, every body posed over the cycle from the
made gears, the clearance between every two that could meet, and the cycle to watch.

:class:`PlanetaryMachineStudy` is built from the files of two earlier parts of its family
(``uses``): the ring/planet pair (its DXFs and assembly record) and the part that made the
carrier plate. It

1. takes the meshing the pair's proof measured on its ring and planet **as re-read from their
   DXFs** (``<pair>.dxf_meshing.csv``) and rebuilds the train from it — so every planet turns as
   the shop's parts let it — checked at the start against the assembly record (the pair's
   ``check`` meshes the DXFs again and holds the table to them);
2. makes the planting arm of each planet as two parts (:mod:`transplanter.arm_parts`): the arm
   plate keyed to the planet shaft, and the needle bolted to it — DXF, STL, STEP, one of each per
   planet — and the obstacles as DXF sections in the machine frame: the seedling box (a block
   ``box`` long up its slope from the end face and as high across it, centred on the box point)
   and the soil (below the soil level the train's metrics find);
3. stacks the bodies in the planes the part script states (:class:`Layers`): gears, carrier,
   arm plates, needles; the box and the soil across all of them;
4. judges every two bodies whose planes overlap and that no joint or mesh joins
   (:func:`machine.pairs_to_judge`) over the carrier's turn, bounded between the samples
   (:mod:`transplanter.clearance`), against the clearance stated (``clearance``); a needle in the
   box or the soil is its work, recorded, not judged;
5. judges seed 004's objectives i (arms do not interfere) and ii (arms clear the box) on these
   bodies, beside the needle-line figures of :mod:`transplanter.objectives`, and says what one
   plane for all arm bodies would do (the reason for the layers);
6. writes the motion table (``driver_deg`` and each body's pose), an animated GIF, the slider's
   script for the report, and a 3MF of the made parts at the start, and records
   ``results.machine`` (the data contract a judge re-poses the DXF bodies from).
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

from transplanter import animation, solids
from transplanter.agronomy import transplanting_metrics
from transplanter.arm_parts import ArmParts, arm_parts
from transplanter.errors import GeometryError, SpecError, check_number
from transplanter.export import csv_bytes, json_bytes
from transplanter.families.gears import ToothedPairStudy
from transplanter.families.machine_record import (
    OBSTACLE,
    clearance_row,
    judged_again,
    obstacle_file,
    pictures,
    read_bodies,
    start_assembly,
)
from transplanter.families.making import Making, check_shop_files, manufacture
from transplanter.families.pair_assembly import read_meshing_csv
from transplanter.families.study import Built, Checked, StudyDefaults
from transplanter.machine import (
    MOTION_POSITIONS,
    Body,
    Judged,
    Pair,
    PlanetaryMachine,
    clearances,
    clearances_under_play,
    motion_rows,
    pairs_to_judge,
    posed,
    tool_phases,
    work_depth,
)
from transplanter.objectives import BOX_CLEARANCE_MM, Site, gearbox_radius, seed004_objectives
from transplanter.planetary import DifferentialTrain
from transplanter.precision import rounded
from transplanter.train_rebuild import meshed_train

__all__ = ["Layers", "PlanetaryMachineStudy", "PHASES"]

#: an arm's phases over the cycle, in order (the tip in the box, then on to the soil, in it, back)
PHASES = ("picking", "conveying", "planting", "return")
#: the start pose of each planet may differ from the assembly record by the measured meshing
#: error only; more than this is a wrong frame, deg
START_POSE_DEG = 1.0


@dataclass(frozen=True)
class Layers:
    """Where each kind of body sits across the machine, z-ranges in mm (0 at the ring's back
    face): which bodies share a plane is the designer's choice, stated in the part script."""

    gears: tuple[float, float]
    carrier: tuple[float, float]
    plates: tuple[float, float]
    needles: tuple[float, float]

    def __post_init__(self) -> None:
        for what in ("gears", "carrier", "plates", "needles"):
            z = getattr(self, what)
            if not (len(z) == 2 and z[0] < z[1]):
                raise SpecError.out_of_range(f"layers.{what}", z, "(z0, z1) mm with z0 < z1")

    @property
    def span(self) -> tuple[float, float]:
        """Across the whole machine (the box and the soil), mm."""
        zs = [z for what in ("gears", "carrier", "plates", "needles") for z in getattr(self, what)]
        return min(zs) - 10.0, max(zs) + 10.0


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

    # -- the files it is posed from -------------------------------------------------------

    @cached_property
    def arm(self) -> ArmParts:
        """The arm plate and the needle in the planet's frame (:func:`arm_parts.arm_parts`)."""
        return arm_parts(self.train.arm, self.hub, self.boss, self.tab, self.needle_width, self.point)

    def _inputs(self, files: dict[str, bytes]) -> tuple[dict, dict[str, str], float | None]:
        """The pair's assembly record, the names of the files the machine is posed from, and how
        far each planet may turn off its driving-flank pose, rad: the bound the pair's proof states
        over its play (``meshing.dxf.train.objectives_under_play.turn_deg``; None without)."""
        p = self.pair.name
        names = {
            "ring": f"{p}.driver.dxf",
            "planet": f"{p}.driven.dxf",
            "carrier": f"{self.carrier}.carrier.dxf",
            "record": f"{p}.teeth.json",
            "meshing": f"{p}.dxf_meshing.csv",
        }
        missing = [n for n in names.values() if n not in files]
        if missing:
            raise GeometryError(f"{self.name}: the machine is posed from {missing}, which are not there")
        results = json.loads(files[names["record"]])["results"]
        record = results.get("assembly")
        if not record:
            raise GeometryError(f"{self.name}: {names['record']} has no assembly record")
        play = results.get("meshing", {}).get("dxf", {}).get("train", {}).get("objectives_under_play", {})
        return record, names, (math.radians(play["turn_deg"]) if "turn_deg" in play else None)

    def _posed(self, files: dict[str, bytes], record: dict, names: dict[str, str]) -> tuple[PlanetaryMachine, dict]:
        """The machine's links from the pair's meshing on its re-read DXFs; their start against
        the assembly record."""
        ang, err = read_meshing_csv(files[names["meshing"]])
        made = meshed_train(self.train, ang, err)
        step = np.diff(np.append(ang, ang[0] + 2 * math.pi))
        slope = float(np.max(np.abs(np.diff(np.append(err, err[0])) / np.maximum(step, 1e-12))))
        machine = PlanetaryMachine(made, slope)
        links = machine.links
        start = self.train.carrier_start
        worst = 0.0
        for k, (c, b) in enumerate(
            zip(record["planet_carrier_angles_deg"], record["planet_body_angle_to_carrier_line_deg"], strict=True)
        ):
            _, _, angle = links[f"planet.{k + 1}"].pose(np.zeros(1))
            want = start + math.radians(c + b)
            worst = max(worst, abs(math.degrees(math.remainder(float(angle[0]) - want, 2 * math.pi))))
        if worst > START_POSE_DEG:
            raise GeometryError(
                f"{self.name}: the planets start {worst:.3g} deg from where the assembly record puts them "
                f"(limit {START_POSE_DEG:g} deg)"
            )
        return machine, {"start_vs_assembly_record_deg": rounded(worst, 6), "error_slope": rounded(slope, 6)}

    def _obstacles(self, module: float) -> dict[str, shapely.Polygon]:
        """The seedling box and the soil as sections in the machine frame."""
        tr, site = self.train, self.site
        soil = transplanting_metrics(
            tr,
            site.seedling_box,
            site.plant_spacing,
            site.planting_depth,
            gearbox_radius(tr.pair.driver.max_radius().value, module),
        ).soil_level
        u = np.array([math.cos(site.box_slope), math.sin(site.box_slope)])
        n = np.array([-u[1], u[0]])
        p = np.asarray(site.seedling_box, dtype=float)
        length, height = self.box
        box = shapely.Polygon(
            [p - n * height / 2, p + u * length - n * height / 2, p + u * length + n * height / 2, p + n * height / 2]
        )
        reach = tr.pair.centre_distance + tr.arm.tip + 100.0
        ground = shapely.box(-2 * reach, soil - 150.0, 2 * reach, soil)
        return {"box": shapely.orient_polygons(box), "soil": ground}

    # -- build ------------------------------------------------------------------------------

    def build(self, out: Path) -> Built:
        raise GeometryError(f"{self.name} is built from the files of {list(self.uses)} (the builder gives them)")

    def build_using(self, out: Path, used: dict[str, bytes]) -> Built:
        record, names, turn = self._inputs(used)
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
            making = dataclasses.replace(making, features=features, quantity=n)
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
        obstacles = self._obstacles(module)
        for what, section in obstacles.items():
            files.update(obstacle_file(self.name, what, section, self.layers.span))
        machine, start = self._posed(used, record, names)
        judged = self._judge({**used, **files}, names, machine, module, turn)
        results["machine"] = judged["record"]
        results["machine"]["posed_from"] = {
            "meshing": f"{names['meshing']} ({names['ring']} and {names['planet']} meshed by the pair's proof)",
            "assembly_record": names["record"],
            **start,
        }
        results["objectives_on_bodies"] = judged["objectives"]
        results["one_plane"] = judged["one_plane"]
        files.update(judged["files"])
        results["assembly"], more = self._assembly(judged["bodies"], machine, record)
        files.update(more)
        files[f"{self.name}.machine.json"] = json_bytes(results["machine"])
        if judged["problems"]:
            raise GeometryError(f"{self.name}: " + "; ".join(judged["problems"]))
        params = {
            "clearance_mm": self.clearance,
            "layers_mm": {k: list(v) for k, v in dataclasses.asdict(self.layers).items()},
            "arm_plate_mm": {"hub_radius": self.hub, "knee_boss_radius": self.boss, "bolting_tab": self.tab},
            "needle_mm": {"width": self.needle_width, "point": self.point},
            "seedling_box_section_mm": {"length_up_the_slope": self.box[0], "height_across": self.box[1]},
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
                "2 x M4 tapped (tap drill 3.3 mm) for the needle",
                f"{where}; the planet shaft ends flush with its outer face (end screw)",
            )
        return (
            f"planting needle, one per arm: mates with the arm plate, bolted on its outer face (2 x M4); tip at "
            f"({arm.tip[0]:.3f}, {arm.tip[1]:.3f}) mm in the planet's frame",
            "timing: its two bolt holes on the plate's tapped holes set its direction",
            f"{self.needle_width:g} mm wide, point ground over its last {self.point:g} mm",
            where,
        )

    def _bodies(self, files: dict[str, bytes], names: dict[str, str]) -> list[Body]:
        """Every body as re-read from its DXF, in its plane, on its link."""
        L, n = self.layers, self.train.planets
        plate, needle = f"{self.name}.arm_plate.dxf", f"{self.name}.needle.dxf"
        specs = [
            ("ring", names["ring"], L.gears, "ring", False),
            ("carrier", names["carrier"], L.carrier, "carrier", False),
        ]
        for k in range(1, n + 1):
            specs += [
                (f"planet_{k}", names["planet"], L.gears, f"planet.{k}", False),
                (f"arm_{k}", plate, L.plates, f"planet.{k}", False),
                (f"needle_{k}", needle, L.needles, f"planet.{k}", False),
            ]
        specs += [(w, f"{self.name}.{w}{OBSTACLE}", L.span, "fixed", False) for w in ("box", "soil")]
        return read_bodies(files, specs)

    def _judge(
        self, files, names, machine: PlanetaryMachine, module: float, turn: float | None, shown: bool = True
    ) -> dict:
        """Bodies, pairs, clearances (and with ``turn``, rad, each planet at either end of its play),
        objectives on bodies and the one-plane finding; with ``shown`` the motion table, the
        animation and the slider too."""
        n = self.train.planets
        bodies = self._bodies(files, names)
        links = machine.links
        ready = posed(bodies, links)
        theta = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
        # the clearances start from a coarser grid (the bound refines between its samples): the
        # slider's positions, so each position's smallest clearance is one of its samples
        grid = 2 * math.pi * np.arange(animation.SLIDER_POSITIONS) / animation.SLIDER_POSITIONS
        joined = set()
        working = {}
        for k in range(1, n + 1):
            joined |= {
                frozenset(("ring", f"planet_{k}")),  # the mesh
                frozenset(("carrier", f"planet_{k}")),  # the planet shaft
                frozenset((f"planet_{k}", f"arm_{k}")),  # the key
                frozenset((f"arm_{k}", f"needle_{k}")),  # the bolts
            }
            working[frozenset((f"needle_{k}", "box"))] = "the needle takes seedlings from the box"
            working[frozenset((f"needle_{k}", "soil"))] = "the needle plants in the soil"
        pairs = pairs_to_judge(bodies, joined, working)
        judged = clearances(ready, pairs, grid)
        played = {}
        if turn is not None:  # the planets anywhere in their play, each independently
            planets = {f"planet.{k}" for k in range(1, n + 1)}
            checked = [p for p in pairs if not p.working]
            nominal = {frozenset((j.pair.a, j.pair.b)): j for j in judged}
            settle = max(self.clearance, BOX_CLEARANCE_MM)  # what the pairs are judged against
            played = {
                frozenset((j.pair.a, j.pair.b)): j
                for j in clearances_under_play(bodies, ready, links, checked, grid, turn, planets, nominal, settle)
            }
        depths = self._work_depths(bodies, links, theta, [j.pair for j in judged if j.pair.working])
        arm = self.arm
        problems = [
            f"{p.a} enters {p.b} {d['at_most_mm']:.4g} mm from its tip, beyond its {arm.bar:.4g} mm bar "
            f"(at driver {d['at_driver_deg']:.1f} deg): more than the needle meets its work"
            for p, d in depths.items()
            if d["at_most_mm"] > arm.bar
        ]
        problems += [
            f"{j.pair.a} and {j.pair.b} come {j.distance:.4g} mm apart at driver {j.at_deg:.2f} deg "
            f"(clearance required {self.clearance:g} mm)"
            for j in judged
            if not j.pair.working and j.distance < self.clearance
        ]
        # what one plane for all arm bodies would do: each arm plate against the other arms' needles
        cross = [Pair(f"arm_{k}", f"needle_{j}") for k in range(1, n + 1) for j in range(1, n + 1) if j != k]
        single = clearances(ready, cross, grid)
        worst_single = min(single, key=lambda j: j.distance)
        one_plane = {
            "min_mm": rounded(worst_single.distance, 6),
            "bodies": [worst_single.pair.a, worst_single.pair.b],
            "at_driver_deg": round(worst_single.at_deg, 4),
            "finding": (
                f"in one plane the arms would not clear: {worst_single.pair.a}'s plate comes "
                f"{worst_single.distance:.3g} mm from {worst_single.pair.b} at driver {worst_single.at_deg:.1f} deg "
                f"(clearance {self.clearance:g} mm) — so the plates and the needles sit in two planes "
                f"(z {self.layers.plates[0]:g}..{self.layers.plates[1]:g} and "
                f"{self.layers.needles[0]:g}..{self.layers.needles[1]:g} mm)"
                if worst_single.distance < self.clearance
                else f"the arms would clear in one plane too ({worst_single.distance:.3g} mm)"
            ),
        }
        objectives = self._objectives(machine, judged, module, played)
        if turn is not None:
            worst = min(played.values(), key=lambda j: j.distance)
            under = [j for j in played.values() if j.distance < self.clearance]
            record_play = {
                "turn_deg": rounded(math.degrees(turn), 6),
                "measured": sum(j.exact for j in played.values()),
                "settled_by_the_bound": sum(not j.exact for j in played.values()),
                "smallest_mm": rounded(worst.distance, 6),
                "bodies": [worst.pair.a, worst.pair.b],
                "at_driver_deg": round(worst.at_deg, 4),
                "below_clearance": sorted(f"{j.pair.a} - {j.pair.b}: {j.distance:.4g} mm" for j in under),
            }
        record = {
            "driver": "the carrier, deg of clockwise turn from the start",
            "frame": "the train's: carrier axis at the origin, y up, the soil below (seed 004 eqs 3-10)",
            "bodies": {b.name: {"dxf": b.dxf, "z_mm": [b.z[0], b.z[1]], "link": b.link} for b in bodies},
            "joined": sorted(" + ".join(sorted(p)) for p in joined),
            "motion": f"{self.name}.motion.csv",
            "positions": MOTION_POSITIONS,
            "clearance_required_mm": self.clearance,
            "clearances": [
                clearance_row(j, self.clearance, played.get(frozenset((j.pair.a, j.pair.b))), depths.get(j.pair))
                for j in judged
            ],
            "animation": f"{self.name}.animation.gif",
            "slider": f"{self.name}.slider.js",
        }
        if turn is not None:
            # each planet anywhere within its play (± the turn the pair's proof bounds), independently
            record["under_play"] = record_play
        files_out = {}
        if shown:
            box, soil = (next(b.section for b in bodies if b.name == w) for w in ("box", "soil"))
            phases = [tool_phases(t, box, soil, PHASES) for t in machine.tips(theta)]
            header, rows = motion_rows(bodies, links, theta)
            files_out[f"{self.name}.motion.csv"] = csv_bytes(header, rows)
            files_out.update(
                pictures(self.name, bodies, links, machine.tips, judged, phases, [f"arm {k + 1}" for k in range(n)])
            )
        return {
            "record": record,
            "objectives": objectives,
            "one_plane": one_plane,
            "files": files_out,
            "problems": problems + [o for o in objectives.get("missed", [])],
            "bodies": bodies,
        }

    def _work_depths(self, bodies: list[Body], links, theta: np.ndarray, pairs: list[Pair]) -> dict:
        """How far from its tip each needle enters its work (box or soil): :func:`machine.work_depth`."""
        by_name = {b.name: b for b in bodies}
        arm = self.arm
        out = {}
        for p in pairs:
            needle, work = (by_name[p.a], by_name[p.b]) if p.a.startswith("needle") else (by_name[p.b], by_name[p.a])
            deepest, at, most = work_depth(needle, work, links[needle.link], theta, arm.tip, arm.knee)
            out[p] = {
                "deepest_from_tip_mm": rounded(deepest, 6),
                "at_driver_deg": round(math.degrees(at), 4),
                "at_most_mm": rounded(most, 6),
            }
        return out

    def _objectives(self, machine: PlanetaryMachine, judged: list[Judged], module: float, played: dict) -> dict:
        """Objectives i and ii on the bodies (and with the planets anywhere in their play), beside
        the needle-line figures."""
        line = {o.number: o for o in seed004_objectives(machine.made, self.site, module)}

        def arm_of(name: str) -> str | None:
            return name.split("_")[1] if name.startswith(("arm_", "needle_")) else None

        between_arms = [
            j for j in judged if arm_of(j.pair.a) and arm_of(j.pair.b) and arm_of(j.pair.a) != arm_of(j.pair.b)
        ]
        at_box = [j for j in judged if "box" in (j.pair.a, j.pair.b) and not j.pair.working]
        i = min(between_arms, key=lambda j: j.distance)
        ii = min(at_box, key=lambda j: j.distance)
        rows = {
            "i arms do not interfere": {
                "bodies": [i.pair.a, i.pair.b],
                "min_mm": rounded(i.distance, 6),
                "limit_mm": self.clearance,
                "margin_mm": rounded(i.distance - self.clearance, 6),
                "at_driver_deg": round(i.at_deg, 4),
                **self._played(played, between_arms),
                "needle_lines_mm": rounded(line["i"].value, 6),
                "needle_lines_limit_mm": line["i"].low,
            },
            "ii arms clear the seedling box": {
                "bodies": [ii.pair.a, ii.pair.b],
                "min_mm": rounded(ii.distance, 6),
                "limit_mm": BOX_CLEARANCE_MM,
                "margin_mm": rounded(ii.distance - BOX_CLEARANCE_MM, 6),
                "at_driver_deg": round(ii.at_deg, 4),
                **self._played(played, at_box),
                "knee_to_box_face_mm": rounded(line["ii"].value, 6),
                "knee_limit_mm": line["ii"].low,
            },
        }
        missed = []
        if i.distance < self.clearance:
            missed.append(f"objective i on the bodies: {i.pair.a} and {i.pair.b} {i.distance:.4g} mm apart")
        if ii.distance < BOX_CLEARANCE_MM:
            missed.append(
                f"objective ii on the bodies: {ii.pair.a} {ii.distance:.4g} mm from the box "
                f"(limit {BOX_CLEARANCE_MM:g})"
            )
        return {**rows, "all_met": not missed, **({"missed": missed} if missed else {})}

    @staticmethod
    def _played(played: dict, among: list[Judged]) -> dict:
        """The smallest of ``among`` with the planets anywhere in their play (nothing without)."""
        found = [played[k] for k in (frozenset((j.pair.a, j.pair.b)) for j in among) if k in played]
        if not found:
            return {}
        worst = min(found, key=lambda j: j.distance)
        key = "under_play_mm" if worst.exact else "under_play_at_least_mm"
        return {key: rounded(worst.distance, 6), "under_play_bodies": [worst.pair.a, worst.pair.b]}

    def _assembly(self, bodies, machine, record: dict) -> tuple[dict, dict[str, bytes]]:
        """A 3MF of the made parts where they sit at the start, the planets where the assembly
        ``record`` puts them (the middle of their play)."""
        start = self.train.carrier_start
        r = self.train.pair.centre_distance
        at = {}
        for k, (c, body) in enumerate(
            zip(record["planet_carrier_angles_deg"], record["planet_body_angle_to_carrier_line_deg"], strict=True)
        ):
            line = start + math.radians(c)
            at[f"planet.{k + 1}"] = (r * math.cos(line), r * math.sin(line), line + math.radians(body))
        return start_assembly(self.name, bodies, machine.links, at)

    def check(self, files: dict[str, bytes]) -> Checked:
        """The machine posed again from the files as found (the bodies re-read, the planets turned
        by the meshing table — which the pair's own check holds to its DXFs) and every clearance
        judged again; each must be the recorded one."""
        record, names, turn = self._inputs(files)
        machine, _ = self._posed(files, record, names)
        judged = self._judge(files, names, machine, float(record["module_mm"]), turn, shown=False)
        again, summary = judged_again(
            judged["record"]["clearances"], files[f"{self.name}.machine.json"], lambda r: self.clearance
        )
        problems = list(judged["problems"]) + again
        # the arm parts' STEP against their DXF and the machine's 3MF, re-read as the other parts' are
        made, more = check_shop_files(
            files,
            {f"{self.name}.arm_plate": self.plate.width, f"{self.name}.needle": self.needle.width},
            (f"{self.name}.assembly.3mf", [b.name for b in judged["bodies"] if b.link != "fixed"]),
        )
        problems += more
        return Checked({"clearances": summary, "made": made}, problems)
