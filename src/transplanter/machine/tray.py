"""A pot-seedling tray as bodies a claw is judged against: its plastic walls and the soil of the pot
it picks, placed where the claw picks.

Seed 002 (§2.2) gives the pot: **30 mm top edge, 20 mm bottom edge, 40 mm deep**, the tray inclined
**about 55°** (requirement 6), and asks that the clip not interfere with the plastic tray
(requirement 2) and enter the soil pot at least **30 mm** (requirement 3). A :class:`PotTray` is
that tray cut through the middle of the column of cells the claw picks from, in the plane the
claw moves in:

* the **walls** (:meth:`PotTray.walls`): the tray's strip — ``cells`` cells at ``pitch`` along its
  slope, from its top face to the underside of its floor — less the picked cell, which opens at the
  top. The other cells count as tray: the claw must meet neither their walls nor their pots. The
  picked cell is in the middle of the strip, or with ``lowest`` the strip's lowest: the seedling box
  feeds its inclined tray down the slope and the mechanism picks its lowest row, the emptied tray
  turning under the box on its roller (seed 002 §2.1), so nothing of the tray lies downhill of the
  picked row's lower wall;
* the **pot** (:meth:`PotTray.pot`): the picked cell's soil, a trapezoid ``top`` wide at the mouth,
  ``bottom`` wide ``depth`` below it — the claw's work while it is picked.

A tray is placed by its picked pot's **mouth** (the middle of the top edge, machine frame, mm) and
its **axis**, the direction into the pot (rad): the tray's top face is at right angles to it, so a
tray inclined ``inclination`` from the horizontal has its axis that far from straight down
(:func:`axis_angle`). :func:`depth_in` is how far below the mouth, along the axis, a moving body
reaches inside the pot.

Examples
--------
>>> tray = PotTray(pitch=36.875)
>>> round(tray.pot((0.0, 0.0), -math.pi / 2).area, 6)  # (30 + 20) / 2 x 40
1000.0
>>> round(math.degrees(axis_angle(55.0, -1.0)), 6)  # into the pot: 55 deg from straight down, to -x
-145.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from transplanter.core.errors import SpecError, check_int, check_number
from transplanter.proof.clearance import posed_sections

__all__ = ["PotTray", "axis_angle", "depth_in", "pot_place"]


@dataclass(frozen=True)
class PotTray:
    """A pot tray cut through its picked column (module docstring), mm and degrees.

    ``pitch`` is the cells' spacing along the slope; ``cells`` how many are drawn, the picked one in
    the middle (``cells`` odd) or, with ``lowest``, the lowest along the slope, the others uphill of
    it; ``floor`` the plastic under a cell; ``inclination_deg`` the slope of the tray's top face from
    the horizontal."""

    pitch: float
    top: float = 30.0
    bottom: float = 20.0
    depth: float = 40.0
    cells: int = 5
    floor: float = 1.0
    inclination_deg: float = 55.0
    lowest: bool = False

    def __post_init__(self) -> None:
        check_number("tray top", self.top, 0.0, 1000.0, low_open=True, unit="mm")
        check_number("tray bottom", self.bottom, 0.0, self.top, low_open=True, unit="mm")
        check_number("tray depth", self.depth, 0.0, 1000.0, low_open=True, unit="mm")
        check_number("tray pitch", self.pitch, self.top, 1000.0, low_open=True, unit="mm")
        check_number("tray floor", self.floor, 0.0, 100.0, low_open=True, unit="mm")
        check_number("tray inclination_deg", self.inclination_deg, 0.0, 90.0, high_open=True, unit="deg")
        check_int("tray cells", self.cells, 1, 99)
        if self.cells % 2 == 0 and not self.lowest:
            raise SpecError.out_of_range("tray cells", self.cells, "odd (the picked cell in the middle)")

    def _placed(self, points, mouth, axis: float) -> np.ndarray:
        """Points ``(u, v)`` of the tray's frame — ``u`` along its top face, ``v`` into the pot from
        the mouth — in the machine frame."""
        p = np.asarray(points, dtype=float)
        n = np.array([math.cos(axis), math.sin(axis)])
        t = np.array([-n[1], n[0]])
        return np.asarray(mouth, dtype=float) + p[:, :1] * t + p[:, 1:] * n

    def _cell(self) -> list[tuple[float, float]]:
        a, b = self.top / 2, self.bottom / 2
        return [(-a, 0.0), (a, 0.0), (b, self.depth), (-b, self.depth)]

    def pot(self, mouth, axis: float) -> shapely.Polygon:
        """The picked pot's soil placed by its ``mouth`` (x, y mm) and ``axis`` (rad), machine frame."""
        return shapely.Polygon(self._placed(self._cell(), mouth, axis)).normalize()

    def walls(self, mouth, axis: float) -> shapely.Polygon:
        """The tray's plastic (and the other cells), the picked cell open at the top, placed likewise
        (with ``lowest``, uphill is the way along the top face that rises: +``u`` when the axis
        points towards +x, a level tray's too)."""
        if self.lowest:
            up = 1.0 if math.cos(axis) >= -1e-12 else -1.0
            ends = sorted((-up * self.pitch / 2, up * (self.cells - 0.5) * self.pitch))
        else:
            ends = [-self.cells * self.pitch / 2, self.cells * self.pitch / 2]
        lo, hi = ends
        strip = [(lo, 0.0), (hi, 0.0), (hi, self.depth + self.floor), (lo, self.depth + self.floor)]
        a = self.top / 2
        # the picked cell, carried a millimetre out past the top face so the mouth is open
        cell = [(-a, -1.0), (a, -1.0), *self._cell()[1:], (-a, 0.0)]
        out = shapely.difference(
            shapely.Polygon(self._placed(strip, mouth, axis)), shapely.Polygon(self._placed(cell, mouth, axis))
        )
        return out.normalize()

    def record(self) -> dict:
        """The tray as a machine record states it (mm, deg)."""
        return {
            "pot_top_mm": self.top,
            "pot_bottom_mm": self.bottom,
            "pot_depth_mm": self.depth,
            "cell_pitch_mm": self.pitch,
            "cells_drawn": self.cells,
            "floor_mm": self.floor,
            "inclination_deg": self.inclination_deg,
            "picked_cell": "the lowest along the slope" if self.lowest else "the middle one drawn",
        }


