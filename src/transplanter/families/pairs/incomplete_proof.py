"""The prove station of an incomplete pair: the meshing proof, each position judged by its phase.

:class:`IncompleteProof` holds what the proof needs — the sized law, the cut gears, the backlash
and tolerance they are cut for and the locking play the dwells are held to — so the build (on the
outlines, then on the DXF and STL it wrote) and ``transplanter check`` (on the files as found) run
the same proof (:func:`transplanter.proof.meshing.mesh_check`, every gap, extremes refined between
the samples and either side of every phase boundary). Each position is judged by its phase:

* **motion** (the sector teeth in mesh): no overlap, the free play inside the backlash band of
  full gears (tolerance budget .. target's upper end), mid-play clearance above half the budget;
* **dwell**: the driven gear held by the locking arcs — its free play, as a driven angle,
  within the **locking play** the study states (``max_play_deg``, degrees in all) at every
  position of the dwell, and at least the tolerance budget (parts off by the tolerance do not
  jam; the mid-play clearance is reported: with the play one-sided it says little);
* **transition** (the stretch of motion whose teeth pass the lock zone, either side of each
  dwell): the same locking play holds — the driven gear never strays further from its law than
  in the dwell — and the figures say how far it does.

It also draws ``<name>.motion.png``: the law with its dwells, the ratio with its jumps and the free
play per phase against the band and the locking play.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from transplanter.core.precision import significant
from transplanter.core.tolerances import CONTACT_TOL_MM, SHOP_OVERLAP_MM2
from transplanter.geometry import contact
from transplanter.geometry.backlash import band_of, tolerance_budget
from transplanter.geometry.incomplete import TRANSITION_PITCHES, IncompleteGears
from transplanter.geometry.pitch import driven_axis
from transplanter.geometry.pitch.intermittent import IncompletePair
from transplanter.proof import validate
from transplanter.proof.mesh_engine import MeshSweep
from transplanter.report import plots
from transplanter.shop import formats

__all__ = ["IncompleteProof", "PHASE_GRID", "ROLES"]

#: degrees that a driver angle taken through radians and back may lose (a few ulps of 360°)
ANGLE_NOISE_DEG = 1e-9

ROLES = ("driver", "driven")
#: the grid the phase boundaries are found on (samples per driver turn: 0.01 deg apart), each
#: boundary then sampled on both sides
PHASE_GRID = 36_000


@dataclass(frozen=True)
class IncompleteProof:
    """The meshing proof of the incomplete pair ``pair`` cut as ``gears`` at ``module`` (mm), named
    ``name`` (files ``<name>.<role>.<source>``): cut for ``backlash`` (mm), made to ``tolerance``
    (± mm), its dwells and transitions held to ``max_play_deg`` (deg, the driven's free play in
    all), meshed in ``steps`` per driver turn; ``made``: shop files follow, so the outlines (the
    design's gate) are meshed at half the steps."""

    name: str
    pair: IncompletePair
    gears: IncompleteGears
    module: float
    backlash: float
    tolerance: float
    max_play_deg: float
    steps: int
    made: bool

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
        return band_of(self.backlash, nu, self.tolerance)

    def driven_radius(self, phi: np.ndarray) -> np.ndarray:
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
            # a sample at the window's start may come back from radians a hair below it (60° as
            # 59.99999999999999°): that is the start, not the far end of the turn — a law written
            # motion-first (a ratio CSV, "60..360: ...; 360..420: dwell") was judged by the motion's
            # band there and refused
            d = np.mod(deg - lo, 360.0)
            sel = ((d < np.mod(hi - lo, 360.0)) | (d > 360.0 - ANGLE_NOISE_DEG)) & (out == 0)
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
        internal = (False, self.pair.mesh == "internal")
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
            steps = self.steps // 2 if source == "outline" and self.made else self.steps
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
        r2 = self.driven_radius(angle)
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
            r2u = self.driven_radius(report.driver_angle)
            middle = report.driven_error[uni] + 0.5 * report.backlash[uni] / r2u[uni]
            out["dwell"]["held_off_law_deg"] = [
                significant(float(np.degrees(middle.min()))),
                significant(float(np.degrees(middle.max()))),
            ]
        contacts = report.contacts[self.phases(report.driver_angle) != 1]
        if len(contacts) and int(np.min(contacts)) == 0:
            problems.append("no tooth pair is in contact somewhere in the motion: the driven gear would jump")
        return out, problems

    def results(self, reports: dict) -> tuple[dict, list[str]]:
        """Each readable source judged (:meth:`judge`, its problems under ``problems``) and each
        unreadable one said in words; the problems of all, each prefixed by its source."""
        readable, unreadable, problems = formats.split_unreadable(reports)
        results: dict = dict(unreadable)
        for source, rep in sorted(readable.items()):
            res, found = self.judge(rep)
            res["problems"] = found
            results[source] = res
            problems += [f"{source}: {p}" for p in found]
        return results, problems

    def figure(self, reports: dict):
        """The law with its dwells, its ratio and each source's free play per phase (a figure)."""
        pair = self.pair
        phi = np.radians(np.linspace(0.0, 360.0, 1441))
        curves = {}
        for source, rep in reports.items():
            if isinstance(rep, str):
                continue
            angle, play = rep.samples("backlash")
            r2 = self.driven_radius(angle)
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
