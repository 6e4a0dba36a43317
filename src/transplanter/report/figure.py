"""How every figure is drawn and saved: the settings that keep its text legible on the report
page, matplotlib imported on first use, and the PNG/SVG bytes (the same input, the same bytes).

**Legible where they are shown.** The report page shows a figure :data:`SHOWN_PX` CSS px wide
(two side by side) and opens it full size on a click; every figure is :data:`WIDTH_IN` wide with
its text at :data:`FONT_PT` or more, so no text is smaller than :data:`MIN_TEXT_PX` on the page
(pt × ``SHOWN_PX`` / (72 × ``WIDTH_IN``) CSS px, whatever the dpi). The PNG is drawn at
:data:`DPI`: opened, it is twice the size it has on the page.
"""

from __future__ import annotations

import functools
import io

__all__ = [
    "DPI",
    "FONT_PT",
    "MIN_TEXT_PX",
    "SHOWN_PX",
    "WIDTH_IN",
    "figure_files",
    "legend_below",
    "plan_view",
    "plt",
    "size",
    "styled",
]

#: CSS px the report page gives a figure (two side by side in its 70em column)
SHOWN_PX = 540
#: the smallest text a figure may show on the page, CSS px at ``SHOWN_PX``
MIN_TEXT_PX = 10
#: every figure's width, inches
WIDTH_IN = 6.4
#: the smallest text size, points: 9 pt on a 6.4 in figure shown 540 px wide is 10.5 px
FONT_PT = 9
#: PNG resolution, dots per inch: a 6.4 in figure is 1088 px, twice its width on the page
DPI = 170
#: matplotlib settings every figure is drawn with: no text under ``FONT_PT``
_RC = {
    "font.size": FONT_PT,
    "axes.titlesize": FONT_PT,
    "axes.labelsize": FONT_PT,
    "xtick.labelsize": FONT_PT,
    "ytick.labelsize": FONT_PT,
    "legend.fontsize": FONT_PT,
    "legend.title_fontsize": FONT_PT,
    "figure.titlesize": FONT_PT + 1,
    "legend.handlelength": 1.5,
    "legend.borderaxespad": 0.3,
}


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


def styled(make):
    """A figure function drawn with the figures' settings (``_RC``): text at ``FONT_PT`` or more."""

    @functools.wraps(make)
    def drawn(*args, **kwargs):
        with _matplotlib()[0].rc_context(_RC):
            return make(*args, **kwargs)

    return drawn


_METADATA = {
    "png": {"Software": None},
    "svg": {"Date": None, "Creator": None},
}


def _render(fig: plt.Figure, fmt: str) -> bytes:
    if fmt not in _METADATA:
        raise ValueError(f"fmt must be 'png' or 'svg', got {fmt!r}")
    buf = io.BytesIO()
    with _matplotlib()[0].rc_context({**_RC, "svg.hashsalt": "transplanter", "svg.fonttype": "none"}):
        # zlib level 1: a fraction of the encoding time of the default 6 for line plots, files ~7 % larger
        extra = {"pil_kwargs": {"compress_level": 1}} if fmt == "png" else {}
        fig.savefig(buf, format=fmt, dpi=DPI, metadata=_METADATA[fmt], **extra)
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


def size(height_in: float) -> tuple[float, float]:
    """A figure's size, inches: every figure is ``WIDTH_IN`` wide (its text legible on the page)."""
    return (WIDTH_IN, height_in)


def plan_view(ax, title: str | None = None, unit: str = "mm") -> None:
    """Equal-aspect x-y axes with a light grid, labelled in ``unit``."""
    ax.set_aspect("equal")
    ax.grid(True, lw=0.3)
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    if title is not None:
        ax.set_title(title)


def legend_below(fig, ax, ncol: int = 3) -> None:
    """The legend of ``ax`` under the figure's panels (a legend inside a 3 in panel hides it)."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        fig.legend(handles, labels, loc="lower center", ncol=ncol, frameon=False)
