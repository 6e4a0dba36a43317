"""Toothed pair studies: teeth by the shaper envelope, the made parts, their meshing check."""

from __future__ import annotations

import dataclasses
import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import shapely

from transplanter import dxf, formats, plots, solids, validate
from transplanter.backlash import backlash_band, resolve_backlash, tolerance_budget
from transplanter.cutter import Cutter, RackCutter
from transplanter.errors import ExportError, GeometryError, SpecError, TransplanterError, check_int, check_number
from transplanter.export import csv_array, csv_bytes, json_bytes
from transplanter.families.making import Making, assembly_file, check_shop_files, manufacture, step_file
from transplanter.families.study import Built, Checked, StudyDefaults
from transplanter.interference import pair_limits
from transplanter.objectives import Site, seed004_objectives
from transplanter.pitch import GearPair, Mesh
from transplanter.planetary import DifferentialTrain
from transplanter.precision import rounded
from transplanter.teeth import CHORD_TOLERANCE, ToothedGear, generate_pair, per_gear
from transplanter.threemf import placement
from transplanter.tolerances import PENETRATION_TOL, SHOP_OVERLAP_MM2, WIRE_EDM_TOLERANCE

__all__ = ["MESH_STEPS", "ToothedPairStudy"]


#: meshing-check steps per driver turn (raised to be coprime with the driver's tooth count)
MESH_STEPS = 180
#: timing-mark hole (external gears) or rim notch (rings): largest diameter, mm, and the
#: smallest wall left to the root, the bore and other holes, mm
MARK_DIAMETER = 2.0
MARK_WALL = 1.0
#: rows per driver turn of the design motion a shop receives (``<part>.motion.csv``)
MOTION_ROWS = 720


def _screen_verdict(meshing: dict, problems: list[str]) -> str:
    """The closed-form screen's warnings judged by the meshing proof on the made parts, in words:
    confirmed (the proof fails too) or shown harmless, with the numbers that show it."""
    if problems:
        return "confirmed by the meshing proof: " + "; ".join(problems)
    shown = [(src, meshing[src]) for src in ("dxf", "stl", "outline") if isinstance(meshing.get(src), dict)]
    worst = min(shown, key=lambda s: s[1].get("clearance_mm", math.inf), default=None)
    if worst is None:
        return "not judged: no source was meshed"
    src, fig = worst
    return (
        f"shown harmless by the meshing proof on every source: no overlap anywhere over the cycle, smallest "
        f"mid-play clearance {fig['clearance_mm'] * 1e3:.1f} µm ({src}, driver {fig['clearance_at_driver_deg']:.2f} "
        f"deg, required {meshing['min_clearance_mm'] * 1e3:.1f} µm), smallest free play "
        f"{fig['backlash_mm'][0] * 1e3:.1f} µm — the screen's closed-form limit is conservative for these curves"
        if meshing.get("min_clearance_mm") is not None
        else f"shown harmless by the meshing proof on every source: no overlap anywhere over the cycle ({src})"
    )


def _timing_mark(gear: ToothedGear, features: solids.Features) -> tuple[float, float, float]:
    """(x, y, diameter) of a timing mark at body angle 0, where the gear meets its mate at the
    start: a through hole between bore and roots on an external gear, a notch in a ring's rim.
    GeometryError when there is no room for it."""
    contour = gear.toothed_contour
    if gear.internal:
        r_rim = float(gear.blank.bounds[2])
        wall = r_rim - float(np.linalg.norm(contour, axis=1).max())
        d = min(MARK_DIAMETER, 0.8 * wall)
        x = r_rim
    else:
        r_root = float(np.linalg.norm(contour, axis=1).min())
        r_in = features.bore / 2 if features.bore else 0.0
        room = r_root - r_in - 2 * MARK_WALL
        d = min(MARK_DIAMETER, room)
        x = r_in + MARK_WALL + room / 2 + (0.0 if features.bore else 0.25 * room)
    if d < 0.5:
        raise GeometryError(
            f"no room for a timing mark on the {'ring' if gear.internal else 'gear'}: {d:.3g} mm (limit 0.5 mm) "
            f"between {'the teeth and the rim' if gear.internal else 'the bore and the roots'}"
        )
    mark = shapely.Point(x, 0.0).buffer(d / 2 + MARK_WALL)
    for hx, hy, hd in features.holes:
        if mark.intersects(shapely.Point(hx, hy).buffer(hd / 2)):
            raise GeometryError(f"the timing mark at ({x:.2f}, 0) mm meets the hole at ({hx:g}, {hy:g}) mm")
    return float(x), 0.0, float(d)


