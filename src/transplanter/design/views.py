"""What the design studio shows of one design: plain data that a part script's problem computes.

A :class:`~transplanter.design.optimise.Problem` may give ``view``, a function of the design
vector returning a :class:`DesignView`: named curves grouped in panels (the tip's path in the
frame and on the ground with the box, the tray, the soil; the arm's attitude over the cycle; the
pitch curves), the mechanism's pose at every sample of the cycle (so a browser scrubs and plays
it without asking the server again), the objectives as :class:`Row` s, and ``later`` — the slow
judgement (the objectives under the gears' play, the module's fouling screen), which the studio
runs after the quick one is drawn. Everything is computed by the library, nothing approximated:
the view is what a build of that design would judge.

A problem without ``view`` still gets a page (its variables, its cost and what ``describe``
says): :func:`rows_from_description` reads its ``(margin M)`` entries.

Examples
--------
>>> import numpy as np
>>> c = Curve("tip", np.array([[0.0, 0.0], [1.0, 2.0]]))
>>> Panel("path", (c,)).curves[0].xy.shape
(2, 2)
>>> [r.ok for r in rows_from_description({"i clearance": "5.2 mm (margin +1.2)", "note": "held"})]
[True]
"""

from __future__ import annotations

import math
import re
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import SpecError

__all__ = [
    "SOIL_DRAWN_MM",
    "Curve",
    "DesignView",
    "Kept",
    "Panel",
    "Pose",
    "Row",
    "rows_from_description",
    "rows_from_objectives",
    "soil",
]


@dataclass(frozen=True)
class Curve:
    """A named polyline ``xy`` (n, 2), mm or (deg, unit) for a series; NaN rows break it;
    ``closed``: drawn back to its first point; ``kind``: ``"path"``, ``"obstacle"`` (a box, a
    tray, the soil: drawn filled grey) or ``"mark"`` (points)."""

    name: str
    xy: np.ndarray
    closed: bool = False
    kind: str = "path"

    def __post_init__(self) -> None:
        xy = np.asarray(self.xy, dtype=float)
        if xy.ndim != 2 or xy.shape[1] != 2:
            raise SpecError(f"curve {self.name!r}: points must be (n, 2), got shape {xy.shape}")
        if self.kind not in ("path", "obstacle", "mark"):
            raise SpecError.out_of_range(f"curve {self.name!r} kind", self.kind, "path, obstacle or mark")
        object.__setattr__(self, "xy", xy)


#: the soil is drawn this deep below its surface, mm
SOIL_DRAWN_MM = 40.0


def soil(level: float, x0: float, x1: float) -> Curve:
    """The soil below ``level`` (mm) from ``x0`` to ``x1``, as an obstacle ``SOIL_DRAWN_MM`` deep."""
    band = [[x0, level], [x1, level], [x1, level - SOIL_DRAWN_MM], [x0, level - SOIL_DRAWN_MM]]
    return Curve("soil", np.array(band), closed=True, kind="obstacle")


@dataclass(frozen=True)
class Panel:
    """One plot: its title, axis labels, curves; ``equal``: the same scale on both axes (a
    drawing), else a chart (a series over the cycle)."""

    title: str
    curves: tuple[Curve, ...]
    x_label: str = "x (mm)"
    y_label: str = "y (mm)"
    equal: bool = True


@dataclass(frozen=True)
class Pose:
    """The mechanism at every sample of its cycle, drawn into panel ``panel`` (its index):
    ``angles`` (n,) deg of the input (the carrier, the crank); ``lines`` (n, m, 2) mm, each
    sample's links as one polyline broken by NaN rows."""

    angles: np.ndarray
    lines: np.ndarray
    panel: int = 0
    label: str = "carrier angle (deg)"
    #: +1: time runs with the angle; -1: against it (a crank turning clockwise, its angle counted
    #: anticlockwise): the page plays the cycle that way
    sense: int = 1

    def __post_init__(self) -> None:
        if self.sense not in (1, -1):
            raise SpecError.out_of_range("pose sense", self.sense, "+1 or -1")
        a = np.asarray(self.angles, dtype=float)
        lines = np.asarray(self.lines, dtype=float)
        if a.ndim != 1 or lines.ndim != 3 or lines.shape[0] != len(a) or lines.shape[2] != 2:
            raise SpecError(f"pose: angles (n,) and lines (n, m, 2) expected, got {a.shape} and {lines.shape}")
        object.__setattr__(self, "angles", a)
        object.__setattr__(self, "lines", lines)


@dataclass(frozen=True)
class Row:
    """One objective: its name, value and unit, its limits in words, the margin (how far inside
    them, in the value's unit; negative: outside) and whether it is met."""

    name: str
    value: float
    unit: str
    limit: str
    margin: float
    ok: bool


@dataclass(frozen=True)
class DesignView:
    """What the studio draws of one design (see the module docstring)."""

    panels: tuple[Panel, ...] = ()
    rows: tuple[Row, ...] = ()
    pose: Pose | None = None
    notes: tuple[str, ...] = ()
    #: the slow judgement, run after the quick one is shown (away from the server): its rows, or a
    #: DesignView whose panels are drawn after these and whose rows are the judgement's
    later: Callable[[], tuple[Row, ...] | DesignView] | None = field(default=None, compare=False)
    later_title: str = ""


def rows_from_objectives(objectives) -> tuple[Row, ...]:
    """Rows of :class:`~transplanter.design.objectives.Objective` s (number and name, value, limit)."""
    return tuple(
        Row(f"{o.number} {o.name}", float(o.value), o.unit, o.limit, float(o.margin), bool(o.ok)) for o in objectives
    )


_MARGIN = re.compile(r"^\s*(?P<value>[-+0-9.eE]+)\s*(?P<unit>[^(]*?)\s*\(margin (?P<margin>[-+0-9.eE]+)\)")


def rows_from_description(said: dict[str, str]) -> tuple[Row, ...]:
    """Rows of a problem's ``describe`` entries that read ``"value unit (margin M)"`` (the
    convention :func:`transplanter.design.optimise.misses` reads); other entries are notes."""
    out = []
    for name, text in said.items():
        m = _MARGIN.match(str(text))
        if m is None:
            continue
        try:
            value, margin = float(m["value"]), float(m["margin"])
        except ValueError:
            continue
        if math.isfinite(margin):
            out.append(Row(str(name), value, m["unit"].strip(), "", margin, margin >= 0.0))
    return tuple(out)


class Kept:
    """The last ``size`` results of a function of a hashable key, the most recently used kept — a
    view's cache of what a moved variable does not change (seed 004's pair and its module when the
    arm moves). A pickle leaves them behind: a search's workers receive the problem (its view too)
    by cloudpickle from a part script's module, which is run rather than imported, where a
    ``functools`` cache would not pickle at all; they start with none."""

    def __init__(self, size: int) -> None:
        self.size = size
        self._lock = threading.Lock()
        self._kept: dict = {}

    def get(self, key, make):
        """The result for ``key``: kept, or ``make()`` (kept unless it raises)."""
        with self._lock:
            if key in self._kept:
                self._kept[key] = self._kept.pop(key)  # the most recently used last
                return self._kept[key]
        value = make()
        with self._lock:
            self._kept[key] = value
            while len(self._kept) > self.size:
                self._kept.pop(next(iter(self._kept)))
        return value

    def __getstate__(self) -> dict:
        return {"size": self.size}

    def __setstate__(self, state: dict) -> None:
        self.size = state["size"]
        self._lock = threading.Lock()
        self._kept = {}
