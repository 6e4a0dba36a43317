"""The picture of an assembled machine: its bodies at the start pose seen from the front, with the
balloons of its bill of materials — the assembly drawing's view (:mod:`transplanter.shop.assembly_drawing`)
drawn for the report page and the README.

Bodies are filled back to front (a body nearer the reader, higher in z, covers the ones behind
it), made parts in greys that darken towards the front, bought parts in blue; each balloon is a
circle with its item number and a leader to the dot on its body, where the drawing puts them.
"""

from __future__ import annotations

import numpy as np
import shapely

from transplanter.report.figure import figure_files, plan_view, plt, size, styled

__all__ = ["assembly_picture"]

#: the picture's height, inches (its width is every figure's)
HEIGHT_IN = 6.4


def _patches(ax, polygon, **style) -> None:
    """``polygon`` (or each of a multipolygon's) filled, its holes open."""
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path

    for p in getattr(polygon, "geoms", [polygon]):
        if not isinstance(p, shapely.Polygon) or p.is_empty:
            continue
        rings = [np.asarray(p.exterior.coords), *(np.asarray(r.coords) for r in p.interiors)]
        codes, verts = [], []
        for ring in rings:
            verts.extend(ring.tolist())
            codes.extend([Path.MOVETO] + [Path.LINETO] * (len(ring) - 2) + [Path.CLOSEPOLY])
        ax.add_patch(PathPatch(Path(verts, codes), **style))


@styled
def assembly_picture(outlines, balloons, title: str, stem: str) -> dict[str, bytes]:
    """``<stem>.png`` and ``<stem>.svg`` of ``outlines`` (:class:`~transplanter.shop.assembly_drawing.Outline`)
    with their ``balloons`` (:class:`~transplanter.shop.assembly_drawing.Balloon`), titled ``title``."""
    fig, ax = plt.subplots(figsize=size(HEIGHT_IN))
    made = sorted({sum(o.z) for o in outlines if not o.bought})
    for o in sorted(outlines, key=lambda o: (sum(o.z), o.bought, o.name)):
        if o.bought:
            style = {"facecolor": "#9ecae1", "edgecolor": "#08519c"}
        else:
            k = made.index(sum(o.z)) / max(1, len(made) - 1)
            grey = 0.88 - 0.45 * k
            style = {"facecolor": (grey, grey, grey), "edgecolor": "0.15"}
        _patches(ax, o.section, lw=0.5, **style)
    for b in balloons:
        (cx, cy), (ax_, ay) = b.centre, b.anchor
        d = float(np.hypot(ax_ - cx, ay - cy))
        if d > b.radius:
            ux, uy = (ax_ - cx) / d, (ay - cy) / d
            ax.plot([cx + b.radius * ux, ax_], [cy + b.radius * uy, ay], color="#a50f15", lw=0.6)
        ax.plot([ax_], [ay], "o", color="#a50f15", ms=2.5)
        ax.add_patch(plt.Circle((cx, cy), b.radius, facecolor="white", edgecolor="#a50f15", lw=0.8))
        ax.text(cx, cy, str(b.item), ha="center", va="center", color="#a50f15")
    plan_view(ax, title)
    ax.autoscale_view()
    fig.tight_layout()
    return figure_files(fig, stem)
