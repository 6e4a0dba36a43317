"""The studio page's drawing: a Bokeh figure per panel of the view, the mechanism posed in one.

:class:`Drawing` keeps the figures, one data source per figure and kind of curve (paths,
obstacles, marks, the pinned design B's paths), and the poses of the cycle with the scrubber and
the play button that walk them in the browser (scrubbing asks nothing of the server). It sends
only what changed: a source whose curves did not move is left alone, a title only when new.

Each figure is a document root of its own (``roots``, placed by the page's template): the
browser lays out a root again when a model in it changes size — a new title, its first curves —
and in one root with the others that would measure every plot's axes again.
"""

from __future__ import annotations

import numpy as np

from transplanter.design.views import Curve, Panel, Pose

__all__ = ["PALETTE", "SLOTS", "Drawing"]

#: plots placed two by two (a view with more draws the rest under the last)
SLOTS = 8

#: curve colours, in order (matplotlib's tab10: the reports' colours)
PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f")

_POSE_JS = """
const X = poses.data.x, Y = poses.data.y;
const n = Math.round(360 / scrub.step), m = X.length / n;
if (!X.length || m != Math.floor(m)) { return; }
const k = Math.round(scrub.value / scrub.step) % n;
pose.data = {x: Array.from(X.slice(k * m, (k + 1) * m)), y: Array.from(Y.slice(k * m, (k + 1) * m))};
"""

_PLAY_JS = """
if (toggle.active) {
  window._studio_play = setInterval(() => {
    scrub.value = (scrub.value + (toggle.tags[0] || 1) * scrub.step * 2 + 360) % 360;
  }, 40);
} else { clearInterval(window._studio_play); }
"""


def _closed(c: Curve) -> np.ndarray:
    return np.vstack([c.xy, c.xy[:1]]) if c.closed and c.kind != "obstacle" else c.xy


def _same(old: dict, new: dict) -> bool:
    """Whether a source's columns hold ``new`` already (lists of arrays compared elementwise)."""
    if set(old) != set(new):
        return False
    for name, column in new.items():
        held = old[name]
        if len(held) != len(column):
            return False
        for a, b in zip(held, column, strict=True):
            if not np.array_equal(np.asarray(a), np.asarray(b)):
                return False
    return True


def _data(kind: str, curves) -> dict:
    """The columns of one source: ``curves`` ((index in its panel, Curve) pairs) of ``kind``."""
    label = f"label_{kind}"
    if kind == "pinned":  # design B's paths, dashed
        return {
            "xs": [_closed(c)[:, 0] for _, c in curves],
            "ys": [_closed(c)[:, 1] for _, c in curves],
            label: [f"B: {c.name}" for _, c in curves],
            "color": ["#555555" for _ in curves],
        }
    if kind == "mark":
        pts = [(j, c.name, xy) for j, c in curves for xy in c.xy]
        return {
            "x": [xy[0] for _, _, xy in pts],
            "y": [xy[1] for _, _, xy in pts],
            label: [n for _, n, _ in pts],
            "color": [PALETTE[j % len(PALETTE)] for j, _, _ in pts],
        }
    return {
        "xs": [_closed(c)[:, 0] for _, c in curves],
        "ys": [_closed(c)[:, 1] for _, c in curves],
        label: [c.name for _, c in curves],
        "color": [PALETTE[j % len(PALETTE)] for j, _ in curves],
    }


