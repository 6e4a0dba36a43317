"""Plots a designer looks at: coupler curves, speed/acceleration diagrams, shaking force.

Figures are rendered with matplotlib's Agg backend to PNG or SVG bytes, with the metadata
that would change between runs (date, software version, SVG ids) fixed, so the same input
gives the same bytes.
"""

from __future__ import annotations

import functools
import io
import math
import textwrap

import numpy as np
import shapely

from transplanter.linkage.planting import PlantingArm, PlantingMetrics
from transplanter.objectives import MIN_MODULE_MM


@functools.cache
def _matplotlib():
    """matplotlib with its Agg backend, and pyplot, imported on first use: a command that draws
    nothing (a rebuild with nothing changed, ``check``) does not pay its 0.26 s."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot

    return matplotlib, matplotlib.pyplot


class _Pyplot:
    """``plt``: matplotlib.pyplot, imported when a figure is first made."""

    def __getattr__(self, name):
        return getattr(_matplotlib()[1], name)


plt = _Pyplot()

__all__ = [
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
]

_METADATA = {
    "png": {"Software": None},
    "svg": {"Date": None, "Creator": None},
}


def _render(fig: plt.Figure, fmt: str) -> bytes:
    if fmt not in _METADATA:
        raise ValueError(f"fmt must be 'png' or 'svg', got {fmt!r}")
    buf = io.BytesIO()
    with _matplotlib()[0].rc_context({"svg.hashsalt": "transplanter", "svg.fonttype": "none"}):
        # zlib level 1: a fraction of the encoding time of the default 6 for line plots, files ~7 % larger
        extra = {"pil_kwargs": {"compress_level": 1}} if fmt == "png" else {}
        fig.savefig(buf, format=fmt, dpi=110, metadata=_METADATA[fmt], **extra)
    return buf.getvalue()


def figure_files(fig: plt.Figure, stem: str) -> dict[str, bytes]:
    """``{stem.png: ..., stem.svg: ...}`` from one figure (built once, saved twice), then closed."""
    # the figures are laid out once, by tight_layout, which leaves a placeholder layout engine
    # behind; without this, every savefig would draw the figure twice (once "to lay it out")
    fig.set_layout_engine(None)
    try:
        return {f"{stem}.{fmt}": _render(fig, fmt) for fmt in ("png", "svg")}
    finally:
        plt.close(fig)


def _plan_view(ax, title: str | None = None, unit: str = "mm") -> None:
    """Equal-aspect x-y axes with a light grid, labelled in ``unit``."""
    ax.set_aspect("equal")
    ax.grid(True, lw=0.3)
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    if title is not None:
        ax.set_title(title, fontsize=9)


def coupler_curve_figure(arm: PlantingArm, metrics: PlantingMetrics | None = None, cycles: int = 3) -> plt.Figure:
    """Tip path relative to the frame (left) and to the ground over ``cycles`` turns (right), cm."""
    cyc = arm.cycle(720)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 5), gridspec_kw={"width_ratios": [1, 2]})
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
    for ax, title in (
        (ax1, "relative to the frame"),
        (ax2, f"relative to the ground, v = {arm.forward_speed / 1000:g} m/s"),
    ):
        _plan_view(ax, f"{arm.name}: tip path {title}", "cm")
    ax1.legend(fontsize=7, loc="best")
    fig.tight_layout()
    return fig


def kinematics_figure(arm: PlantingArm, metrics: PlantingMetrics | None = None) -> plt.Figure:
    """Tip speed and acceleration (and components) over the crank angle, frame-relative."""
    t = np.linspace(0.0, 2 * math.pi, 721)
    theta2 = arm.angle_reference + t
    pm = arm.tip_motion(theta2)
    deg = np.degrees(t)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
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
            ax1.annotate(name, (math.degrees(st.crank_angle), ax1.get_ylim()[1]), fontsize=7, ha="center", va="top")
    ax1.set_ylabel("velocity (m/s)")
    ax2.set_ylabel("acceleration (m/s²)")
    ax2.set_xlabel("crank angle from the reference axis (deg)")
    ax1.set_title(f"{arm.name}: tip velocity and acceleration relative to the frame", fontsize=9)
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7, loc="upper right")
    ax2.set_xlim(0, 360)
    ax2.set_xticks(range(0, 361, 45))
    fig.tight_layout()
    return fig


def shaking_figure(angle_deg: np.ndarray, force: np.ndarray, torque: np.ndarray, title: str) -> plt.Figure:
    """Shaking force components (N) and crank torque (N m) over the crank angle."""
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    ax1.plot(angle_deg, force[:, 0], "C0-", label="F_x")
    ax1.plot(angle_deg, force[:, 1], "C1-", label="F_y")
    ax2.plot(angle_deg, torque, "k-", label="crank torque")
    ax1.set_ylabel("shaking force on frame (N)")
    ax2.set_ylabel("torque (N m)")
    ax2.set_xlabel("crank angle from the ground link (deg)")
    ax1.set_title(title, fontsize=9)
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    return fig


def pitch_pair_figure(pair, title: str) -> plt.Figure:
    """Both pitch curves in mesh at the start (left) and their ratio and curvature (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5))
    phi = np.linspace(0.0, 2 * math.pi, 2001)
    p1 = pair.driver.points(phi)
    a = pair.centre_distance
    p2 = pair.driven.points(phi)
    if pair.mesh.value == "external":  # driven body frame is turned by π at the start
        p2 = np.stack([a - p2[:, 0], -p2[:, 1]], axis=1)
    else:
        p2 = p2 + [a, 0.0]
    ax1.plot(p1[:, 0], p1[:, 1], "C0-", label=f"driver ({pair.driver.lobes} lobes)")
    ax1.plot(p2[:, 0], p2[:, 1], "C1-", label=f"driven ({pair.driven.lobes} lobes)")
    ax1.plot([0, a], [0, 0], "k+", ms=10)
    _plan_view(ax1, f"{title}: pitch curves, a = {a:.4f} mm")
    ax1.legend(fontsize=7)
    deg = np.degrees(phi)
    ax2.plot(deg, pair.ratio(phi), "k-", label="ratio ω2/ω1")
    ax2.set_xlabel("driver angle (deg)")
    ax2.set_ylabel("ratio")
    ax2.grid(True, lw=0.3)
    ax3 = ax2.twinx()
    ax3.plot(deg, np.degrees(pair.driver.pressure_deviation(phi)), "C0--", lw=0.8, label="driver ν")
    ax3.set_ylabel("pitch-curve pressure deviation ν (deg)")
    ax2.set_xlim(0, 360)
    ax2.set_xticks(range(0, 361, 45))
    ax2.legend(fontsize=7, loc="upper left")
    ax3.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    return fig


