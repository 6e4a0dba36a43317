"""Mass properties of a machine's bodies: a prism slab's mass, centre and moment of inertia from its
section (Green's theorem on the flattened outline), placed in the machine and carried into the
frame of the link that moves it — the lumps :mod:`~transplanter.machine.dynamics` moves.

Units: mm, kg; ``izz`` kg·mm² about the lump's own centre, about z.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import GeometryError, check_number

__all__ = ["Lump", "polygon_moments", "slab_lump", "to_link_frame"]


@dataclass(frozen=True)
class Lump:
    """A mass: ``mass`` kg, centre ``com`` (x, y, z) mm in its link's frame, ``izz`` kg·mm² about
    its centre (the z-axis). A prism slab's products of inertia about its centre vanish."""

    mass: float
    com: tuple[float, float, float]
    izz: float = 0.0

    def __post_init__(self) -> None:
        check_number("mass", self.mass, 0.0, 1e6, unit="kg")
        check_number("izz", self.izz, 0.0, 1e15, unit="kg mm^2")


def polygon_moments(points: np.ndarray) -> tuple[float, np.ndarray, float]:
    """Area (mm², signed: counter-clockwise +), centroid (mm) and polar second moment about the
    origin (mm⁴, same sign) of a closed polygon (Green's theorem; the last point need not repeat
    the first).

    >>> a, c, j = polygon_moments(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]))
    >>> round(a, 12), [round(float(v), 12) for v in c], round(j - a * float(c @ c), 12)  # (4 + 1) * 2 / 12
    (2.0, [1.0, 0.5], 0.833333333333)
    """
    p = np.asarray(points, dtype=float)
    q = np.roll(p, -1, axis=0)
    cross = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    area = 0.5 * float(cross.sum())
    if area == 0.0:
        return 0.0, np.zeros(2), 0.0
    centroid = np.array([((p[:, 0] + q[:, 0]) * cross).sum(), ((p[:, 1] + q[:, 1]) * cross).sum()]) / (6 * area)
    polar = float((cross * ((p**2).sum(1) + (p * q).sum(1) + (q**2).sum(1))).sum()) / 12.0
    return area, centroid, polar


def slab_lump(rings: list[tuple[np.ndarray, bool]], z0: float, width: float, density_kg_mm3: float, at) -> Lump:
    """The lump of a prism slab — its section ``rings`` ``[(points (n, 2) mm, is_hole)]`` extruded
    from ``z0`` by ``width`` mm, of ``density_kg_mm3`` — placed by the 4×4 ``at`` (its own frame in
    the machine's; a turn about z, a flip about x): its mass, centre and ``izz`` in the machine frame."""
    area, first, polar = 0.0, np.zeros(2), 0.0
    for pts, hole in rings:
        a, c, j = polygon_moments(pts)
        s = -1.0 if (a > 0) == bool(hole) else 1.0  # outlines count +, holes -, whatever their winding
        area, first, polar = area + s * a, first + s * a * c, polar + s * j
    if area <= 0.0:
        raise GeometryError(f"a slab's section has no area ({area:.6g} mm²)")
    c = first / area
    mass = density_kg_mm3 * area * width
    izz = density_kg_mm3 * width * (polar - area * float(c @ c))
    at = np.asarray(at, dtype=float)
    x, y, z = at[:3, :3] @ np.array([c[0], c[1], z0 + width / 2]) + at[:3, 3]
    return Lump(mass, (float(x), float(y), float(z)), max(izz, 0.0))


def to_link_frame(lump: Lump, pose: tuple[float, float, float]) -> Lump:
    """``lump`` (machine frame) in the frame of a link posed at ``pose`` (x, y mm, angle rad)."""
    x0, y0, a0 = pose
    c, s = math.cos(a0), math.sin(a0)
    dx, dy = lump.com[0] - x0, lump.com[1] - y0
    return Lump(lump.mass, (c * dx + s * dy, -s * dx + c * dy, lump.com[2]), lump.izz)
