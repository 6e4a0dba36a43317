"""Plots a designer looks at: coupler curves, speed/acceleration diagrams, shaking force, a
planetary train's trajectory, a synthesis, a cam, a design front — and, from
:mod:`~transplanter.report.gear_plots`, a gear pair's pitch curves, teeth and meshing.

Figures are rendered with matplotlib's Agg backend to PNG or SVG bytes, with the metadata
that would change between runs (date, software version, SVG ids) fixed, so the same input
gives the same bytes (:mod:`~transplanter.report.figure`). Every figure is drawn to be read where
the report page shows it: :data:`~transplanter.report.figure.WIDTH_IN` wide, no text under
:data:`~transplanter.report.figure.FONT_PT` (10 CSS px or more at the width the page gives it).
"""

from __future__ import annotations

import math
import textwrap

import numpy as np

from transplanter.design.linkage.planting import PlantingArm, PlantingMetrics
from transplanter.design.objectives import MIN_MODULE_MM
from transplanter.report.figure import (
    DPI,
    FONT_PT,
    MIN_TEXT_PX,
    SHOWN_PX,
    WIDTH_IN,
    figure_files,
    legend_below,
    plan_view,
    plt,
    size,
    styled,
)
from transplanter.report.gear_plots import intermittent_figure, meshing_figure, pitch_pair_figure, toothed_pair_figure

__all__ = [
    "DPI",
    "FONT_PT",
    "MIN_TEXT_PX",
    "SHOWN_PX",
    "WIDTH_IN",
    "figure_files",
    "coupler_curve_figure",
    "kinematics_figure",
    "shaking_figure",
    "pitch_pair_figure",
    "planetary_trajectory_figure",
    "toothed_pair_figure",
    "synthesis_figure",
    "cam_figure",
    "meshing_figure",
    "follower_figure",
    "front_figure",
    "intermittent_figure",
]


@styled
def coupler_curve_figure(arm: PlantingArm, metrics: PlantingMetrics | None = None, cycles: int = 3) -> plt.Figure:
    """Tip path relative to the frame (left) and to the ground over ``cycles`` turns (right), cm."""
    cyc = arm.cycle(720)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=size(3.9), gridspec_kw={"width_ratios": [1, 2]})
    p = cyc.frame.position / 10
    ax1.plot(p[:, 0], p[:, 1], "C0-", lw=1.5)
    ax1.plot(arm.linkage.origin[0] / 10, arm.linkage.origin[1] / 10, "k^", label="crank pivot")
    ax1.plot(arm.linkage.rocker_pivot[0] / 10, arm.linkage.rocker_pivot[1] / 10, "ks", label="rocker pivot")
    time = np.linspace(0.0, cycles * arm.period, cycles * 720 + 1)
    g = arm.ground_path(time) / 10
    ax2.plot(g[:, 0], g[:, 1], "C1-", lw=1.2)
    if metrics is not None:
        for ax in (ax1, ax2):
            ax.axhline(metrics.soil_level / 10, color="saddlebrown", ls="--", lw=1, label="soil surface")
    plan_view(ax1, "to the frame", "cm")
    plan_view(ax2, f"to the ground, v = {arm.forward_speed / 1000:g} m/s", "cm")
    fig.suptitle(f"{arm.name}: tip path")
    legend_below(fig, ax1)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    return fig


