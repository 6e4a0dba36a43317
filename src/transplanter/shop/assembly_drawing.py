"""A machine's assembly drawing (DXF R2000): every body at its start pose, seen from the front
(+z towards the reader), a balloon on each item of the bill of materials, the parts list and the
assembly order.

Each body is an :class:`Outline`: its section's bulge contours (the lines and arcs of its DXF, or
a bought part's simple section) placed in the machine frame (:func:`placed`), its z-range and its
item number. The drawing puts a made part's contours on layer ``PARTS`` and a bought part's on
``BOUGHT``; nothing is on ``CUT`` (the drawing is for assembly, not for the wire).

**Balloons** (:func:`balloons`, layer ``BALLOONS``): one per item — a circle with the item
number, and a leader from it to a dot on the item's body where the reader sees it: the point of
its section farthest inside the part of it that no body nearer the reader covers (the body of the
item with the most of it in sight). The balloons sit on a circle around the drawing, each near
the angle of its dot from the drawing's centre, spread so no two touch (:func:`_spread`), and two
whose leaders would cross trade places.

The parts list (item, quantity, name, designation, material, mass) and the assembly order — one
numbered note a step — go on ``ANNOTATION``, in :func:`~transplanter.shop.dxf.lettering` (ISO
3098) under the drawing. The bytes are the same on every rebuild (ezdxf's fixed metadata, as
:mod:`~transplanter.shop.dxf` writes every drawing).

Examples
--------
>>> import numpy as np
>>> square = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]], float)
>>> a = Outline("a", 1, placed([(square, False)]), (0.0, 5.0))
>>> b = Outline("b", 2, placed([(square, False)], x=5.0), (6.0, 9.0))
>>> [(p.item, round(p.anchor[0], 1)) for p in balloons([a, b], 3.5)]  # a's dot left of b, which covers it
[(1, 2.5), (2, 10.0)]
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import numpy as np
import shapely
from ezdxf.enums import TextEntityAlignment

from transplanter.core.errors import SpecError
from transplanter.shop import dxf
from transplanter.shop.arcs import bulge_points

__all__ = ["PARTS", "BALLOONS", "Outline", "Balloon", "placed", "balloons", "layout", "drawing_bytes"]

#: the drawing's own layers (beside the part drawings' ``dxf.LAYERS``) and their colours (ACI)
PARTS, BALLOONS = "PARTS", "BALLOONS"
LAYERS = {PARTS: 7, BALLOONS: 6}
#: a balloon's radius, in lettering heights
BALLOON_RADIUS = 1.2
#: contours are flattened to this for finding where a body is seen, mm
FLATTEN_MM = 0.05


def placed(contours, x: float = 0.0, y: float = 0.0, angle: float = 0.0, mirrored: bool = False) -> tuple:
    """Bulge contours ``[(verts (n, 3), is_hole)]`` — mirrored about their x-axis first with
    ``mirrored`` (a part turned over) — turned by ``angle`` (rad) about the origin, then moved to
    (x, y) mm. A rigid motion keeps every bulge; the mirror turns each arc the other way and each
    run back, so the outline stays counter-clockwise and the holes clockwise."""
    c, s = math.cos(angle), math.sin(angle)
    out = []
    for verts, hole in contours:
        v = np.asarray(verts, dtype=float)
        if mirrored:
            # span k (v_k -> v_k+1) mirrored turns the other way; walked back from v_k+1 to v_k its
            # bulge changes sign again: the vertices reversed, each with the bulge of the old span
            # that now leaves it
            v = np.column_stack([v[::-1, 0], -v[::-1, 1], np.roll(v[::-1, 2], -1)])
        moved = np.column_stack([x + c * v[:, 0] - s * v[:, 1], y + s * v[:, 0] + c * v[:, 1], v[:, 2]])
        out.append((moved, bool(hole)))
    return tuple(out)


@dataclass(frozen=True)
class Outline:
    """A body as the drawing shows it: its name, its item number, its contours placed in the
    machine frame (mm; the outline first), its z-range (mm) and whether it is bought."""

    name: str
    item: int
    contours: tuple
    z: tuple[float, float]
    bought: bool = False

    def __post_init__(self) -> None:
        if not self.contours or self.contours[0][1]:
            raise SpecError(f"{self.name}: an outline's contours start with its outer contour")

    @functools.cached_property
    def section(self) -> shapely.Polygon:
        """The section, arcs flattened to ``FLATTEN_MM`` (the largest contour the outline)."""
        rings = [shapely.Polygon(bulge_points(v, FLATTEN_MM)) for v, _ in self.contours]
        rings.sort(key=lambda p: -p.area)
        section = rings[0]
        for hole in rings[1:]:
            section = section.difference(hole)
        return section.buffer(0)


@dataclass(frozen=True)
class Balloon:
    """An item's balloon: its number, the dot on the body it points at and the body's name, the
    balloon's centre and radius (mm)."""

    item: int
    anchor: tuple[float, float]
    body: str
    centre: tuple[float, float]
    radius: float


