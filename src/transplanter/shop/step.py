"""STEP (ISO 10303-21, AP214) of prismatic parts from exact lines and arcs, with OCP (OpenCASCADE).

A part's section is the DXF's: its contours as one-sided arc fits (``arcs.section_arcs``), each
a closed run of bulge vertices. Every straight span becomes a line edge and every bulged span a
circular arc through its end points and its mid point (``GC_MakeArcOfCircle``), neighbouring
edges sharing one vertex; the outer wire (counter-clockwise) and the hole wires (clockwise) make a planar face, which
is extruded along +z by the width (``BRepPrimAPI_MakePrism``). The solid is therefore exactly
the DXF's section × width — the same lines and arcs a wire-EDM shop cuts — never the STL's
triangles, and its volume is known in closed form (:func:`arcs_area`). A section of more than
``4 × SECTOR_EDGES`` edges has its two planar faces split into sectors by straight cuts across
the material (:func:`_sectors`): the same solid, but no face bounded by thousands of edges, which
OpenCASCADE's importers repair in time that grows with the square of that count (the seed-004
ring: 98.6 s → 4.5 s in OCP's reader with its default repairs, 56 s → 4.8 s in gmsh;
``benchmarks/step_import.py``).

The file's header is fixed (part name, no time stamp, transplanter as the originating system),
so rebuilding gives identical bytes. :func:`read_step` re-reads a file with OCP's own
STEP reader; :func:`solid_report` checks a shape the way a CAD system does on import
(one solid, valid by ``BRepCheck_Analyzer`` or, above ``FULL_CHECK_FACES``, a closed and
consistently oriented shell) and measures its volume (``BRepGProp``).

OCP is imported on first use (it is large): importing this module is cheap.

Examples
--------
>>> import numpy as np
>>> square_with_round_end = np.array([[0, 0, 0], [10, 0, 1], [10, 10, 0], [0, 10, 0]], float)
>>> round(arcs_area([(square_with_round_end, False)]), 9)  # 100 + a half disc of radius 5
139.26990817
"""

from __future__ import annotations

import cmath
import functools
import math
import os
import re
import tempfile
from dataclasses import dataclass

import numpy as np
import shapely

from transplanter.core.errors import ExportError, GeometryError
from transplanter.core.tolerances import FLAT_ARC_RADIUS_MM
from transplanter.shop.arcs import bulge_area, bulge_points
from transplanter.shop.step_writing import fixed_header, model_bytes, write_settings

__all__ = ["arcs_area", "prism", "step_bytes", "read_step", "SolidReport", "solid_report"]


def arcs_area(contours: list[tuple[np.ndarray, bool]]) -> float:
    """Exact area (mm²) of a section given as closed bulge contours ``[(verts (n, 3), is_hole)]``
    (``arcs.bulge_area`` of each, the holes subtracted)."""
    return sum(-abs(bulge_area(v)) if hole else abs(bulge_area(v)) for v, hole in contours)


@functools.cache
def _occ():
    """The OCP modules this file uses, imported once, with OpenCASCADE's console messages off."""
    from OCP import (
        GC,
        BRepBuilderAPI,
        BRepCheck,
        BRepGProp,
        BRepPrimAPI,
        GeomConvert,
        GProp,
        IFSelect,
        Interface,
        Message,
        STEPControl,
        TopAbs,
        TopExp,
        gp,
    )
    from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
    from OCP.BRep import BRep_Builder
    from OCP.StepData import StepData_StepWriter
    from OCP.TCollection import TCollection_AsciiString, TCollection_HAsciiString
    from OCP.TopoDS import TopoDS, TopoDS_Shell, TopoDS_Solid, TopoDS_Wire

    for printer in Message.Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message.Message_Gravity.Message_Fail)
    ns = {}
    for mod in (BRepBuilderAPI, BRepCheck, BRepGProp, BRepPrimAPI, GC, GProp, Interface, STEPControl, IFSelect):
        ns.update({k: getattr(mod, k) for k in dir(mod) if not k.startswith("_")})
    ns["GeomConvert"] = GeomConvert.GeomConvert
    ns.update({k: getattr(m, k) for m in (TopAbs, TopExp, gp) for k in dir(m) if not k.startswith("_")})
    ns["MakeHeader"] = APIHeaderSection_MakeHeader
    ns["StepData_StepWriter"] = StepData_StepWriter
    ns["BRep_Builder"] = BRep_Builder
    ns["TopoDS_Wire"] = TopoDS_Wire
    ns["TopoDS_Shell"] = TopoDS_Shell
    ns["TopoDS_Solid"] = TopoDS_Solid
    ns["TopoDS"] = TopoDS
    ns["HString"] = TCollection_HAsciiString
    ns["AString"] = TCollection_AsciiString
    return type("OCC", (), ns)


