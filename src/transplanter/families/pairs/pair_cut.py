"""The size and cut stations of a gear pair: the pair sized once, both gears cut as one value.

:func:`size` states the module once (by the driver's tooth count; a cutter given with a module
must agree). :func:`cut` resolves the backlash the pair is cut for and passes the pair gate
(:func:`pair_gate.generate_pair`); the :class:`CutPair` it returns carries everything the later
stations read — the sized pair, the gears, the cutter at the pair's module, the backlash and
tolerance — and writes its own parameters, per-gear figures, outlines and interference summary.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import SpecError, TransplanterError
from transplanter.core.precision import rounded
from transplanter.geometry.backlash import resolve_backlash
from transplanter.geometry.cutter import Cutter, RackCutter
from transplanter.geometry.interference import pair_limits
from transplanter.geometry.pair_gate import generate_pair, per_gear
from transplanter.geometry.pitch import GearPair, Mesh
from transplanter.geometry.teeth import CHORD_TOLERANCE, ToothedGear
from transplanter.report import plots
from transplanter.shop import formats

__all__ = ["CutPair", "Sized", "cut", "rejected_alternatives", "size"]

ROLES = ("driver", "driven")


@dataclass(frozen=True)
class Sized:
    """A pair sized by its driver's tooth count, and the cutter at its module."""

    #: the sized pair (perimeters ``z π m``)
    pair: GearPair
    #: its sizing (module, teeth, scale)
    sizing: object
    #: the cutter at the pair's module: as given, or sized here when given without one
    tool: Cutter
    #: circumferential backlash the pair is cut for, mm at the pitch point
    backlash: float


def size(
    pair: GearPair, cutter: Cutter, backlash: float | None, *, teeth: int | None = None, module: float | None = None
) -> Sized:
    """``pair`` sized by ``teeth`` (the driver's) or ``module`` (mm, the curves scaled), exactly one
    (``GearPair.sized``); ``cutter`` takes its module, or must agree with it; ``backlash`` None =
    twice the cutter's thickening, else the ISO/TR 10064-2 default."""
    sized, sizing = pair.sized(teeth=teeth, module=module)
    if cutter.module is not None and abs(sizing.module - cutter.module) > 1e-9 * sizing.module:
        raise SpecError.out_of_range(
            "cutter module", cutter.module, f"the pair's module {sizing.module!r} mm at {sizing.teeth[0]} teeth"
        )
    tool = cutter if cutter.module is not None else cutter.sized(sizing.module)
    j = resolve_backlash(backlash, tool.thickening, sizing.module, sized.centre_distance, tool.pressure_angle)
    return Sized(sized, sizing, tool, j)


