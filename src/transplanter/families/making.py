"""How a prismatic part is made: section, solid, DXF and STL with their checks."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely

from transplanter import dxf, solids, stl
from transplanter.errors import ExportError, GeometryError, SpecError, check_number, finite_positive
from transplanter.export import rounded, significant
from transplanter.tolerances import DXF_READBACK_MM

#: re-read DXF points outside the part by more than this (mm) count as added material: float
#: round-off of the arc reconstruction is ~1e-12 mm
ONE_SIDED_MM = 1e-9

#: arcs of the re-read DXF are sampled to this chord (mm): what ``dxf.read_section`` uses for the
#: meshing check, a tenth of the arc fit's tolerance; the samples lie on the arcs exactly, so the
#: one-sided check is unaffected, and the read-back deviation is overstated by at most this
READBACK_FLATTEN_MM = 5e-5

__all__ = ["Making", "manufacture", "material_added", "read_shop_file", "split_unreadable", "ONE_SIDED_MM"]


@dataclass(frozen=True)
class Making:
    """How a part is made: face width (mm), holes, wire (diameter, spark gap, mm), DXF versions."""

    width: float
    features: solids.Features = field(default_factory=solids.Features)
    wire: tuple[float, float] = (0.25, 0.02)
    dxf_versions: tuple[str, ...] = ("R2000",)

    def __post_init__(self) -> None:
        finite_positive("face width", self.width)
        if not isinstance(self.features, solids.Features):
            raise SpecError(f"features must be solids.Features, got {type(self.features).__name__}")
        if not isinstance(self.wire, tuple | list) or len(self.wire) != 2:
            raise SpecError.out_of_range("wire", self.wire, "(diameter, spark gap) in mm")
        check_number("wire diameter", self.wire[0], 0.0, 5.0, low_open=True, unit="mm")
        check_number("wire spark gap", self.wire[1], 0.0, 1.0, unit="mm")
        for v in self.dxf_versions:
            if v not in ("R2000", "R12"):
                raise SpecError.out_of_range("dxf_versions", self.dxf_versions, "'R2000' and/or 'R12'")


def _matching(src: np.ndarray, contours: list[np.ndarray]) -> np.ndarray:
    """The read-back contour that corresponds to ``src``: nearest perimeter plus centroid offset."""

    def key(c):
        per = float(np.sum(np.linalg.norm(np.diff(c, axis=0), axis=1)))
        return abs(per - src_len) + float(np.linalg.norm(c.mean(axis=0) - src.mean(axis=0)))

    src_len = float(np.sum(np.linalg.norm(np.diff(src, axis=0), axis=1)))
    return min(contours, key=key)


def read_shop_file(name: str, data: bytes, reader):
    """``reader(data)`` — a DXF/STL/CSV reader — or ExportError saying the file cannot be read
    (a truncated or damaged file must be reported as such, not end the check)."""
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


def material_added(section: shapely.Polygon, contours: list[np.ndarray]) -> float:
    """Largest distance (mm) by which re-read ``contours`` stray outside ``section``: 0 when an
    approximation only removed material (the DXF's one-sided arc fit)."""
    pts = np.concatenate(contours)
    shapely.prepare(section)
    out = ~shapely.contains_xy(section, pts[:, 0], pts[:, 1])
    if not out.any():
        return 0.0
    return float(shapely.distance(section, shapely.points(pts[out])).max())


def manufacture(
    stem: str, blank, cut, making: Making, notes: tuple[str, ...], locate, marks: tuple = ()
) -> tuple[dict, dict]:
    """Section, solid, DXF and STL of one prismatic part, with their checks.

    ``locate(point)`` names where a wire violation sits (e.g. "tooth space 12"); ``marks`` go
    to the DXF's ANNOTATION layer (``dxf.DxfPart.marks``). The DXF must re-read within
    ``DXF_READBACK_MM`` of the section and never outside it (:func:`material_added` below
    ``ONE_SIDED_MM``: the arc fit may remove material, never add it).
    """
    section = solids.part_section(blank, cut, making.features)
    wire_r = making.wire[0] / 2 + making.wire[1]
    bad = dxf.wire_violations(section, wire_r)
    if not bad.is_empty:
        worst = max(bad.geoms, key=lambda g: g.area)
        where = locate(worst.centroid.coords[0])
        raise GeometryError(
            f"{stem}: an inside corner at {where} is tighter than the wire radius {wire_r:.4g} mm "
            f"(wire {making.wire[0]:g} mm + gap {making.wire[1]:g} mm; {len(bad.geoms)} places, "
            f"{worst.area:.3g} mm² uncut here); use a finer wire or a larger cutter tip fillet"
        )
    solid = solids.part_solid(blank, cut, making.features, making.width)
    expected = section.area * making.width
    files: dict[str, bytes] = {}
    results: dict = {
        "section_area_mm2": rounded(section.area, 6),
        "solid_volume_mm3": rounded(solid.volume(), 6),
        "volume_rel_error": significant(abs(solid.volume() / expected - 1)),
        "wire_radius_mm": wire_r,
    }
    data = stl.stl_bytes(solid)
    rep = stl.mesh_report(data)
    results["stl"] = {
        "triangles": rep.triangles,
        "watertight": rep.watertight,
        "winding_consistent": rep.winding_consistent,
        "volume_rel_error": significant(abs(rep.volume / expected - 1)),
    }
    if not (rep.watertight and rep.winding_consistent and abs(rep.volume / expected - 1) < 1e-6):
        raise GeometryError(f"{stem}: the STL fails its checks {results['stl']}")
    files[f"{stem}.stl"] = data
    rings = [np.asarray(section.exterior.coords), *(np.asarray(r.coords) for r in section.interiors)]
    for version in making.dxf_versions:
        data = dxf.dxf_bytes(dxf.DxfPart(stem, section, notes, marks=marks), version)
        back = dxf.read_contours(data, READBACK_FLATTEN_MM)
        crossing = [shapely.is_valid_reason(shapely.Polygon(c)) for c in back if not shapely.Polygon(c).is_valid]
        if crossing:
            raise GeometryError(f"{stem}: a DXF contour is not a simple closed curve after the arc fit: {crossing[0]}")
        dev = max(dxf.contour_deviation(src, _matching(src, back)) for src in rings)
        added = material_added(section, back)
        results[f"dxf_{version}"] = {
            "contours": len(back),
            "readback_deviation_mm": significant(dev),
            "material_added_mm": significant(added),
        }
        if dev > DXF_READBACK_MM:
            raise GeometryError(
                f"{stem}: the DXF re-reads {dev * 1000:.3f} µm from the source (limit {DXF_READBACK_MM * 1000:g} µm)"
            )
        if added > ONE_SIDED_MM:
            raise GeometryError(
                f"{stem}: the DXF adds material: a re-read contour lies {added * 1000:.4f} µm outside the part "
                f"(limit {ONE_SIDED_MM:g} mm; the arc fit must only remove material)"
            )
        suffix = "" if version == "R2000" else f".{version}"
        files[f"{stem}{suffix}.dxf"] = data
    return results, files