def _seen(outlines: list[Outline]) -> dict[str, shapely.Geometry]:
    """Each body's section less what bodies nearer the reader (higher in z) cover."""
    # what covers a body depends on its height alone: the bodies above it, gathered from the top
    # down, each level's cover the one above's and that level's bodies
    levels = sorted({sum(o.z) for o in outlines}, reverse=True)
    covers = {levels[0]: shapely.Polygon()} if levels else {}
    for level, below in itertools.pairwise(levels):  # (nothing lies below the lowest: no cover for it)
        covers[below] = shapely.union_all([covers[level], *(o.section for o in outlines if sum(o.z) == level)])
    return {o.name: o.section.difference(covers[sum(o.z)]) for o in outlines}


def _dot(region, fallback: shapely.Polygon) -> tuple[float, float]:
    """The point farthest inside the largest piece of ``region`` (or of ``fallback`` when nothing
    of the body is in sight)."""
    pieces = [g for g in getattr(region, "geoms", [region]) if isinstance(g, shapely.Polygon) and not g.is_empty]
    piece = max(pieces, key=lambda g: g.area) if pieces else fallback
    circle = shapely.maximum_inscribed_circle(piece, tolerance=max(1e-3, 1e-3 * math.sqrt(piece.area)))
    x, y = shapely.get_coordinates(circle)[0]
    return float(x), float(y)


def _spread(angles: np.ndarray, gap: float) -> np.ndarray:
    """Angles (rad, ascending) moved apart so neighbours round the circle are at least ``gap``
    apart, each as near its own as that lets it be (least squares): the circle is cut at the widest
    gap between neighbours and the run laid out by pooling adjacent violators — ``angle_k - k gap``
    made non-decreasing — then each moved back by ``k gap``. ``len(angles) × gap`` must be under
    a turn."""
    n = len(angles)
    if n < 2:
        return angles.copy()
    gaps = (np.roll(angles, -1) - angles) % (2 * math.pi)
    start = (int(np.argmax(gaps)) + 1) % n  # the run starts after the widest gap
    order = np.roll(np.arange(n), -start)
    run = np.unwrap(angles[order])
    q = run - gap * np.arange(n)
    blocks: list[list[float]] = []  # [mean, count]
    for v in q:
        blocks.append([v, 1])
        while len(blocks) > 1 and blocks[-2][0] > blocks[-1][0]:
            m2, c2 = blocks.pop()
            m1, c1 = blocks.pop()
            blocks.append([(m1 * c1 + m2 * c2) / (c1 + c2), c1 + c2])
    fitted = np.concatenate([np.full(int(c), m) for m, c in blocks]) + gap * np.arange(n)
    out = np.empty(n)
    out[order] = fitted
    return out


def _crosses(p1, p2, q1, q2) -> bool:
    """Whether the segments p1-p2 and q1-q2 cross (touching ends do not count)."""

    def side(a, b, c) -> float:
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    d1, d2 = side(q1, q2, p1), side(q1, q2, p2)
    d3, d4 = side(p1, p2, q1), side(p1, p2, q2)
    return d1 * d2 < 0 and d3 * d4 < 0


def _uncrossed(items, anchors, slots) -> list[int]:
    """Which slot each balloon takes: its own, then two whose leaders cross swap slots until none
    do (each swap shortens the leaders in all, so it ends)."""
    slot = list(range(len(items)))
    for _ in range(len(items) ** 2):
        swapped = False
        for j in range(len(items)):
            for k in range(j + 1, len(items)):
                if _crosses(anchors[j], slots[slot[j]], anchors[k], slots[slot[k]]):
                    slot[j], slot[k] = slot[k], slot[j]
                    swapped = True
        if not swapped:
            break
    return slot


