"""The studio's view of a four-bar planting arm (seed 000's kind): its tip in the frame with the
soil line, its tip on the ground at the machine's forward speed, the finger's attitude over the
crank angle, and the four-bar posed at every sample of the crank's turn.

The rows (the objectives and their limits) are the part script's: it states them from the arm's
:class:`~transplanter.design.linkage.planting.PlantingMetrics` (seed 000's Table 2, the same
call its ``ArmStudy`` makes) and hands them in with the metrics, so the marks drawn here are the
entry, exit and lowest points the rows judge.

Crank angles are the arm's reported ones (:meth:`PlantingArm.reported_angle`: from its
``angle_reference``, seed 000's frame axis X1), whichever way the crank turns; ``n`` samples of
the turn, uniform in that angle (so sample k is the studio's scrub angle ``360 k / n``).
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.errors import check_int
from transplanter.design.linkage.fourbar import Link
from transplanter.design.linkage.planting import PlantingArm, PlantingMetrics
from transplanter.design.views import Curve, DesignView, Panel, Pose, Row, soil

__all__ = ["planting_arm_view", "arm_pose"]

#: the soil is drawn this far beyond the tip's path either side, mm
SOIL_BEYOND_MM = 40.0


def arm_pose(arm: PlantingArm, n: int = 360) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(reported crank angles (n,) deg, the four-bar's lines (n, 13, 2) mm, the tip (n, 2) mm) at
    ``n`` crank angles uniform from the arm's angle reference: the frame O2-O4, the crank O2-B, the
    coupler with its finger B-C-tip-B and the rocker O4-C, NaN rows between the links."""
    check_int("n", n, 8, 100_000)
    deg = 360.0 * np.arange(n) / n
    motion = arm.linkage.solve(arm.angle_reference + np.radians(deg), arm.crank_speed)
    j = motion.joints()
    tip = motion.point(Link.COUPLER, arm.tip).position
    gap = np.full((n, 2), np.nan)
    pieces = [j["O2"], j["O4"], gap, j["O2"], j["B"], gap, j["B"], j["C"], tip, j["B"], gap, j["O4"], j["C"]]
    return deg, np.stack(pieces, axis=1), tip


def planting_arm_view(
    arm: PlantingArm, metrics: PlantingMetrics, rows: tuple[Row, ...], n: int = 360, notes: tuple[str, ...] = ()
) -> DesignView:
    """The :class:`~transplanter.design.views.DesignView` of ``arm`` whose metrics (at its
    planting depth) are ``metrics`` and objectives ``rows``: three panels (the tip in the frame
    with the soil and the entry, lowest and exit points; the tip on the ground over two crank
    turns at the arm's forward speed; the finger's attitude — crank pin to tip — over the crank
    angle) and the four-bar posed at ``n`` crank angles in the first."""
    deg, lines, tip = arm_pose(arm, n)
    marks = np.array([metrics.entry.position, metrics.lowest.position, metrics.exit.position])
    joints = lines[:, [0, 1, 4, 7], :].reshape(-1, 2)  # O2, O4, B, C: the soil spans the linkage too
    lo = min(float(tip[:, 0].min()), float(joints[:, 0].min())) - SOIL_BEYOND_MM
    hi = max(float(tip[:, 0].max()), float(joints[:, 0].max())) + SOIL_BEYOND_MM
    frame = Panel(
        "tip in the frame",
        (
            soil(metrics.soil_level, lo, hi),
            Curve("tip", tip, closed=True),
            Curve("entry, lowest, exit", marks, kind="mark"),
            Curve("pivots O2, O4", np.array([lines[0, 0], lines[0, 1]]), kind="mark"),
        ),
    )
    time = np.linspace(0.0, 2 * arm.period, 2 * n + 1)
    ground = arm.ground_path(time)
    on_ground = Panel(
        f"tip on the ground, {arm.forward_speed:.0f} mm/s",
        (
            soil(metrics.soil_level, float(ground[:, 0].min()) - 20.0, float(ground[:, 0].max()) + 20.0),
            Curve("tip", ground),
        ),
    )
    b = lines[:, 4, :]  # the crank pin B
    attitude = np.degrees(np.unwrap(np.arctan2(tip[:, 1] - b[:, 1], tip[:, 0] - b[:, 0])))
    chart = Panel(
        "finger attitude over the crank angle",
        (Curve("finger (crank pin to tip)", np.stack([deg, attitude], axis=1)),),
        "crank angle (deg)",
        "finger direction (deg)",
        equal=False,
    )
    turning = "counter-clockwise" if arm.crank_speed > 0 else "clockwise"
    notes = (
        f"{arm.name}: the crank turns {turning} at {abs(arm.crank_speed) * 30 / math.pi:.0f} r/min; crank angles "
        f"from {math.degrees(arm.angle_reference) % 360:.1f} deg (the arm's reference); entry "
        f"{math.degrees(metrics.entry.crank_angle):.1f}, lowest {math.degrees(metrics.lowest.crank_angle):.1f}, "
        f"exit {math.degrees(metrics.exit.crank_angle):.1f} deg",
        *notes,
    )
    pose = Pose(deg, lines, 0, "crank angle (deg)", 1 if arm.crank_speed > 0 else -1)  # played as it turns
    return DesignView((frame, on_ground, chart), rows, pose, notes)
