"""The assembly STEP (ISO 10303-21, AP214) of a machine: every body a named solid, placed.

A body is a :class:`Solid` in its own frame — slabs of a section extruded along +z: a made part
is its DXF's lines and arcs extruded by its width (:meth:`Solid.prism`, the solid
:mod:`~transplanter.shop.step` writes for the part alone; a part mounted face down is the same
solid turned over, :func:`frame`'s ``flip``), a bought part a simple solid of its catalogue
dimensions (:func:`solid_of`: :meth:`Solid.ring` for a bearing, a bush, a washer or a circlip,
:meth:`Solid.box` for a key, :meth:`Solid.screw` for a cap screw, :meth:`Solid.hexagon` for a
nut; :meth:`Solid.rod` for a shaft or a pin) — and a :class:`Placed` body puts it where the body
sits at the start by a 4×4 transform (:func:`frame`). The file is an assembly of OpenCASCADE's
XCAF document (``STEPCAFControl_Writer``): one product per part, ``"<item> <part>"``, and one
occurrence of it per body, ``"<item> <body>"`` (``NEXT_ASSEMBLY_USAGE_OCCURRENCE``), so a CAD
tree, gmsh and the bill of materials name the same thing by the same item number; the three
planets of a machine are three occurrences of one product.

**Deterministic.** The header is :mod:`~transplanter.shop.step`'s (no time stamp, transplanter
as the originating system) and the occurrences' ids, which OpenCASCADE numbers per process, are
numbered in the file's order: rebuilding gives identical bytes.

**Checked.** :func:`write_checked` checks the solids it writes (each part one solid of its exact
volume), as a part's STEP is checked when it is written; :mod:`~transplanter.shop.assembly_read`
reads the file back, with OCP and with gmsh, one volume per body where it was placed. A machine's
assembly holds all its parts' arcs (seed 002's: 31 bodies, 22 MB, ~25 s to read): it is re-read
when the export is checked, not at every build.

OCP is imported on first use.

Examples
--------
>>> plate = Solid.ring(0.0, 20.0, 5.0)  # a disc: Ø20 x 5
>>> round(plate.volume, 6), round(Solid.ring(10.0, 20.0, 5.0).volume, 6)
(1570.796327, 1178.097245)
>>> frame(1.0, 2.0, 3.0, flip=True)[:3, 2].tolist()  # the body's +z turned to -z
[0.0, 0.0, -1.0]
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from transplanter.core import heap
from transplanter.core.errors import ExportError, GeometryError, SpecError, check_number
from transplanter.core.precision import significant
from transplanter.core.tolerances import SOLID_VOLUME_REL
from transplanter.shop import step, step_writing

__all__ = ["Placed", "Slab", "Solid", "frame", "solid_of", "step_bytes", "write_checked"]


def _circle(r: float, hole: bool = False) -> np.ndarray:
    """A circle of radius ``r`` about the origin as two half arcs (bulge vertices; clockwise for a hole)."""
    b = -1.0 if hole else 1.0
    return np.array([[r, 0.0, b], [-r, 0.0, b]])


@dataclass(frozen=True)
class Slab:
    """A section (bulge contours ``[(verts (n, 3), is_hole)]``, the outline first, mm) extruded
    along +z from ``z0`` by ``width`` (mm)."""

    contours: tuple
    z0: float
    width: float

    @property
    def area(self) -> float:
        """The section's exact area, mm²."""
        return step.arcs_area(list(self.contours))

    @property
    def volume(self) -> float:
        return self.area * self.width