class Drawing:
    """The figures of one page (module docstring): ``roots`` to add to the document, ``scrub`` and
    ``play`` to place, :meth:`draw` a view's panels (and its pose), :meth:`hide_from` the slow
    judgement's panels of the design before."""

    def __init__(self) -> None:
        from bokeh.layouts import column
        from bokeh.models import ColumnDataSource, CustomJS, Div, Slider, Toggle

        self.figures: list = []
        self.sources: dict = {}
        self.roots = [column(name=f"slot{i}") for i in range(SLOTS)]
        self.roots[0].children = [Div(text="<i>computing the first design…</i>")]  # the first figure replaces it
        self.scrub = Slider(
            start=0.0, end=359.5, value=0.0, step=0.5, title="carrier angle (deg)", name="scrub", width=400
        )
        self.play = Toggle(label="play", name="play", width=70)
        self.pose_src = ColumnDataSource({"x": [], "y": []}, name="pose")
        self.poses_src = ColumnDataSource({"x": [], "y": []}, name="poses")
        self.scrub.js_on_change(
            "value", CustomJS(args={"poses": self.poses_src, "pose": self.pose_src, "scrub": self.scrub}, code=_POSE_JS)
        )
        self.play.js_on_change("active", CustomJS(args={"toggle": self.play, "scrub": self.scrub}, code=_PLAY_JS))

    def ensure(self, panels: tuple[Panel, ...], pose: Pose | None) -> None:
        """A figure for every panel (the ones there are kept), the pose drawn in its panel's."""
        from bokeh.plotting import figure

        while len(self.figures) < len(panels):
            p = panels[len(self.figures)]
            f = figure(
                title=p.title,
                width=450,
                height=360,
                x_axis_label=p.x_label,
                y_axis_label=p.y_label,
                match_aspect=p.equal,
                name=f"panel-{len(self.figures)}",
                tools="pan,wheel_zoom,box_zoom,reset,save",
            )
            f.toolbar.logo = None
            self.figures.append(f)
            if pose is not None and pose.panel == len(self.figures) - 1:
                f.line("x", "y", source=self.pose_src, color="black", line_width=2)
                f.scatter("x", "y", source=self.pose_src, color="black", size=5)
            slot = self.roots[min(len(self.figures), len(self.roots)) - 1]  # past the last slot, under it
            slot.children = [f] if len(self.figures) <= len(self.roots) else [*slot.children, f]
            slot.min_height = 360 * len(slot.children)  # its place kept while its figures are hidden

    def draw(self, panels: tuple[Panel, ...], first: int = 0, pinned: tuple[Panel, ...] = ()) -> None:
        """``panels`` into the figures from index ``first`` (made if missing); ``pinned``: design
        B's panels (same order), their paths dashed."""
        for k, p in enumerate(panels):
            i = first + k
            f = self.figures[i]
            if f.title.text != p.title:
                f.title.text = p.title
            if not f.visible:
                f.visible = True
            for kind in ("path", "obstacle", "mark"):
                self._update(i, kind, [(j, c) for j, c in enumerate(p.curves) if c.kind == kind])
            b = pinned[k].curves if k < len(pinned) else ()
            self._update(i, "pinned", [(j, c) for j, c in enumerate(b) if c.kind == "path"])

    def hide_from(self, first: int) -> None:
        """The figures from index ``first`` hidden until drawn again: the slow judgement's of the
        design before, which are not this design's. Their places are kept (no jump), and a hidden
        plot costs the browser nothing: shown, seed 002's three stage plots added ~50 ms to every
        change of its quick ones (the compositor's frames carry every canvas on the page; 215
        against 259-276 ms, ``benchmarks/studio.py``)."""
        for f in self.figures[first:]:
            f.visible = False

    def pose(self, pose: Pose) -> None:
        """Every pose of the cycle to the browser (float32: drawn only, 0.01 µm at 1 m), the one at
        the scrubber's angle drawn, the play button turning the way the mechanism does."""
        n = pose.lines.shape[0]
        flat = pose.lines.reshape(-1, 2).astype(np.float32)
        self.poses_src.data = {"x": flat[:, 0], "y": flat[:, 1]}
        if self.scrub.step != 360.0 / n:
            self.scrub.step = 360.0 / n
        i = int(round(self.scrub.value / 360.0 * n)) % n
        self.pose_src.data = {"x": pose.lines[i, :, 0], "y": pose.lines[i, :, 1]}
        if self.play.tags != [pose.sense]:
            self.play.tags = [pose.sense]
        if self.scrub.title != pose.label:
            self.scrub.title = pose.label

    def _update(self, i: int, kind: str, curves) -> None:
        """One source per figure and kind of curve (a message per figure), left alone if nothing
        moved; its labels in a column of its own (a legend merges the items of one column name)."""
        data = _data(kind, curves)
        key = (i, kind)
        if key in self.sources:
            if not _same(self.sources[key].data, data):
                self.sources[key].data = data
            return
        if not curves:
            return
        from bokeh.models import ColumnDataSource

        src = self.sources[key] = ColumnDataSource(data, name=f"curves-{i}-{kind}")
        f = self.figures[i]
        label = f"label_{kind}"
        if kind == "obstacle":
            f.patches(
                "xs", "ys", source=src, fill_color="#999999", fill_alpha=0.25, line_color="#777777", legend_field=label
            )
        elif kind == "mark":
            f.scatter("x", "y", source=src, color="color", size=8, legend_field=label)
        elif kind == "pinned":
            f.multi_line("xs", "ys", source=src, color="color", line_dash="dashed", line_width=1.2, legend_field=label)
        else:
            f.multi_line("xs", "ys", source=src, color="color", line_width=1.6, legend_field=label)
        f.legend.location = "top_left"
        f.legend.label_text_font_size = "10px"
        f.legend.click_policy = "hide"