@styled
def kinematics_figure(arm: PlantingArm, metrics: PlantingMetrics | None = None) -> plt.Figure:
    """Tip speed and acceleration (and components) over the crank angle, frame-relative."""
    t = np.linspace(0.0, 2 * math.pi, 721)
    theta2 = arm.angle_reference + t
    pm = arm.tip_motion(theta2)
    deg = np.degrees(t)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=size(5.6), sharex=True)
    ax1.plot(deg, pm.speed / 1000, "k-", label="|v|")
    ax1.plot(deg, pm.velocity[:, 0] / 1000, "C0--", label="v_x")
    ax1.plot(deg, pm.velocity[:, 1] / 1000, "C1--", label="v_y")
    ax2.plot(deg, pm.acceleration_magnitude / 1000, "k-", label="|a|")
    ax2.plot(deg, pm.acceleration[:, 0] / 1000, "C0--", label="a_x")
    ax2.plot(deg, pm.acceleration[:, 1] / 1000, "C1--", label="a_y")
    if metrics is not None:
        for st, name in ((metrics.entry, "entry"), (metrics.exit, "exit"), (metrics.lowest, "lowest")):
            for ax in (ax1, ax2):
                ax.axvline(math.degrees(st.crank_angle), color="0.6", lw=0.8)
            ax1.annotate(
                name, (math.degrees(st.crank_angle), 1.0), xycoords=("data", "axes fraction"), ha="center", va="bottom"
            )
    ax1.set_ylabel("velocity (m/s)")
    ax2.set_ylabel("acceleration (m/s²)")
    ax2.set_xlabel("crank angle from the reference axis (deg)")
    fig.suptitle(f"{arm.name}: tip velocity and acceleration relative to the frame")
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax2.set_xlim(0, 360)
    ax2.set_xticks(range(0, 361, 45))
    fig.tight_layout()
    return fig


@styled
def shaking_figure(angle_deg: np.ndarray, force: np.ndarray, torque: np.ndarray, title: str) -> plt.Figure:
    """Shaking force components (N) and crank torque (N m) over the crank angle."""
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=size(4.8), sharex=True)
    ax1.plot(angle_deg, force[:, 0], "C0-", label="F_x")
    ax1.plot(angle_deg, force[:, 1], "C1-", label="F_y")
    ax2.plot(angle_deg, torque, "k-", label="crank")
    ax1.set_ylabel("force on frame (N)")
    ax2.set_ylabel("crank torque (N m)")
    ax2.set_xlabel("crank angle from the ground link (deg)")
    fig.suptitle(title)
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    return fig


@styled
def planetary_trajectory_figure(train, metrics, title: str, seedling_box=None, cycles: int = 2) -> plt.Figure:
    """Static trajectory with all arms at the start (left) and the absolute trajectory (right)."""
    n = 1440
    cyc = train.cycle(n)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=size(4.4), gridspec_kw={"width_ratios": [1, 1.4]})
    ax1.plot(cyc.tip[:, 0], cyc.tip[:, 1], "C0-", lw=1.4, label="tip trajectory")
    for k in range(train.planets):
        s = train.state(np.array([0.0]), k)
        xs = [s.centre[0, 0], s.knee[0, 0], s.tip[0, 0]]
        ys = [s.centre[0, 1], s.knee[0, 1], s.tip[0, 1]]
        ax1.plot(xs, ys, "-o", color=f"C{k + 2}", ms=3, lw=1.2, label=f"arm {k + 1} at start")
    ax1.add_patch(plt.Circle((0, 0), train.pair.centre_distance, fill=False, ls=":", color="0.5"))
    ax1.plot(*metrics.picking_point, "g^", label=f"picking {metrics.picking_angle:.1f}°")
    ax1.plot(*metrics.pushing_point, "rv", label=f"pushing {metrics.pushing_angle:.1f}°")
    if seedling_box is not None:
        ax1.plot(*seedling_box, "ks", label="seedling box")
    ax1.axhline(metrics.soil_level, color="saddlebrown", ls="--", lw=1, label="soil surface")
    theta = np.linspace(0.0, 2 * math.pi * cycles, n * cycles + 1)
    tip = train.state(theta).tip
    gx = tip[:, 0] + metrics.travel_direction * metrics.forward_speed * theta / train.carrier_speed
    ax2.plot(gx, tip[:, 1], "C1-", lw=1.2)
    ax2.axhline(metrics.soil_level, color="saddlebrown", ls="--", lw=1)
    plan_view(ax1, "to the frame")
    plan_view(ax2, f"to the ground, spacing {metrics.plant_spacing:g} mm")
    fig.suptitle(f"{title}: tip trajectory")
    legend_below(fig, ax1, ncol=4)
    fig.tight_layout(rect=(0, 0.15, 1, 1))
    return fig