@dataclass(frozen=True)
class Solid:
    """A body's solid in its own frame: slabs stacked along z (touching, never overlapping)."""

    slabs: tuple[Slab, ...]

    def __post_init__(self) -> None:
        if not self.slabs:
            raise SpecError("a Solid needs at least one slab")
        spans = sorted((s.z0, s.z0 + s.width) for s in self.slabs)
        for s in self.slabs:
            check_number("slab width", s.width, 0.0, 1e5, low_open=True, unit="mm")
        if any(b[0] < a[1] - 1e-12 for a, b in zip(spans, spans[1:], strict=False)):
            raise SpecError(f"the slabs of a Solid overlap along z: {spans}")

    @property
    def volume(self) -> float:
        """The exact volume, mm³ (each slab's arcs' area × width)."""
        return sum(s.volume for s in self.slabs)

    @classmethod
    def prism(cls, contours, width: float) -> Solid:
        """A made part: its section's bulge contours (a DXF's, the outline counter-clockwise, the
        holes clockwise) extruded by ``width`` from z = 0."""
        return cls((Slab(tuple((np.asarray(v, float), bool(h)) for v, h in contours), 0.0, width),))

    @classmethod
    def ring(cls, inner_d: float, outer_d: float, width: float) -> Solid:
        """An annulus ``inner_d`` .. ``outer_d`` × ``width`` about z from z = 0 (a disc for
        ``inner_d`` 0): a bearing d .. D × B, a bush, a washer, a circlip."""
        check_number("outer diameter", outer_d, inner_d, 1e5, low_open=True, unit="mm")
        contours = [(_circle(outer_d / 2), False)]
        if inner_d > 0:
            contours.append((_circle(inner_d / 2, hole=True), True))
        return cls((Slab(tuple(contours), 0.0, width),))

    @classmethod
    def rod(cls, d: float, length: float) -> Solid:
        """A shaft or a pin: a cylinder Ø``d`` × ``length`` from z = 0."""
        return cls.ring(0.0, d, length)

    @classmethod
    def box(cls, b: float, h: float, length: float) -> Solid:
        """A key: ``b`` across x, ``h`` up y, ``length`` along z from z = 0, centred on the z axis in x
        and standing on y = 0."""
        verts = np.array([[-b / 2, 0.0, 0.0], [b / 2, 0.0, 0.0], [b / 2, h, 0.0], [-b / 2, h, 0.0]])
        return cls((Slab(((verts, False),), 0.0, length),))

    @classmethod
    def hexagon(cls, across_flats: float, hole_d: float, height: float) -> Solid:
        """A nut: a hexagon ``across_flats`` with a hole Ø``hole_d``, ``height`` from z = 0."""
        r = across_flats / math.sqrt(3.0)
        a = math.pi / 6 + np.arange(6) * math.pi / 3
        verts = np.column_stack([r * np.cos(a), r * np.sin(a), np.zeros(6)])
        return cls((Slab(((verts, False), (_circle(hole_d / 2, hole=True), True)), 0.0, height),))

    @classmethod
    def screw(cls, d: float, length: float, head_d: float, head_h: float) -> Solid:
        """A cap screw: its head Ø``head_d`` × ``head_h`` below z = 0, its shank Ø``d`` × ``length``
        (the nominal length, under the head) above."""
        head = Slab(((_circle(head_d / 2), False),), -head_h, head_h)
        shank = Slab(((_circle(d / 2), False),), 0.0, length)
        return cls((head, shank))


def solid_of(part) -> Solid:
    """The simple solid of a part the catalogue (:mod:`transplanter.shop.catalogue`) chose, about
    its own z axis from z = 0: a bearing or a bush its ring d .. D × B, a washer its ring, a
    retaining ring the ring it fills round its groove (DIN 471: groove diameter .. + 2 lug
    heights; DIN 472: groove diameter - 2 lug heights .. groove diameter, its thickness), a key its
    box b × h × length (standing on y = 0), a cap screw its head below z = 0 and its shank above,
    a nut its hexagon; SpecError for anything else."""
    from transplanter.shop import catalogue as c

    if isinstance(part, c.SelectedBearing | c.Bearing | c.SelectedBush | c.Bush):
        row = getattr(part, "bearing", None) or getattr(part, "bush", None) or part
        return Solid.ring(row.d, row.D, row.B)
    if isinstance(part, c.Washer):
        return Solid.ring(part.inner, part.outer, part.thickness)
    if isinstance(part, c.Circlip):
        g = part.groove_diameter
        inner, outer = (g, g + 2 * part.lug) if part.standard == "DIN 471" else (g - 2 * part.lug, g)
        return Solid.ring(inner, outer, part.s)
    if isinstance(part, c.Key):
        return Solid.box(part.b, part.h, part.length)
    if isinstance(part, c.Screw):
        return Solid.screw(part.d, part.length, part.head_diameter, part.head_height)
    if isinstance(part, c.Nut):
        return Solid.hexagon(part.across_flats, part.d, part.height)
    raise SpecError(f"no simple solid for a bought {type(part).__name__}: expected a catalogue part")


