"""Where each kind of body sits across a machine: the planes (z-ranges, mm) the part script states,
and the smallest axial gap two bodies that move against each other must keep between their planes.

Which bodies share a plane is the designer's choice. Every two bodies that move against each other
are judged in 3D (:func:`transplanter.machine.bodies.judge_pairs`): planes at least
``min_axial_gap`` apart pass on that gap; closer (or touching, or overlapping) planes must keep the
in-plane clearance over the cycle, unless the design declares the two a joint. :class:`Layers` are
seed 004's (gears, carrier, arm plates, needles), :class:`CarrierLayers` seed 002's (cam, lever,
carriers, both gear stages, sectors, spurs, arm and claw); the obstacles (the seedling box, the
soil) lie across the whole machine (``span``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar

from transplanter.core.errors import SpecError

__all__ = ["CarrierLayers", "Layers", "MIN_AXIAL_GAP_FLOOR_MM"]

#: no stated minimum axial gap may be below this, mm (issue 42: faces that run against each other
#: without a thrust washer or bearing between them keep at least 0.5 mm)
MIN_AXIAL_GAP_FLOOR_MM = 0.5


class _Planes:
    """A frozen dataclass of planes — each field a z-range ``(z0, z1)`` mm with ``z0 < z1`` —
    and ``min_axial_gap``, mm (at least :data:`MIN_AXIAL_GAP_FLOOR_MM`)."""

    #: the fields that are not planes
    FIGURES: ClassVar[tuple[str, ...]] = ("min_axial_gap",)

    def __post_init__(self) -> None:
        for name, z in self.planes().items():
            if not (len(z) == 2 and z[0] < z[1]):
                raise SpecError.out_of_range(f"layers.{name}", z, "(z0, z1) mm with z0 < z1")
        gap = self.min_axial_gap
        if not (isinstance(gap, int | float) and MIN_AXIAL_GAP_FLOOR_MM <= gap <= 100.0):
            raise SpecError.out_of_range(
                "layers.min_axial_gap", gap, f"{MIN_AXIAL_GAP_FLOOR_MM:g}..100 mm (a joint takes a closer contact)"
            )

    def planes(self) -> dict[str, tuple[float, float]]:
        """Each plane by name, z-ranges in mm."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name not in self.FIGURES}

    def record(self) -> dict:
        """The planes and the figures as a record states them (lists of mm, mm)."""
        return {
            **{name: [z[0], z[1]] for name, z in self.planes().items()},
            **{f"{name}_mm": getattr(self, name) for name in self.FIGURES},
        }

    @property
    def span(self) -> tuple[float, float]:
        """Across the whole machine (the box and the soil), mm: 10 mm beyond the outermost planes."""
        zs = [z for plane in self.planes().values() for z in plane]
        return min(zs) - 10.0, max(zs) + 10.0


@dataclass(frozen=True)
class Layers(_Planes):
    """Where each kind of body sits across the machine, z-ranges in mm (0 at the ring's back
    face): which bodies share a plane is the designer's choice, stated in the part script."""

    gears: tuple[float, float]
    carrier: tuple[float, float]
    plates: tuple[float, float]
    needles: tuple[float, float]
    #: the smallest gap between the planes of two bodies that move against each other, mm
    min_axial_gap: float = MIN_AXIAL_GAP_FLOOR_MM


@dataclass(frozen=True)
class CarrierLayers(_Planes):
    """Where each plane of bodies sits across the machine, z-ranges in mm (0 at the cam's back
    face): the designer's choice, stated in the part script."""

    FIGURES: ClassVar[tuple[str, ...]] = ("min_axial_gap", "pivot_end")

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
    #: the smallest gap between the planes of two bodies that move against each other, mm
    min_axial_gap: float = MIN_AXIAL_GAP_FLOOR_MM
    #: how far the follower pivot's shaft end (what retains the lever on it) stands out of the
    #: lever's face towards the cam, mm: it passes over the cam, so the cam's plane must lie
    #: ``min_axial_gap`` beyond it
    pivot_end: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if not (isinstance(self.pivot_end, int | float) and 0.0 <= self.pivot_end <= 100.0):
            raise SpecError.out_of_range("layers.pivot_end", self.pivot_end, "0..100 mm")
        if self.pivot_gap < self.min_axial_gap:
            raise SpecError.out_of_range(
                "layers.lever",
                self.lever,
                f"at least {self.cam[1] + self.pivot_end + self.min_axial_gap:g} mm at its back face: the cam's "
                f"face ({self.cam[1]:g}) + the pivot's shaft end ({self.pivot_end:g}) + the minimum axial gap "
                f"({self.min_axial_gap:g})",
            )

    @property
    def pivot_gap(self) -> float:
        """The axial gap between the follower pivot's shaft end and the cam's plane, mm."""
        return self.lever[0] - self.pivot_end - self.cam[1]
