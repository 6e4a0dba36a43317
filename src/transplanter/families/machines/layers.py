"""Where each kind of body sits across a machine: the planes (z-ranges, mm) the part script states.

Which bodies share a plane is the designer's choice: two bodies are judged against each other only
when their planes overlap. :class:`Layers` are seed 004's (gears, carrier, arm plates, needles),
:class:`CarrierLayers` seed 002's (cam, lever, carriers, both gear stages, sectors, spurs, arm and
claw); the obstacles (the seedling box, the soil) lie across the whole machine (``span``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from transplanter.core.errors import SpecError

__all__ = ["CarrierLayers", "Layers"]


class _Planes:
    """A frozen dataclass of planes: each field a z-range ``(z0, z1)`` mm with ``z0 < z1``."""

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            z = getattr(self, f.name)
            if not (len(z) == 2 and z[0] < z[1]):
                raise SpecError.out_of_range(f"layers.{f.name}", z, "(z0, z1) mm with z0 < z1")

    @property
    def span(self) -> tuple[float, float]:
        """Across the whole machine (the box and the soil), mm: 10 mm beyond the outermost planes."""
        zs = [z for f in dataclasses.fields(self) for z in getattr(self, f.name)]
        return min(zs) - 10.0, max(zs) + 10.0


@dataclass(frozen=True)
class Layers(_Planes):
    """Where each kind of body sits across the machine, z-ranges in mm (0 at the ring's back
    face): which bodies share a plane is the designer's choice, stated in the part script."""

    gears: tuple[float, float]
    carrier: tuple[float, float]
    plates: tuple[float, float]
    needles: tuple[float, float]


@dataclass(frozen=True)
class CarrierLayers(_Planes):
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