def _edges(occ, verts: np.ndarray) -> tuple[list, list]:
    """The vertices of bulge vertices ``(n, 3)`` and the edge of each span (span k from vertex k
    to k + 1: a line, or an arc through its end points and mid point), neighbours sharing one
    vertex."""
    n = len(verts)
    pts = [occ.gp_Pnt(float(x), float(y), 0.0) for x, y, _ in verts]
    vertices = [occ.BRepBuilderAPI_MakeVertex(p).Vertex() for p in pts]
    edges = []
    for k in range(n):
        j = (k + 1) % n
        (x0, y0, bulge), (x1, y1, _) = verts[k], verts[j]
        if bulge == 0.0:
            edge = occ.BRepBuilderAPI_MakeEdge(vertices[k], vertices[j])
        else:
            # the arc's mid point lies off the chord's mid point by the sagitta, bulge × half chord,
            # to the right of the chord for a counter-clockwise (positive) arc
            dx, dy = x1 - x0, y1 - y0
            s = bulge / 2.0
            mid = occ.gp_Pnt((x0 + x1) / 2 + s * dy, (y0 + y1) / 2 - s * dx, 0.0)
            arc = occ.GC_MakeArcOfCircle(pts[k], mid, pts[j])
            if not arc.IsDone():
                raise GeometryError(f"cannot build the STEP arc from ({x0:g}, {y0:g}) to ({x1:g}, {y1:g}) mm")
            curve = arc.Value()
            if math.hypot(dx, dy) / (2 * abs(math.sin(2 * math.atan(bulge)))) > FLAT_ARC_RADIUS_MM:
                # STEP's 13 significant digits would put this circle's centre µm off: the same arc as
                # a rational B-spline, whose poles lie by the chord
                curve = occ.GeomConvert.CurveToBSplineCurve_s(curve)
            edge = occ.BRepBuilderAPI_MakeEdge(curve, vertices[k], vertices[j])
        if not edge.IsDone():
            raise GeometryError(f"cannot build the STEP edge from ({x0:g}, {y0:g}) to ({x1:g}, {y1:g}) mm")
        edges.append(edge.Edge())
    return vertices, edges


def _wire_of(occ, edges):
    """A closed wire of ``edges`` that join in order through shared vertices, assembled directly
    (BRepBuilderAPI_MakeWire searches the wire for each new edge's vertex: quadratic)."""
    wire = occ.TopoDS_Wire()
    builder = occ.BRep_Builder()
    builder.MakeWire(wire)
    for edge in edges:
        builder.Add(wire, edge)
    wire.Closed(True)
    return wire


def _wire(occ, verts: np.ndarray):
    """A closed wire of lines and arcs through bulge vertices ``(n, 3)``, the vertices shared."""
    return _wire_of(occ, _edges(occ, verts)[1])


#: a planar face bounded by more edges than this is split into sectors (:func:`_sectors`)
SECTOR_EDGES = 80


