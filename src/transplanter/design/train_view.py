"""The studio's view of a differential train (seed 004's kind): its tip in the frame and on the
ground with the seedling box and the soil, the arm's attitude over the cycle, the pitch curves,
every arm posed at every sample, and the twelve objectives at the design place
(:func:`transplanter.design.objectives.seed004_objectives`, the same call a search and a build
make). ``n`` samples of the carrier's turn (720 by default, a search's resolution).
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.design.agronomy import transplanting_metrics
from transplanter.design.objectives import Site, gearbox_radius, seed004_objectives
from transplanter.design.views import Curve, DesignView, Panel, Pose, rows_from_objectives, soil

__all__ = ["BOX_DRAWN_MM", "differential_train_view"]

#: the seedling box is drawn this far up its slope and this wide along its end face, mm (the
#: objectives judge the half-plane beyond the end face; the drawing shows where that is)
BOX_DRAWN_MM = (120.0, 160.0)


def _box(site: Site) -> Curve:
    up = np.array([math.cos(site.box_slope), math.sin(site.box_slope)])
    along = np.array([-up[1], up[0]])
    o = np.asarray(site.seedling_box, dtype=float)
    deep, wide = BOX_DRAWN_MM
    corners = [
        o - along * wide / 2,
        o + along * wide / 2,
        o + along * wide / 2 + up * deep,
        o - along * wide / 2 + up * deep,
    ]
    return Curve("seedling box", np.array(corners), closed=True, kind="obstacle")


def differential_train_view(train, site: Site, module: float, n: int = 720) -> DesignView:
    """The :class:`~transplanter.design.views.DesignView` of ``train`` cut at ``module`` (mm)
    working at ``site``: the objectives at the design place (no play; a search's ``later`` adds
    them under play)."""
    gb = gearbox_radius(train.pair.driver.max_radius().value, module)
    metrics = transplanting_metrics(train, site.seedling_box, site.plant_spacing, site.planting_depth, gb, n=n)
    objectives = seed004_objectives(train, site, module, metrics=metrics, n=n)
    arms = [train.cycle(n, k) for k in range(train.planets)]
    tip = arms[0].tip
    theta = arms[0].theta
    lo, hi = float(tip[:, 0].min()) - 60.0, float(tip[:, 0].max()) + 60.0
    frame = Panel(
        "tip in the frame",
        (
            _box(site),
            soil(metrics.soil_level, min(lo, -gb), max(hi, gb)),
            Curve("tip", tip, closed=True),
            Curve("knee", arms[0].knee, closed=True),
            Curve("gearbox", gb * np.stack([np.cos(theta), np.sin(theta)], axis=1), closed=True),
            Curve("picking, pushing", np.array([metrics.picking_point, metrics.pushing_point]), kind="mark"),
        ),
    )
    turns = np.linspace(0.0, 4 * math.pi, 2 * n + 1)
    two = train.state(turns).tip
    gx = two[:, 0] + metrics.travel_direction * metrics.forward_speed * turns / abs(train.carrier_speed)
    ground = Panel(
        f"tip on the ground, {metrics.forward_speed:.0f} mm/s",
        (
            soil(metrics.soil_level, float(gx.min()) - 20.0, float(gx.max()) + 20.0),
            Curve("tip", np.stack([gx, two[:, 1]], axis=1)),
        ),
    )
    deg = np.degrees(theta)
    attitude = Panel(
        "arm attitude over the cycle",
        (Curve("needle attitude", np.stack([deg, np.degrees(np.unwrap(arms[0].attitude))], axis=1)),),
        "carrier angle (deg)",
        "needle direction (deg)",
        equal=False,
    )
    pair = train.pair
    phi = 2 * math.pi * np.arange(n) / n
    pitch = Panel(
        f"pitch curves, a = {pair.centre_distance:.3f} mm",
        (
            Curve("ring", pair.driver.points(phi), closed=True),
            Curve("planet", pair.driven.points(phi) + [pair.centre_distance, 0.0], closed=True),
        ),
    )
    # every arm at every sample: carrier O -> planet centre -> knee -> tip, NaN between arms
    gap = np.full((n, 1, 2), np.nan)
    pieces = []
    for s in arms:
        pieces += [np.zeros((n, 1, 2)), s.centre[:, None], s.knee[:, None], s.tip[:, None], gap]
    pose = Pose(deg, np.concatenate(pieces, axis=1), panel=0)
    notes = (
        f"picking {metrics.picking_angle:.2f} deg at carrier {metrics.picking_theta:.1f} deg, "
        f"pushing {metrics.pushing_angle:.2f} deg at {metrics.pushing_theta:.1f} deg; "
        f"trajectory {metrics.trajectory_height:.1f} x {metrics.trajectory_width:.1f} mm",
    )
    return DesignView((frame, ground, attitude, pitch), rows_from_objectives(objectives), pose, notes)
