"""Toothed pair studies: teeth by the shaper envelope, the made parts, their meshing check."""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

from transplanter.core.errors import GeometryError, SpecError, check_int, check_number
from transplanter.core.tolerances import WIRE_EDM_TOLERANCE
from transplanter.families.builder.making import Making, check_shop_files
from transplanter.families.builder.study import Built, Checked, StudyDefaults
from transplanter.families.builder.workers import Beside
from transplanter.families.pairs import pair_assembly
from transplanter.families.pairs.pair_cut import Sized, cut, rejected_alternatives, size
from transplanter.families.pairs.pair_proof import SHOP_SOURCES, SOURCES, Carried, PairProof, TrainHook, screen_verdict
from transplanter.geometry.backlash import design_backlash
from transplanter.geometry.cutter import Cutter
from transplanter.geometry.pitch import GearPair
from transplanter.shop.export import json_bytes

__all__ = ["MESH_STEPS", "ToothedPairStudy"]

#: meshing-check steps per driver turn (raised to be coprime with the driver's tooth count)
MESH_STEPS = 180


@dataclass(frozen=True)
class ToothedPairStudy(StudyDefaults):
    """Teeth of both gears of ``pair`` cut by ``cutter``; ``teeth`` is the driver's tooth count.

    **Sizing is stated once**, as for every pair study: ``teeth`` (the driver's) or ``module``
    (mm; the curves scaled to a whole number of its teeth), exactly one; a cutter given without a
    module (``ShaperCutter(12)``, ``RackCutter()``) takes the pair's, one given with a module must
    agree.

    ``rejected`` lists ``(label, teeth, cutter)`` alternatives (e.g. a published module) that
    are tried and must fail: their errors go into the manifest as findings.

    The pair is then *meshed* (``meshing.mesh_check``) through a full cycle at the design ratio:
    penetration, fouling, transmission error, backlash against ``backlash.backlash_band``, the
    mid-play clearance, contact ratio, a plot. With ``making`` it is meshed once, on the DXF as
    re-read, and the proof carried to the outlines and the STL's mid-plane section whose teeth lie
    within a certified distance of it (:meth:`PairProof.mesh_once`; a source it cannot be carried
    to is meshed); without, the outlines are meshed. A pair that does not mesh fails the part,
    unless ``must_mesh`` is False: then the study is a finding — every source meshed, figures and
    plot written, the shop files (DXF, STL) not. With ``train`` (the ``DifferentialTrain`` the
    pair drives) the train is rebuilt from each meshed source and its needle tip compared.

    **Backlash and tolerance by design.** ``backlash`` (mm, circumferential at the pitch
    point; None = the ISO/TR 10064-2 default from module and centre distance, see
    :mod:`transplanter.geometry.backlash`) thins the teeth; ``tolerance`` (± mm, default wire EDM) is what
    the shop may be off by. The made pair's smallest backlash must stay above the tolerance
    budget and its largest inside the target's band, and no step may overlap. Zero backlash
    only when ``backlash=0`` is given; its shop files then carry a warning note.
    ``min_backlash`` (mm, or ``"iso"``: the ISO/TR 10064-2 minimum at the pair's module and centre
    distance) is a floor the smallest free play must reach at *every* position — where a tooth
    tip passes a flank near its tip the free play dips below the play cut at the pitch point, so
    a pair held to the ISO minimum everywhere is cut for more (the proof names how much).

    **Internal pairs** are checked against the closed-form interference limits along the pitch
    curves before cutting (:mod:`transplanter.geometry.interference`); with ``trim_ring_tips`` the ring's
    addendum is shortened to clear them, and the manifest says so. ``addendum`` and ``shift``
    are per gear (driver, driven) or one value for both.

    **Assembly.** With ``making`` the results carry ``assembly`` (kind, mates, teeth, module,
    centre distance, where the driven gear's axis is in the driver's DXF frame and how it is
    turned at the start, the backlash measured on the re-read DXF, the tolerance, the timing
    marks), each gear has a timing mark (a hole facing the mate, or a notch in a ring's rim)
    at the start contact, its DXF notes name the mate, centre distance and tolerance, and
    ``<name>.assembly.dxf`` draws the pair in mesh with the centre distance dimensioned;
    ``<name>.motion.csv`` is the design motion (driven angle per driver angle).

    **Trains.** ``train`` is the proof hook of the train the pair drives
    (:class:`~transplanter.families.pairs.pair_proof.TrainHook`; ``families.trains.TrainProof`` for a
    planetary train): each source's meshing rebuilds the train and the hook judges it (seed 004:
    the needle tip, and with a site its objectives); the driven gear is made once per planet and
    the 3MF places each on the carrier. This study knows no train and no paper.

    **Stations.** :meth:`build` runs the pair's journey as stations that pass frozen values:
    size (:func:`pair_cut.size`) → cut and gate (:func:`pair_cut.cut`, a ``CutPair``) → make
    (:func:`pair_assembly.make`) → prove the DXF, carried to the outlines and the STL
    (:class:`pair_proof.PairProof`) → assemble (:func:`pair_assembly.assemble`) → record (a
    finding, or a pair without ``making``, proves its outlines before making). Forked processes
    (``workers.Beside``) write the STEPs beside the proof and draw the plots from the cut on:
    the same files, each made once.
    """

    cost = 10

    name: str
    #: the pitch pair, any size: sized here by ``teeth``
    pair: GearPair
    #: the cutter; without a module it takes the pair's
    cutter: Cutter
    #: the driver's tooth count (the module follows from the curves); or give ``module``
    teeth: int | None = None
    allow_undercut: bool = False
    #: ``(label, teeth, cutter)`` alternatives that must fail at the gate (findings)
    rejected: tuple[tuple[str, int, Cutter], ...] = ()
    #: (driver, driven) shop files; None: teeth, figures and proof only
    making: tuple[Making, Making] | None = None
    #: False: a finding, expected not to mesh (no shop files)
    must_mesh: bool = True
    #: the proof hook of the train the pair drives (``families.trains.TrainProof``)
    train: TrainHook | None = None
    #: circumferential backlash at the pitch point, mm (None: ISO/TR 10064-2)
    backlash: float | None = None
    #: what the shop may be off by, ± mm
    tolerance: float = WIRE_EDM_TOLERANCE
    #: addendum coefficients, modules: one for both gears or (driver, driven)
    addendum: float | tuple[float, float] = 1.0
    #: profile-shift coefficients: one for both gears or (driver, driven)
    shift: float | tuple[float, float] = 0.0
    #: shorten the ring's tips to the closed-form limit where they would foul
    trim_ring_tips: bool = True
    #: meshing-check steps per driver turn (raised to be coprime with the driver's tooth count)
    mesh_steps: int = MESH_STEPS
    #: the module, mm, instead of ``teeth``: the curves are scaled to a whole number of its teeth
    #: (as ``PitchPairStudy`` and ``GearPair.sized`` size a pair)
    module: float | None = None
    #: more notes for both gears' shop files (e.g. that another part is cut from these teeth)
    notes: tuple[str, ...] = ()
    #: the smallest free play the made pair must keep at every position: mm, or "iso" (ISO/TR
    #: 10064-2 minimum at this module and centre distance); None: the tolerance budget
    min_backlash: float | str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.pair, GearPair):
            raise SpecError(f"{self.name}: pair must be a pitch.GearPair, got {type(self.pair).__name__}")
        if not isinstance(self.cutter, Cutter):
            raise SpecError(
                f"{self.name}: cutter must be a cutter (ShaperCutter, RackCutter), got {type(self.cutter).__name__}"
            )
        if (self.teeth is None) == (self.module is None):
            raise SpecError(
                f"{self.name}: give exactly one of teeth (the driver's, the module follows) or module (mm, the "
                f"curves scaled to it); got teeth={self.teeth!r}, module={self.module!r}"
            )
        check_int("mesh_steps", self.mesh_steps, 4, 100_000)
        if self.min_backlash is not None and self.min_backlash != "iso":
            check_number("min_backlash", self.min_backlash, 0.0, 10.0, unit="mm")
        check_number("tolerance", self.tolerance, 0.0, 1.0, unit="mm")
        if self.making is not None and (len(self.making) != 2 or not all(isinstance(m, Making) for m in self.making)):
            raise SpecError(f"{self.name}: making must be a (driver, driven) pair of Making")
        if self.train is not None and not isinstance(self.train, TrainHook):
            raise SpecError(
                f"{self.name}: train must be a proof hook (families.trains.TrainProof(train, site)), "
                f"got {type(self.train).__name__}"
            )

    @cached_property
    def sized(self) -> Sized:
        """The pair sized by ``teeth``, the cutter at its module and the backlash it is cut for."""
        return size(self.pair, self.cutter, self.backlash, teeth=self.teeth, module=self.module)

    @property
    def tool(self) -> Cutter:
        """The cutter at the pair's module (the module is stated once, by the sizing)."""
        return self.sized.tool

    @property
    def design_backlash(self) -> float:
        """The circumferential backlash the pair is cut for, mm."""
        return self.sized.backlash

    def cut_teeth(self):
        """Both gears' teeth cut through the pair gate (``pair_cut.cut``): the design's own answer,
        before anything is made or proved."""
        return cut(
            self.name,
            self.sized,
            tolerance=self.tolerance,
            addendum=self.addendum,
            shift=self.shift,
            trim_ring_tips=self.trim_ring_tips,
            must_mesh=self.must_mesh,
            allow_undercut=self.allow_undercut,
        )

    @cached_property
    def proof(self) -> PairProof:
        """The meshing proof of this pair, on whatever of its files are at hand."""
        s = self.sized
        return PairProof(
            self.name,
            s.pair,
            s.sizing.module,
            int(s.sizing.teeth[0]),
            s.backlash,
            self.tolerance,
            self.mesh_steps,
            self.must_mesh,
            self.train,
            self._floor(s),
        )

    def _floor(self, sized) -> float | None:
        if self.min_backlash != "iso":
            return self.min_backlash
        return design_backlash(sized.sizing.module, sized.pair.centre_distance, sized.tool.pressure_angle)

    def build(self, out: Path) -> Built:
        """Teeth of both gears (outlines CSV, JSON, plot); with ``making`` the shop files with
        timing marks, the assembly data and 3MF, and the meshing proof on the DXF carried to the
        outline and STL;
        rejected alternatives as findings (see the class docstring)."""
        sized, proof = self.sized, self.proof
        if self.train is not None and abs(self.train.centre_distance - sized.pair.centre_distance) > 1e-9:
            raise SpecError.out_of_range(
                "train",
                self.train.centre_distance,
                f"a train on this pair (centre distance {sized.pair.centre_distance})",
            )
        made_pair = self.cut_teeth()
        params = made_pair.parameters(backlash_default=self.backlash is None, must_mesh=self.must_mesh)
        results: dict = {}
        if sized.pair.ring is not None:
            results["interference"] = made_pair.interference(proof.names)
        results.update(made_pair.gear_results())
        files = made_pair.outline_files()
        once = self.must_mesh and self.making is not None
        with contextlib.ExitStack() as beside:
            # the plots in a fork of their own (issue 46): the teeth drawn now, the meshing once proved
            drawn = beside.enter_context(Beside(made_pair.plots, inbox=True))
            reports = {} if once else proof.mesh(files, ("outline",))
            problems = [] if once else proof.problems(reports["outline"])
            if problems and self.must_mesh:
                raise GeometryError(f"{self.name}: the generated teeth do not mesh: " + "; ".join(problems))
            if problems:
                results["shop_files"] = "withheld: the generated teeth do not mesh (see meshing)"
            if not problems and self.making is not None:
                made = pair_assembly.make(made_pair, self.making, self.train, tuple(self.notes))
                for role, res in made.results.items():
                    results[role]["made"] = res
                files.update(made.files)
                # the STEPs (OpenCASCADE) are written from the made parts in a process of their own,
                # beside the meshing proof: once, on the re-read DXF, carried to the outline and the
                # STL where their teeth are the DXF's within a certified distance (issue 46)
                written = beside.enter_context(Beside(pair_assembly.steps, made))
                reports.update(proof.mesh_once(files) if once else proof.mesh(files, ("dxf", "stl")))
                # the outline meshed on its own (the DXF failed) is the design's gate, as before making
                outline = reports.get("outline")
                problems = proof.problems(outline) if once and not isinstance(outline, Carried | str) else []
                if problems:
                    raise GeometryError(f"{self.name}: the generated teeth do not mesh: " + "; ".join(problems))
            meshing, meshing_plot, problems = proof.results(reports)
            drawn.send(meshing_plot)  # drawn beside the assembly and the STEPs still being written
            if self.making is not None and not results.get("shop_files"):
                results["assembly"], more, steps = pair_assembly.assemble(
                    made_pair, made, reports["dxf"], proof.min_clearance, self.train, written.result
                )
                for role, res in steps.items():
                    results[role]["made"]["step"] = res
                files.update(more)
                if sized.backlash == 0:
                    results["warning"] = (
                        "zero backlash by request: the shop files carry a note; cut oversize, the pair binds"
                    )
            results["meshing"] = meshing
            if results.get("interference", {}).get("screen_findings"):
                results["interference"]["verdict"] = screen_verdict(meshing, problems)
            if problems and not results.get("shop_files"):
                raise GeometryError(f"{self.name}: the made parts do not mesh: " + "; ".join(problems))
            results["rejected_alternatives"] = rejected_alternatives(
                self.pair,
                self.rejected,
                addendum=self.addendum,
                trim_ring_tips=self.trim_ring_tips,
                check_interference=self.must_mesh,
                allow_undercut=self.allow_undercut,
            )
            figures = drawn.result()
        files.update((k, v) for k, v in figures.items() if k.startswith(f"{self.name}.meshing."))
        files[f"{self.name}.teeth.json"] = json_bytes({"parameters": params, "results": results})
        files.update((k, v) for k, v in figures.items() if k.startswith(f"{self.name}.teeth."))
        return Built({"kind": "toothed_pair", "parameters": params, "results": results}, files)

    def check(self, files: dict[str, bytes]) -> Checked:
        """Re-run the meshing proof on this part's shop files as found on disk — on the DXF, carried
        to the STL as the build does (the outline CSV is the design's own record, proved at the
        build and held to its digest); say so when a DXF is the design turned about its axis. A pair built as a finding
        (``must_mesh`` False, no shop files) is checked on its outline and expected not to mesh."""
        proof = self.proof
        once = self.must_mesh and self.making is not None
        reports = proof.mesh_once(files, SHOP_SOURCES) if once else proof.mesh(files, SOURCES)
        results, _, problems = proof.results(reports)
        problems += pair_assembly.meshing_table_problems(files, f"{self.name}.dxf_meshing.csv", reports.get("dxf"))
        made, more = self._check_made(files)
        results["made"] = made
        return Checked(results, proof.turned(files) + problems + more, expected=not self.must_mesh)

    def _check_made(self, files: dict[str, bytes]) -> tuple[dict, list[str]]:
        """Each gear's STEP against its DXF, and the 3MF assembly, re-read from the files."""
        if self.making is None:
            return {}, []
        widths = {f"{self.name}.{role}": m.width for role, m in zip(("driver", "driven"), self.making, strict=True)}
        bodies = pair_assembly.bodies(self.name, self.train)
        return check_shop_files(files, widths, (f"{self.name}.assembly.3mf", bodies))