def frame(x: float = 0.0, y: float = 0.0, z: float = 0.0, angle: float = 0.0, flip: bool = False) -> np.ndarray:
    """4×4 placement: the body (turned half a turn about its x-axis first, with ``flip``: its +z
    then points down) turned by ``angle`` (rad) about z, then moved to (x, y, z) mm."""
    c, s = math.cos(angle), math.sin(angle)
    t = np.eye(4)
    t[:2, :2] = [[c, -s], [s, c]]
    if flip:
        t[:3, :3] = t[:3, :3] @ np.diag([1.0, -1.0, -1.0])
    t[:3, 3] = (x, y, z)
    return t


@dataclass(frozen=True)
class Placed:
    """One body of the assembly: its name, the part it is an occurrence of (bodies of one part
    share its solid), the bill of materials' item number, the solid and its 4×4 placement."""

    name: str
    part: str
    item: int
    solid: Solid
    at: np.ndarray

    def __post_init__(self) -> None:
        at = np.asarray(self.at, dtype=float)
        if at.shape != (4, 4) or not np.allclose(at[:3, :3] @ at[:3, :3].T, np.eye(3), atol=1e-9):
            raise SpecError(f"{self.name}: the placement must be a 4x4 rigid transform")
        for what in (self.name, self.part):
            if not isinstance(what, str) or not what or "/" in what or "'" in what:
                raise SpecError(f"assembly body name {what!r} must be a non-empty name without / or '")

    @property
    def label(self) -> str:
        """The occurrence's name in the file: ``"<item> <body>"``."""
        return f"{self.item} {self.name}"

    @property
    def product(self) -> str:
        """The product's name in the file: ``"<item> <part>"``."""
        return f"{self.item} {self.part}"


@functools.cache
def xcaf_modules():
    """The OCP modules of the XCAF document, imported once (shared with the reader)."""
    from OCP import (
        TDF,
        BRepAlgoAPI,
        BRepBuilderAPI,
        IFSelect,
        STEPCAFControl,
        TCollection,
        TDataStd,
        TDocStd,
        TopLoc,
        XCAFDoc,
    )
    from OCP.collections import Sequence_TDF_Label

    ns = {"TDF_LabelSequence": Sequence_TDF_Label}
    for mod in (BRepAlgoAPI, BRepBuilderAPI, IFSelect, STEPCAFControl, TCollection, TDataStd, TDF, TDocStd, TopLoc):
        ns.update({k: getattr(mod, k) for k in dir(mod) if not k.startswith("_")})
    ns["XCAFDoc_DocumentTool"] = XCAFDoc.XCAFDoc_DocumentTool
    return type("XCAF", (), ns)


def _shape(solid: Solid):
    """The OCC solid of ``solid``: each slab :func:`step.prism`, moved to its z, fused."""
    occ, x = step._occ(), xcaf_modules()
    shape = None
    for slab in solid.slabs:
        piece = step.prism(list(slab.contours), slab.width)
        if slab.z0:
            t = occ.gp_Trsf()
            t.SetTranslation(occ.gp_Vec(0.0, 0.0, float(slab.z0)))
            piece = x.BRepBuilderAPI_Transform(piece, t, True).Shape()
        if shape is None:
            shape = piece
        else:
            fused = x.BRepAlgoAPI_Fuse(shape, piece)
            if not fused.IsDone():
                raise GeometryError("cannot fuse the slabs of an assembly body")
            shape = _one_solid(occ, fused.Shape())
    return shape


def _solids(occ, shape) -> list:
    explorer = occ.TopExp_Explorer(shape, occ.TopAbs_ShapeEnum.TopAbs_SOLID)
    found = []
    while explorer.More():
        found.append(explorer.Current())
        explorer.Next()
    return found


def count_solids(occ, shape) -> int:
    """How many solids an OCC shape holds (shared with the reader)."""
    return len(_solids(occ, shape))


def _one_solid(occ, shape):
    found = _solids(occ, shape)
    if len(found) != 1:
        raise GeometryError(f"an assembly body's slabs fuse into {len(found)} solids, not one")
    return occ.TopoDS.Solid(found[0])


def _trsf(occ, at: np.ndarray):
    t = occ.gp_Trsf()
    m = np.asarray(at, dtype=float)
    t.SetValues(*(float(v) for v in m[:3, :4].ravel()))
    return t


def _name(x, label, text: str) -> None:
    x.TDataStd_Name.Set_s(label, x.TCollection_ExtendedString(text))


def step_bytes(name: str, placed: list[Placed]) -> bytes:
    """The assembly ``name`` of the ``placed`` bodies as AP214 STEP bytes (module docstring)."""
    return write_checked(name, placed)[0]


