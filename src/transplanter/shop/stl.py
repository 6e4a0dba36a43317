"""Binary STL of manifold3d solids (trimesh), with the checks a shop's slicer or CAM would make.

The mesh is brought to a canonical order (vertices merged, faces sorted) so rebuilding gives
identical bytes even though manifold3d may order triangles differently between runs.
:func:`mesh_report` checks watertightness, consistent outward winding and the volume; tests
also run admesh (Debian's package) on the files when it is installed. :func:`section` cuts a
re-read STL at a height (default mid-plane) back into a 2D part section.

Examples
--------
>>> import manifold3d
>>> from transplanter.shop.stl import stl_bytes, mesh_report
>>> data = stl_bytes(manifold3d.Manifold.cube((10.0, 20.0, 5.0)))
>>> r = mesh_report(data)
>>> r.watertight, r.winding_consistent, round(r.volume, 9)
(True, True, 1000.0)
"""

from __future__ import annotations

import io
from dataclasses import dataclass

import numpy as np
import shapely
import trimesh

from transplanter.core.errors import GeometryError

__all__ = ["canonical_mesh", "stl_bytes", "StlReport", "mesh_report", "section"]


def canonical_mesh(solid) -> trimesh.Trimesh:
    """The trimesh of a manifold3d solid in canonical order (see the module docstring)."""
    mesh = solid.to_mesh()
    verts = np.asarray(mesh.vert_properties)[:, :3].astype(float)
    faces = np.asarray(mesh.tri_verts).astype(np.int64)
    tm = trimesh.Trimesh(verts, faces, process=True, validate=False)
    # canonical order: vertices lexicographically, each face rotated to start at its lowest
    # index (keeps the winding), faces sorted
    order = np.lexsort(tm.vertices.T[::-1])
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    f = rank[tm.faces]
    roll = np.argmin(f, axis=1)
    f = np.take_along_axis(f, (np.arange(3)[None, :] + roll[:, None]) % 3, axis=1)
    f = f[np.lexsort(f.T[::-1])]
    return trimesh.Trimesh(tm.vertices[order], f, process=False, validate=False)


def stl_bytes(solid) -> bytes:
    """Binary STL of a manifold3d solid, in canonical order."""
    tm = canonical_mesh(solid)
    if len(tm.faces) == 0:
        raise GeometryError("cannot write an STL of an empty solid")
    return trimesh.exchange.stl.export_stl(tm)


@dataclass(frozen=True)
class StlReport:
    triangles: int
    watertight: bool
    winding_consistent: bool
    volume: float
    outward: bool


def mesh_report(data: bytes) -> StlReport:
    """Re-read an STL and check it (trimesh)."""
    tm = trimesh.load(io.BytesIO(data), file_type="stl", process=True)
    return StlReport(
        triangles=len(tm.faces),
        watertight=bool(tm.is_watertight),
        winding_consistent=bool(tm.is_winding_consistent),
        volume=float(tm.volume),
        outward=bool(tm.volume > 0),
    )


def section(data: bytes, z: float | None = None) -> shapely.Polygon:
    """Section of an STL by the plane at height ``z`` (default: mid-height), as a shapely polygon.

    The triangles' intersection segments (trimesh ``mesh_plane``), snapped to 1e-9 mm so that
    neighbours share end points, are assembled by ``shapely.build_area`` (even-odd nesting:
    holes stay holes), and collinear points dropped. Coordinates carry the STL's float32
    resolution (~1e-5 mm at 100 mm).
    """
    tm = trimesh.load(io.BytesIO(data), file_type="stl")
    lo, hi = tm.bounds[:, 2]
    z = 0.5 * (lo + hi) if z is None else float(z)
    if not lo < z < hi:
        raise GeometryError(f"section height z = {z:g} mm is outside the solid ({lo:g}..{hi:g} mm)")
    lines = trimesh.intersections.mesh_plane(tm, [0.0, 0.0, 1.0], [0.0, 0.0, z])
    area = shapely.build_area(shapely.multilinestrings(shapely.linestrings(np.round(lines[:, :, :2], 9))))
    # each side quad is two triangles: drop the collinear points their diagonals leave (2 nm
    # tolerance, a tenth of float32's resolution at 100 mm — the outline's vertices stay)
    area = shapely.simplify(area, 2e-6)
    if not isinstance(area, shapely.Polygon) or area.is_empty:
        raise GeometryError(f"the STL's section at z = {z:g} mm is not one closed part section")
    return area
