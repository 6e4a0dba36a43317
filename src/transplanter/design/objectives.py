"""Seed 004's twelve design objectives (its §"Parameter optimisation", i-xii), measured on a train.

The paper lists the objectives in words; where a word is not a number, the reading below makes
it one (each is tested, and the README repeats them):

i. **arms do not interfere**: each arm's needle (knee → tip) keeps ``ARM_CLEARANCE_MM`` from
   every other arm's needle over the cycle (10 mm: two needles 10 mm wide on their centre
   lines). The needles all work in the seedling box's plane; the arm bodies (planet centre →
   knee) cannot share it — drawn straight in one plane, even the published design's bodies
   cross the other arms' needles (``agronomy``'s straight-arm clearance is 0), so they sit in
   planes staggered along the planet shafts, and only the needles can meet;
ii. **arms clear the seedling box**: the box is the region beyond its end face, the line through
   ``(Yx, Yy)`` perpendicular to its slope ``Ya`` (seedlings slide down the slope to that face,
   where the needle takes one). The knee — and so the arm body, which lies behind it — stays
   ``BOX_CLEARANCE_MM`` outside the face; only the needle enters;
iii-v. **picking angle** (needle attitude at the picking point, ``agronomy``) 320-350°,
   **pushing angle** (at the lowest point) 270-310°, their **difference** 45-65°;
vi. **the seedling is taken**: the tip enters the box by a picking depth of ``PICK_DEPTH_MM``
   (10-25 mm: a block of mat seedlings is 10-17 mm wide), and the picking point is within
   ``PICK_SPREAD_MM`` of the box point;
vii. **the seedling is not bridged** (left lying across the hole): the needle enters the soil
   once per cycle and points down when it pushes (attitude within 180-360°);
viii. **the arm does not push the seedling down**: after leaving the soil the tip does not pass
   back over the plant (its absolute x at the push) while lower than ``SEEDLING_HEIGHT_MM``
   above the soil; value = how far it comes back over it, limit 0;
ix. **hole width** < 30 mm at the stated plant spacing (``agronomy.transplanting_metrics``);
x. **gearbox** >= 20 mm above the ground; the gearbox is a circle of :func:`gearbox_radius`:
   the ring's largest pitch radius, its dedendum (1.25 m), its rim (3 m, as ``teeth.generate``
   makes it) and the housing wall ``HOUSING_WALL_MM``;
xi. **module** > 2.5 mm (of the teeth that are cut);
xii. **the needle does not press the seedlings when picking**: it enters the box point first —
   the angle between the needle and the slope direction at entry is below 90°.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import check_number, finite_positive
from transplanter.design.agronomy import TransplantingMetrics, transplanting_metrics
from transplanter.geometry.proportions import RING_DEPTH

__all__ = [
    "Site",
    "Objective",
    "gearbox_radius",
    "seed004_objectives",
    "worst_of",
    "back_over_plant",
    "box_depth",
    "ARM_CLEARANCE_MM",
    "ANGLE_DIFFERENCE_DEG",
    "HOLE_WIDTH_MAX_MM",
    "GEARBOX_CLEARANCE_MM",
    "MIN_MODULE_MM",
]

ARM_CLEARANCE_MM = 10.0
BOX_CLEARANCE_MM = 5.0
PICK_DEPTH_MM = (10.0, 25.0)
PICK_SPREAD_MM = 15.0
SEEDLING_HEIGHT_MM = 100.0
ANGLE_DIFFERENCE_DEG = (45.0, 65.0)
HOLE_WIDTH_MAX_MM = 30.0
GEARBOX_CLEARANCE_MM = 20.0
MIN_MODULE_MM = 2.5
HOUSING_WALL_MM = 5.0
#: ring dedendum and rim below its pitch curve, modules (``proportions.RING_DEPTH``)
RING_DEPTH_MODULES = RING_DEPTH


@dataclass(frozen=True)
class Site:
    """Where the train works: seedling box end ``(Yx, Yy)`` mm and slope ``Ya`` rad, plant
    spacing and planting depth mm."""

    seedling_box: tuple[float, float]
    box_slope: float
    plant_spacing: float
    planting_depth: float

    def __post_init__(self) -> None:
        for i, v in enumerate(self.seedling_box):
            check_number(f"seedling_box[{i}]", v, -1e4, 1e4, unit="mm")
        check_number("box_slope (Ya)", self.box_slope, -2 * math.pi, 2 * math.pi, unit="rad")
        finite_positive("plant_spacing", self.plant_spacing)
        finite_positive("planting_depth", self.planting_depth)


@dataclass(frozen=True)
class Objective:
    """One objective: its number in seed 004, what it measures, the value and the limits."""

    number: str
    name: str
    value: float
    low: float
    high: float
    unit: str

    @property
    def ok(self) -> bool:
        return bool(self.low <= self.value <= self.high)

    @property
    def limit(self) -> str:
        if math.isinf(self.high):
            return f">= {self.low:g} {self.unit}".strip()
        if math.isinf(self.low):
            return f"<= {self.high:g} {self.unit}".strip()
        return f"{self.low:g}..{self.high:g} {self.unit}".strip()

    @property
    def verdict(self) -> str:
        """``value unit pass`` or ``... FAIL``, as the report shows it."""
        return " ".join(x for x in (f"{self.value:.4g}", self.unit, "pass" if self.ok else "FAIL") if x)

    @property
    def margin(self) -> float:
        """How far inside the limits, in the value's unit (negative: how far outside)."""
        return min(self.value - self.low, self.high - self.value)

    @property
    def shortfall(self) -> float:
        """How far outside the limits, in the value's unit (0 inside)."""
        return max(0.0, self.low - self.value, self.value - self.high)


