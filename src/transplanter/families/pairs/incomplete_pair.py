"""Incomplete gear pairs: from an intermittent law to shop files, meshing proof and report.

:class:`IncompletePairStudy` sizes an :class:`~transplanter.geometry.pitch.intermittent.IncompletePair`
(the law of dwells and motions, external or a planet driving its ring), cuts it
(:func:`transplanter.geometry.incomplete.cut_incomplete`: toothed sectors by the cutter's envelope,
locking arcs, the transitions relieved by the driver's own sweep), and proves it on the outlines
and on the DXF and STL re-read from their bytes, as full pairs are proved, each position judged by
its phase — motion, dwell (the driven held by the locking arcs within the study's **locking
play**, ``max_play_deg``) or transition — in the prove station
(:class:`~transplanter.families.pairs.incomplete_proof.IncompleteProof`); the make and assemble
station (:mod:`~transplanter.families.pairs.incomplete_assembly`) writes the shop files and places
the pair in mesh.

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

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import shapely
from scipy import optimize

from transplanter.core.errors import GeometryError, SpecError, check_int, check_number
from transplanter.core.forwarding import forward
from transplanter.core.precision import rounded, significant
from transplanter.core.tolerances import WIRE_EDM_TOLERANCE
from transplanter.families.builder.making import Making, check_shop_files
from transplanter.families.builder.study import Built, Checked, StudyDefaults
from transplanter.families.pairs import incomplete_assembly
from transplanter.families.pairs.incomplete_proof import ROLES, IncompleteProof
from transplanter.geometry.backlash import design_backlash
from transplanter.geometry.cutter import Cutter, ShaperCutter
from transplanter.geometry.dwell_entry import entry_contacts
from transplanter.geometry.incomplete import IncompleteGears, check_fit, cut_incomplete
from transplanter.geometry.pair_gate import per_gear
from transplanter.geometry.pitch.intermittent import IncompletePair, IntermittentLaw
from transplanter.geometry.toothed_sectors import sector_pitches
from transplanter.report import plots
from transplanter.shop import formats
from transplanter.shop.export import json_bytes

__all__ = ["IncompletePairStudy", "LOCKING_PLAY_DEG"]

#: names this module gave before issue 41 moved them to modules of their own, still found here
__getattr__ = forward(
    __name__,
    {
        "PHASE_GRID": "transplanter.families.pairs.incomplete_proof",
    },
)

#: the locking play a study holds its dwells and transitions to unless told, deg of driven turn (in
#: all): what the locks and the relieved end teeth of the examples keep (0.5-1.5 deg at modules 2-3)
LOCKING_PLAY_DEG = 2.0
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

    def _cut_arguments(self) -> tuple[tuple, dict]:
        """The study's pair, cutter, backlash and sizes as ``cut_incomplete`` and ``check_fit`` take them."""
        sizes = {"addendum": self.addendum, "lock_clearance": self.lock_clearance, "lock_depth": self.lock_depth}
        return (self.pair, self.tool, self.design_backlash), sizes

    @cached_property
    def gears(self) -> IncompleteGears:
        args, sizes = self._cut_arguments()
        return cut_incomplete(*args, **sizes)

    def fit(self) -> None:
        """A TransplanterError unless every lock and sector fits at the study's size: what
        :attr:`gears` finds before it cuts, without cutting (``incomplete.check_fit``)."""
        args, sizes = self._cut_arguments()
        check_fit(*args, **sizes)

    # -- the proof (incomplete_proof) -----------------------------------------------------------

    @cached_property
    def proof(self) -> IncompleteProof:
        """The prove station: the meshing proof of the cut gears, each position judged by its phase."""
        return IncompleteProof(
            self.name,
            self.pair,
            self.gears,
            self.module,
            self.design_backlash,
            self.tolerance,
            self.max_play_deg,
            self.steps,
            self.making is not None,
        )

    @property
    def band(self) -> tuple[float, float]:
        """Free play of the teeth in mesh, mm at the driven pitch point (:attr:`IncompleteProof.band`)."""
        return self.proof.band

    def phases(self, phi: np.ndarray) -> np.ndarray:
        """Per driver angle (rad): 0 motion, 1 dwell, 2 transition (:meth:`IncompleteProof.phases`)."""
        return self.proof.phases(phi)

    def meshed(self, files: dict[str, bytes], sources=("outline", "dxf", "stl")) -> dict:
        """``{source: MeshReport}`` of the sources present in ``files`` (or why one cannot be read)."""
        return self.proof.meshed(files, sources)

    def judge(self, report) -> tuple[dict, list[str]]:
        """One source's figures per phase and the problems (:meth:`IncompleteProof.judge`)."""
        return self.proof.judge(report)

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
        meshing, problems = self.proof.results(reports)
        if problems:
            raise GeometryError(f"{self.name}: the cut sectors do not mesh: " + "; ".join(problems))
        if self.making is not None:
            made_files, parts, marks = incomplete_assembly.make(
                self.name, g, pair, self.module, self.design_backlash, self.making, self.tolerance
            )
            files.update(made_files)
            reports.update(self.meshed(files, ("dxf", "stl")))
            meshing, problems = self.proof.results(reports)
            if problems:
                raise GeometryError(f"{self.name}: the made parts do not mesh: " + "; ".join(problems))
            results["assembly"], more = incomplete_assembly.assemble(
                self.name, pair, parts, marks, reports["dxf"], files
            )
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
        files.update(plots.figure_files(self.proof.figure(reports), f"{self.name}.motion"))
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

    def check(self, files: dict[str, bytes]) -> Checked:
        """Re-run the proof on the DXF and STL as found, and re-read the STEP and 3MF."""
        reports = self.meshed(files, ("dxf", "stl") if self.making is not None else ("outline",))
        results, problems = self.proof.results(reports)
        if self.making is not None:
            widths = {f"{self.name}.{role}": m.width for role, m in zip(ROLES, self.making, strict=True)}
            made, more = check_shop_files(
                files, widths, (f"{self.name}.assembly.3mf", [f"{self.name}.driver", f"{self.name}.driven"])
            )
            results["made"] = made
            problems += more
        return Checked(results, problems)