@dataclass(frozen=True)
class CutPair:
    """Both gears of a sized pair as cut, with what they were cut for."""

    name: str
    sized: Sized
    #: (driver, driven) as cut
    gears: tuple[ToothedGear, ToothedGear]
    #: the addenda asked for (the ring's may have been trimmed at the gate), modules
    requested: tuple[float, float]
    #: ± mm the shop may be off by
    tolerance: float

    @property
    def pair(self) -> GearPair:
        return self.sized.pair

    def teeth_plot(self) -> dict[str, bytes]:
        """The two gears in mesh at the start, drawn (``<name>.teeth.png`` and ``.svg``)."""
        pair, gears = self.pair, self.gears
        external, r0 = pair.mesh is Mesh.EXTERNAL, float(pair.driver.r(0.0))
        fig = plots.toothed_pair_figure(
            gears[0].polygon, gears[1].polygon, pair.centre_distance, external, r0, self.name
        )
        return plots.figure_files(fig, f"{self.name}.teeth")

    def plots(self, receive: Callable[[], Callable[[], dict[str, bytes]]]) -> dict[str, bytes]:
        """The teeth plot, then the meshing plot ``receive()`` gives when the proof has been made
        (:meth:`PairProof.results`): drawn beside the build, the teeth while the shop files are
        made (:class:`~transplanter.families.builder.workers.Beside` with an inbox)."""
        teeth = self.teeth_plot()
        return receive()() | teeth

    def parameters(self, *, backlash_default: bool, must_mesh: bool) -> dict:
        """The parameters record of the pair as cut."""
        c, sizing = self.sized.tool, self.sized.sizing
        return {
            "teeth": list(sizing.teeth),
            "module_mm": rounded(sizing.module, 12),
            "cutter": {
                "kind": "rack" if isinstance(c, RackCutter) else "shaper",
                "teeth": getattr(c, "teeth", None),
                "pressure_angle_deg": rounded(math.degrees(c.pressure_angle)),
                "addendum": c.addendum,
                "dedendum": c.dedendum,
                "tip_fillet": c.tip_fillet,
                "thickening_mm": rounded(self.gears[0].cutter.thickening, 9),
            },
            "backlash_mm": rounded(self.sized.backlash, 6),
            "backlash_default": backlash_default and c.thickening == 0,
            "tolerance_mm": self.tolerance,
            "addendum": [g.addendum for g in self.gears],
            "shift": [g.shift for g in self.gears],
            "chord_tolerance_mm": CHORD_TOLERANCE,
            "must_mesh": must_mesh,
        }

    def gear_results(self) -> dict:
        """Per gear: teeth, vertices, area, undercut and smallest tip land."""
        return {
            role: {
                "teeth": gear.teeth,
                "internal": gear.internal,
                "vertices": len(gear.toothed_contour),
                "area_mm2": rounded(gear.polygon.area, 6),
                "undercut_mm": rounded(gear.undercut),
                "min_tip_land_mm": rounded(float(gear.tip_lands.min())),
            }
            for role, gear in zip(ROLES, self.gears, strict=True)
        }

    def outline_files(self) -> dict[str, bytes]:
        """``<name>.<role>.outline.csv``: each gear's toothed contour."""
        return {
            f"{self.name}.{role}.outline.csv": formats.CSV.write(gear.toothed_contour)
            for role, gear in zip(ROLES, self.gears, strict=True)
        }

    def interference(self, names: tuple[str, str]) -> dict:
        """An internal pair's closed-form screen as cut: limits, margins, the screen's warnings
        (each gets the meshing proof's verdict at the record station) and how it assembles."""
        pair, gears = self.pair, self.gears
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
            "ring_tips_trimmed_from": None if self.requested[r] == gears[r].addendum else self.requested[r],
            "ring_addendum_limit": rounded(lim.max_ring_addendum, 4),
            "min_fillet_margin_mm": rounded(float(np.nanmin(lim.fillet)), 4),
            "min_trochoid_margin_rad": rounded(float(np.nanmin(lim.trochoid)), 5),
            "min_contact_ratio": rounded(lim.min_contact_ratio, 3),
            "radial_assembly": lim.radial_assembly,
            "screen_findings": lim.problems(names),
            "assembly_note": "radial or axial"
            if lim.radial_assembly
            else "axial only: pushed in radially the planet trims the ring's teeth",
        }


def cut(
    name: str,
    sized: Sized,
    *,
    tolerance: float,
    addendum,
    shift,
    trim_ring_tips: bool,
    must_mesh: bool,
    allow_undercut: bool,
) -> CutPair:
    """Both gears of ``sized`` through the pair gate (``must_mesh`` False: an interfering
    internal pair is cut anyway, as a finding)."""
    gears = generate_pair(
        sized.pair,
        dataclasses.replace(sized.tool, thickening=0.0),
        sized.sizing.teeth,
        backlash=sized.backlash,
        addendum=addendum,
        shift=shift,
        trim_ring_tips=trim_ring_tips,
        check_interference=must_mesh,
        allow_undercut=allow_undercut,
    )
    return CutPair(name, sized, gears, per_gear("addendum", addendum), tolerance)


def rejected_alternatives(pair: GearPair, rejected, **gate) -> dict[str, str]:
    """Each ``(label, teeth, cutter)`` alternative tried at the gate (``gate``: ``addendum``,
    ``trim_ring_tips``, ``check_interference``, ``allow_undercut``): the error that rejects it."""
    findings = {}
    for label, teeth, cutter in rejected:
        alt, alt_sizing = pair.sized(teeth=teeth)
        try:
            generate_pair(
                alt,
                cutter if cutter.module is not None else cutter.sized(alt_sizing.module),
                alt_sizing.teeth,
                **gate,
            )
        except TransplanterError as exc:
            findings[label] = f"{type(exc).__name__}: {exc}"
        else:
            findings[label] = "generated without error"
    return findings