def planetary_trajectory_figure(train, metrics, title: str, seedling_box=None, cycles: int = 2) -> plt.Figure:
    """Static trajectory with all arms at the start (left) and the absolute trajectory (right)."""
    n = 1440
    cyc = train.cycle(n)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5.5), gridspec_kw={"width_ratios": [1, 1.4]})
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
    for ax, sub in (
        (ax1, "relative to the frame"),
        (ax2, f"relative to the ground, spacing {metrics.plant_spacing:g} mm"),
    ):
        _plan_view(ax, f"{title}: {sub}")
    ax1.legend(fontsize=6, loc="best")
    fig.tight_layout()
    return fig


def toothed_pair_figure(
    driver_polygon, driven_polygon, centre_distance: float, external: bool, contact_x: float, title: str
):
    """The two generated gears in their start position (left) and a zoom on the start contact (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5.5))

    def rings(poly, place, box):
        # clipped to the panel and thinned to a tenth of a pixel: outlines of 5-90 k vertices
        # draw no differently
        tol = (box[2] - box[0]) / 6000
        for ring in (poly.exterior, *poly.interiors):
            for piece in getattr(clipped := shapely.clip_by_rect(ring, *box), "geoms", [clipped]):
                if not piece.is_empty:
                    yield place(np.asarray(shapely.simplify(piece, tol).coords))

    def driven_place(xy):
        if external:  # the driven body frame is turned by π at the start
            return np.stack([centre_distance - xy[:, 0], -xy[:, 1]], axis=1)
        return xy + [centre_distance, 0.0]

    span = 0.06 * abs(contact_x) + 3.0
    x0 = contact_x
    zoom = (x0 - 1.5 * span, -1.5 * span, x0 + 1.5 * span, 1.5 * span)
    # the zoom box in the driven gear's body frame (the inverse of driven_place)
    corners = np.array([[zoom[0], zoom[1]], [zoom[2], zoom[3]]])
    back = (
        np.stack([centre_distance - corners[:, 0], -corners[:, 1]], axis=1)
        if external
        else corners - [centre_distance, 0.0]
    )
    for ax, box1, box2 in (
        (ax1, driver_polygon.bounds, driven_polygon.bounds),
        (ax2, zoom, (*back.min(axis=0), *back.max(axis=0))),
    ):
        for xy in rings(driver_polygon, lambda v: v, box1):
            ax.plot(xy[:, 0], xy[:, 1], "C0-", lw=0.6)
        for xy in rings(driven_polygon, driven_place, box2):
            ax.plot(xy[:, 0], xy[:, 1], "C1-", lw=0.6)
        _plan_view(ax)
    ax2.set_xlim(x0 - span, x0 + span)
    ax2.set_ylim(-span, span)
    ax1.set_title(f"{title}: generated gears at the start", fontsize=9)
    ax2.set_title("start contact", fontsize=9)
    fig.tight_layout()
    return fig


def synthesis_figure(chain, sample, feasible, title: str) -> plt.Figure:
    """Circle- and centre-point curves with the feasible part (left); the mechanism's paths (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5.5))
    # the curves as dots, rasterised: tens of thousands of markers would be as many SVG elements
    dots = {"ls": "none", "marker": ".", "rasterized": True}
    ax1.plot(sample.circle[:, 0], sample.circle[:, 1], color="C0", ms=1, label="circle points", **dots)
    ax1.plot(sample.centre[:, 0], sample.centre[:, 1], color="C1", ms=1, label="centre points", **dots)
    ax1.plot(sample.circle[feasible, 0], sample.circle[feasible, 1], color="C2", ms=1.5, label="feasible", **dots)
    ax1.plot(sample.centre[feasible, 0], sample.centre[feasible, 1], color="C3", ms=1.5, **dots)
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
        ax2.annotate(str(k + 1), ps.q[k], fontsize=8)
    for ax, sub in ((ax1, "Burmester curves"), (ax2, "open-chain 3R mechanism through the four poses")):
        _plan_view(ax, f"{title}: {sub}")
        ax.legend(fontsize=6, loc="best")
    fig.tight_layout()
    return fig