def prism(contours: list[tuple[np.ndarray, bool]], width: float):
    """The OCC solid: the face bounded by ``contours`` (the first the outline) extruded by ``width``;
    above ``4 × SECTOR_EDGES`` edges its two planar faces are split into sectors (:func:`_sectors`)."""
    occ = _occ()
    outer = [v for v, hole in contours if not hole]
    if len(outer) != 1:
        raise GeometryError(f"a STEP part needs exactly one outer contour, got {len(outer)}")
    if sum(len(v) for v, _ in contours) > 4 * SECTOR_EDGES:
        sectored = _sectors(occ, contours, width)
        if sectored is not None:
            return sectored
    # on the plane z = 0, normal +z (the outline counter-clockwise): given, not fitted to the points
    face = occ.BRepBuilderAPI_MakeFace(occ.gp_Pln(), _wire(occ, outer[0]), True)
    for verts, hole in contours:
        if hole:  # clockwise (``arcs.section_arcs`` orients the section): material on its left
            face.Add(_wire(occ, verts))
    if not face.IsDone():
        raise GeometryError("the STEP section does not make a planar face")
    return occ.BRepPrimAPI_MakePrism(face.Face(), occ.gp_Vec(0.0, 0.0, float(width))).Shape()


def _subdivided(verts: np.ndarray, n: int) -> np.ndarray:
    """The closed contour ``verts`` (bulge vertices), each line or arc split into ``n`` alike: the same curve."""
    out = []
    for k, (x0, y0, b) in enumerate(verts):
        p0, p1, t = complex(x0, y0), complex(*verts[(k + 1) % len(verts), :2]), 4.0 * math.atan(b)
        c = (p0 + p1) / 2 + 1j * (p1 - p0) / 2 / math.tan(t / 2) if t else 0j  # the arc's centre
        pts = [c + (p0 - c) * cmath.exp(1j * t * j / n) if t else p0 + (p1 - p0) * j / n for j in range(n)]
        out += [(p.real, p.imag, math.tan(t / (4 * n))) for p in pts]
    return np.array(out, dtype=float)