@styled
def synthesis_figure(chain, sample, feasible, title: str) -> plt.Figure:
    """Circle- and centre-point curves with the feasible part (left); the mechanism's paths (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=size(4.2))
    # the curves as dots, rasterised: tens of thousands of markers would be as many SVG elements
    dots = {"ls": "none", "marker": ".", "rasterized": True}
    ax1.plot(sample.circle[:, 0], sample.circle[:, 1], color="C0", ms=1, **dots)
    ax1.plot(sample.centre[:, 0], sample.centre[:, 1], color="C1", ms=1, **dots)
    ax1.plot(sample.circle[feasible, 0], sample.circle[feasible, 1], color="C2", ms=1.5, **dots)
    ax1.plot(sample.centre[feasible, 0], sample.centre[feasible, 1], color="C3", ms=1.5, **dots)
    for colour, name in (("C0", "circle points"), ("C1", "centre points"), ("C2", "feasible")):
        ax1.plot([], [], "o", color=colour, ms=4, label=name)  # the legend's dots, visible
    ax1.plot(*chain.circle, "k^", label="chosen circle point")
    ax1.plot(*chain.centre, "ks", label="its centre point")
    ax1.set_xlim(-150, 150)
    ax1.set_ylim(-150, 150)
    tau = np.linspace(0.0, 2 * math.pi, 1441)
    st = chain.state(tau)
    ax2.plot(st.tip[:, 0], st.tip[:, 1], "C0-", label="arm tip")
    ax2.plot(st.q[:, 0], st.q[:, 1], "C1-", lw=0.8, label="hinge Q")
    ps = chain.state(chain.pose_tau)
    for k in range(4):
        ax2.plot(
            [chain.centre[0], ps.circle[k, 0], ps.q[k, 0], ps.tip[k, 0]],
            [chain.centre[1], ps.circle[k, 1], ps.q[k, 1], ps.tip[k, 1]],
            "-o",
            ms=3,
            lw=0.8,
            color=f"C{k + 2}",
        )
        ax2.annotate(str(k + 1), ps.q[k])
    plan_view(ax1, "Burmester curves")
    plan_view(ax2, "3R chain through the four poses")
    fig.suptitle(f"{title}: open-chain synthesis")
    handles, labels = ax1.get_legend_handles_labels()
    more = ax2.get_legend_handles_labels()
    fig.legend([*handles, *more[0]], [*labels, *more[1]], loc="lower center", ncol=4, frameon=False)
    fig.tight_layout(rect=(0, 0.14, 1, 1))
    return fig


@styled
def cam_figure(cam, title: str) -> plt.Figure:
    """Cam profile and pitch curve (left); pressure angle and follower motion over a turn (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=size(3.6))
    p = np.vstack([cam.profile, cam.profile[:1]])
    ax1.plot(p[:, 0], p[:, 1], "k-", lw=1.2, label="working profile")
    if cam.pitch is not None:
        q = np.vstack([cam.pitch, cam.pitch[:1]])
        ax1.plot(q[:, 0], q[:, 1], "C0--", lw=0.8, label="pitch curve")
    ax1.plot(0, 0, "k+")
    plan_view(ax1, "profile (cam frame)")
    deg = np.degrees(cam.theta)
    ax2.plot(deg, np.degrees(cam.pressure_angle), "C3-", label="pressure angle")
    ax3 = ax2.twinx()
    ax3.plot(deg, np.degrees(cam.follower_position(cam.theta)), "C0-", lw=0.8, label="follower swing")
    ax2.set_xlabel("cam angle (deg)")
    ax2.set_ylabel("pressure angle (deg)", color="C3")
    ax3.set_ylabel("follower swing (deg)", color="C0")
    ax2.set_xlim(0, 360)
    ax2.set_xticks(range(0, 361, 90))
    ax2.grid(True, lw=0.3)
    ax2.set_title(f"max pressure angle {math.degrees(cam.max_pressure_angle):.2f} deg")
    fig.suptitle(f"{title}: cam")
    legend_below(fig, ax1, ncol=2)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return fig


