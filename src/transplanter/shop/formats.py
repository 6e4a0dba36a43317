"""The shop formats behind one interface: write a made part, read it back, verify it.

A *made part* (:class:`MadePart`) is a prismatic part as the shop receives it: its section
(shapely), its solid (manifold3d), its width and what its drawing says. Each format turns it
into bytes and reads them back the way the shop's software would:

========  ==============================  =======================================  =========================
format    written from                    read back as                             verified
========  ==============================  =======================================  =========================
DXF       the section's one-sided arcs    the section (outline layer, arcs exact)  within 1 µm, never outside
STL       the solid's canonical mesh      the mid-plane section / the mesh         watertight, volume 1e-6
STEP      the same arcs, extruded (OCC)   the OCC solid                            valid solid, volume 1e-6
CSV       a contour's points              the section (outline or profile)         —
3MF       several solids, placed          one body per part, assembled             no two bodies overlap
========  ==============================  =======================================  =========================

:func:`section_of` reads any file that describes a section (DXF, STL, outline or profile CSV)
by its name; the meshing and follower checks read every source through it. Every reader turns
a damaged file into :class:`~transplanter.core.errors.ExportError` naming it. A DXF's outline is
on the layer that says what the drawing is (``MadePart.layer``: ``CUT`` for a part to cut,
``REFERENCE`` or ``BOUGHT`` otherwise, :data:`~transplanter.shop.dxf.OUTLINES`); the readers take
it from there, or from the layer they name.

**STEP verification.** The build checks the solid it writes (one solid, its volume against the
arcs' exact area × width); ``transplanter check`` and the tests re-read the file and check it
as a CAD import does (:meth:`Step.verify`: a valid solid — ``BRepCheck_Analyzer``, or above
``step.FULL_CHECK_FACES`` (500) faces a closed, consistently oriented shell — and the volume against
the DXF's own arcs). OpenCASCADE's import and ``BRepCheck_Analyzer`` grow faster than a
face's edge count: re-reading takes ~1 s for a 1270-face gear and ~4 s for the 5900-face ring
(its planar faces in sectors, ``step.SECTOR_EDGES``) — fine for a check, too slow for every build.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import shapely

from transplanter.core import heap
from transplanter.core.errors import ExportError, GeometryError
from transplanter.core.precision import significant
from transplanter.core.tolerances import DXF_READBACK_MM, ONE_SIDED_MM, READBACK_FLATTEN_MM, SOLID_VOLUME_REL
from transplanter.shop import arcs, dxf, solids, step, stl, threemf
from transplanter.shop.export import csv_array

__all__ = [
    "MadePart",
    "Dxf",
    "Stl",
    "Step",
    "Csv",
    "ThreeMf",
    "DXF",
    "STL",
    "STEP",
    "CSV",
    "THREEMF",
    "section_of",
    "read_shop_file",
    "split_unreadable",
    "placement",
    "ONE_SIDED_MM",
    "CUT",
    "REFERENCE",
    "BOUGHT",
    "REFERENCE_ONLY",
]

#: what a drawing not to cut or make (quantity 0) ships, in its record: a printer, a CAM or a CAD
#: import takes an STL, STEP or 3MF as a part to make
REFERENCE_ONLY = "DXF only: a drawing not to make (no STL or STEP, no 3MF)"


@dataclass(frozen=True)
class MadePart:
    """A prismatic part as made: ``section`` × ``width`` (mm), its manifold3d ``solid``; the DXF's
    ``notes``, ``marks`` ``(x, y, text)`` and open ``paths`` (n, 2) for its ANNOTATION layer, and the
    ``layer`` of its outline: what the drawing is (``dxf.CUT``, a part to cut; ``dxf.REFERENCE``, an
    outline not to cut; ``dxf.BOUGHT``, a bought part)."""

    stem: str
    section: shapely.Polygon
    solid: object
    width: float
    notes: tuple[str, ...] = ()
    marks: tuple[tuple[float, float, str], ...] = ()
    paths: tuple[np.ndarray, ...] = field(default=(), compare=False)
    layer: str = dxf.CUT

    @cached_property
    def arcs(self) -> list[tuple[np.ndarray, bool]]:
        """The section's contours as the DXF's one-sided arcs (``arcs.section_arcs``)."""
        return arcs.section_arcs(self.section)

    @property
    def volume(self) -> float:
        """Section area × width, mm³: what the STL must enclose."""
        return self.section.area * self.width


def _relative(value: float, expected: float) -> float:
    return abs(value / expected - 1)


def _matching(src: np.ndarray, contours: list[np.ndarray]) -> np.ndarray:
    """The read-back contour that corresponds to ``src``: nearest perimeter plus centroid offset."""

    def key(c):
        per = float(np.sum(np.linalg.norm(np.diff(c, axis=0), axis=1)))
        return abs(per - src_len) + float(np.linalg.norm(c.mean(axis=0) - src.mean(axis=0)))

    src_len = float(np.sum(np.linalg.norm(np.diff(src, axis=0), axis=1)))
    return min(contours, key=key)


def material_added(section: shapely.Polygon, contours: list[np.ndarray]) -> float:
    """Largest distance (mm) by which re-read ``contours`` stray outside ``section``: 0 when an
    approximation only removed material (the DXF's one-sided arc fit)."""
    pts = np.concatenate(contours)
    shapely.prepare(section)
    out = ~shapely.contains_xy(section, pts[:, 0], pts[:, 1])
    if not out.any():
        return 0.0
    return float(shapely.distance(section, shapely.points(pts[out])).max())


@dataclass(frozen=True)
class Dxf:
    """DXF for wire EDM (:mod:`transplanter.shop.dxf`), R2000 (``<stem>.dxf``) or R12 (``<stem>.R12.dxf``)."""

    version: str = "R2000"
    name = "dxf"

    @property
    def suffix(self) -> str:
        return ".dxf" if self.version == "R2000" else f".{self.version}.dxf"

    def write(self, part: MadePart) -> bytes:
        dxf_part = dxf.DxfPart(
            part.stem, part.section, part.notes, marks=part.marks, paths=part.paths, layer=part.layer
        )
        return dxf.dxf_bytes(dxf_part, self.version, arcs=part.arcs)

    def read(self, data: bytes, layer: str | None = None) -> shapely.Polygon:
        """The section of the outline on ``layer`` (None: the layer the drawing has it on)."""
        return dxf.read_section(data, layer=layer)

    def contours(self, data: bytes, flatten: float = 1e-5, layer: str | None = None) -> list[np.ndarray]:
        """The outline's contours as points, each arc sampled to ``flatten`` mm (``dxf.read_contours``)."""
        return dxf.read_contours(data, flatten, layer)

    def arcs(self, data: bytes, layer: str | None = None) -> list[tuple[np.ndarray, bool]]:
        """The outline's contours as bulge vertices ``(n, 3)``, largest first, the others holes."""
        return dxf.bulge_contours(data, layer)

    def arc_centres(self, data: bytes, layer: str | None = None) -> list[np.ndarray]:
        """Every arc of the outline's contours, per contour: ``(n, 4)`` centre x, y, radius, sweep (rad)."""
        return dxf.arc_centres(data, layer)

    def assembly(self, name: str, parts: list[tuple[str, bytes, tuple[float, float, float]]], notes=()) -> bytes:
        """An assembly drawing of parts read from their DXF bytes, each placed at ``(x, y, angle_rad)``
        (``dxf.assembly_bytes``): contours, centre crosses, the axis distances dimensioned, notes."""
        return dxf.assembly_bytes(name, parts, tuple(notes))

    def verify(self, part: MadePart, data: bytes) -> dict:
        """Re-read contours — on the part's own layer — simple and closed, within ``DXF_READBACK_MM``
        of the section and never outside it by more than ``ONE_SIDED_MM`` (the arc fit may remove
        material, never add it)."""
        back = dxf.read_contours(data, READBACK_FLATTEN_MM, part.layer)
        crossing = [shapely.is_valid_reason(shapely.Polygon(c)) for c in back if not shapely.Polygon(c).is_valid]
        if crossing:
            raise GeometryError(
                f"{part.stem}: a DXF contour is not a simple closed curve after the arc fit: {crossing[0]}"
            )
        rings = [np.asarray(part.section.exterior.coords), *(np.asarray(r.coords) for r in part.section.interiors)]
        dev = max(dxf.contour_deviation(src, _matching(src, back)) for src in rings)
        added = material_added(part.section, back)
        if dev > DXF_READBACK_MM:
            raise GeometryError(
                f"{part.stem}: the DXF re-reads {dev * 1000:.3f} µm from the source "
                f"(limit {DXF_READBACK_MM * 1000:g} µm)"
            )
        if added > ONE_SIDED_MM:
            raise GeometryError(
                f"{part.stem}: the DXF adds material: a re-read contour lies {added * 1000:.4f} µm outside the part "
                f"(limit {ONE_SIDED_MM:g} mm; the arc fit must only remove material)"
            )
        return {
            "contours": len(back),
            "readback_deviation_mm": significant(dev),
            "material_added_mm": significant(added),
        }


@dataclass(frozen=True)
class Stl:
    """Binary STL (:mod:`transplanter.shop.stl`)."""

    name = "stl"
    suffix = ".stl"

    def write(self, part: MadePart) -> bytes:
        return stl.stl_bytes(part.solid)

    def read(self, data: bytes) -> shapely.Polygon:
        return stl.section(data)

    def verify(self, part: MadePart, data: bytes) -> dict:
        """Watertight, consistently wound, enclosing section area × width within ``SOLID_VOLUME_REL``."""
        rep = stl.mesh_report(data)
        err = _relative(rep.volume, part.volume)
        out = {
            "triangles": rep.triangles,
            "watertight": rep.watertight,
            "winding_consistent": rep.winding_consistent,
            "volume_rel_error": significant(err),
        }
        if not (rep.watertight and rep.winding_consistent and err < SOLID_VOLUME_REL):
            raise GeometryError(f"{part.stem}: the STL fails its checks {out}")
        return out


@dataclass(frozen=True)
class Step:
    """AP214 STEP (:mod:`transplanter.shop.step`): the DXF's lines and arcs extruded by OpenCASCADE."""

    name = "step"
    suffix = ".step"

    def write(self, part: MadePart) -> bytes:
        return self.write_checked(part)[0]

    def write_checked(self, part: MadePart) -> tuple[bytes, dict]:
        """The file and the check of the solid it was written from: one solid, of the arcs'
        volume (the build's check; the file's validity is checked on re-reading it, see the
        module docstring). The OpenCASCADE solid is built once and released afterwards."""
        with heap.released():
            solid = step.prism(part.arcs, part.width)
            data = step.step_bytes(part.stem, solid)
            report = self.report(solid, self.expected_volume(part), part.stem, check=False)
            del solid
        return data, report | {"reread": False}

    def read(self, data: bytes):
        """The OCC shape (``step.read_step``)."""
        return step.read_step(data)

    def expected_volume(self, part: MadePart) -> float:
        """The arcs' exact area × width, mm³."""
        return step.arcs_area(part.arcs) * part.width

    def report(self, shape, expected: float, stem: str, check: bool = True) -> dict:
        """One solid (valid, with ``check``) of volume ``expected`` (within ``SOLID_VOLUME_REL``),
        or GeometryError."""
        rep = step.solid_report(shape, check)
        err = _relative(rep.volume, expected)
        out = {"solids": rep.solids, "faces": rep.faces, "volume_rel_error": significant(err)}
        if rep.check:
            out.update(valid=rep.valid, checked_by=rep.check)
        if rep.solids != 1 or rep.valid is False or err >= SOLID_VOLUME_REL:
            raise GeometryError(f"{stem}: the STEP solid fails its checks {out} (volume {expected:.6f} mm³ expected)")
        return out

    def verify(self, stem: str, data: bytes, dxf_data: bytes, width: float) -> dict:
        """Re-read the file and check its solid against the part's DXF as found: one valid solid
        whose volume is the DXF section's exact area × ``width`` (slow for many flanks: see the
        module docstring)."""
        contours = read_shop_file(f"{stem}.dxf", dxf_data, dxf.bulge_contours)
        shape = read_shop_file(f"{stem}.step", data, self.read)
        return self.report(shape, step.arcs_area(contours) * width, stem) | {"reread": True}


@dataclass(frozen=True)
class Csv:
    """A contour as ``x_mm, y_mm`` rows (an outline), or with leading columns (a cam profile);
    read back as a section — for an internal gear's outline, the material outside it."""

    name = "csv"
    suffix = ".csv"

    def write(self, contour: np.ndarray, leading: dict[str, np.ndarray] | None = None) -> bytes:
        cols = dict(leading or {})
        # what csv_bytes writes for these rows (no field needs quoting), one format per row
        row = ",".join(["{:.6f}"] * len(cols) + ["{:.9f}", "{:.9f}"])
        table = np.column_stack([*(np.asarray(c, dtype=float) for c in cols.values()), np.asarray(contour, float)])
        return "\n".join([",".join([*cols, "x_mm", "y_mm"]), *(row.format(*r) for r in table.tolist()), ""]).encode()

    def read(self, data: bytes, internal: bool = False) -> shapely.Polygon:
        xy = csv_array(data)[:, -2:]
        if not internal:
            return shapely.Polygon(xy)
        # a ring's material: outside the outline, to a rim 5 mm beyond its farthest point
        rim = float(np.linalg.norm(xy, axis=1).max()) + 5.0
        return shapely.Polygon(solids.circle_polygon(0.0, 0.0, rim).exterior.coords, [xy])


@dataclass(frozen=True)
class ThreeMf:
    """3MF assembly (:mod:`transplanter.shop.threemf`): named solids in their assembled positions."""

    name = "3mf"
    suffix = ".3mf"

    def write(self, parts: list[tuple[str, object, np.ndarray]]) -> bytes:
        return threemf.assembly_bytes(parts)

    def read(self, data: bytes) -> dict:
        return threemf.read_assembly(data)

    def verify(self, data: bytes, names: list[str], volumes: dict[str, float] | None = None) -> dict:
        """One closed body per named part (of the given volumes, mm³) and no two overlapping."""
        try:
            return self._verified(self.read(data), names, volumes)
        finally:
            # the re-read meshes hold reference cycles (trimesh's caches): freed now, not at the
            # collector's next pass, and their heap handed back — ~230 MB for the seed-004 ring
            # and planet, which would otherwise lie under the stages that follow
            heap.trim(1)

    def _verified(self, bodies: dict, names: list[str], volumes: dict[str, float] | None) -> dict:
        if sorted(bodies) != sorted(names):
            raise GeometryError(f"the 3MF holds {sorted(bodies)}, expected one body per part {sorted(names)}")
        for name, body in bodies.items():
            if not body.is_watertight:
                raise GeometryError(f"the 3MF body {name} is not closed")
            if volumes and _relative(float(body.volume), volumes[name]) >= SOLID_VOLUME_REL:
                raise GeometryError(f"the 3MF body {name} encloses {body.volume:.6f} mm³, not {volumes[name]:.6f}")
        found = threemf.overlaps(bodies)
        worst = max(found, key=lambda t: t[2], default=("", "", 0.0))
        if worst[2] > threemf.ASSEMBLY_OVERLAP_MM3:
            raise GeometryError(
                f"in the 3MF assembly {worst[0]} and {worst[1]} overlap by {worst[2]:.4g} mm³ "
                f"(limit {threemf.ASSEMBLY_OVERLAP_MM3:g} mm³)"
            )
        return {
            "bodies": len(bodies),
            "pairs_checked": len(found),
            "max_overlap_mm3": significant(worst[2]),
        }


DXF, STL, STEP, CSV, THREEMF = Dxf(), Stl(), Step(), Csv(), ThreeMf()

#: the DXF layers a made part's outline may be on (``MadePart.layer``): a part to cut, an outline
#: not to cut, a bought part (:data:`transplanter.shop.dxf.OUTLINES`)
CUT, REFERENCE, BOUGHT = dxf.CUT, dxf.REFERENCE, dxf.BOUGHT

#: 4×4 placement of a part in an assembly: turned by ``angle`` (rad) about z, then moved (mm)
placement = threemf.placement


def section_of(name: str, data: bytes, internal: bool = False, layer: str | None = None) -> shapely.Polygon:
    """The part section a file describes, read by the format its name says (``.dxf``, ``.stl``,
    ``.csv``); ``internal`` for a ring gear's outline CSV; a DXF's outline from ``layer`` (None:
    the layer the drawing has it on, ``dxf.outline_layer``). ExportError naming the file if it
    cannot be read."""
    fmt = next((f for f in (DXF, STL, CSV) if name.endswith(f.suffix)), None)
    if fmt is None:
        raise ExportError(f"{name}: no section reader for this file type (.dxf, .stl, .csv)")
    if fmt is CSV:
        return read_shop_file(name, data, lambda d: fmt.read(d, internal))
    return read_shop_file(name, data, lambda d: fmt.read(d, layer) if fmt is DXF else fmt.read(d))


def read_shop_file(name: str, data: bytes, reader):
    """``reader(data)`` or ExportError saying the file cannot be read (a truncated or damaged
    file must be reported as such, not end the check)."""
    try:
        return reader(data)
    except Exception as exc:  # any reader's error on damaged bytes
        raise ExportError(f"cannot read {name}: {type(exc).__name__}: {exc}") from exc


def split_unreadable(reports: dict) -> tuple[dict, dict, list[str]]:
    """``{source: report, or the reason its file cannot be read}`` split into the readable
    reports, the results entries ``{source: {"error": reason}}`` and the problems ``source: reason``
    (for a check that must report a damaged file and go on)."""
    bad = {k: v for k, v in sorted(reports.items()) if isinstance(v, str)}
    readable = {k: v for k, v in reports.items() if k not in bad}
    return readable, {k: {"error": v} for k, v in bad.items()}, [f"{k}: {v}" for k, v in bad.items()]