@dataclass(frozen=True)
class ToothedPairStudy(StudyDefaults):
    """Teeth of both gears of ``pair`` cut by ``cutter``; ``teeth`` is the driver's tooth count.

    **Sizing is stated once**: the pair is sized by ``teeth``, and a cutter given without a module
    (``ShaperCutter(12)``, ``RackCutter()``) takes the pair's; one given with a module must agree.

    ``rejected`` lists ``(label, teeth, cutter)`` alternatives (e.g. a published module) that
    are tried and must fail: their errors go into the manifest as findings.

    The pair is then *meshed* (``validate.mesh_check``): the generated outlines, and with
    ``making`` the DXF and the mid-plane section of the STL re-read from their bytes, turn
    through a full cycle at the design ratio; the report carries penetration, fouling,
    transmission error, backlash against ``backlash.backlash_band`` and contact ratio, and a
    plot. A pair that does not mesh fails the part, unless ``must_mesh`` is False: then the
    study is a finding — figures and plot are written, the shop files (DXF, STL) are not.
    With ``train`` (the ``DifferentialTrain`` the pair drives) the train is rebuilt from each
    source's meshing and its needle-tip path compared with the designed one.

    **Backlash and tolerance by design.** ``backlash`` (mm, circumferential at the pitch
    point; None = the ISO/TR 10064-2 default from module and centre distance, see
    :mod:`transplanter.backlash`) thins the teeth; ``tolerance`` (± mm, default wire EDM) is what
    the shop may be off by. The made pair's smallest backlash must stay above the tolerance
    budget and its largest inside the target's band, and no step may overlap. Zero backlash
    only when ``backlash=0`` is given; its shop files then carry a warning note.

    **Internal pairs** are checked against the closed-form interference limits along the pitch
    curves before cutting (:mod:`transplanter.interference`); with ``trim_ring_tips`` the ring's
    addendum is shortened to clear them, and the manifest says so. ``addendum`` and ``shift``
    are per gear (driver, driven) or one value for both.

    **Assembly.** With ``making`` the results carry ``assembly`` (kind, mates, teeth, module,
    centre distance, where the driven gear's axis is in the driver's DXF frame and how it is
    turned at the start, the backlash measured on the re-read DXF, the tolerance, the timing
    marks), each gear has a timing mark (a hole facing the mate, or a notch in a ring's rim)
    at the start contact, its DXF notes name the mate, centre distance and tolerance, and
    ``<name>.assembly.dxf`` draws the pair in mesh with the centre distance dimensioned;
    ``<name>.motion.csv`` is the design motion (driven angle per driver angle).

    **Trains.** With ``train`` the train is rebuilt from each source's meshing and its needle
    tip compared with the design; with ``site`` too, seed 004's objectives are measured again on
    the rebuilt train (:mod:`transplanter.objectives`) and must all still be met.
    """

    cost = 10

    name: str
    pair: GearPair
    cutter: Cutter
    teeth: int
    allow_undercut: bool = False
    rejected: tuple[tuple[str, int, Cutter], ...] = ()
    making: tuple[Making, Making] | None = None
    must_mesh: bool = True
    train: DifferentialTrain | None = None
    backlash: float | None = None
    tolerance: float = WIRE_EDM_TOLERANCE
    addendum: float | tuple[float, float] = 1.0
    shift: float | tuple[float, float] = 0.0
    trim_ring_tips: bool = True
    #: meshing-check steps per driver turn (raised to be coprime with the driver's tooth count)
    mesh_steps: int = MESH_STEPS
    #: with ``train``: where it works; seed 004's objectives are then measured again on the
    #: train rebuilt from each source's meshing, and a missed one fails the part
    site: Site | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.pair, GearPair):
            raise SpecError(f"{self.name}: pair must be a pitch.GearPair, got {type(self.pair).__name__}")
        if not isinstance(self.cutter, Cutter):
            raise SpecError(
                f"{self.name}: cutter must be a cutter (ShaperCutter, RackCutter), got {type(self.cutter).__name__}"
            )
        check_int("mesh_steps", self.mesh_steps, 4, 100_000)
        check_number("tolerance", self.tolerance, 0.0, 1.0, unit="mm")
        if self.making is not None and (len(self.making) != 2 or not all(isinstance(m, Making) for m in self.making)):
            raise SpecError(f"{self.name}: making must be a (driver, driven) pair of Making")

    def _sized(self) -> tuple[GearPair, object]:
        pair, sizing = self.pair.sized(teeth=self.teeth)
        if self.cutter.module is not None and abs(sizing.module - self.cutter.module) > 1e-9 * sizing.module:
            raise SpecError.out_of_range(
                "cutter module", self.cutter.module, f"the pair's module {sizing.module!r} mm at {self.teeth} teeth"
            )
        return pair, sizing

    @property
    def _names(self) -> tuple[str, str]:
        return ("ring", "planet") if self.pair.ring == "driver" else ("driver", "driven")

    def meshing(self, files: dict[str, bytes], sources=("outline", "dxf", "stl")) -> dict:
        """Mesh the pair as found in ``files`` (this study's file names → bytes) for each source
        present; returns ``{source: validate.MeshReport}``, or the reason where a file cannot be read."""
        pair, sizing = self._sized()
        out, sections = {}, {}
        for source in sources:
            suffix = "outline.csv" if source == "outline" else source
            names = [f"{self.name}.{role}.{suffix}" for role in ("driver", "driven")]
            if not all(n in files for n in names):
                continue
            try:
                sections[source] = [
                    formats.section_of(n, files[n], internal) for n, internal in zip(names, self._internal, strict=True)
                ]
            except ExportError as exc:
                out[source] = str(exc)

        def check(polys):
            # every gap, and the extremes refined between the samples (meshing module docstring) —
            # not for a finding, whose overlaps are the result
            return validate.mesh_check(
                pair, *polys, sizing.module, steps=self.mesh_steps, teeth=int(sizing.teeth[0]), refine=self.must_mesh
            )

        # the sources side by side: numpy, GEOS and the k-d tree release the GIL for most of a check
        with ThreadPoolExecutor(max_workers=min(2, max(1, len(sections)))) as pool:
            done = dict(zip(sections, pool.map(check, sections.values()), strict=True))
        return out | done

    @cached_property
    def tool(self) -> Cutter:
        """The cutter at the pair's module: as given, or sized here when it was given without one
        (the module is then stated once, by the sizing)."""
        module = self._sized()[1].module
        return self.cutter if self.cutter.module is not None else self.cutter.sized(module)

    @cached_property
    def design_backlash(self) -> float:
        """The circumferential backlash the pair is cut for, mm."""
        pair, sizing = self._sized()
        c = self.tool
        return resolve_backlash(self.backlash, c.thickening, sizing.module, pair.centre_distance, c.pressure_angle)

    @cached_property
    def _backlash_band(self) -> tuple[float, float]:
        return backlash_band(self._sized()[0], self.design_backlash, self.tolerance)

    @property
    def min_clearance(self) -> float | None:
        """The smallest mid-play clearance a pair cut with backlash must keep everywhere (mm): half
        the tolerance budget — what each flank gets when the backlash equals the budget; None for
        a pair cut without backlash (its flanks touch by design)."""
        return tolerance_budget(self.tolerance) / 2 if self.design_backlash > 0 else None

    def _problems(self, report) -> list[str]:
        overlap = SHOP_OVERLAP_MM2 if self.design_backlash > 0 else PENETRATION_TOL
        return report.problems(
            max_penetration=overlap, backlash=self._backlash_band, names=self._names, clearance=self.min_clearance
        )

    def _assembly(self, pair, sizing, marks, dxf_report) -> dict:
        """What a shop needs to put the two gears together (see the class docstring)."""
        external = pair.ring is None
        centre = -pair.centre_distance if pair.ring == "driven" else pair.centre_distance
        lo, hi = dxf_report.backlash_min.value, dxf_report.backlash_max.value
        return {
            "kind": "external" if external else "internal",
            "ring": pair.ring,
            "driver": f"{self.name}.driver",
            "driven": f"{self.name}.driven",
            "teeth": [int(z) for z in sizing.teeth],
            "module_mm": rounded(sizing.module, 9),
            "centre_distance_mm": rounded(pair.centre_distance, 9),
            "driven_centre_mm": [rounded(centre, 9), 0.0],
            "driven_angle_at_start_deg": 180.0 if external else 0.0,
            "driver_turns": "clockwise",
            "driven_turns": "counter-clockwise" if external else "clockwise",
            "timing_marks_mm": {role: [rounded(x, 6), rounded(y, 6)] for role, (x, y, _) in marks.items()},
            "backlash_mm": {"min": rounded(lo, 6), "max": rounded(hi, 6)},
            "backlash_at_driver_deg": {
                "min": round(dxf_report.backlash_min.at_deg, 4),
                "max": round(dxf_report.backlash_max.at_deg, 4),
            },
            "clearance_mm": {
                "min": rounded(dxf_report.clearance_min.value, 6),
                "at_driver_deg": round(dxf_report.clearance_min.at_deg, 4),
                "required": None if self.min_clearance is None else rounded(self.min_clearance, 6),
            },
            "backlash_target_mm": rounded(self.design_backlash, 6),
            "tolerance_mm": self.tolerance,
            "tolerance_budget_mm": rounded(tolerance_budget(self.tolerance), 6),
            "motion": f"{self.name}.motion.csv",
            "drawing": f"{self.name}.assembly.dxf",
        } | self._planets()

    def _placed(self, a: dict, parts: dict) -> list:
        """The made gears where they sit at the start, from the assembly data a shop gets: the
        driven gear at its centre and start angle, or each planet on its carrier line."""
        if self.train is None:
            x, y = a["driven_centre_mm"]
            driven = [
                (a["driven"], parts["driven"], placement(x, y, 0.0, math.radians(a["driven_angle_at_start_deg"])))
            ]
        else:
            r = a["centre_distance_mm"]
            driven = []
            for name, carrier, body in zip(
                self._bodies()[1:],
                a["planet_carrier_angles_deg"],
                a["planet_body_angle_to_carrier_line_deg"],
                strict=True,
            ):
                c = math.radians(carrier)
                driven.append(
                    (name, parts["driven"], placement(r * math.cos(c), r * math.sin(c), 0.0, c + math.radians(body)))
                )
        return [(a["driver"], parts["driver"], placement()), *driven]

    def _bodies(self) -> list[str]:
        """The bodies of ``<name>.assembly.3mf``: driver and driven, or the ring and each planet."""
        if self.train is None:
            return [f"{self.name}.driver", f"{self.name}.driven"]
        return [f"{self.name}.driver", *(f"{self.name}.driven.{k + 1}" for k in range(self.train.planets))]

    def _planets(self) -> dict:
        """With a train: how many planets to make, and where they sit on the carrier."""
        if self.train is None:
            return {}
        n = self.train.planets
        offsets = -2 * math.pi * np.arange(n) / n  # arm k's carrier line, from arm I's
        contact = self.train.pair.driven_contact_angle(offsets)  # on each planet, at the start
        return {
            "planets": n,
            # counter-clockwise in the ring's DXF frame: planet k's contact with the ring lies on its
            # carrier line, where the ring meets it at the start (arm k+1 is where arm k will be
            # after a further 360/N deg of clockwise carrier turn)
            "planet_carrier_angles_deg": [rounded(math.degrees(o) % 360.0) for o in offsets],
            # the planet's DXF +x from its carrier line (centre of the ring -> planet centre), turning
            # counter-clockwise: its pitch point at polar angle `contact` then meets the ring
            "planet_body_angle_to_carrier_line_deg": [rounded(math.degrees(-c) % 360.0) for c in contact],
            "ring_contact_angles_deg": [rounded(math.degrees(o) % 360.0) for o in offsets],
        }

    def _notes(self, role: str, gear: ToothedGear, mate: ToothedGear, making: Making, pair, mark) -> tuple:
        external = pair.ring is None
        other = "driven" if role == "driver" else "driver"
        turn = (
            "the driven gear is turned 180 deg from its DXF frame at assembly"
            if external
            else "both gears keep their DXF orientation at assembly"
        )
        j = self.design_backlash
        notes = [
            f"{gear.teeth} teeth, module {gear.module:.6g} mm, face width {making.width:g} mm",
            f"mates with {self.name}.{other} ({mate.teeth} teeth), {'external' if external else 'internal'} mesh, "
            f"centre distance {pair.centre_distance:.4f} mm",
            f"backlash {j:.4f} mm circumferential by design",
            f"timing mark: {'notch' if gear.internal else 'hole'} dia {mark[2]:.2f} mm at +x meets the mate's mark "
            f"at the start; {turn}",
        ]
        if self.train is not None and role == "driven":
            notes.append(f"one planet per arm, {360 / self.train.planets:g} deg apart on the carrier")
        if j == 0:
            notes.append(
                "ZERO BACKLASH by request: no play for the cutting tolerance - the pair binds unless the centre "
                "distance is opened"
            )
        return tuple(notes)

    def _motion_csv(self, pair) -> bytes:
        phi = 2 * math.pi * np.arange(MOTION_ROWS + 1) / MOTION_ROWS
        sense = 1.0 if pair.ring is None else -1.0  # counter-clockwise positive
        driven = sense * pair.driven_rotation(phi)
        rows = [[f"{math.degrees(a):.4f}", f"{math.degrees(b):.9f}"] for a, b in zip(phi, driven, strict=True)]
        return csv_bytes(["driver_clockwise_deg", "driven_counterclockwise_deg"], rows)

    def _interference(self, pair, gears, requested) -> dict:
        r = 0 if pair.ring == "driver" else 1
        lim = pair_limits(
            pair,
            gears[r].cutter,
            ring_addendum=gears[r].addendum,
            pinion_addendum=gears[1 - r].addendum,
            ring_shift=gears[r].shift,
            pinion_shift=gears[1 - r].shift,
        )
        return {
            "ring_addendum": gears[r].addendum,
            "ring_tips_trimmed_from": None if requested[r] == gears[r].addendum else requested[r],
            "ring_addendum_limit": rounded(lim.max_ring_addendum, 4),
            "min_fillet_margin_mm": rounded(float(np.nanmin(lim.fillet)), 4),
            "min_trochoid_margin_rad": rounded(float(np.nanmin(lim.trochoid)), 5),
            "min_contact_ratio": rounded(lim.min_contact_ratio, 3),
            "radial_assembly": lim.radial_assembly,
            # the closed-form screen's warnings: each gets the meshing proof's verdict (build)
            "screen_findings": lim.problems(self._names),
            "assembly_note": "radial or axial"
            if lim.radial_assembly
            else "axial only: pushed in radially the planet trims the ring's teeth",
        }

    def meshing_results(self, reports: dict) -> tuple[dict, dict[str, bytes], list[str]]:
        """Figures per source, the meshing plot, and the problems (``source: text``)."""
        band = self._backlash_band
        results: dict = {
            "backlash_band_mm": [rounded(band[0], 6), rounded(band[1], 6)],
            "backlash_target_mm": rounded(self.design_backlash, 6),
            "tolerance_mm": self.tolerance,
            "min_clearance_mm": None if self.min_clearance is None else rounded(self.min_clearance, 6),
            "steps": self.mesh_steps,
        }
        readable, unreadable, problems = formats.split_unreadable(reports)
        results.update(unreadable)
        trains = {}
        for source, rep in sorted(readable.items()):
            res = rep.summary()
            found = self._problems(rep)
            res["problems"] = found
            problems += [f"{source}: {p}" for p in found]
            if self.train is not None:
                trains[source] = validate.train_check(self.train, rep)
                res["train"] = trains[source].summary()
                # the planet may turn by (half the backlash + transmission error) / its pitch radius
                # off the design: the needle tip by S times that at most
                bound = (
                    self.train.arm.tip
                    * (rep.backlash_max.value / 2 + rep.max_transmission_error)
                    / self.train.pair.driven.min_radius().value
                )
                res["train"]["predicted_bound_mm"] = rounded(bound, 6)
                if not found and trains[source].max_deviation > bound:
                    problems.append(
                        f"{source}: the train rebuilt from the parts leaves the design by "
                        f"{trains[source].max_deviation:.4g} mm, more than the {bound:.4g} mm its backlash allows"
                    )
                if found:
                    res["train"]["note"] = "from the contact at the pitch point; the problems above are ignored"
                if self.site is not None:
                    missed = self._train_objectives(trains[source].made, res["train"])
                    problems += [f"{source}: the train rebuilt from the parts misses objective {m}" for m in missed]
            results[source] = res
        files = {}
        shown = trains.get("stl", trains.get("outline"))
        note = " (pitch-point contact; the interference above ignored)" if problems else ""
        fig = plots.meshing_figure(readable, self.name, shown, note, band=band, clearance=self.min_clearance)
        files.update(plots.figure_files(fig, f"{self.name}.meshing"))
        return results, files, problems

    def _train_objectives(self, made, out: dict) -> list[str]:
        """Seed 004's objectives measured on the train rebuilt from the parts' meshing (into ``out``)."""
        found = seed004_objectives(made, self.site, self._sized()[1].module)
        out["objectives"] = {f"{o.number} {o.name}": f"{o.verdict} (limit {o.limit})" for o in found}
        return [f"{o.number} {o.name} = {o.value:.4g} {o.unit} (limit {o.limit})" for o in found if not o.ok]

    def build(self, out: Path) -> Built:
        """Teeth of both gears (outlines CSV, JSON, plot); with ``making`` the shop files with
        timing marks, the assembly data and 3MF, and the meshing check of outline, DXF and STL;
        rejected alternatives as findings (see the class docstring)."""
        pair, sizing = self._sized()
        if self.train is not None and abs(self.train.pair.centre_distance - pair.centre_distance) > 1e-9:
            raise SpecError.out_of_range(
                "train",
                self.train.pair.centre_distance,
                f"a train on this pair (centre distance {pair.centre_distance})",
            )
        requested = per_gear("addendum", self.addendum)
        gears = generate_pair(
            pair,
            dataclasses.replace(self.tool, thickening=0.0),
            sizing.teeth,
            backlash=self.design_backlash,
            addendum=self.addendum,
            shift=self.shift,
            trim_ring_tips=self.trim_ring_tips,
            check_interference=self.must_mesh,
            allow_undercut=self.allow_undercut,
        )
        c = self.tool
        params = {
            "teeth": list(sizing.teeth),
            "module_mm": rounded(sizing.module, 12),
            "cutter": {
                "kind": "rack" if isinstance(c, RackCutter) else "shaper",
                "teeth": getattr(c, "teeth", None),
                "pressure_angle_deg": rounded(math.degrees(c.pressure_angle)),
                "addendum": c.addendum,
                "dedendum": c.dedendum,
                "tip_fillet": c.tip_fillet,
                "thickening_mm": rounded(gears[0].cutter.thickening, 9),
            },
            "backlash_mm": rounded(self.design_backlash, 6),
            "backlash_default": self.backlash is None and c.thickening == 0,
            "tolerance_mm": self.tolerance,
            "addendum": [g.addendum for g in gears],
            "shift": [g.shift for g in gears],
            "chord_tolerance_mm": CHORD_TOLERANCE,
            "must_mesh": self.must_mesh,
        }
        results: dict = {}
        files: dict[str, bytes] = {}
        if pair.ring is not None:
            results["interference"] = self._interference(pair, gears, requested)
        for role, gear in zip(("driver", "driven"), gears, strict=True):
            results[role] = {
                "teeth": gear.teeth,
                "internal": gear.internal,
                "vertices": len(gear.toothed_contour),
                "area_mm2": rounded(gear.polygon.area, 6),
                "undercut_mm": rounded(gear.undercut),
                "min_tip_land_mm": rounded(float(gear.tip_lands.min())),
            }
            files[f"{self.name}.{role}.outline.csv"] = formats.CSV.write(gear.toothed_contour)
        reports = self.meshing(files, ("outline",))
        problems = self._problems(reports["outline"])
        if problems and self.must_mesh:
            raise GeometryError(f"{self.name}: the generated teeth do not mesh: " + "; ".join(problems))
        if problems:
            results["shop_files"] = "withheld: the generated teeth do not mesh (see meshing)"
        elif self.making is not None:
            marks, parts = {}, {}
            for k, (role, gear) in enumerate(zip(("driver", "driven"), gears, strict=True)):
                making = self.making[k]
                mark = _timing_mark(gear, making.features)
                marks[role] = mark
                making = dataclasses.replace(
                    making,
                    features=dataclasses.replace(making.features, notches=(mark,))
                    if gear.internal
                    else dataclasses.replace(making.features, holes=(*making.features.holes, mark)),
                    tolerance=self.tolerance,
                    quantity=self.train.planets if self.train is not None and role == "driven" else making.quantity,
                )
                res, made, part = manufacture(
                    f"{self.name}.{role}",
                    gear.blank,
                    gear.cut,
                    dataclasses.replace(making, step=False),  # written after the 3MF's re-read (step_file)
                    self._notes(role, gear, gears[1 - k], making, pair, mark),
                    lambda pt, g=gear: f"tooth space {g.nearest_space(pt)}",
                    marks=((mark[0], mark[1], "TIMING"),),
                )
                res["timing_mark_mm"] = {"x": rounded(mark[0], 6), "y": 0.0, "diameter": rounded(mark[2], 6)}
                results[role]["made"] = res
                parts[role] = part
                files.update(made)
            reports.update(self.meshing(files, ("dxf", "stl")))
            results["assembly"] = self._assembly(pair, sizing, marks, reports["dxf"])
            results["assembly"]["model"], model = assembly_file(self.name, self._placed(results["assembly"], parts))
            files.update(model)
            for role, making in zip(("driver", "driven"), self.making, strict=True):
                if making.step:
                    results[role]["made"]["step"] = step_file(parts[role], files)
            files[f"{self.name}.motion.csv"] = self._motion_csv(pair)
            a = results["assembly"]
            files[f"{self.name}.assembly.dxf"] = dxf.assembly_bytes(
                self.name,
                [
                    (a["driver"], files[f"{a['driver']}.dxf"], (0.0, 0.0, 0.0)),
                    (
                        a["driven"],
                        files[f"{a['driven']}.dxf"],
                        (*a["driven_centre_mm"], math.radians(a["driven_angle_at_start_deg"])),
                    ),
                ],
                (
                    f"centre distance {pair.centre_distance:.4f} mm; driver turns clockwise",
                    f"backlash measured on the DXF {a['backlash_mm']['min']:.4f}..{a['backlash_mm']['max']:.4f} mm "
                    f"(target {a['backlash_target_mm']:.4f}, tolerance +/-{self.tolerance:g} mm)",
                    "timing marks meet at the start contact",
                ),
            )
            if self.design_backlash == 0:
                results["warning"] = (
                    "zero backlash by request: the shop files carry a note; cut oversize, the pair binds"
                )
        meshing, plot_files, problems = self.meshing_results(reports)
        results["meshing"] = meshing
        if results.get("interference", {}).get("screen_findings"):
            results["interference"]["verdict"] = _screen_verdict(meshing, problems)
        files.update(plot_files)
        if problems and not results.get("shop_files"):
            raise GeometryError(f"{self.name}: the made parts do not mesh: " + "; ".join(problems))
        findings = {}
        for label, teeth, cutter in self.rejected:
            alt, alt_sizing = self.pair.sized(teeth=teeth)
            try:
                generate_pair(
                    alt,
                    cutter if cutter.module is not None else cutter.sized(alt_sizing.module),
                    alt_sizing.teeth,
                    addendum=self.addendum,
                    trim_ring_tips=self.trim_ring_tips,
                    check_interference=self.must_mesh,
                    allow_undercut=self.allow_undercut,
                )
            except TransplanterError as exc:
                findings[label] = f"{type(exc).__name__}: {exc}"
            else:
                findings[label] = "generated without error"
        results["rejected_alternatives"] = findings
        files[f"{self.name}.teeth.json"] = json_bytes({"parameters": params, "results": results})
        fig = plots.toothed_pair_figure(
            gears[0].polygon,
            gears[1].polygon,
            pair.centre_distance,
            pair.mesh is Mesh.EXTERNAL,
            float(pair.driver.r(0.0)),
            self.name,
        )
        files.update(plots.figure_files(fig, f"{self.name}.teeth"))
        return Built({"kind": "toothed_pair", "parameters": params, "results": results}, files)

    def _turned(self, files: dict[str, bytes]) -> list[str]:
        """A DXF whose toothed contour is the design turned about its axis, said in those words."""
        out = []
        for role, internal in zip(("driver", "driven"), self._internal, strict=True):
            csv_name, dxf_name = f"{self.name}.{role}.outline.csv", f"{self.name}.{role}.dxf"
            if csv_name not in files or dxf_name not in files:
                continue
            try:
                design = shapely.Polygon(csv_array(files[csv_name]))
                section = dxf.read_section(files[dxf_name])
            except Exception:  # unreadable files are reported by the meshing check
                continue
            rings = [section.exterior] if not internal else sorted(section.interiors, key=lambda r: -r.length)[:1]
            if not rings:
                continue
            angle = validate.turned_by(shapely.Polygon(rings[0]), design)
            if angle is not None:
                out.append(
                    f"{dxf_name}: its contour is the design turned by {angle:.2f} deg about the gear's axis — the "
                    "file was rotated after the build (any interference below follows from that)"
                )
        return out

    @property
    def _internal(self) -> tuple[bool, bool]:
        return (self.pair.ring == "driver", self.pair.ring == "driven")

    def check(self, files: dict[str, bytes]) -> Checked:
        """Re-run the meshing checks on this part's files as found on disk (and say so when a
        DXF is the design turned about its axis); a pair built as a finding (``must_mesh``
        False) is expected not to mesh."""
        results, _, problems = self.meshing_results(self.meshing(files))
        made, more = self._check_made(files)
        results["made"] = made
        return Checked(results, self._turned(files) + problems + more, expected=not self.must_mesh)

    def _check_made(self, files: dict[str, bytes]) -> tuple[dict, list[str]]:
        """Each gear's STEP against its DXF, and the 3MF assembly, re-read from the files."""
        if self.making is None:
            return {}, []
        widths = {f"{self.name}.{role}": m.width for role, m in zip(("driver", "driven"), self.making, strict=True)}
        return check_shop_files(files, widths, (f"{self.name}.assembly.3mf", self._bodies()))
