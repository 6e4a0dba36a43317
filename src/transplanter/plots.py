"""Plots a designer looks at: coupler curves, speed/acceleration diagrams, shaking force.

Figures are rendered with matplotlib's Agg backend to PNG or SVG bytes, with the metadata
that would change between runs (date, software version, SVG ids) fixed, so the same input
gives the same bytes.
"""

from __future__ import annotations

import io
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from transplanter.linkage.planting import PlantingArm, PlantingMetrics  # noqa: E402

__all__ = ["figure_bytes", "coupler_curve_figure", "kinematics_figure", "shaking_figure"]

_METADATA = {
    "png": {"Software": None},
    "svg": {"Date": None, "Creator": None},
}


def figure_bytes(fig: plt.Figure, fmt: str) -> bytes:
    """Render and close ``fig``; ``fmt`` is "png" or "svg"."""
    if fmt not in _METADATA:
        raise ValueError(f"fmt must be 'png' or 'svg', got {fmt!r}")
    buf = io.BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "transplanter", "svg.fonttype": "none"}):
        fig.savefig(buf, format=fmt, dpi=110, metadata=_METADATA[fmt])
    plt.close(fig)
    return buf.getvalue()


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
        ax.set_aspect("equal")
        ax.grid(True, lw=0.3)
        ax.set_xlabel("x (cm)")
        ax.set_ylabel("y (cm)")
        ax.set_title(f"{arm.name}: tip path {title}", fontsize=9)
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
