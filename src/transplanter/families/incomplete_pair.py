"""Incomplete gear pairs: from an intermittent law to shop files, meshing proof and report.

:class:`IncompletePairStudy` sizes an :class:`~transplanter.pitch.intermittent.IncompletePair`
(the law of dwells and motions, external or a planet driving its ring), cuts it
(:func:`transplanter.incomplete.cut_incomplete`: toothed sectors by the cutter's envelope,
locking arcs, the transitions relieved by the driver's own sweep), and proves it on the outlines
and on the DXF and STL re-read from their bytes, as full pairs are proved
(:func:`transplanter.meshing.mesh_check`, every gap, extremes refined between the samples), each
position judged by its phase:

* **motion** (the sector teeth in mesh): no overlap, the free play inside the backlash band of
  full gears (tolerance budget .. target's upper end), mid-play clearance above half the budget;
* **dwell**: the driven gear held by the locking arcs — its free play, as a driven angle,
  within the **locking play** the study states (``max_play_deg``, degrees in all) at every
  position of the dwell, and at least the tolerance budget (parts off by the tolerance do not
  jam; the mid-play clearance is reported: with the play one-sided it says little);
* **transition** (the stretch of motion whose teeth pass the lock zone, either side of each
  dwell): the same locking play holds — the driven gear never strays further from its law than
  in the dwell — and the figures say how far it does.

Each dwell/motion boundary is reported with the jump of the driven's speed and acceleration the
law asks for (per unit driver speed: the entry shock), and where the entry contact is: the
driver angle from which the driving flanks stay closed within the band, and the radii of that
first contact on both gears against their tips (a contact within ``incomplete.TIP_BAND`` modules of both
tips is tip-on-tip and refused).

Files: ``<name>.driver|driven.dxf/.stl/.step`` with timing marks, ``<name>.assembly.3mf`` and
``.assembly.dxf``, ``<name>.motion.csv`` (the law), ``<name>.dxf_meshing.csv``, outlines, and
``<name>.motion.png`` — the law with its dwells, the ratio with its jumps and the free play per
phase against the band and the locking play.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import shapely
from scipy import optimize

from transplanter import contact, formats, plots, validate
from transplanter.backlash import band_of, design_backlash, tolerance_budget
from transplanter.cutter import Cutter, ShaperCutter
from transplanter.errors import GeometryError, SpecError, check_int, check_number
from transplanter.export import csv_bytes, json_bytes
from transplanter.families import pair_assembly
from transplanter.families.making import Making, assembly_file, check_shop_files, manufacture, step_file
from transplanter.families.study import Built, Checked, StudyDefaults
from transplanter.incomplete import (
    TRANSITION_PITCHES,
    IncompleteGears,
    cut_incomplete,
    entry_contacts,
    sector_pitches,
)
from transplanter.mesh_engine import MeshSweep
from transplanter.pair_gate import per_gear
from transplanter.pitch import driven_axis, driven_turn
from transplanter.pitch.intermittent import IncompletePair, IntermittentLaw
from transplanter.precision import rounded, significant
from transplanter.tolerances import CONTACT_TOL_MM, SHOP_OVERLAP_MM2, WIRE_EDM_TOLERANCE

__all__ = ["IncompletePairStudy", "LOCKING_PLAY_DEG"]

ROLES = ("driver", "driven")
#: the locking play a study holds its dwells and transitions to unless told, deg of driven turn (in
#: all): what the locks and the relieved end teeth of the examples keep (0.5-1.5 deg at modules 2-3)
LOCKING_PLAY_DEG = 2.0
#: the grid the phase boundaries are found on (samples per driver turn: 0.01 deg apart), each
#: boundary then sampled on both sides
PHASE_GRID = 36_000
#: meshing steps per driver turn
STEPS = 720


@dataclass(frozen=True)
class IncompletePairStudy(StudyDefaults):
    """An incomplete pair of ``law`` at ``module`` (mm), sized by ``teeth`` (the driver's teeth on
    the first motion's sector: the centre distance is then the one at which its entry and exit
    contacts fall on the motion's ends) or ``centre_distance`` (mm), exactly one; ``mesh``
    ``"external"`` or ``"internal"`` (the planet drives its ring); cut by ``cutter`` (a shaper,
    ``ShaperCutter(16)`` by default) for ``backlash`` (mm; None: ISO/TR 10064-2); the locks' radial
    clearance ``lock_clearance`` (mm; default 0.4 of the backlash), how deep the driver's locking
    arc reaches into the driven's tips ``lock_depth`` (modules; None: 0.3 for an external pair, 0.3
    short of the planet's tips for an internal one: ``incomplete.default_lock_depth``), and the
    locking play the proof holds the dwells and transitions to, ``max_play_deg``
    (deg, the driven's free play in all)."""

    cost = 12  # its sweep and three proofs: start it first

    name: str
    law: IntermittentLaw
    module: float
    mesh: str = "external"
    teeth: int | None = None
    centre_distance: float | None = None
    cutter: Cutter | None = None
    backlash: float | None = None
    lock_clearance: float | None = None
    lock_depth: float | None = None
    max_play_deg: float = LOCKING_PLAY_DEG
    making: tuple[Making, Making] | None = None
    tolerance: float = WIRE_EDM_TOLERANCE
    steps: int = STEPS
    addendum: float | tuple[float, float] = 1.0

    def __post_init__(self) -> None:
        if not isinstance(self.law, IntermittentLaw):
            raise SpecError(f"{self.name}: law must be an IntermittentLaw, got {type(self.law).__name__}")
        check_number("module", self.module, 0.05, 100.0, unit="mm")
        if (self.teeth is None) == (self.centre_distance is None):
            raise SpecError(
                f"{self.name}: give exactly one of teeth (the driver's on the first motion's sector) or "
                "centre_distance (mm) "
                f"with the module; got teeth={self.teeth!r}, centre_distance={self.centre_distance!r}"
            )
        if self.teeth is not None:
            check_int("teeth", self.teeth, 3, 10_000)
        if self.centre_distance is not None:
            check_number("centre_distance", self.centre_distance, 0.0, 100_000.0, low_open=True, unit="mm")
        check_number("max_play_deg", self.max_play_deg, 0.0, 45.0, low_open=True, unit="deg")
        if self.lock_depth is not None:  # into the driven's tips, short of its roots
            depth = sum(per_gear("addendum", self.addendum))
            check_number("lock_depth", self.lock_depth, 0.0, depth, low_open=True, high_open=True, unit="modules")
        check_number("tolerance", self.tolerance, 0.0, 1.0, unit="mm")
        check_int("steps", self.steps, 36, 100_000)
        if self.cutter is not None and not isinstance(self.cutter, Cutter):
            raise SpecError(
                f"{self.name}: cutter must be a ShaperCutter or RackCutter, got {type(self.cutter).__name__}"
            )
        if self.making is not None and (len(self.making) != 2 or not all(isinstance(m, Making) for m in self.making)):
            raise SpecError(f"{self.name}: making must be a (driver, driven) pair of Making")

    # -- size and cut --------------------------------------------------------------------------

    @cached_property
    def pair(self) -> IncompletePair:
        """The law at the centre distance its sizing gives: as given, or the one at which the first
        motion's sector carries ``teeth`` teeth whose first pair's contact begins as the motion
        begins and whose last pair's ends as it ends (:func:`incomplete.sector_pitches`)."""
        nominal = IncompletePair(self.law, 100.0, self.mesh)
        if self.centre_distance is not None:
            return nominal.scaled(self.centre_distance / 100.0)
        motion = self.law.motions[0]
        tool = self.tool

        def misfit(a: float) -> float:
            pair = nominal.scaled(a / 100.0)
            return sector_pitches(pair, motion, tool, self._addenda, pair.sector_lengths()[0]) - (self.teeth - 1)

        rolled = nominal.sector_lengths()[0] / 100.0  # mm of roll per mm of centre distance
        guess = (self.teeth + 1) * math.pi * self.module / rolled
        try:
            a = optimize.brentq(misfit, 0.3 * guess, 3.0 * guess, xtol=1e-9)
        except ValueError as exc:
            raise SpecError.out_of_range(
                "teeth", self.teeth, "a tooth count this law's first motion can carry"
            ) from exc
        return nominal.scaled(a / 100.0)

    @property
    def _addenda(self) -> tuple[float, float]:
        return per_gear("addendum", self.addendum)

    @property
    def tool(self) -> Cutter:
        cutter = self.cutter if self.cutter is not None else ShaperCutter(16)
        if cutter.module is None:
            return cutter.sized(self.module)
        if abs(cutter.module - self.module) > 1e-9 * self.module:
            raise SpecError.out_of_range("cutter module", cutter.module, f"the study's module {self.module!r} mm")
        return cutter

    @cached_property
    def design_backlash(self) -> float:
        if self.backlash is not None:
            return check_number("backlash", self.backlash, 0.0, self.module, low_open=True, high_open=True, unit="mm")
        return design_backlash(self.module, self.pair.centre_distance, self.tool.pressure_angle)

    @cached_property
    def gears(self) -> IncompleteGears:
        return cut_incomplete(
            self.pair,
            self.tool,
            self.design_backlash,
            addendum=self.addendum,
            lock_clearance=self.lock_clearance,
            lock_depth=self.lock_depth,
        )

    # -- the proof -------------------------------------------------------------------------------

    @property
    def band(self) -> tuple[float, float]:
        """Free play of the teeth in mesh, mm at the driven pitch point: tolerance budget .. the
        target grown by the driven curve's largest pressure deviation (as for full gears)."""
        pair = self.pair
        nu = 0.0
        for motion in pair.law.motions:
            phi = np.linspace(math.radians(motion.start), math.radians(motion.end), 2001)
            dr1 = pair.r1(phi, 1, motion=motion)
            r2 = pair.r2(phi, motion=motion)
            dr2 = dr1 / motion.ratio(phi)  # |dr2/dψ|
            nu = max(nu, float(np.max(np.abs(np.arctan2(dr2, r2)))))
        return band_of(self.design_backlash, nu, self.tolerance)

    def _driven_radius(self, phi: np.ndarray) -> np.ndarray:
        """The driven's radius at the pitch point, driver angles ``phi`` (rad): free play in mm per
        radian of driven turn."""
        return np.abs(self.pair.driver.r(phi) - driven_axis(self.pair))

    @property
    def min_clearance(self) -> float:
        return tolerance_budget(self.tolerance) / 2

    def phases(self, phi: np.ndarray) -> np.ndarray:
        """Per driver angle (rad): 0 motion, 1 dwell, 2 transition (motion whose teeth pass a lock
        zone: the lock zone's roll and ``TRANSITION_PITCHES`` pitches beyond it)."""
        out = np.where(self.pair.moving(phi), 0, 1)
        deg = np.mod(np.degrees(phi), 360.0)
        for lo, hi in self._transition_windows:
            sel = (np.mod(deg - lo, 360.0) < np.mod(hi - lo, 360.0)) & (out == 0)
            out[sel] = 2
        return out

    @cached_property
    def _transition_windows(self) -> list[tuple[float, float]]:
        """The driver angles (deg, from .. to) of each motion's transitions, its start's and its end's."""
        out = []
        reach = TRANSITION_PITCHES * math.pi * self.module
        for k, motion in enumerate(self.pair.law.motions):
            table_phi, u = self.pair.roll(motion, 2001)
            zone = self.gears.zones[k]
            a = math.degrees(float(np.interp(min(zone[0] + reach, u[-1]), u, table_phi)))
            b = math.degrees(float(np.interp(max(u[-1] - zone[1] - reach, 0.0), u, table_phi)))
            out += [(motion.start, a), (b, motion.end)]
        return out

    def meshed(self, files: dict[str, bytes], sources=("outline", "dxf", "stl")) -> dict:
        """``{source: MeshReport}`` of the sources present in ``files`` (or why one cannot be read)."""
        out = {}
        internal = (False, self.mesh == "internal")
        for source in sources:
            suffix = "outline.csv" if source == "outline" else source
            names = [f"{self.name}.{role}.{suffix}" for role in ROLES]
            if not all(n in files for n in names):
                continue
            try:
                polys = [formats.section_of(n, files[n], i) for n, i in zip(names, internal, strict=True)]
            except Exception as exc:  # noqa: BLE001 - any unreadable file is a finding, said in words
                out[source] = str(exc)
                continue
            # the outlines are the design's gate before anything is made: half the steps (refined all the
            # same); the shop files are proved at the full count
            steps = self.steps // 2 if source == "outline" and self.making is not None else self.steps
            report = validate.mesh_check(self.pair, *polys, self.module, steps=steps, refine=True)
            out[source] = self._with_phase_edges(report, polys)
        return out

    def _with_phase_edges(self, report, polys):
        """``report`` with samples either side of every phase boundary added to its refined ones: a
        phase's extreme may sit on its edge (the free play rising into a transition), where neither
        the uniform steps nor the refinement of the cycle's own extremes put a sample."""
        grid = 2 * math.pi * np.arange(PHASE_GRID) / PHASE_GRID
        ph = self.phases(grid)
        cut = np.flatnonzero(ph != np.roll(ph, -1))
        phi = np.unique(np.concatenate([grid[cut], grid[(cut + 1) % PHASE_GRID]]))
        if not len(phi):
            return report
        drv, drn = contact.Outline(polys[0]), contact.Outline(polys[1])
        sweep = MeshSweep(self.pair, drv, drn, self.module, phi, math.inf, CONTACT_TOL_MM)
        sweep.all()
        a, b, c = report.refined if report.refined is not None else (np.zeros(0), np.zeros(0), np.zeros(0))
        refined = (np.concatenate([a, phi]), np.concatenate([b, sweep.bl]), np.concatenate([c, sweep.clear]))
        return dataclasses.replace(report, refined=refined)

    def judge(self, report) -> tuple[dict, list[str]]:
        """One source's figures per phase and the problems (module docstring)."""
        angle, play = report.samples("backlash")
        _, clear = report.samples("clearance")
        r2 = self._driven_radius(angle)
        deg_play = np.degrees(play / r2)
        phase = self.phases(angle)
        lo, hi = self.band
        problems = []
        out: dict = {"steps": len(report.driver_angle), "refined_samples": len(angle) - len(report.driver_angle)}
        pen = float(report.penetration.max())
        out["max_penetration_mm2"] = significant(pen) if pen > 1e-12 else 0.0
        if pen > SHOP_OVERLAP_MM2:
            k = int(np.argmax(report.penetration))
            problems.append(
                f"the gears overlap by {pen:.3g} mm² at driver {math.degrees(report.driver_angle[k]):.2f} deg "
                f"(limit {SHOP_OVERLAP_MM2:g} mm²)"
            )
        for code, label in ((0, "motion"), (1, "dwell"), (2, "transition")):
            sel = phase == code
            if not sel.any():
                continue
            k_lo, k_hi = np.flatnonzero(sel)[np.argmin(play[sel])], np.flatnonzero(sel)[np.argmax(play[sel])]
            k_deg = np.flatnonzero(sel)[np.argmax(deg_play[sel])]
            k_clear = np.flatnonzero(sel)[np.argmin(clear[sel])]
            out[label] = {
                "free_play_mm": [significant(float(play[k_lo])), significant(float(play[k_hi]))],
                "free_play_at_driver_deg": [round(math.degrees(angle[k_lo]), 4), round(math.degrees(angle[k_hi]), 4)],
                "largest_play_deg": significant(float(deg_play[k_deg])),
                "largest_play_at_driver_deg": round(math.degrees(angle[k_deg]), 4),
                "clearance_mm": significant(float(clear[k_clear])),
                "clearance_at_driver_deg": round(math.degrees(angle[k_clear]), 4),
            }
            if code == 0 and float(clear[k_clear]) < self.min_clearance:
                problems.append(
                    f"{label}: clearance {clear[k_clear] * 1e3:.1f} µm at driver "
                    f"{math.degrees(angle[k_clear]):.2f} deg is below {self.min_clearance * 1e3:.1f} µm "
                    "(half the tolerance budget)"
                )
            if code == 0 and (play[k_lo] < lo or play[k_hi] > hi):
                problems.append(
                    f"motion: free play {play[k_lo]:.4g}..{play[k_hi]:.4g} mm leaves the band "
                    f"{lo:.4g}..{hi:.4g} mm (at driver {math.degrees(angle[k_lo]):.2f} and "
                    f"{math.degrees(angle[k_hi]):.2f} deg)"
                )
            if code in (1, 2) and play[k_lo] < lo:
                problems.append(
                    f"{label}: free play {play[k_lo] * 1e3:.1f} µm at driver {math.degrees(angle[k_lo]):.2f} deg "
                    f"is below the tolerance budget {lo * 1e3:.1f} µm: parts off by the tolerance would jam"
                )
            if code in (1, 2) and deg_play[k_deg] > self.max_play_deg:
                problems.append(
                    f"{label}: the driven gear can turn {deg_play[k_deg]:.3f} deg at driver "
                    f"{math.degrees(angle[k_deg]):.2f} deg, beyond the locking play {self.max_play_deg:g} deg"
                )
        if "dwell" in out:  # where the locks hold the driven: the middle of its play, off its law's angle
            uni = self.phases(report.driver_angle) == 1
            r2u = self._driven_radius(report.driver_angle)
            middle = report.driven_error[uni] + 0.5 * report.backlash[uni] / r2u[uni]
            out["dwell"]["held_off_law_deg"] = [
                significant(float(np.degrees(middle.min()))),
                significant(float(np.degrees(middle.max()))),
            ]
        contacts = report.contacts[self.phases(report.driver_angle) != 1]
        if len(contacts) and int(np.min(contacts)) == 0:
            problems.append("no tooth pair is in contact somewhere in the motion: the driven gear would jump")
        return out, problems

    def dwell_table(self, entry: list[dict], meshing: dict) -> list[dict]:
        """Each dwell as asked (the law) and as made: it ends where the first tooth meets the held
        driven gear (``entry``), and the driven is held at its law's angle within the middle of the
        locking play measured on the re-read DXF (or the outlines)."""
        src = meshing.get("dxf", meshing.get("outline", {}))
        held = src.get("dwell", {}).get("held_off_law_deg", [math.nan, math.nan])
        out = []
        for dwell, e in zip(self.pair.law.dwells, entry, strict=True):
            psi = math.degrees(float(self.pair.law.psi(np.radians([dwell.start + 1e-9]))[0]))
            end = e.get("first_contact_driver_deg", math.nan)
            made = (end - dwell.start) % 360 if math.isfinite(end) else math.nan
            out.append(
                {
                    "asked_driver_deg": [dwell.start, dwell.end],
                    "asked_duration_deg": dwell.end - dwell.start,
                    "made_driver_deg": [dwell.start, end],
                    "made_duration_deg": round(made, 4),
                    "driven_angle_deg": round(psi % 360, 6),
                    "held_off_law_deg": held,
                }
            )
        return out

    def transitions(self) -> list[dict]:
        """Each dwell/motion boundary: what the law asks (speed and acceleration jumps, per unit
        driver speed) and where the entry contact is on the cut gears."""
        out = []
        for t in self.pair.law.transitions():
            out.append(
                {
                    "driver_deg": round(t.at_deg, 6),
                    "kind": t.kind,
                    "speed_jump_w2_per_w1": significant(t.speed_jump),
                    "acceleration_jump_per_w1_squared": significant(t.accel_jump),
                }
            )
        return out

    def entry_contacts(self, driver: shapely.Polygon, driven: shapely.Polygon) -> list[dict]:
        """Where each motion's first tooth contact is on ``driver`` and ``driven`` (outlines or
        sections re-read), the driven held at its dwell angle (:func:`incomplete.entry_contacts`)."""
        return entry_contacts(self.gears, driver, driven)

    # -- build and check -------------------------------------------------------------------------

    def parameters(self) -> dict:
        pair, tool, g = self.pair, self.tool, self.gears
        return {
            "law": pair.law.describe(),
            "mesh": pair.mesh,
            "module_mm": rounded(self.module, 12),
            "centre_distance_mm": rounded(pair.centre_distance, 9),
            "pitches_rolled_per_turn": rounded(sum(pair.sector_lengths()) / (math.pi * self.module), 6),
            "sector_pitches_first_to_last_tooth": [
                rounded(sector_pitches(pair, mo, tool, self._addenda, length), 6)
                for mo, length in zip(pair.law.motions, pair.sector_lengths(), strict=True)
            ],
            "driven_turns_per_driver_turn": f"1/{pair.law.turn_fraction}",
            "cutter": {"kind": type(tool).__name__, "teeth": getattr(tool, "teeth", None)},
            "backlash_mm": rounded(self.design_backlash, 6),
            "backlash_band_mm": [rounded(v, 6) for v in self.band],
            "lock_clearance_mm": rounded(g.locks[0].clearance, 6),
            "locking_play_deg": self.max_play_deg,
            "tolerance_mm": self.tolerance,
            "addendum": self.addendum,
        }

    def _outlines(self) -> dict[str, bytes]:
        g = self.gears
        return {
            f"{self.name}.{role}.outline.csv": formats.CSV.write(gear.toothed_contour)
            for role, gear in zip(ROLES, g.gears, strict=True)
        }

    def _proof(self, reports: dict) -> tuple[dict, list[str]]:
        readable, unreadable, problems = formats.split_unreadable(reports)
        results: dict = dict(unreadable)
        for source, rep in sorted(readable.items()):
            res, found = self.judge(rep)
            res["problems"] = found
            results[source] = res
            problems += [f"{source}: {p}" for p in found]
        return results, problems

    def build(self, out: Path) -> Built:
        """Cut, prove on the outlines, make the shop files, prove on the DXF and STL re-read, and
        assemble (module docstring)."""
        g, pair = self.gears, self.pair
        files = self._outlines()
        results: dict = {
            "locks": [
                {
                    "dwell_deg": list(lk.dwell_deg),
                    "driver_arc_radius_mm": rounded(lk.radius, 6),
                    "driven_arc_radius_mm": rounded(lk.radius + lk.clearance, 6),
                    "horns_half_angle_deg": rounded(lk.horn_deg, 4),
                    "nominal_play_each_way_deg": rounded(lk.nominal_play_deg, 5),
                }
                for lk in g.locks
            ],
            "relief": list(g.relief),
            "transitions": self.transitions(),
            "teeth": {role: gear.teeth for role, gear in zip(ROLES, g.gears, strict=True)},
            "driver_sectors_deg": [list(s) for s in g.driver.sectors_deg],
        }
        reports = self.meshed(files, ("outline",))
        meshing, problems = self._proof(reports)
        if problems:
            raise GeometryError(f"{self.name}: the cut sectors do not mesh: " + "; ".join(problems))
        if self.making is not None:
            made_files, parts, marks = self._make()
            files.update(made_files)
            reports.update(self.meshed(files, ("dxf", "stl")))
            meshing, problems = self._proof(reports)
            if problems:
                raise GeometryError(f"{self.name}: the made parts do not mesh: " + "; ".join(problems))
            results["assembly"], more = self._assemble(parts, marks, reports["dxf"], files)
            files.update(more)
            sections = [
                formats.section_of(f"{self.name}.{r}.dxf", files[f"{self.name}.{r}.dxf"], i)
                for r, i in zip(ROLES, (False, pair.mesh == "internal"), strict=True)
            ]
            results["entry"] = self.entry_contacts(*sections)
        else:
            results["entry"] = self.entry_contacts(g.driver.polygon, g.driven.polygon)
        results["dwells"] = self.dwell_table(results["entry"], meshing)
        tip_on_tip = [e for e in results["entry"] if e.get("tip_on_tip")]
        if tip_on_tip:
            raise GeometryError(f"{self.name}: the first tooth contact after a dwell is tip on tip: {tip_on_tip[0]}")
        results["meshing"] = meshing
        files.update(plots.figure_files(self._figure(reports), f"{self.name}.motion"))
        fig = plots.toothed_pair_figure(
            g.driver.polygon,
            g.driven.polygon,
            pair.centre_distance,
            pair.mesh == "external",
            float(pair.driver.r(0.0)),
            self.name,
        )
        files.update(plots.figure_files(fig, f"{self.name}.teeth"))
        files[f"{self.name}.teeth.json"] = json_bytes({"parameters": self.parameters(), "results": results})
        return Built({"kind": "incomplete_pair", "parameters": self.parameters(), "results": results}, files)

    def _make(self):
        g = self.gears
        files, parts, marks = {}, {}, {}
        for k, (role, gear) in enumerate(zip(ROLES, g.gears, strict=True)):
            m = self.making[k]
            mark = pair_assembly.timing_mark(gear, m.features)
            features = (
                dataclasses.replace(m.features, notches=(mark,))
                if gear.internal
                else dataclasses.replace(m.features, holes=(*m.features.holes, mark))
            )
            m = dataclasses.replace(m, features=features, tolerance=self.tolerance, step=False)
            notes = (
                f"incomplete {'ring' if gear.internal else 'gear'}: {gear.teeth} teeth on toothed sectors, module "
                f"{self.module:.6g} mm, face width {m.width:g} mm",
                f"mates with {self.name}.{ROLES[1 - k]}, {self.pair.mesh} mesh, centre distance "
                f"{self.pair.centre_distance:.4f} mm; law: {self.pair.law.describe()}",
                f"backlash {self.design_backlash:.4f} mm on the teeth; locking arcs {g.locks[0].radius:.4f} / "
                f"{g.locks[0].radius + g.locks[0].clearance:.4f} mm about the driver's axis",
                f"timing mark: {'notch' if gear.internal else 'hole'} dia {mark[2]:.2f} mm at +x meets the mate's "
                "at the start",
            )
            res, shop, part = manufacture(
                f"{self.name}.{role}",
                gear.blank,
                gear.cut,
                m,
                notes,
                lambda pt, gg=gear: f"tooth space {gg.nearest_space(pt)}",
                marks=((mark[0], mark[1], "TIMING"),),
            )
            files.update(shop)
            parts[role] = part
            marks[role] = mark
        return files, parts, marks

    def _assemble(self, parts: dict, marks: dict, dxf_report, made: dict[str, bytes]) -> tuple[dict, dict[str, bytes]]:
        pair = self.pair
        external = pair.mesh == "external"
        centre = driven_axis(pair)
        turn = round(math.degrees(float(driven_turn(pair, np.zeros(1))[0])) % 360.0, 9)  # at driver angle 0
        placed = [
            (f"{self.name}.driver", parts["driver"], formats.placement()),
            (f"{self.name}.driven", parts["driven"], formats.placement(centre, 0.0, 0.0, math.radians(turn))),
        ]
        record, files = assembly_file(self.name, placed)
        steps = {role: step_file(parts[role], files) for role in ROLES}
        phi = 2 * math.pi * np.arange(pair_assembly.MOTION_ROWS + 1) / pair_assembly.MOTION_ROWS
        sense = 1.0 if external else -1.0
        rows = [
            [f"{math.degrees(a):.4f}", f"{math.degrees(b):.9f}", "dwell" if not mv else "motion"]
            for a, b, mv in zip(phi, sense * pair.law.psi(phi), pair.moving(phi), strict=True)
        ]
        files[f"{self.name}.motion.csv"] = csv_bytes(
            ["driver_clockwise_deg", "driven_counterclockwise_deg", "phase"], rows
        )
        files[f"{self.name}.dxf_meshing.csv"] = pair_assembly.meshing_csv(dxf_report)
        files[f"{self.name}.assembly.dxf"] = formats.DXF.assembly(
            self.name,
            [
                (f"{self.name}.driver", made[f"{self.name}.driver.dxf"], (0.0, 0.0, 0.0)),
                (f"{self.name}.driven", made[f"{self.name}.driven.dxf"], (centre, 0.0, math.radians(turn))),
            ],
            (f"centre distance {pair.centre_distance:.4f} mm; driver turns clockwise", f"law: {pair.law.describe()}"),
        )
        return {
            "kind": pair.mesh,
            "driver": f"{self.name}.driver",
            "driven": f"{self.name}.driven",
            "centre_distance_mm": rounded(pair.centre_distance, 9),
            "driven_centre_mm": [rounded(centre, 9), 0.0],
            "driven_angle_at_start_deg": turn,
            "driver_turns": "clockwise",
            "driven_turns": "counter-clockwise" if external else "clockwise",
            "timing_marks_mm": {role: [rounded(x, 6), rounded(y, 6)] for role, (x, y, _) in marks.items()},
            "model": record,
            "step": steps,
            "motion": f"{self.name}.motion.csv",
            "drawing": f"{self.name}.assembly.dxf",
        }, files

    def check(self, files: dict[str, bytes]) -> Checked:
        """Re-run the proof on the DXF and STL as found, and re-read the STEP and 3MF."""
        reports = self.meshed(files, ("dxf", "stl") if self.making is not None else ("outline",))
        results, problems = self._proof(reports)
        if self.making is not None:
            widths = {f"{self.name}.{role}": m.width for role, m in zip(ROLES, self.making, strict=True)}
            made, more = check_shop_files(
                files, widths, (f"{self.name}.assembly.3mf", [f"{self.name}.driver", f"{self.name}.driven"])
            )
            results["made"] = made
            problems += more
        return Checked(results, problems)

    def _figure(self, reports: dict):
        pair = self.pair
        phi = np.radians(np.linspace(0.0, 360.0, 1441))
        curves = {}
        for source, rep in reports.items():
            if isinstance(rep, str):
                continue
            angle, play = rep.samples("backlash")
            r2 = self._driven_radius(angle)
            curves[source] = (np.degrees(angle), np.degrees(play / r2))
        dwells = [(d.start, d.end) for d in pair.law.dwells]
        return plots.intermittent_figure(
            self.name,
            np.degrees(phi),
            np.degrees(pair.law.psi(phi)),
            pair.law.ratio(phi),
            dwells,
            curves,
            self.max_play_deg,
        )