def write_checked(name: str, placed: list[Placed]) -> tuple[bytes, dict]:
    """The STEP bytes (:func:`step_bytes`) and the check of the solids written: each part's one
    solid, of its exact volume within ``SOLID_VOLUME_REL`` (GeometryError otherwise) — the
    build's check, as :mod:`~transplanter.shop.formats` checks a part's STEP;
    :func:`transplanter.shop.assembly_read.verify` re-reads the file."""
    if not placed:
        raise SpecError(f"the assembly {name} has no body")
    labels = [p.label for p in placed]
    if len(set(labels)) != len(labels):
        raise SpecError(f"the assembly {name} names a body twice: {sorted({n for n in labels if labels.count(n) > 1})}")
    found: dict = {}
    lines = _lines(name, placed, found)
    heap.trim(0)  # what went with _lines' document and writer handed back before the file is made
    data = step_writing.joined(lines)
    error = significant(found["worst"])
    return data, {"bodies": len(placed), "parts": found["parts"], "volume_rel_error": error, "reread": False}


def _lines(name: str, placed: list[Placed], found: dict):
    """The assembly's STEP text lines (:func:`~transplanter.shop.step_writing.sent`): its XCAF
    document of one product per part (each checked, ``found`` given their count and the largest
    volume error) and one named occurrence per body, transferred. The transfer's results and the
    document are dropped before the lines are made, the writer when this returns, and the lines
    are joined by :func:`~transplanter.shop.step_writing.joined` (issue 46: seed 002's, a 23 MB
    file, written in ~240 MB more than the process held before, not ~390)."""
    occ, x = step._occ(), xcaf_modules()
    doc = x.TDocStd_Document(x.TCollection_ExtendedString("XmlOcaf"))
    tool = x.XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    root = tool.NewShape()
    _name(x, root, name)
    parts: dict[str, object] = {}
    worst = 0.0
    for p in placed:
        if p.product not in parts:
            shape = _shape(p.solid)
            volume = mass_properties(occ, shape)[0]
            err = abs(volume / p.solid.volume - 1.0)
            if count_solids(occ, shape) != 1 or err >= SOLID_VOLUME_REL:
                raise GeometryError(
                    f"{p.product}: its assembly solid encloses {volume:.6f} mm3, {p.solid.volume:.6f} exact"
                )
            worst = max(worst, err)
            parts[p.product] = tool.AddShape(shape, False)
            _name(x, parts[p.product], p.product)
        occurrence = tool.AddComponent(root, parts[p.product], x.TopLoc_Location(_trsf(occ, p.at)))
        _name(x, occurrence, p.label)
    found.update(parts=len(parts), worst=worst)
    tool.UpdateAssemblies()
    step_writing.write_settings(occ)
    writer = x.STEPCAFControl_Writer()
    writer.SetNameMode(True)
    if not writer.Transfer(doc, occ.STEPControl_StepModelType.STEPControl_AsIs):
        raise ExportError(f"cannot write the assembly STEP {name}: OpenCASCADE refused the document")
    inner = writer.ChangeWriter()
    step_writing.fixed_header(occ, inner, name)
    _number_occurrences(inner.Model())
    inner.WS().ClearData(5)  # the transfer's results (from shapes to entities): the model stays
    del doc, tool, root, parts, shape, occurrence
    return step_writing.sent(occ, inner)


def _number_occurrences(model) -> None:
    """The occurrences' ids, which OpenCASCADE counts up per process, numbered in the model's
    order instead (identical bytes on every rebuild)."""
    from OCP.StepRepr import StepRepr_NextAssemblyUsageOccurrence as Occurrence

    # the occurrences picked out by OpenCASCADE in the model's order (a Python loop over seed 002's
    # 465 000 entities took 3.9 s)
    found = model.Entities()
    found.SelectType(Occurrence.get_type_descriptor_s(), True)
    count = 0
    found.Start()
    while found.More():
        count += 1
        found.Value().SetId(step._occ().HString(str(count)))
        found.Next()


def mass_properties(occ, shape) -> tuple[float, np.ndarray]:
    """The volume (mm³) and centre of mass (mm) of an OCC shape (shared with the reader)."""
    props = occ.GProp_GProps()
    occ.BRepGProp.VolumeProperties_s(shape, props)
    c = props.CentreOfMass()
    return props.Mass(), np.array([c.X(), c.Y(), c.Z()])