def axis_angle(inclination_deg: float, side: float) -> float:
    """The direction into a pot (rad) of a tray whose top face slopes ``inclination_deg`` from the
    horizontal: that far from straight down, towards +x (``side`` > 0) or -x."""
    check_number("inclination_deg", inclination_deg, 0.0, 90.0, high_open=True, unit="deg")
    turn = math.radians(inclination_deg)
    return -math.pi / 2 + (turn if side > 0 else -turn)


def pot_place(inclination_deg: float, tip, attitude: float, depth: float) -> tuple[np.ndarray, float]:
    """The picked pot's mouth (x, y mm) and axis (rad, into the pot) of a tray inclined
    ``inclination_deg`` when a claw tip at ``tip`` pointing ``attitude`` (rad) is ``depth`` (mm) down
    the pot's axis: the axis is the tray's normal on the side the claw points to (:func:`axis_angle`)."""
    axis = axis_angle(inclination_deg, math.cos(attitude))
    return np.asarray(tip, dtype=float) - depth * np.array([math.cos(axis), math.sin(axis)]), axis


def depth_in(section: shapely.Polygon, poses, pot: shapely.Polygon, mouth, axis: float) -> tuple[float, int]:
    """How far below the ``mouth`` along the ``axis`` (rad) the body ``section`` (its own frame)
    reaches inside the fixed ``pot`` at ``poses`` ((x, y, angle) arrays, mm and rad, machine frame):
    the deepest, mm (0: it never enters), and the index of the pose where it is."""
    placed = posed_sections(section, *poses)
    n = np.array([math.cos(axis), math.sin(axis)])
    best, at = 0.0, 0
    for k, g in enumerate(shapely.intersection(placed, pot)):
        pts = shapely.get_coordinates(g)
        if len(pts):
            d = float(np.max((pts - np.asarray(mouth, dtype=float)) @ n))
            if d > best:
                best, at = d, k
    return best, at