def balloons(outlines: list[Outline], height: float) -> list[Balloon]:
    """One balloon per item of ``outlines``, for lettering ``height`` mm (module docstring), in
    item order."""
    seen = _seen(outlines)
    best: dict[int, Outline] = {}
    for o in outlines:
        if o.item not in best or seen[o.name].area > seen[best[o.item].name].area + 1e-9:
            best[o.item] = o
    anchors = {item: _dot(seen[o.name], o.section) for item, o in best.items()}
    everything = shapely.union_all([o.section for o in outlines])
    minx, miny, maxx, maxy = everything.bounds
    cx, cy = (minx + maxx) / 2, (miny + maxy) / 2
    r_balloon = BALLOON_RADIUS * height
    reach = float(np.max(np.hypot(*(shapely.get_coordinates(everything) - [cx, cy]).T)))
    items = sorted(anchors, key=lambda i: (math.atan2(anchors[i][1] - cy, anchors[i][0] - cx), i))
    radius = max(reach + 4 * r_balloon, 2.6 * r_balloon * len(items) / (2 * math.pi) * 1.15)
    angles = np.array([math.atan2(anchors[i][1] - cy, anchors[i][0] - cx) for i in items])
    angles = _spread(angles, 2.6 * r_balloon / radius)
    slots = [(cx + radius * math.cos(t), cy + radius * math.sin(t)) for t in angles]
    slot = _uncrossed(items, [anchors[i] for i in items], slots)
    out = [Balloon(i, anchors[i], best[i].name, slots[slot[k]], r_balloon) for k, i in enumerate(items)]
    return sorted(out, key=lambda b: b.item)


def layout(outlines: list[Outline]) -> tuple[float, list[Balloon]]:
    """The drawing's lettering height (mm, :func:`~transplanter.shop.dxf.lettering` of its span)
    and its balloons (:func:`balloons`) — what the drawing shows, and a picture of it."""
    if not outlines:
        raise SpecError("an assembly drawing needs at least one body")
    minx, miny, maxx, maxy = shapely.union_all([o.section for o in outlines]).bounds
    height = dxf.lettering(max(maxx - minx, maxy - miny))
    return height, balloons(outlines, height)


def drawing_bytes(
    name: str,
    outlines: list[Outline],
    parts_list: list[list[str]],
    order: tuple[str, ...],
    notes: tuple[str, ...] = (),
) -> bytes:
    """The assembly drawing ``name`` (R2000; module docstring): ``outlines`` placed, a balloon per
    item, the ``parts_list`` (a header row, then one row of text per item) and the assembly
    ``order`` (one step each, numbered here) under it, then the ``notes``."""
    if not outlines:
        raise SpecError(f"the assembly drawing {name} has no body")
    with dxf._writing(f"the assembly drawing {name}"):
        doc = dxf._new_doc("R2000")
        for layer, colour in LAYERS.items():
            doc.layers.add(layer, color=colour)
        msp = doc.modelspace()
        for o in sorted(outlines, key=lambda o: (o.z, o.name)):
            for verts, _ in o.contours:
                dxf.add_contour(msp, verts, "R2000", dxf.BOUGHT if o.bought else PARTS)
        minx, miny, _, _ = shapely.union_all([o.section for o in outlines]).bounds
        height, shown = layout(outlines)
        for b in shown:
            _balloon(msp, b, height)
        low = min(miny, *(b.centre[1] - b.radius for b in shown))
        left = min(minx, *(b.centre[0] - b.radius for b in shown))
        lines = [f"{name}: assembly in the start position, seen from the front (mm)", "parts list:"]
        lines += ["  " + " | ".join(row) for row in parts_list]
        lines += ["assembly order:", *(f"  {k}. {step}" for k, step in enumerate(order, 1)), *notes]
        for k, line in enumerate(lines):
            msp.add_text(line, dxfattribs={"layer": "ANNOTATION", "height": height}).set_placement(
                (left, low - (k + 2) * 1.6 * height)
            )
        return dxf._write(doc)


def _balloon(msp, b: Balloon, height: float) -> None:
    """A balloon: its circle and number, and the leader from the circle's edge to a dot on the body."""
    attribs = {"layer": BALLOONS}
    cx, cy = b.centre
    msp.add_circle((cx, cy), b.radius, dxfattribs=attribs)
    msp.add_text(str(b.item), dxfattribs={**attribs, "height": height}).set_placement(
        (cx, cy), align=TextEntityAlignment.MIDDLE_CENTER
    )
    ax, ay = b.anchor
    d = math.hypot(ax - cx, ay - cy)
    if d > b.radius:
        ux, uy = (ax - cx) / d, (ay - cy) / d
        msp.add_line((cx + b.radius * ux, cy + b.radius * uy), (ax, ay), dxfattribs=attribs)
    msp.add_circle((ax, ay), 0.25 * height, dxfattribs=attribs)
