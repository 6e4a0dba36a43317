"""Agronomic metrics of a rotary transplanting arm's tip trajectory (seeds 002 and 004).

The mechanism is anything with ``state(theta, arm_index) -> ArmState`` (tip, knee, planet
centre and needle attitude at input rotations ``theta``), ``planets`` arms spaced evenly in
phase, and ``carrier_speed`` (rad/s): :class:`transplanter.design.planetary.DifferentialTrain` is one.

Definitions (seed 004 §Results, items i-xi; the paper states targets, not formulas, so these
are written down here and tested):

- **trajectory height / width**: vertical / horizontal extent of the tip path relative to the
  frame (the "static" trajectory), mm.
- **picking point**: the point of the static trajectory nearest the seedling-box opening
  ``(Yx, Yy)``; **picking angle**: needle attitude (direction knee → tip, CCW from +x, deg)
  there.
- **pushing point**: the lowest point of the static trajectory (where the seedling is
  pushed into the soil); **pushing angle**: needle attitude there.
- **angle difference**: picking angle minus pushing angle, deg.
- **soil surface**: ``planting_depth`` above the lowest point.
- **machine travel**: N plants per carrier turn at ``plant_spacing`` gives the forward
  speed ``v = N s / T``; the machine travels opposite to the tip's frame-relative horizontal
  motion at the pushing point (so the tip nearly stands still in the soil). The absolute
  trajectory is ``x + d v t``.
- **hole width**: horizontal extent of the absolute trajectory below the soil surface, mm.
- **gearbox clearance**: soil surface to the lowest point of the gearbox (a circle of
  ``gearbox_radius`` about the carrier axis), mm; > 0 means the box stays out of the soil.
- **needle clearance**: smallest distance over a cycle between arm I's needle (knee → tip)
  and every other arm's needle, mm.
- **arm clearance**: the same with each arm drawn as the straight polyline planet centre →
  knee → tip, mm; 0 means the straight lines cross (seed 004 gives no arm-body shape, so
  this is a conservative bound: real arm housings are shaped or offset to pass).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from scipy import optimize

from transplanter.core.errors import GeometryError, finite_positive
from transplanter.core.extrema import refine_extreme
from transplanter.core.tolerances import ANGLE_ROOT_RAD

__all__ = ["ArmMechanism", "TransplantingMetrics", "transplanting_metrics", "segment_distance"]


class ArmMechanism(Protocol):
    planets: int
    carrier_speed: float

    def state(self, theta, arm_index: int = 0): ...


@dataclass(frozen=True)
class TransplantingMetrics:
    """Metrics of one arm; angles in deg, lengths in mm, carrier angles in deg."""

    trajectory_height: float
    trajectory_width: float
    picking_theta: float
    picking_point: tuple[float, float]
    picking_box_distance: float
    picking_angle: float
    pushing_theta: float
    pushing_point: tuple[float, float]
    pushing_angle: float
    angle_difference: float
    soil_level: float
    plant_spacing: float
    forward_speed: float
    travel_direction: int
    hole_width: float
    gearbox_clearance: float
    needle_clearance: float
    arm_clearance: float
    arm_clearance_theta: float

    def table(self) -> list[tuple[str, float, str]]:
        """(quantity, value, unit) rows in a fixed order."""
        return [
            ("trajectory height", self.trajectory_height, "mm"),
            ("trajectory width", self.trajectory_width, "mm"),
            ("picking angle", self.picking_angle, "deg"),
            ("pushing angle", self.pushing_angle, "deg"),
            ("angle difference", self.angle_difference, "deg"),
            ("picking point distance to seedling box", self.picking_box_distance, "mm"),
            ("picking carrier angle", self.picking_theta, "deg"),
            ("pushing carrier angle", self.pushing_theta, "deg"),
            ("hole width", self.hole_width, "mm"),
            ("forward speed", self.forward_speed, "mm/s"),
            ("gearbox clearance above soil", self.gearbox_clearance, "mm"),
            ("needle-needle clearance", self.needle_clearance, "mm"),
            ("straight-arm clearance", self.arm_clearance, "mm"),
        ]


def segment_distance(p0, p1, q0, q1) -> np.ndarray:
    """Distance between segments p0p1 and q0q1, each (n, 2); 0 where they cross."""

    def point_seg(x, a, b):
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", x - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
        return np.linalg.norm(x - (a + t[:, None] * ab), axis=1)

    def cross(u, v):
        return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]

    d = np.minimum.reduce([point_seg(p0, q0, q1), point_seg(p1, q0, q1), point_seg(q0, p0, p1), point_seg(q1, p0, p1)])
    r, s = p1 - p0, q1 - q0
    d1, d2 = cross(r, q0 - p0), cross(r, q1 - p0)
    d3, d4 = cross(s, p0 - q0), cross(s, p1 - q0)
    hit = (d1 * d2 < 0) & (d3 * d4 < 0)
    return np.where(hit, 0.0, d)


def transplanting_metrics(
    mech: ArmMechanism,
    seedling_box: tuple[float, float],
    plant_spacing: float,
    planting_depth: float,
    gearbox_radius: float,
    n: int = 3600,
) -> TransplantingMetrics:
    """Metrics of arm I of ``mech`` (see the module docstring for the definitions)."""
    finite_positive("plant_spacing", plant_spacing)
    finite_positive("planting_depth", planting_depth)
    finite_positive("gearbox_radius", gearbox_radius)
    box = np.asarray(seedling_box, dtype=float)
    theta = 2 * math.pi * np.arange(n) / n
    s = mech.state(theta)
    tip = s.tip

    def tip_at(t: float) -> np.ndarray:
        return mech.state(np.array([t])).tip[0]

    def att_at(t: float) -> float:
        return float(mech.state(np.array([t])).attitude[0])

    t_low, _ = refine_extreme(lambda t: tip_at(t)[1], theta, tip[:, 1])
    t_high, _ = refine_extreme(lambda t: tip_at(t)[1], theta, tip[:, 1], largest=True)
    low, high = tip_at(t_low), tip_at(t_high)
    t_pick, _ = refine_extreme(
        lambda t: float(np.linalg.norm(tip_at(t) - box)), theta, np.linalg.norm(tip - box, axis=1)
    )
    pick = tip_at(t_pick)
    pick_att, push_att = math.degrees(att_at(t_pick)), math.degrees(att_at(t_low))
    diff = (pick_att - push_att + 180.0) % 360.0 - 180.0

    soil = float(low[1] + planting_depth)
    period = 2 * math.pi / mech.carrier_speed
    speed = mech.planets * plant_spacing / period
    dx = (tip_at(t_low + 1e-6)[0] - tip_at(t_low - 1e-6)[0]) / 2e-6  # mm per rad of carrier
    direction = -1 if dx > 0 else 1

    # soil entry and exit around the lowest point, by root finding on the dense crossings
    below = tip[:, 1] < soil
    shift = int(np.argmin(tip[:, 1]))
    rolled = np.roll(below, -shift)
    if rolled.all():
        raise GeometryError(f"planting_depth = {planting_depth} mm puts the whole trajectory below the soil")
    first_out = int(np.argmin(rolled))  # samples after the lowest point still in the soil
    last_out = n - int(np.argmin(rolled[::-1]))  # first sample back in the soil, counting backwards
    k_exit = (shift + first_out) % n
    k_entry = (shift + last_out) % n
    step = theta[1] - theta[0]

    def y_minus_soil(t: float) -> float:
        return float(tip_at(t)[1] - soil)

    t_exit = optimize.brentq(y_minus_soil, theta[k_exit] - step, theta[k_exit], xtol=ANGLE_ROOT_RAD)
    t_entry = optimize.brentq(y_minus_soil, theta[k_entry] - step, theta[k_entry], xtol=ANGLE_ROOT_RAD)
    if t_entry > t_low:
        t_entry -= 2 * math.pi
    if t_exit < t_low:
        t_exit += 2 * math.pi
    tt = np.linspace(t_entry, t_exit, 4001)
    ground_x = mech.state(tt).tip[:, 0] + direction * speed * tt / mech.carrier_speed
    hole = float(ground_x.max() - ground_x.min())

    # arm-arm clearance: arm I against every other arm, each a polyline O1 -> knee -> tip
    clearance = np.full(n, np.inf)
    needles = np.full(n, np.inf)
    for k in range(1, mech.planets):
        o = mech.state(theta, k)
        needles = np.minimum(needles, segment_distance(s.knee, s.tip, o.knee, o.tip))
        for a0, a1 in ((s.centre, s.knee), (s.knee, s.tip)):
            for b0, b1 in ((o.centre, o.knee), (o.knee, o.tip)):
                clearance = np.minimum(clearance, segment_distance(a0, a1, b0, b1))
    k_c = int(np.argmin(clearance)) if mech.planets > 1 else 0

    return TransplantingMetrics(
        trajectory_height=float(high[1] - low[1]),
        trajectory_width=float(tip[:, 0].max() - tip[:, 0].min()),
        picking_theta=math.degrees(t_pick),
        picking_point=(float(pick[0]), float(pick[1])),
        picking_box_distance=float(np.linalg.norm(pick - box)),
        picking_angle=pick_att,
        pushing_theta=math.degrees(t_low),
        pushing_point=(float(low[0]), float(low[1])),
        pushing_angle=push_att,
        angle_difference=diff,
        soil_level=soil,
        plant_spacing=float(plant_spacing),
        forward_speed=float(speed),
        travel_direction=direction,
        hole_width=hole,
        gearbox_clearance=float(-gearbox_radius - soil),
        needle_clearance=float(needles.min()) if mech.planets > 1 else math.inf,
        arm_clearance=float(clearance[k_c]) if mech.planets > 1 else math.inf,
        arm_clearance_theta=math.degrees(theta[k_c]),
    )