def cam_figure(cam, title: str) -> plt.Figure:
    """Cam profile and pitch curve (left); pressure angle and follower motion over a turn (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5))
    p = np.vstack([cam.profile, cam.profile[:1]])
    ax1.plot(p[:, 0], p[:, 1], "k-", lw=1.2, label="working profile")
    if cam.pitch is not None:
        q = np.vstack([cam.pitch, cam.pitch[:1]])
        ax1.plot(q[:, 0], q[:, 1], "C0--", lw=0.8, label="pitch curve")
    ax1.plot(0, 0, "k+")
    ax1.set_aspect("equal")
    ax1.grid(True, lw=0.3)
    ax1.legend(fontsize=7)
    ax1.set_title(f"{title}: profile (cam frame)", fontsize=9)
    deg = np.degrees(cam.theta)
    ax2.plot(deg, np.degrees(cam.pressure_angle), "C3-", label="pressure angle (deg)")
    ax3 = ax2.twinx()
    ax3.plot(deg, np.degrees(cam.follower_position(cam.theta)), "C0-", lw=0.8, label="follower swing (deg)")
    ax2.set_xlabel("cam angle (deg)")
    ax2.set_ylabel("pressure angle (deg)")
    ax3.set_ylabel("follower swing (deg)")
    ax2.set_xlim(0, 360)
    ax2.set_xticks(range(0, 361, 45))
    ax2.grid(True, lw=0.3)
    ax2.set_title(f"max pressure angle {math.degrees(cam.max_pressure_angle):.2f} deg", fontsize=9)
    fig.tight_layout()
    return fig


def meshing_figure(
    reports: dict, title: str, train=None, train_note: str = "", band=None, clearance=None
) -> plt.Figure:
    """Penetration (with the fouling share), transmission error, backlash and mid-play clearance
    over the driver's turn for each checked source of a gear pair (``{"outline": MeshReport,
    "dxf": ..., ...}``) — backlash and clearance at the uniform and the refined samples — the
    backlash against the design ``band`` (mm: tolerance budget .. target's upper end), the
    clearance against the ``clearance`` it must keep (mm), and the needle-tip deviation of a train
    rebuilt from the parts if ``train`` (a TrainReport) is given."""
    rows = 5 if train is not None else 4
    fig, axes = plt.subplots(rows, 1, figsize=(10, 2.4 * rows + 0.6), sharex=False)
    ax1, ax2, ax3, ax5 = axes[0], axes[1], axes[2], axes[3]
    for i, (source, r) in enumerate(sorted(reports.items())):
        deg = np.degrees(r.driver_angle)
        ax1.plot(deg, r.penetration, f"C{i}-", lw=0.9, label=f"{source}: overlap")
        if r.max_fouling > 0:
            ax1.plot(deg, r.fouling, f"C{i}:", lw=0.9, label=f"{source}: fouling (away from pitch point)")
        ax2.plot(deg, 1000 * r.transmission_error, f"C{i}-", lw=0.8, label=source)
        angle, values = r.samples("backlash")
        lo = r.backlash_min
        ax3.plot(np.degrees(angle), 1000 * values, f"C{i}-", lw=0.8, label=f"{source} (min {1000 * lo.value:.1f})")
        ax3.plot([lo.at_deg], [1000 * lo.value], f"C{i}v", ms=5)
        if r.clearance is not None:
            angle, values = r.samples("clearance")
            c = r.clearance_min
            ax5.plot(np.degrees(angle), 1000 * values, f"C{i}-", lw=0.8, label=f"{source} (min {1000 * c.value:.1f})")
            ax5.plot([c.at_deg], [1000 * c.value], f"C{i}v", ms=5)
    if band is not None:
        ax3.axhspan(1000 * band[0], 1000 * band[1], color="0.85", zorder=0, label="design band")
        ax3.axhline(1000 * band[0], color="C3", lw=0.8, ls="--", label="tolerance budget")
    if clearance is not None:
        ax5.axhline(1000 * clearance, color="C3", lw=0.8, ls="--", label="required (half the budget)")
    ax5.set_ylabel("clearance (µm)")
    ax5.set_title(
        "smallest distance between the outlines, driven gear at mid-play (every gap; refined between samples)",
        fontsize=9,
    )
    ax1.set_ylabel("overlap (mm²)")
    ax1.set_title(f"{title}: penetration over the driver's turn", fontsize=9)
    ax2.set_ylabel("transmission error (µm)")
    ax2.set_title("geometric transmission error at the driven pitch point (driving flanks)", fontsize=9)
    ax3.set_ylabel("backlash (µm)")
    ax3.set_title(
        "circumferential backlash (free play) at the driven pitch point against the design band; v: its minimum",
        fontsize=9,
    )
    for ax in (ax1, ax2, ax3, ax5):
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 45))
        ax.set_xlabel("driver angle (deg)")
        ax.grid(True, lw=0.3)
        if ax.get_legend_handles_labels()[0]:  # nothing to name when no source could be read
            ax.legend(fontsize=7, loc="upper right")
    if train is not None:
        ax4 = axes[4]
        ax4.plot(np.degrees(train.theta), 1000 * train.deviation, "C3.", ms=2)
        ax4.set_xlabel("carrier angle (deg)")
        ax4.set_ylabel("tip deviation (µm)")
        ax4.set_title(
            f"needle tip of the train rebuilt from the parts vs the designed trajectory{train_note}", fontsize=9
        )
        ax4.grid(True, lw=0.3)
    fig.tight_layout()
    return fig


def follower_figure(reports: dict, title: str) -> plt.Figure:
    """Follower error on the made cam contour over the cam's turn, per checked source."""
    fig, ax = plt.subplots(figsize=(10, 3.2))
    for i, (source, r) in enumerate(sorted(reports.items())):
        ax.plot(np.degrees(r.theta), 1000 * r.error, f"C{i}-", lw=0.8, label=source)
    ax.set_xlim(0, 360)
    ax.set_xticks(range(0, 361, 45))
    ax.set_xlabel("cam angle (deg)")
    ax.set_ylabel("error at the roller (µm)")
    ax.set_title(f"{title}: follower on the made contour minus the prescribed law", fontsize=9)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def front_figure(rows: list[dict], title: str, binding: str) -> plt.Figure:
    """The Pareto front of a design problem: module against the smallest objective margin
    (``rows``: dicts with ``module_mm``, ``smallest_margin``, ``binding_objective``, ``label``,
    ``chosen``, ``feasible``, ``pareto``); the non-dominated designs joined, designs that miss an
    objective crossed, the design made starred."""
    fig, ax = plt.subplots(figsize=(8.5, 5.0))
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
        ax.plot(
            margin[missed], module[missed], "x", color="C3", ms=7, label="best found misses an objective or a gear rule"
        )
    order = np.argsort(margin[best])
    ax.plot(margin[best][order], module[best][order], "o-", color="C0", ms=6, lw=1.2, label="Pareto front")
    for r, x, y in zip(rows, margin, module, strict=True):
        ax.annotate(
            f"{r['label']}\n{r['binding_objective']}", (x, y), fontsize=6, xytext=(4, 4), textcoords="offset points"
        )
    if chosen.any():
        ax.plot(margin[chosen], module[chosen], "r*", ms=15, label="the design made")
    ax.axvline(0.0, color="C3", ls="--", lw=1, label="every objective keeps its margin under play")
    ax.axhline(MIN_MODULE_MM, color="C2", ls=":", lw=1, label=f"module objective xi ({MIN_MODULE_MM:g} mm)")
    ax.set_xlabel("smallest objective margin beyond what it must keep under play (mm or deg)")
    ax.set_ylabel("module the teeth can be cut at (mm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    ax.set_title(f"{title}: module against the smallest objective margin", fontsize=9)
    fig.text(0.01, 0.01, "\n".join(textwrap.wrap(binding, 150)), fontsize=7, va="bottom")
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return fig


def intermittent_figure(title: str, phi_deg, psi_deg, ratio, dwells, curves: dict, play_limit: float) -> plt.Figure:
    """An intermittent motion over the driver's turn: the driven angle (the dwells shaded), the
    ratio ω2/ω1 with its jumps at each dwell, and the driven gear's free play (deg) per checked
    source at the uniform and refined samples, against the locking play it must stay within."""
    fig, (ax1, ax2, ax3) = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for ax in (ax1, ax2, ax3):
        for lo, hi in dwells:
            ax.axvspan(lo % 360, (lo % 360) + (hi - lo), color="0.88", lw=0)
            if (lo % 360) + (hi - lo) > 360:
                ax.axvspan(0, (lo % 360) + (hi - lo) - 360, color="0.88", lw=0)
        ax.grid(alpha=0.3)
    ax1.plot(phi_deg, psi_deg, "k-", lw=1.2)
    ax1.set_ylabel("driven angle (deg)")
    ax1.set_title(f"{title}: dwells shaded")
    ax2.plot(phi_deg, ratio, "C0-", lw=1.2)
    ax2.set_ylabel("ratio ω2/ω1")
    for k, (source, (a, p)) in enumerate(sorted(curves.items())):
        order = np.argsort(a)
        ax3.plot(np.asarray(a)[order], np.asarray(p)[order], f"C{k}-", lw=0.9, label=source)
    ax3.axhline(play_limit, color="C3", ls="--", lw=1, label=f"locking play {play_limit:g} deg")
    ax3.set_yscale("log")
    ax3.set_ylabel("free play of the driven (deg)")
    ax3.set_xlabel("driver angle (deg)")
    ax3.set_xlim(0, 360)
    ax3.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig
