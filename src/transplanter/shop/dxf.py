"""DXF for wire EDM: closed contours as arcs, millimetres, deterministic bytes (ezdxf).

The arcs come from :mod:`transplanter.shop.arcs` (tangent-continuous, one-sided fits: bulge vertices);
this module writes them as a DXF LWPOLYLINE (R2000) or POLYLINE (R12) — far fewer entities than
points, no gaps (each arc ends on the next one's start vertex) — and reads them back.

**Files.** One DXF per part: ``$INSUNITS`` = 4 (mm; ezdxf defaults to metres — and R12 has no
units header, so the annotation says mm); the outline's contours on the one layer that says what
the drawing is (:data:`OUTLINES`): ``CUT`` for a part to cut — the only layer a shop's CAM
takes — ``REFERENCE`` for an outline not to cut (an obstacle such as the seedling box or the
soil, a drawing marked "do not cut" that other parts are cut from), ``BOUGHT`` for a bought
part drawn for the assembly and the judges; ``START_HOLES`` (on a part to cut: a start hole in
every inner contour, in the waste: centred in the largest circle inscribed in the hole's exact
arcs and ``START_HOLE_MARGIN_MM`` from every cut contour, or where none fits a NO START HOLE
note instead, :func:`start_hole`), ``ANNOTATION`` (part name, tooth count, module, material and
quantity, marks, paths such as a finger's tip path); ezdxf's fixed metadata so rebuilding gives
identical bytes. With a wire offset the contours are the wire-centre path
(:func:`machining.wire_path`).

**Read-back.** :func:`read_contours` re-reads the outline — from the layer it is on
(:func:`outline_layer`: a drawing has its contours on exactly one of :data:`OUTLINES`), or from
the layer a reader names — and flattens the arcs (:func:`read_section` nests them into the part
section), :func:`bulge_contours` gives them as bulge vertices and :func:`arc_centres` every
arc's centre, radius and sweep (where a shop finds a hole); :func:`contour_deviation` gives the
largest distance between source and read-back (both ways).

**Assembly drawings** (:func:`assembly_bytes`) are dimensioned in their own dimension style
(:data:`DIMSTYLE`, also the header's ``$DIM*`` defaults): scale 1, length factor 1, millimetres
with a decimal point, ISO 3098 lettering (:func:`lettering`) — no entity overrides it, so every
reader (LibreCAD, which ignores an entity's overrides, as well as ezdxf and GDAL) shows the
length the dimension measures, at a height one can read.

Examples
--------
>>> import numpy as np
>>> from transplanter.shop.arcs import fit_arcs
>>> from transplanter.shop.dxf import arcs_to_points, contour_deviation
>>> t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
>>> ellipse = np.stack([40 * np.cos(t), 25 * np.sin(t)], axis=1)
>>> contour_deviation(ellipse, arcs_to_points(fit_arcs(ellipse, tolerance=1e-3))) < 1.05e-3
True
"""

from __future__ import annotations

import functools
import io
import math
from contextlib import contextmanager
from dataclasses import dataclass, field

import ezdxf
import numpy as np
import shapely
from ezdxf.enums import TextEntityAlignment
from ezdxf.math import bulge_to_arc

from transplanter.core.errors import MAX_MAGNITUDE, ExportError, GeometryError, SpecError, check_number
from transplanter.core.tolerances import DXF_ARC_TOLERANCE_MM, MIN_CONTOUR_AREA
from transplanter.geometry.contact import distance_to_ring
from transplanter.shop.arcs import bulge_area, section_arcs, with_arcs
from transplanter.shop.machining import wire_path

__all__ = [
    "OUTLINES",
    "CUT",
    "REFERENCE",
    "BOUGHT",
    "DIMSTYLE",
    "lettering",
    "ascii_text",
    "outline_layer",
    "arcs_to_points",
    "DxfPart",
    "dxf_bytes",
    "start_hole",
    "START_HOLE_MARGIN_MM",
    "read_contours",
    "assembly_bytes",
    "bulge_contours",
    "read_section",
    "contour_deviation",
    "arc_centres",
]

#: the names of the three outline layers
CUT, REFERENCE, BOUGHT = "CUT", "REFERENCE", "BOUGHT"
#: the layers an outline may be on, by what the drawing is (only ``CUT`` is for the wire)
OUTLINES = {
    CUT: "a part to cut",
    REFERENCE: "not to cut: an obstacle, or a drawing other parts are cut from",
    BOUGHT: "a bought part, drawn for the assembly (not to cut)",
}
#: every layer of a part's DXF and its colour (ACI)
LAYERS = {CUT: 7, REFERENCE: 8, BOUGHT: 4, "START_HOLES": 1, "ANNOTATION": 3}

#: the assembly drawings' dimension style: true scale, mm, ISO 3098 lettering (:func:`lettering`)
DIMSTYLE = "TRANSPLANTER"
#: ISO 3098-0 lettering heights (the nominal series), mm
ISO_3098_HEIGHTS_MM = (2.5, 3.5, 5.0, 7.0, 10.0, 14.0, 20.0)

#: a start hole keeps at least this much material (mm) between it and every cut contour, so the
#: wire's first pass never reaches the part (a wire-EDM start hole is drilled, not cut: ±0.05 mm)
START_HOLE_MARGIN_MM = 0.1


def arcs_to_points(verts: np.ndarray, max_sagitta: float = 1e-5) -> np.ndarray:
    """Flatten closed bulge vertices ``(n, 3)`` back to points (for checks and plots)."""
    return _bulge_points(np.asarray(verts, dtype=float), max_sagitta)


@dataclass(frozen=True)
class DxfPart:
    """What goes into one part's DXF."""

    name: str
    section: shapely.Polygon
    notes: tuple[str, ...] = ()
    start_hole: float = 1.0  # diameter, mm
    #: ANNOTATION marks: (x, y, text) — a cross at the point and the text beside it (timing marks)
    marks: tuple[tuple[float, float, str], ...] = ()
    #: wire-centre compensation (wire radius + spark gap, mm); None writes the nominal contour
    #: and leaves the offset to the CAM
    wire_offset: float | None = None
    #: ANNOTATION paths: open polylines (n, 2), mm (a planting finger's tip path)
    paths: tuple[np.ndarray, ...] = field(default=(), compare=False)
    #: the layer of its outline: what the drawing is (one of :data:`OUTLINES`; only a part to cut,
    #: ``CUT``, gets start holes and a wire offset)
    layer: str = CUT

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise SpecError(f"DXF part name must be a non-empty string, got {self.name!r}")
        if not isinstance(self.section, shapely.Polygon) or self.section.is_empty or not self.section.is_valid:
            kind = type(self.section).__name__
            raise SpecError(
                f"{self.name}: the DXF section must be one valid, non-empty shapely Polygon (a part), got {kind}"
                + (
                    " (several pieces: write one DXF per part)"
                    if isinstance(self.section, shapely.MultiPolygon)
                    else ""
                )
            )
        for ring in (self.section.exterior, *self.section.interiors):
            area = abs(shapely.Polygon(ring).area)
            if area < MIN_CONTOUR_AREA:
                raise GeometryError(
                    f"{self.name}: a contour encloses {area:.3g} mm² (limit {MIN_CONTOUR_AREA:g} mm²): nothing to cut"
                )
        check_number("start_hole", self.start_hole, 0.0, 100.0, low_open=True, unit="mm")
        if self.layer not in OUTLINES:
            raise SpecError.out_of_range("layer", self.layer, " or ".join(repr(k) for k in OUTLINES))
        if self.wire_offset is not None:
            check_number("wire_offset", self.wire_offset, 0.0, 10.0, low_open=True, unit="mm")
            if self.layer != CUT:
                raise SpecError(
                    f"{self.name}: wire_offset = {self.wire_offset:g} mm on a {self.layer} outline: only a part to "
                    "cut (layer CUT) has a wire path"
                )
        for x, y, _ in self.marks:
            check_number("mark x", x, -MAX_MAGNITUDE, MAX_MAGNITUDE)
            check_number("mark y", y, -MAX_MAGNITUDE, MAX_MAGNITUDE)


def start_hole(verts: np.ndarray, diameter: float) -> tuple[float, float] | str:
    """Where the wire's start hole goes in a hole of the part: the centre of the largest circle
    inscribed in the hole's *exact* arcs (bulges flattened to 0.1 µm, far inside the margin), if
    a start hole of ``diameter`` fits there with ``START_HOLE_MARGIN_MM`` to every cut contour;
    else a note saying why there is none (the wire must then start from the outside)."""
    hole = shapely.Polygon(_bulge_points(np.asarray(verts, dtype=float), 1e-4))
    if hole.is_valid and hole.area > 0:
        circle = shapely.maximum_inscribed_circle(hole, tolerance=1e-4)
        centre = shapely.get_coordinates(circle)[0]
        room = float(shapely.distance(shapely.Point(centre), hole.exterior))
        if room >= diameter / 2 + START_HOLE_MARGIN_MM:
            return float(centre[0]), float(centre[1])
        widest = f"largest inscribed diameter {2 * room:.3f} mm"
    else:
        widest = "no area"
    return (
        f"NO START HOLE: a {diameter:g} mm start hole does not fit this hole with {START_HOLE_MARGIN_MM:g} mm "
        f"to its contour ({widest}); thread the wire from outside or drill it smaller"
    )


def _new_doc(version: str):
    """An empty R2000/R12 document in mm with our layers (fixed metadata must be switched on)."""
    if version not in ("R2000", "R12"):
        raise SpecError.out_of_range("DXF version", version, "'R2000' or 'R12'")
    doc = ezdxf.new(version)
    if version == "R12":  # R12 has no units header; ezdxf would warn about the default
        del doc.header["$INSUNITS"]
    else:
        doc.header["$INSUNITS"] = 4
    doc.header["$MEASUREMENT"] = 1
    for name, colour in LAYERS.items():
        doc.layers.add(name, color=colour)
    return doc


@contextmanager
def _writing(what: str):
    """Build a document with ezdxf's fixed metadata (byte-identical rebuilds); its errors become
    ExportError naming ``what``."""
    previous = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    except (ezdxf.DXFError, OSError) as exc:
        raise ExportError(f"cannot write {what}: {exc}") from exc
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = previous


#: the characters a drawing's text uses that DXF writes as its own control codes (read as the
#: character by LibreCAD, GDAL and ezdxf's ``plain_text``)
_CONTROL_CODES = {"Ø": "%%c", "ø": "%%c", "°": "%%d", "±": "%%p"}


def ascii_text(text: str) -> str:
    """``text`` as a DXF holds it in ASCII: Ø, ° and ± as DXF's control codes ``%%c``, ``%%d``,
    ``%%p``, any other character past ASCII as its ``\\U+XXXX`` escape — never raw bytes a reader
    takes in the file's code page (R2000's ANSI_1252 showed a UTF-8 Ø as "Ã˜")."""
    if text.isascii():  # a whole drawing, mostly: not rebuilt a character at a time
        return text
    return "".join(c if ord(c) < 128 else _CONTROL_CODES.get(c, f"\\U+{ord(c):04X}") for c in text)


def _write(doc) -> bytes:
    """The document's DXF bytes, ASCII whatever its text (:func:`ascii_text`)."""
    buf = io.StringIO()
    doc.write(buf)
    return ascii_text(buf.getvalue()).encode("ascii")


def add_contour(msp, verts: np.ndarray, version: str, layer: str) -> None:
    """One closed bulge polyline (LWPOLYLINE, or POLYLINE for R12) on ``layer``."""
    attribs = {"layer": layer}
    if version == "R12":
        msp.add_polyline2d(verts.tolist(), format="xyb", close=True, dxfattribs=attribs)
    else:
        msp.add_lwpolyline(verts.tolist(), format="xyb", close=True, dxfattribs=attribs)


def _cross(msp, x: float, y: float, size: float, layer: str) -> None:
    msp.add_line((x - size, y), (x + size, y), dxfattribs={"layer": layer})
    msp.add_line((x, y - size), (x, y + size), dxfattribs={"layer": layer})


def dxf_bytes(part: DxfPart, version: str = "R2000", tolerance: float = DXF_ARC_TOLERANCE_MM, arcs=None) -> bytes:
    """The DXF of ``part`` (see the module docstring), as bytes; ``arcs`` are the section's
    :func:`section_arcs` when the caller has them already (without a wire offset)."""
    with _writing(f"the DXF of {part.name}"):
        doc = _new_doc(version)
        msp = doc.modelspace()
        section = part.section if part.wire_offset is None else wire_path(part.section, part.wire_offset)
        if part.wire_offset is not None:
            doc.layers.get(CUT).dxf.color = 5
        if arcs is None or part.wire_offset is not None or tolerance != DXF_ARC_TOLERANCE_MM:
            arcs = section_arcs(section, tolerance)
        for verts, inner in arcs:
            add_contour(msp, verts, version, part.layer)
            if inner and part.layer == CUT:
                placed = start_hole(verts, part.start_hole)
                if isinstance(placed, str):
                    x, y = verts[0, :2]
                    msp.add_text(placed, dxfattribs={"layer": "ANNOTATION", "height": 0.5}).set_placement((x, y))
                else:
                    msp.add_circle(placed, part.start_hole / 2, dxfattribs={"layer": "START_HOLES"})
        minx, miny, maxx, maxy = section.bounds
        height = max(2.0, 0.02 * (maxy - miny))
        for path in part.paths:
            pts = np.asarray(path, dtype=float)[:, :2].tolist()
            if version == "R12":
                msp.add_polyline2d(pts, dxfattribs={"layer": "ANNOTATION"})
            else:
                msp.add_lwpolyline(pts, format="xy", dxfattribs={"layer": "ANNOTATION"})
        for x, y, text in part.marks:
            _cross(msp, x, y, 0.4 * height, "ANNOTATION")
            msp.add_text(text, dxfattribs={"layer": "ANNOTATION", "height": 0.5 * height}).set_placement(
                (x + 0.5 * height, y + 0.5 * height)
            )
        label = f"{part.name} (mm)" + ("" if part.wire_offset is None else f", wire path offset {part.wire_offset:g}")
        if part.layer != CUT:
            label += f"; outline on layer {part.layer}: {OUTLINES[part.layer]}"
        for k, line in enumerate((label, *part.notes)):
            msp.add_text(line, dxfattribs={"layer": "ANNOTATION", "height": height}).set_placement(
                (minx, miny - (k + 2) * 1.6 * height)
            )
        return _write(doc)


def _bulge_points(verts, flatten: float) -> np.ndarray:
    """Points of a closed bulge polyline, each arc from ezdxf.math.bulge_to_arc sampled exactly
    (every arc's points at once: :func:`~transplanter.shop.arcs.with_arcs`)."""
    v = np.asarray(verts, dtype=float)
    rows = v.tolist()
    arcs = []
    for k, (x0, y0, b) in enumerate(rows):
        if b == 0:
            continue
        x1, y1, _ = rows[(k + 1) % len(rows)]
        centre, a0, a1, r = bulge_to_arc((x0, y0), (x1, y1), b)
        if r == 0.0:  # a bulge on a segment of no length: no arc, nothing between its ends
            continue
        sweep = (a1 - a0) % (2 * math.pi)
        steps = max(1, int(math.ceil(sweep / (2 * math.acos(max(-1.0, 1 - flatten / r))))))
        arcs.append((k, centre.x, centre.y, r, a0, sweep, steps, b < 0))  # a clockwise arc walked back
    return with_arcs(v[:, :2], arcs)


def _outline_polylines(data: bytes, layer: str | None = None) -> list[np.ndarray]:
    """Bulge vertices (n, 3) of every polyline of the outline, as ezdxf reads them: on ``layer``,
    or (None) on the one layer of :data:`OUTLINES` the drawing has them on (:func:`outline_layer`)."""
    found = _parsed_outlines(data)
    if layer is None:
        layer = outline_layer(data)
    elif layer not in OUTLINES:
        raise SpecError.out_of_range("layer", layer, " or ".join(repr(k) for k in OUTLINES))
    return [v.copy() for v in found.get(layer, ())]


def outline_layer(data: bytes) -> str:
    """The layer of :data:`OUTLINES` a drawing has its outline on — what the drawing is (a part to
    cut, a reference, a bought part); ExportError if it has none, or contours on more than one."""
    found = sorted(_parsed_outlines(data))
    if len(found) != 1:
        on = f"on {' and '.join(found)}" if found else f"on none of {', '.join(OUTLINES)}"
        raise ExportError(f"the DXF must have its closed contours on one outline layer: they are {on}")
    return found[0]


@functools.lru_cache(maxsize=64)
def _parsed_outlines(data: bytes) -> dict[str, tuple[np.ndarray, ...]]:
    # a part's DXF is read back by its own check, by the meshing check and by the assembly
    # drawing: parse it once (ezdxf's parser is most of the cost; a machine reads ~40 DXFs, and
    # with room for 8 it parsed 58 times)
    doc = ezdxf.read(io.StringIO(data.decode()))
    out: dict[str, list[np.ndarray]] = {}
    for e in doc.modelspace().query("LWPOLYLINE POLYLINE"):
        if e.dxf.layer not in OUTLINES:
            continue
        if e.dxftype() == "LWPOLYLINE":
            verts = [(x, y, b) for x, y, b in e.get_points("xyb")]
        else:
            verts = [(v.dxf.location.x, v.dxf.location.y, v.dxf.bulge) for v in e.vertices]
        out.setdefault(e.dxf.layer, []).append(np.array(verts, dtype=float))
    return {k: tuple(v) for k, v in out.items()}


