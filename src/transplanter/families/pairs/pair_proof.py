"""The prove station of a gear pair: the meshing proof on whatever files of the pair are at hand.

:class:`PairProof` holds what the proof needs — the sized pair, its names, the backlash band
it is cut for and the clearance it must keep — and nothing of how the gears were made, so the
build (on the outlines, then the DXF and STL it wrote) and ``transplanter check`` (on the files as
found on disk) run the same proof. A pair that drives a train is proved further by a
:class:`TrainHook` its part passes in (``families.trains.TrainProof`` for seed 004's planetary
train: the train rebuilt from each source's meshing, its needle tip and the paper's objectives);
this module knows no train and no paper.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import shapely

from transplanter.core import heap
from transplanter.core.errors import ExportError
from transplanter.core.precision import rounded, significant
from transplanter.core.tolerances import PENETRATION_TOL, SHOP_OVERLAP_MM2
from transplanter.geometry.backlash import backlash_band, tolerance_budget
from transplanter.geometry.pitch import GearPair
from transplanter.proof import sameness, validate
from transplanter.proof.meshing import MeshReport
from transplanter.report import plots
from transplanter.shop import formats
from transplanter.shop.export import csv_array

__all__ = ["Carried", "MeshingPlot", "PairProof", "TrainHook", "screen_verdict", "SOURCES", "SHOP_SOURCES"]

#: the sources a pair is meshed from: the generated outlines, the DXF and the STL's mid-plane section
SOURCES = ("outline", "dxf", "stl")
#: what a shop receives: the sources ``check`` re-proves on the files as found
SHOP_SOURCES = ("dxf", "stl")


@dataclass(frozen=True)
class Carried:
    """A source's meshing carried from the proved source's (:meth:`PairProof.mesh_once`): its
    driver's and driven's teeth lie within ``within_mm`` of the proved ones (both ways,
    :func:`~transplanter.proof.sameness.within`), so placed as the proved pair is at every position
    of its proof, its gears are no closer than the proved mid-play clearance less their sum."""

    #: the source whose meshing proof is carried ("dxf")
    proved: str
    #: (driver, driven): how far this source's teeth lie from the proved source's at most, mm
    within_mm: tuple[float, float]
    #: the proved source's smallest mid-play clearance (mm) and the driver angle there (deg)
    clearance_mm: float
    at_deg: float

    @property
    def clearance_at_least(self) -> float:
        """The smallest gap this source's gears can have at the proved pair's positions, mm."""
        return self.clearance_mm - sum(self.within_mm)

    def summary(self) -> dict:
        """The figures it carries (mm, deg)."""
        return {
            "carried_from": self.proved,
            "teeth_within_mm": [significant(w) for w in self.within_mm],
            "clearance_at_least_mm": significant(self.clearance_at_least),
            "clearance_at_driver_deg": round(self.at_deg, 4),
        }


@runtime_checkable
class TrainHook(Protocol):
    """What a pair that drives a train adds to its proof (and to its assembly)."""

    #: driven gears (planets) per driver, evenly spaced on the carrier
    planets: int
    #: the train's centre distance, mm (must be the pair's)
    centre_distance: float

    def carrier(self) -> dict:
        """How many planets to make and where they sit on the carrier (assembly record keys)."""

    def prove(self, source: str, report: MeshReport, found: list[str], module: float) -> tuple[object, dict, list[str]]:
        """The train rebuilt from ``report`` (a source's meshing; ``found`` its meshing
        problems): (its check, for the plot; its figures; the problems it finds)."""


@dataclass(frozen=True)
class MeshingPlot:
    """A pair's meshing plot, drawn when called (its files by name): plain data, so the plots'
    process may be sent it once the proof has been made (:meth:`CutPair.plots`)."""

    name: str
    meshed: dict  # source -> MeshReport (the sources meshed, not carried)
    shown: object  # the train rebuilt on the source the plot shows, or None
    note: str
    band: tuple[float, float]
    clearance: float | None

    def __call__(self) -> dict[str, bytes]:
        fig = plots.meshing_figure(
            self.meshed, self.name, self.shown, self.note, band=self.band, clearance=self.clearance
        )
        return plots.figure_files(fig, f"{self.name}.meshing")


@dataclass(frozen=True)
class PairProof:
    """The meshing proof of a sized pair named ``name`` (files ``<name>.<role>.<source>``).

    ``backlash`` is the circumferential backlash it is cut for and ``tolerance`` (± mm) what the
    shop may be off by: the made pair's free play must stay inside ``backlash_band`` (tolerance
    budget .. target's upper end), no step may overlap, and with backlash the mid-play clearance
    must stay above ``min_clearance`` everywhere. ``must_mesh`` False: the pair is a finding,
    expected not to mesh (its overlaps are the result, so its extremes are not refined)."""

    name: str
    #: the sized pair
    pair: GearPair
    #: module, mm
    module: float
    #: driver's tooth count (the check steps are made coprime with it)
    driver_teeth: int
    #: circumferential backlash the pair is cut for, mm at the pitch point
    backlash: float
    #: what the shop may be off by, ± mm
    tolerance: float
    #: meshing-check steps per driver turn
    steps: int
    must_mesh: bool = True
    train: TrainHook | None = field(default=None, compare=False)
    #: the smallest free play the made pair must keep at every position, mm (None: the tolerance
    #: budget, the band's own lower end)
    min_backlash: float | None = None

    @property
    def internal(self) -> tuple[bool, bool]:
        """(driver, driven) is a ring."""
        return (self.pair.ring == "driver", self.pair.ring == "driven")

    @property
    def names(self) -> tuple[str, str]:
        """What the two gears are called in the problems: ring and planet, or driver and driven."""
        return ("ring", "planet") if self.pair.ring == "driver" else ("driver", "driven")

    @property
    def band(self) -> tuple[float, float]:
        """The free play the made pair must keep, mm (:func:`backlash.backlash_band`), its lower
        end raised to ``min_backlash`` when that is given."""
        low, high = backlash_band(self.pair, self.backlash, self.tolerance)
        if self.min_backlash is None:
            return low, high
        # a floor over the play cut at the pitch point raises the whole band (never inverted)
        return max(low, self.min_backlash), max(high, backlash_band(self.pair, self.min_backlash, self.tolerance)[1])

    @property
    def min_clearance(self) -> float | None:
        """The smallest mid-play clearance a pair cut with backlash must keep everywhere (mm): half
        the tolerance budget — what each flank gets when the backlash equals the budget; None for
        a pair cut without backlash (its flanks touch by design)."""
        return tolerance_budget(self.tolerance) / 2 if self.backlash > 0 else None

    def sections(self, files: dict[str, bytes], sources=SOURCES) -> tuple[dict, dict]:
        """Each present source's (driver, driven) sections as read from ``files`` (file names →
        bytes), and ``{source: reason}`` for those whose files cannot be read."""
        sections, unreadable = {}, {}
        for source in sources:
            suffix = "outline.csv" if source == "outline" else source
            names = [f"{self.name}.{role}.{suffix}" for role in ("driver", "driven")]
            if not all(n in files for n in names):
                continue
            try:
                sections[source] = [
                    formats.section_of(n, files[n], internal) for n, internal in zip(names, self.internal, strict=True)
                ]
            except ExportError as exc:
                unreadable[source] = str(exc)
        return sections, unreadable

    def mesh(self, files: dict[str, bytes], sources=SOURCES) -> dict:
        """Mesh the pair as found in ``files`` (file names → bytes) for each source present;
        ``{source: MeshReport}``, or the reason where a file cannot be read."""
        sections, out = self.sections(files, sources)
        return out | self._checked(sections)

    def mesh_once(self, files: dict[str, bytes], sources=SOURCES, proved: str = "dxf") -> dict:
        """Mesh ``proved`` (the DXF a shop cuts, re-read) and carry its proof to the other sources
        present whose teeth lie within a certified distance of its own (:mod:`~transplanter.proof.
        sameness`): ``{source: MeshReport | Carried}``, or the reason a file cannot be read.

        What is carried is the clearance; the free play, transmission error and contact ratio are
        the proved source's. A source is meshed on its own instead where nothing can be carried:
        the proved source failing, a pair cut without backlash (its flanks touch by design: no gap
        to carry), a floor on the free play at every position (``min_backlash``: a play is not
        carried by a distance, so each file shows it), a finding (``must_mesh`` False), teeth
        farther apart than the ladder, or a carried gap below ``min_clearance``."""
        sections, out = self.sections(files, sources)
        if proved not in sections:
            return out | self._checked(sections)
        rep = out[proved] = self._checked({proved: sections[proved]})[proved]
        gap = rep.clearance_min
        carry = (
            self.must_mesh
            and self.min_backlash is None
            and self.min_clearance is not None
            and gap is not None
            and not self.problems(rep)
        )
        alone = {source: polys for source, polys in sections.items() if source != proved}
        for source, polys in list(alone.items()) if carry else ():
            try:
                r = [sameness.within(a, b, i) for a, b, i in zip(polys, sections[proved], self.internal, strict=True)]
            except ValueError:  # a ring without its toothed hole (a damaged file): its own proof says what
                continue
            if None not in r and gap.value - sum(r) >= self.min_clearance:
                out[source] = Carried(proved, (r[0], r[1]), gap.value, gap.at_deg)
                del alone[source]
        return out | self._checked(alone)

    def _checked(self, sections: dict) -> dict:
        def check(polys):
            # every gap, and the extremes refined between the samples (meshing module docstring) —
            # not for a finding, whose overlaps are the result
            return validate.mesh_check(
                self.pair, *polys, self.module, steps=self.steps, teeth=self.driver_teeth, refine=self.must_mesh
            )

        if not sections:
            return {}
        if len(sections) == 1:
            done = {k: check(v) for k, v in sections.items()}
        else:  # the sources side by side: numpy, GEOS and the k-d tree release the GIL for most of a check
            with ThreadPoolExecutor(max_workers=2) as pool:
                done = dict(zip(sections, pool.map(check, sections.values()), strict=True))
        heap.trim(0)  # the threads' arenas: their vertex/edge pairs would stay resident under what follows
        return done

    def problems(self, report: MeshReport) -> list[str]:
        """What keeps ``report``'s pair from meshing as designed, in words (empty: it does)."""
        overlap = SHOP_OVERLAP_MM2 if self.backlash > 0 else PENETRATION_TOL
        found = report.problems(
            max_penetration=overlap, backlash=self.band, names=self.names, clearance=self.min_clearance
        )
        low = report.backlash_min
        if self.min_backlash is not None and low.value < self.min_backlash:
            # the remedy with its number: thinning the teeth raises the free play everywhere alike
            need = math.ceil((self.backlash + self.min_backlash - low.value) * 1e3) / 1e3
            found.append(
                f"the smallest free play {low.value * 1e3:.1f} µm (driver {low.at_deg:.2f} deg) is below the "
                f"{self.min_backlash * 1e3:.1f} µm this pair must keep at every position: cut it for a backlash of "
                f"at least {need:g} mm (now {self.backlash:.4g} mm)"
            )
        return found

    def results(self, reports: dict) -> tuple[dict, MeshingPlot, list[str]]:
        """Figures per source, the meshing plot — drawn when called (its files by name; a check
        that shows no plot draws none) — and the problems (``source: text``)."""
        band = self.band
        results: dict = {
            "backlash_band_mm": [rounded(band[0], 6), rounded(band[1], 6)],
            "backlash_target_mm": rounded(self.backlash, 6),
            "min_backlash_mm": None if self.min_backlash is None else rounded(self.min_backlash, 6),
            "tolerance_mm": self.tolerance,
            "min_clearance_mm": None if self.min_clearance is None else rounded(self.min_clearance, 6),
            "steps": self.steps,
        }
        readable, unreadable, problems = formats.split_unreadable(reports)
        results.update(unreadable)
        trains = {}
        for source, rep in sorted(readable.items()):
            if isinstance(rep, Carried):  # its gap is above min_clearance, or it was meshed on its own
                results[source] = rep.summary() | {"problems": []}
                continue
            res = rep.summary()
            found = self.problems(rep)
            res["problems"] = found
            problems += [f"{source}: {p}" for p in found]
            if self.train is not None:
                trains[source], res["train"], more = self.train.prove(source, rep, found, self.module)
                problems += more
            results[source] = res
        shown = trains.get("stl", trains.get("dxf", trains.get("outline")))
        note = " (pitch-point contact; the interference above ignored)" if problems else ""
        meshed = {k: v for k, v in readable.items() if not isinstance(v, Carried)}
        return results, MeshingPlot(self.name, meshed, shown, note, band, self.min_clearance), problems

    def turned(self, files: dict[str, bytes]) -> list[str]:
        """A DXF whose toothed contour is the design turned about its axis, said in those words."""
        out = []
        for role, internal in zip(("driver", "driven"), self.internal, strict=True):
            csv_name, dxf_name = f"{self.name}.{role}.outline.csv", f"{self.name}.{role}.dxf"
            if csv_name not in files or dxf_name not in files:
                continue
            try:
                design = shapely.Polygon(csv_array(files[csv_name]))
                section = formats.section_of(dxf_name, files[dxf_name])
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


def screen_verdict(meshing: dict, problems: list[str]) -> str:
    """The closed-form screen's warnings judged by the meshing proof on the made parts, in words:
    confirmed (the proof fails too) or shown harmless, with the numbers that show it."""
    if problems:
        return "confirmed by the meshing proof: " + "; ".join(problems)
    # the shop files first: on a tie the verdict names the file a shop cuts from
    shown = [
        (src, meshing[src])
        for src in ("dxf", "stl", "outline")
        if isinstance(meshing.get(src), dict) and "backlash_mm" in meshing[src]  # meshed, not carried
    ]
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
