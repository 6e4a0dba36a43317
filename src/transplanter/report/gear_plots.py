"""Plots of a gear pair: its pitch curves, its generated teeth, its meshing over a cycle, an
intermittent motion's dwells and play — drawn, like every figure, to be read at the width the
report page gives them (:mod:`~transplanter.report.figure`)."""

from __future__ import annotations

import math
import textwrap

import numpy as np
import shapely

from transplanter.report.figure import legend_below, plan_view, plt, size, styled

__all__ = ["intermittent_figure", "meshing_figure", "pitch_pair_figure", "toothed_pair_figure"]

#: a legend beside its panel, right of the axes
_BESIDE = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0)}


@styled
def pitch_pair_figure(pair, title: str) -> plt.Figure:
    """Both pitch curves in mesh at the start (left) and their ratio and curvature (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=size(3.7))
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
    plan_view(ax1, "in mesh at the start")
    deg = np.degrees(phi)
    ax2.plot(deg, pair.ratio(phi), "k-", label="ratio ω2/ω1")
    ax2.set_xlabel("driver angle (deg)")
    ax2.set_ylabel("ratio ω2/ω1")
    ax2.grid(True, lw=0.3)
    ax3 = ax2.twinx()
    ax3.plot(deg, np.degrees(pair.driver.pressure_deviation(phi)), "C0--", lw=0.8, label="driver ν (deg)")
    ax3.set_ylabel("pressure deviation ν (deg)", color="C0")
    ax2.set_xlim(0, 360)
    ax2.set_xticks(range(0, 361, 90))
    ax2.set_title("ratio and pressure deviation")
    fig.suptitle(f"{title}: pitch curves, a = {a:.4f} mm")
    handles, labels = ax1.get_legend_handles_labels()
    for ax in (ax2, ax3):
        more = ax.get_legend_handles_labels()
        handles, labels = [*handles, *more[0]], [*labels, *more[1]]
    fig.legend(handles, labels, loc="lower center", ncol=2, frameon=False)
    fig.tight_layout(rect=(0, 0.13, 1, 1))
    return fig


@styled
def toothed_pair_figure(
    driver_polygon, driven_polygon, centre_distance: float, external: bool, contact_x: float, title: str
):
    """The two generated gears in their start position (left) and a zoom on the start contact (right)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=size(3.6))

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
        plan_view(ax)
    ax2.set_xlim(x0 - span, x0 + span)
    ax2.set_ylim(-span, span)
    ax1.set_title("at the start (driver blue)")
    ax2.set_title("start contact")
    fig.suptitle(f"{title}: generated gears")
    fig.tight_layout()
    return fig


@styled
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
    fig, axes = plt.subplots(rows, 1, figsize=size(1.4 * rows + 0.6))
    ax1, ax2, ax3, ax5 = axes[0], axes[1], axes[2], axes[3]
    for i, (source, r) in enumerate(sorted(reports.items())):
        deg = np.degrees(r.driver_angle)
        ax1.plot(deg, r.penetration, f"C{i}-", lw=0.9, label=source)
        if r.max_fouling > 0:
            ax1.plot(deg, r.fouling, f"C{i}:", lw=0.9, label=f"{source}: fouling")
        ax2.plot(deg, 1000 * r.transmission_error, f"C{i}-", lw=0.8, label=source)
        angle, values = r.samples("backlash")
        lo = r.backlash_min
        ax3.plot(np.degrees(angle), 1000 * values, f"C{i}-", lw=0.8, label=f"{source} ≥ {1000 * lo.value:.1f}")
        ax3.plot([lo.at_deg], [1000 * lo.value], f"C{i}v", ms=5)
        if r.clearance is not None:
            angle, values = r.samples("clearance")
            c = r.clearance_min
            ax5.plot(np.degrees(angle), 1000 * values, f"C{i}-", lw=0.8, label=f"{source} ≥ {1000 * c.value:.1f}")
            ax5.plot([c.at_deg], [1000 * c.value], f"C{i}v", ms=5)
    if band is not None:
        ax3.axhspan(1000 * band[0], 1000 * band[1], color="0.85", zorder=0, label="design band")
        ax3.axhline(1000 * band[0], color="C3", lw=0.8, ls="--", label="tolerance budget")
    if clearance is not None:
        ax5.axhline(1000 * clearance, color="C3", lw=0.8, ls="--", label="required")
    fig.suptitle(f"{title}: meshing over the driver's turn")
    for ax, label, sub in (
        (ax1, "overlap (mm²)", "overlap of the teeth (fouling: away from the pitch point)"),
        (ax2, "error (µm)", "transmission error at the driven pitch point"),
        (ax3, "backlash (µm)", "backlash (free play) at the driven pitch point; v: minimum"),
        (ax5, "clearance (µm)", "smallest gap, driven gear at mid-play"),
    ):
        ax.set_ylabel(label)
        ax.set_title(sub)
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 45))
        ax.grid(True, lw=0.3)
        if ax.get_legend_handles_labels()[0]:  # nothing to name when no source could be read
            ax.legend(**_BESIDE)
    ax5.set_xlabel("driver angle (deg)")
    if train is not None:
        ax4 = axes[4]
        ax4.plot(np.degrees(train.theta), 1000 * train.deviation, "C3.", ms=2)
        ax4.set_xlabel("carrier angle (deg)")
        ax4.set_ylabel("deviation (µm)")
        note = textwrap.shorten(train_note.strip(" ;,:()"), 60)
        ax4.set_title("needle tip of the train rebuilt from the parts vs the design" + (f"\n({note})" if note else ""))
        ax4.grid(True, lw=0.3)
    fig.tight_layout(h_pad=0.4)
    return fig


@styled
def intermittent_figure(title: str, phi_deg, psi_deg, ratio, dwells, curves: dict, play_limit: float) -> plt.Figure:
    """An intermittent motion over the driver's turn: the driven angle (the dwells shaded), the
    ratio ω2/ω1 with its jumps at each dwell, and the driven gear's free play (deg) per checked
    source at the uniform and refined samples, against the locking play it must stay within."""
    fig, (ax1, ax2, ax3) = plt.subplots(3, 1, figsize=size(6.4), sharex=True)
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
    # plain numbers: the log axis' 10^n labels carry exponents at 70 % of the text size
    ax3.yaxis.set_major_formatter(plt.FuncFormatter(lambda v, _: f"{v:g}"))
    ax3.yaxis.set_minor_formatter(plt.NullFormatter())
    ax3.set_ylabel("free play (deg)")
    ax3.set_xlabel("driver angle (deg)")
    ax3.set_xlim(0, 360)
    ax3.set_xticks(range(0, 361, 45))
    legend_below(fig, ax3, ncol=4)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    return fig