def bulge_contours(data: bytes, layer: str | None = None) -> list[tuple[np.ndarray, bool]]:
    """The outline's contours as read (on ``layer``, or the drawing's :func:`outline_layer`), bulge
    vertices ``(n, 3)`` each, the largest (by :func:`bulge_area`) first and the others marked as
    holes: ``[(verts, is_hole)]``, the form ``section_arcs`` gives."""
    polys = _outline_polylines(data, layer)
    if not polys:
        raise ExportError(f"the DXF has no closed contour on its {layer} layer")
    order = sorted(range(len(polys)), key=lambda k: -abs(bulge_area(polys[k])))
    return [(polys[k], i > 0) for i, k in enumerate(order)]


def arc_centres(data: bytes, layer: str | None = None) -> list[np.ndarray]:
    """Every arc of the outline's contours as read, per contour (largest first, as
    :func:`bulge_contours`, on ``layer`` or the drawing's own): ``(n, 4)`` rows of centre x, y,
    radius and sweep (rad), by ``ezdxf.math.bulge_to_arc`` — where a shop's CAM finds a hole's
    or a nose's centre."""
    out = []
    for verts, _ in bulge_contours(data, layer):
        rows = []
        for k in range(len(verts)):
            x0, y0, b = verts[k]
            if b == 0:
                continue
            x1, y1, _ = verts[(k + 1) % len(verts)]
            centre, _, _, r = bulge_to_arc((x0, y0), (x1, y1), b)
            rows.append((centre.x, centre.y, r, abs(4 * math.atan(b))))
        out.append(np.array(rows, dtype=float).reshape(-1, 4))
    return out


def read_contours(data: bytes, flatten: float = 1e-5, layer: str | None = None) -> list[np.ndarray]:
    """Closed contours of the outline (on ``layer``, or the drawing's :func:`outline_layer`):
    vertices and bulges as ezdxf reads them, each arc rebuilt with ``ezdxf.math.bulge_to_arc`` and
    sampled to ``flatten`` mm (ezdxf's own path flattening goes through cubic Béziers, which miss
    a 90° arc by 2.7e-4 of its radius)."""
    return [_bulge_points(v, flatten) for v in _outline_polylines(data, layer)]


def lettering(span: float) -> float:
    """The drawing's lettering height (mm) for a drawing ``span`` mm across: 2 % of it, rounded up
    to the ISO 3098 series and never below 3.5 mm (ISO 3098's size for dimensions on a drawing
    printed 1:1) — so the text stays readable when a large drawing is printed to fit a page."""
    want = max(3.5, 0.02 * span)
    return next((h for h in ISO_3098_HEIGHTS_MM if h >= want - 1e-9), ISO_3098_HEIGHTS_MM[-1])


#: :data:`DIMSTYLE`'s values apart from the lettering's: true scale (DIMSCALE 1, DIMLFAC 1), decimal
#: mm to 4 places with a point and no trailing zeros, text above the line and aligned with it, the
#: closed filled arrow, colours by layer
_DIMSTYLE_SCALE = {"dimscale": 1.0, "dimlfac": 1.0, "dimlunit": 2, "dimdec": 4, "dimzin": 8, "dimdsep": ord(".")}
_DIMSTYLE_LOOK = {"dimtad": 1, "dimtih": 0, "dimtoh": 0, "dimtxsty": "Standard", "dimblk": ""}
_DIMSTYLE_COLOURS = {"dimclrd": 256, "dimclre": 256, "dimclrt": 256}


def _add_dimension_style(doc, height: float) -> None:
    """:data:`DIMSTYLE` in the document's table for lettering ``height`` (mm; arrows and extension
    lines in proportion), and the same values as the header's ``$DIM*`` defaults with
    ``$DIMSTYLE`` naming it (a reader that takes the header, as LibreCAD does for some, finds the
    same)."""
    h = height
    values = {**_DIMSTYLE_SCALE, **_DIMSTYLE_LOOK, **_DIMSTYLE_COLOURS, "dimtxt": h, "dimasz": h}
    values |= {"dimgap": 0.25 * h, "dimexe": 0.5 * h, "dimexo": 0.5 * h}
    doc.dimstyles.new(DIMSTYLE, dxfattribs=dict(values))
    doc.header["$DIMSTYLE"] = DIMSTYLE
    for key, value in values.items():
        doc.header[f"${key.upper()}"] = value