def gearbox_radius(ring_max_radius: float, module: float) -> float:
    """Radius of the gearbox around the carrier axis, mm (objective x, see the module docstring)."""
    return ring_max_radius + RING_DEPTH_MODULES * module + HOUSING_WALL_MM


def back_over_plant(tip: np.ndarray, soil_level: float, velocity: float, period: float) -> float:
    """Objective viii: how far (mm) the tip goes back over the plant after leaving the soil, while
    lower than ``SEEDLING_HEIGHT_MM`` above it.

    ``tip`` (n, 2) mm: one cycle of the tip, frame coordinates, in time order (uniform samples
    over ``period`` s); ``velocity`` the machine's forward speed along x (mm/s, signed). The ground
    track is followed from the push (the lowest point) for one cycle, its time counted from the
    push — so a push late in the sampled cycle is judged as one early in it (the time of a cycle
    that wraps past its end is unwrapped, not set back by a period).

    The side the tip retreats to is where it is, on the ground, when it reaches the seedling's
    height (or at the end of the cycle if it never does); "back over the plant" is how far it
    comes to the other side of the plant before that. (Taking the side from the first sample out
    of the soil — right above the hole, a few tenths of a mm either side — made the figure jump
    between 0 and tens of mm for a 0.3 mm change of the carrier radius.)
    """
    n = len(tip)
    low = int(np.argmin(tip[:, 1]))
    path = np.roll(tip, -low, axis=0)  # from the push onwards
    ground_x = path[:, 0] + velocity * period * np.arange(n) / n
    below = path[:, 1] < soil_level
    if below.all():
        return 0.0
    after = np.arange(int(np.flatnonzero(~below)[0]), n)
    high = np.flatnonzero(path[after, 1] > soil_level + SEEDLING_HEIGHT_MM)
    rising = after[: int(high[0])] if len(high) else after
    if len(rising) == 0:
        return 0.0
    retreat = after[int(high[0])] if len(high) else after[-1]
    side = np.sign(ground_x[retreat] - ground_x[0]) or 1.0
    return float(np.max(np.maximum(0.0, -side * (ground_x[rising] - ground_x[0])), initial=0.0))


def box_depth(points: np.ndarray, site: Site) -> np.ndarray:
    """How far ``points`` (n, 2) mm lie beyond the seedling box's end face, up its slope, mm
    (negative: outside); the picking point is the tip's deepest."""
    up = np.array([math.cos(site.box_slope), math.sin(site.box_slope)])
    return (np.asarray(points, dtype=float) - np.asarray(site.seedling_box, dtype=float)) @ up


def seed004_objectives(
    train, site: Site, module: float, metrics: TransplantingMetrics | None = None, n: int = 1440
) -> tuple[Objective, ...]:
    """The twelve objectives of seed 004 for ``train`` cut at ``module`` (mm) at ``site``."""
    gb = gearbox_radius(train.pair.driver.max_radius().value, module)
    m = metrics or transplanting_metrics(train, site.seedling_box, site.plant_spacing, site.planting_depth, gb, n=n)
    s = train.cycle(n)
    up = np.array([math.cos(site.box_slope), math.sin(site.box_slope)])  # into the box
    depth = box_depth(s.tip, site)
    k = int(np.argmax(depth))
    inside = depth > 0
    entry = int(np.flatnonzero(inside & ~np.roll(inside, 1))[0]) if inside.any() and not inside.all() else k
    needle = s.tip[entry] - s.knee[entry]
    entry_angle = math.degrees(math.acos(float(np.clip(needle @ up / np.linalg.norm(needle), -1, 1))))
    # soil: entries per cycle, and the return over the plant
    below = s.tip[:, 1] < m.soil_level
    entries = int(np.count_nonzero(below & ~np.roll(below, 1)))
    period = 2 * math.pi / abs(train.carrier_speed)
    over = back_over_plant(s.tip, m.soil_level, m.travel_direction * m.forward_speed, period)
    push_down = 1.0 if 180.0 <= m.pushing_angle <= 360.0 and entries == 1 else 0.0
    inf = math.inf
    return (
        Objective("i", "needle-needle clearance", m.needle_clearance, ARM_CLEARANCE_MM, inf, "mm"),
        Objective(
            "ii", "knee outside the seedling box", float(-np.max(box_depth(s.knee, site))), BOX_CLEARANCE_MM, inf, "mm"
        ),
        Objective("iii", "picking angle", m.picking_angle, 320.0, 350.0, "deg"),
        Objective("iv", "pushing angle", m.pushing_angle, 270.0, 310.0, "deg"),
        Objective("v", "angle difference", m.angle_difference, *ANGLE_DIFFERENCE_DEG, "deg"),
        Objective("vi", "picking depth into the box", float(depth[k]), *PICK_DEPTH_MM, "mm"),
        Objective("vi", "picking point to the box point", m.picking_box_distance, -inf, PICK_SPREAD_MM, "mm"),
        Objective("vii", "one soil entry, needle down at the push (1 = yes)", push_down, 1.0, 1.0, ""),
        Objective("viii", "tip back over the plant after leaving the soil", over, -inf, 0.0, "mm"),
        Objective("ix", "hole width", m.hole_width, -inf, HOLE_WIDTH_MAX_MM, "mm"),
        Objective("x", "gearbox clearance above the ground", m.gearbox_clearance, GEARBOX_CLEARANCE_MM, inf, "mm"),
        Objective("xi", "module", module, MIN_MODULE_MM, inf, "mm"),
        Objective("xii", "needle to box slope at entry", entry_angle, -inf, 90.0, "deg"),
    )


def worst_of(*measured: tuple[Objective, ...]) -> tuple[Objective, ...]:
    """Each objective at its least margin over several measurements of one design (e.g. with the
    planets at either end of their play); the first such on a tie."""
    return tuple(min(group, key=lambda o: o.margin) for group in zip(*measured, strict=True))