@styled
def follower_figure(reports: dict, title: str) -> plt.Figure:
    """Follower error on the made cam contour over the cam's turn, per checked source."""
    fig, ax = plt.subplots(figsize=size(2.8))
    for i, (source, r) in enumerate(sorted(reports.items())):
        ax.plot(np.degrees(r.theta), 1000 * r.error, f"C{i}-", lw=0.8, label=source)
    ax.set_xlim(0, 360)
    ax.set_xticks(range(0, 361, 45))
    ax.set_xlabel("cam angle (deg)")
    ax.set_ylabel("error at the roller (µm)")
    ax.set_title(f"{title}: follower on the made contour\nminus the prescribed law")
    ax.grid(True, lw=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    return fig


@styled
def front_figure(rows: list[dict], title: str, binding: str) -> plt.Figure:
    """The Pareto front of a design problem: module against the smallest objective margin
    (``rows``: dicts with ``module_mm``, ``smallest_margin``, ``binding_objective``, ``label``,
    ``chosen``, ``feasible``, ``pareto``); the non-dominated designs joined, designs that miss an
    objective crossed, the design made starred; each design numbered, its label and binding
    objective listed under the plot."""
    notes = [f"{k + 1}: {r['label']} — binds {r['binding_objective']}" for k, r in enumerate(rows)]
    lines = [*notes, *textwrap.wrap(binding, 92)]
    fig, ax = plt.subplots(figsize=size(4.2 + 0.17 * len(lines)))
    margin = np.array([r["smallest_margin"] for r in rows], dtype=float)
    module = np.array([r["module_mm"] for r in rows], dtype=float)
    best = np.array([r["pareto"] for r in rows], dtype=bool)
    chosen = np.array([r["chosen"] for r in rows], dtype=bool)
    feasible = np.array([r["feasible"] for r in rows], dtype=bool)
    rest = ~best & feasible
    if rest.any():
        ax.plot(margin[rest], module[rest], "o", color="0.6", ms=5, label="dominated")
    missed = ~feasible
    if missed.any():
        ax.plot(margin[missed], module[missed], "x", color="C3", ms=7, label="misses an objective or a gear rule")
    order = np.argsort(margin[best])
    ax.plot(margin[best][order], module[best][order], "o-", color="C0", ms=6, lw=1.2, label="Pareto front")
    for k, (x, y) in enumerate(zip(margin, module, strict=True)):
        ax.annotate(str(k + 1), (x, y), xytext=(5, 3), textcoords="offset points")
    if chosen.any():
        ax.plot(margin[chosen], module[chosen], "r*", ms=15, label="the design made")
    ax.axvline(0.0, color="C3", ls="--", lw=1, label="every margin kept under play")
    ax.axhline(MIN_MODULE_MM, color="C2", ls=":", lw=1, label=f"objective xi, m ≥ {MIN_MODULE_MM:g} mm")
    ax.set_xlabel("smallest objective margin beyond what it must keep (mm or deg)")
    ax.set_ylabel("module of the teeth (mm)")
    ax.grid(alpha=0.3)
    ax.legend(loc="best")
    ax.set_title(f"{title}: module against the smallest margin")
    fig.text(0.01, 0.01, "\n".join(lines), va="bottom")
    fig.tight_layout(rect=(0, (0.17 * len(lines) + 0.15) / (4.2 + 0.17 * len(lines)), 1, 1))
    return fig