def _cuts(outer, inner, inner_ring, others, count: int) -> list[tuple[int, int]] | None:
    """``count`` cuts across the material, each ``(inner vertex, outer vertex)``: a straight line
    from a vertex of the largest hole ``inner`` (bulge vertices; ``inner_ring`` its points) to the
    vertex of the outline ``outer`` nearest its angle, inside the section (arcs flattened to 1 µm)
    and 0.05 mm clear of every other hole (``others``, polygons), in order of angle; None when
    fewer than two are found or they do not run round both contours in the same order.

    The cuts aim at the angles that share both contours' edges out evenly — by edge count, not by
    even angles: a sector gear's edges crowd into its toothed arc, and even angles left its faces
    ~220 edges each; each cut looks for a hole vertex within 0.45 of the gap to its neighbours."""
    section = shapely.Polygon(bulge_points(outer, 1e-3), [inner_ring, *(h.exterior.coords for h in others)])
    shapely.prepare(section)
    others = shapely.union_all([h.buffer(0.05) for h in others])
    angle_in = np.arctan2(inner[:, 1], inner[:, 0]) % (2 * math.pi)
    angle_out = np.arctan2(outer[:, 1], outer[:, 0]) % (2 * math.pi)
    radius_in = np.hypot(inner[:, 0], inner[:, 1])
    n_out = len(outer)
    every = np.sort(np.concatenate([angle_out, angle_in]))  # both contours' edges, by angle
    targets = every[(np.arange(count) * len(every)) // count]
    gaps = np.abs(np.angle(np.exp(1j * (targets - np.roll(targets, 1)))))
    window = 0.45 * np.minimum(gaps, np.roll(gaps, -1))
    found: list[tuple[int, int]] = []
    for target, reach in zip(targets, window, strict=True):
        off = np.abs(np.angle(np.exp(1j * (angle_in - target))))
        near = np.flatnonzero(off < reach)
        for a in sorted(near, key=lambda i: (round(off[i] / reach * 9), -radius_in[i])):
            b = int(np.argmin(np.abs(np.angle(np.exp(1j * (angle_out - angle_in[a]))))))
            line = shapely.LineString([inner[a, :2], outer[b, :2]])
            ends = (line.interpolate(1e-6, normalized=True), line.interpolate(1 - 1e-6, normalized=True))
            inside = shapely.LineString(ends)
            if section.contains(inside) and not inside.intersects(others):
                found.append((int(a), b))
                break
    found = sorted(set(found), key=lambda c: angle_in[c[0]])
    if len({a for a, _ in found}) != len(found) or len({b for _, b in found}) != len(found) or len(found) < 2:
        return None
    # both contours' runs between neighbouring cuts must go once round: the hole's clockwise, the
    # outline's counter-clockwise (a crossing pair of cuts would fold a sector over another)
    outs = [b for _, b in found]
    ins = [a for a, _ in found]
    if sum((outs[(k + 1) % len(outs)] - outs[k]) % n_out for k in range(len(outs))) != n_out:
        return None
    if sum((ins[k] - ins[(k + 1) % len(ins)]) % len(inner) for k in range(len(ins))) != len(inner):
        return None
    return found


def _run(verts: np.ndarray, start: int, stop: int) -> np.ndarray:
    """The points of a closed contour's bulge vertices from vertex ``start`` to ``stop`` along it,
    arcs flattened to 1 µm (a sector's boundary, to tell which holes it holds)."""
    n = len(verts)
    pieces = []
    for j in range((stop - start) % n or n):
        k = (start + j) % n
        span = np.array([verts[k], [verts[(k + 1) % n, 0], verts[(k + 1) % n, 1], 0.0]])
        pieces.append(bulge_points(span, 1e-3)[:-1])
    pieces.append(verts[stop % n, :2][None])
    return np.concatenate(pieces)


def _sectors(occ, contours, width: float):
    """The prism with its two planar faces split into sectors (one per ``SECTOR_EDGES`` edges) by
    straight cuts from the largest hole to the outline (:func:`_cuts`), the other holes in the
    sector that holds them: the same lines and arcs, the same solid (the cuts are edges on its
    planar faces, no wall), but no face bounded by thousands of edges — OpenCASCADE's import
    (gmsh, FreeCAD, OCP) grows with the square of a face's edge count: the seed-004 ring's
    5744-edge faces took 56 s in gmsh, its 72 sectors 4.8 s. None where the section has no hole or
    no cuts are found (the caller makes the plain prism)."""
    holes = [v for v, hole in contours if hole]
    if not holes:
        return None
    outer = next(v for v, hole in contours if not hole)
    inner = max(holes, key=lambda v: abs(bulge_area(v)))
    # the other holes, each to go into the sector that holds it
    rest = [(h, shapely.Polygon(bulge_points(h, 1e-3))) for h in holes if h is not inner]
    count = max(2, round(sum(len(v) for v, _ in contours) / SECTOR_EDGES))
    if len(inner) < 4 * count:  # a plain bore (a circle of a few arcs): room for a cut at each target
        inner = _subdivided(inner, -(-4 * count // len(inner)))
    cuts = _cuts(outer, inner, bulge_points(inner, 1e-3), [p for _, p in rest], count)
    if cuts is None:
        return None
    out_v, out_e = _edges(occ, outer)
    in_v, in_e = _edges(occ, inner)
    cut_e = [occ.BRepBuilderAPI_MakeEdge(in_v[a], out_v[b]).Edge() for a, b in cuts]
    builder = occ.BRep_Builder()
    shell = occ.TopoDS_Shell()
    builder.MakeShell(shell)
    n_out, n_in = len(outer), len(inner)
    regions: list[shapely.Polygon] = []
    sector_faces = []
    for k in range(len(cuts)):
        (a0, b0), (a1, b1) = cuts[k], cuts[(k + 1) % len(cuts)]
        along_out = [out_e[(b0 + j) % n_out] for j in range((b1 - b0) % n_out or n_out)]
        along_in = [in_e[(a1 + j) % n_in] for j in range((a0 - a1) % n_in or n_in)]  # the hole runs clockwise
        edges = [*along_out, occ.TopoDS.Edge(cut_e[(k + 1) % len(cuts)].Reversed()), *along_in, cut_e[k]]
        face = occ.BRepBuilderAPI_MakeFace(occ.gp_Pln(), _wire_of(occ, edges), True)
        regions.append(shapely.Polygon(np.concatenate([_run(outer, b0, b1), _run(inner, a1, a0)])))
        sector_faces.append(face)
    # each other hole in exactly one sector (the one that holds a point inside it), or no sectors
    for h, polygon in rest:
        point = polygon.representative_point()
        holding = [k for k, region in enumerate(regions) if region.is_valid and region.contains(point)]
        if len(holding) != 1:
            return None
        sector_faces[holding[0]].Add(_wire(occ, h))
    for face in sector_faces:
        if not face.IsDone():
            return None
        builder.Add(shell, face.Face())
    made = occ.BRepPrimAPI_MakePrism(shell, occ.gp_Vec(0.0, 0.0, float(width)))
    walls: dict[int, list] = {}  # by hash (OCP's: the shape and its place, as IsSame), then IsSame
    for e in cut_e:
        for f in made.Generated(e):
            walls.setdefault(hash(f), []).append(f)
    solid_shell = occ.TopoDS_Shell()
    builder.MakeShell(solid_shell)
    cells = occ.TopExp_Explorer(made.Shape(), occ.TopAbs_ShapeEnum.TopAbs_SOLID)
    while cells.More():
        faces = occ.TopExp_Explorer(cells.Current(), occ.TopAbs_ShapeEnum.TopAbs_FACE)
        while faces.More():
            face = faces.Current()
            if not any(face.IsSame(w) for w in walls.get(hash(face), ())):
                builder.Add(solid_shell, face)
            faces.Next()
        cells.Next()
    solid = occ.TopoDS_Solid()
    builder.MakeSolid(solid)
    builder.Add(solid, solid_shell)
    return solid


def step_bytes(name: str, shape) -> bytes:
    """AP214 STEP of an OCC solid (:func:`prism`; see the module docstring), in mm, as bytes."""
    occ = _occ()
    write_settings(occ)
    writer = occ.STEPControl_Writer()
    # compgraph=False: the session's entity graph and its check of every entity (quadratic in a
    # face's edge count: 60 % of a ring gear's export) are for its own file writer; the model is
    # written by the STEP writer that one calls, giving the same bytes
    if writer.Transfer(shape, occ.STEPControl_StepModelType.STEPControl_AsIs, False) != occ.IFSelect_RetDone:
        raise ExportError(f"cannot write the STEP of {name}: OpenCASCADE refused the solid")
    fixed_header(occ, writer, name)
    data = model_bytes(occ, writer, f"the STEP of {name}")
    # the writer numbers its products per process ('... translator 8.0 3'): name the part instead
    return re.sub(rb"PRODUCT\('[^']*',\s*'[^']*'", b"PRODUCT('%s','%s'" % (name.encode(), name.encode()), data, count=1)


#: OpenCASCADE's import repairs self-intersecting wires, wires crossing each other on a face and
#: re-orients a face's wires with searches that grow with the square of a face's edge count
#: (minutes for a ring gear's 5800-face solid; the crossing-wires search alone was 40 % of its
#: 10 s re-read), and re-fits every edge's parameters to its face (a fifth of the rest); checking
#: a file must see what it holds, not a repaired version, so these repairs are off
#: ("0": do not perform) — the solid's validity is then asked of ``BRepCheck_Analyzer`` or the
#: closed-shell check (:func:`solid_report`), and a wrongly oriented hole shows in the volume.
#: (The wire repair that derives each edge's 2D curve on its face stays on: the files carry none.)
READ_REPAIR = {
    "FixShape.FixSelfIntersectionMode": "0",
    "FixShape.FixIntersectingWiresMode": "0",
    "FixShape.FixOrientationMode": "0",
    "FixShape.FixSameParameterMode": "0",
}


def read_step(data: bytes):
    """The shape in STEP ``data`` (OCP's STEPControl_Reader, without the wire repair
    ``READ_REPAIR`` switches off); ExportError if it cannot be read."""
    occ = _occ()
    with tempfile.TemporaryDirectory(prefix="transplanter-step-") as d:
        path = os.path.join(d, "part.step")
        with open(path, "wb") as f:
            f.write(data)
        reader = occ.STEPControl_Reader()
        if reader.ReadFile(path) != occ.IFSelect_RetDone:
            raise ExportError("the STEP file cannot be parsed")
        params = reader.GetShapeFixParameters()  # after ReadFile: the map goes to its transfer actor
        for key, value in READ_REPAIR.items():
            params.Bind(occ.AString(key), occ.AString(value))
        reader.SetShapeFixParameters(params)
        if reader.TransferRoots() < 1:
            raise ExportError("the STEP file holds no shape")
        return reader.OneShape()


#: up to this many faces a solid is checked by ``BRepCheck_Analyzer``, whose vertex check explores
#: the whole solid for every vertex (quadratic: ~0.1 s at 300 faces, ~1.5 s at a gear's 1250,
#: ~60 s for a ring gear's 5800); above it, by the linear checks a closed solid must pass (see
#: :func:`solid_report`)
FULL_CHECK_FACES = 500


@dataclass(frozen=True)
class SolidReport:
    """A STEP shape as a CAD import sees it: solids, faces, validity (None: not checked) and by
    which check ("BRepCheck_Analyzer" or "closed shell"), volume (mm³)."""

    solids: int
    faces: int
    valid: bool | None
    volume: float
    check: str = ""


def _closed_shell(occ, shape) -> bool:
    """Every edge bounds exactly two faces, used once forward and once reversed (a closed,
    consistently oriented shell): linear in the edge count."""
    from OCP.collections import IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as EdgeFaces
    from OCP.TopAbs import TopAbs_Orientation

    ancestors = EdgeFaces()
    occ.TopExp.MapShapesAndAncestors_s(
        shape, occ.TopAbs_ShapeEnum.TopAbs_EDGE, occ.TopAbs_ShapeEnum.TopAbs_FACE, ancestors
    )
    if ancestors.Extent() == 0:
        return False
    for k in range(1, ancestors.Extent() + 1):
        if ancestors.FindFromIndex(k).Size() != 2:
            return False
    uses: dict[tuple[int, int], int] = {}
    faces = occ.TopExp_Explorer(shape, occ.TopAbs_ShapeEnum.TopAbs_FACE)
    while faces.More():
        face = faces.Current()
        edges = occ.TopExp_Explorer(face, occ.TopAbs_ShapeEnum.TopAbs_EDGE)
        while edges.More():
            e = edges.Current()
            forward = e.Orientation() == TopAbs_Orientation.TopAbs_FORWARD  # composed with the face's
            key = (ancestors.FindIndex(e), int(forward))
            uses[key] = uses.get(key, 0) + 1
            edges.Next()
        faces.Next()
    return all(uses.get((k, 0)) == 1 and uses.get((k, 1)) == 1 for k in range(1, ancestors.Extent() + 1))


def solid_report(shape, check: bool = True) -> SolidReport:
    """Count the solids and faces of ``shape``, measure its volume and, with ``check``, check it:
    ``BRepCheck_Analyzer`` up to ``FULL_CHECK_FACES`` faces, beyond that a closed, consistently
    oriented shell (each edge bounding two faces, once each way) — for an extruded section whose
    contours the DXF check proved simple, with the volume right, that is a valid solid."""
    occ = _occ()

    def count(kind) -> int:
        explorer = occ.TopExp_Explorer(shape, kind)
        n = 0
        while explorer.More():
            n += 1
            explorer.Next()
        return n

    props = occ.GProp_GProps()
    occ.BRepGProp.VolumeProperties_s(shape, props)
    faces = count(occ.TopAbs_ShapeEnum.TopAbs_FACE)
    valid, how = None, ""
    if check and faces <= FULL_CHECK_FACES:
        valid, how = bool(occ.BRepCheck_Analyzer(shape).IsValid()), "BRepCheck_Analyzer"
    elif check:
        valid, how = _closed_shell(occ, shape), "closed shell"
    return SolidReport(
        solids=count(occ.TopAbs_ShapeEnum.TopAbs_SOLID),
        faces=faces,
        valid=valid,
        volume=float(props.Mass()),
        check=how,
    )