def assembly_bytes(
    name: str,
    parts: list[tuple[str, bytes, tuple[float, float, float]]],
    notes: tuple[str, ...] = (),
) -> bytes:
    """An assembly drawing (R2000): each part's outline contours, read from its DXF ``bytes`` and
    placed at ``(x, y, angle_rad)`` (turned about its own origin, then moved), on layer PARTS;
    a centre cross at each part's axis (CENTRES) and an aligned dimension from the first
    part's axis to each other's (DIMENSIONS), in the :data:`DIMSTYLE` dimension style with no
    entity override; the notes (ANNOTATION), in :func:`lettering` as the dimensions. Nothing is
    on CUT: the drawing is for assembly, not for the wire."""
    with _writing(f"the assembly drawing {name}"):
        doc = _new_doc("R2000")
        for layer, colour in (("PARTS", 7), ("CENTRES", 1), ("DIMENSIONS", 5)):
            doc.layers.add(layer, color=colour)
        msp = doc.modelspace()
        span = 0.0
        for _, data, (x, y, angle) in parts:
            c, s_ = math.cos(angle), math.sin(angle)
            for verts in _outline_polylines(data):
                moved = verts.copy()
                moved[:, 0] = x + c * verts[:, 0] - s_ * verts[:, 1]
                moved[:, 1] = y + s_ * verts[:, 0] + c * verts[:, 1]
                add_contour(msp, moved, "R2000", "PARTS")
                span = max(span, float(np.max(np.hypot(moved[:, 0], moved[:, 1]))))
        height = lettering(2 * span)
        _add_dimension_style(doc, height)
        x0, y0, _ = parts[0][2]
        for k, (label, _, (x, y, _)) in enumerate(parts):
            _cross(msp, x, y, 2 * height, "CENTRES")
            # the first part's name left of its centre, the others' right of theirs: two names
            # never run into each other between neighbouring centres
            side = -1.0 if k == 0 else 1.0
            msp.add_text(label, dxfattribs={"layer": "ANNOTATION", "height": height}).set_placement(
                (x + side * 0.6 * height, y - 1.6 * height),
                align=TextEntityAlignment.TOP_RIGHT if k == 0 else TextEntityAlignment.TOP_LEFT,
            )
            if k:
                dim = msp.add_aligned_dim(
                    p1=(x0, y0),
                    p2=(x, y),
                    distance=-(span * 0.15 + 4 * height),
                    dimstyle=DIMSTYLE,
                    dxfattribs={"layer": "DIMENSIONS"},
                )
                dim.render()
        for k, line in enumerate((f"{name}: assembly in the start position (mm)", *notes)):
            msp.add_text(line, dxfattribs={"layer": "ANNOTATION", "height": height}).set_placement(
                (-span, -span - (k + 2) * 1.6 * height)
            )
        return _write(doc)


def read_section(data: bytes, flatten: float = 5e-5, layer: str | None = None) -> shapely.Polygon:
    """The part section a DXF describes: its outline's contours (on ``layer``, or the drawing's
    :func:`outline_layer`) nested even-odd (the largest is the outline, contours inside it holes),
    as one shapely polygon; arcs flattened to 0.05 µm, a tenth of the arc fit's tolerance."""
    polys = sorted((shapely.Polygon(c) for c in read_contours(data, flatten, layer)), key=lambda p: -p.area)
    if not polys:
        raise ExportError(f"the DXF has no closed contour on its {layer} layer")
    section = polys[0]
    for p in polys[1:]:
        section = shapely.symmetric_difference(section, p)
    if not isinstance(section, shapely.Polygon) or not section.is_valid:
        raise ExportError("the DXF's outline contours do not nest into one part section")
    return section


def _one_way(points: np.ndarray, ring: np.ndarray) -> float:
    return float(distance_to_ring(ring)(points).max())


def contour_deviation(source: np.ndarray, readback: np.ndarray) -> float:
    """Largest distance between two closed contours, both ways: every vertex and edge midpoint of
    each against the other's edges (an STRtree keeps it n log n)."""
    a = np.asarray(source, dtype=float)
    b = np.asarray(readback, dtype=float)
    a = a[:-1] if np.allclose(a[0], a[-1]) else a
    b = b[:-1] if np.allclose(b[0], b[-1]) else b
    am = np.concatenate([a, 0.5 * (a + np.roll(a, -1, axis=0))])
    bm = np.concatenate([b, 0.5 * (b + np.roll(b, -1, axis=0))])
    return max(_one_way(am, b), _one_way(bm, a))
