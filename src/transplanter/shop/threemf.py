"""3MF assemblies: a mechanism's made parts, each one named object, placed where they sit at the start.

A 3MF (3D Manufacturing Format) is what slicers, viewers and most CAD systems open as an
assembly: every part is written once as a mesh in its own frame (the STL's canonical mesh of
its manifold3d solid) and placed by the build item's transform, named by ``partnumber`` and
the object's name. trimesh writes the package; we keep it to the 3MF core specification, which
the 3MF Consortium's lib3mf reads in strict mode (its conformance check, run by the tests): the
production extension's random ``p:UUID`` attributes are dropped (lib3mf refuses a file that uses
that extension without a UUID on every build, item and object — and random ones would change the
bytes at every build), and so are the extension namespaces trimesh declares and repeats on every
build item ("Invalid Attribute in namespace"). Rebuilding gives identical bytes.

:func:`read_assembly` re-reads a package with lib3mf (strict), one body per part in its assembled
position; :func:`overlaps` intersects every two bodies (manifold3d) and returns the volumes
where they overlap — in an assembled mechanism nothing may overlap beyond round-off
(``ASSEMBLY_OVERLAP_MM3``): gears mesh with backlash, plates sit on their own layers.

Examples
--------
>>> import manifold3d, numpy as np
>>> from transplanter.shop.threemf import assembly_bytes, placement, read_assembly, overlaps
>>> cube = manifold3d.Manifold.cube((10.0, 10.0, 10.0))
>>> data = assembly_bytes([("a", cube, placement()), ("b", cube, placement(x=5.0))])
>>> bodies = read_assembly(data)
>>> sorted(bodies), [(a, b, round(v, 6)) for a, b, v in overlaps(bodies)]
(['a', 'b'], [('a', 'b', 500.0)])
"""

from __future__ import annotations

import io
import itertools
import re
import zipfile

import manifold3d
import numpy as np
import trimesh

from transplanter.core.errors import ExportError, GeometryError
from transplanter.core.tolerances import ASSEMBLY_OVERLAP_MM3
from transplanter.shop.stl import canonical_mesh

__all__ = ["ASSEMBLY_OVERLAP_MM3", "placement", "assembly_bytes", "read_assembly", "overlaps"]

#: the 3MF core namespace: the only one our models declare
CORE = b"http://schemas.microsoft.com/3dmanufacturing/core/2015/02"


def placement(x: float = 0.0, y: float = 0.0, z: float = 0.0, angle: float = 0.0) -> np.ndarray:
    """4×4 transform: turned by ``angle`` (rad) about the part's z axis, then moved to (x, y, z) mm."""
    c, s = np.cos(angle), np.sin(angle)
    t = np.eye(4)
    t[:2, :2] = [[c, -s], [s, c]]
    t[:3, 3] = (x, y, z)
    return t


def assembly_bytes(parts: list[tuple[str, object, np.ndarray]]) -> bytes:
    """The 3MF package of ``parts``: ``(name, manifold3d solid, 4×4 placement)`` each."""
    names = [n for n, _, _ in parts]
    if len(set(names)) != len(names):
        raise ExportError(f"an assembly names two parts alike: {names}")
    scene = trimesh.Scene()
    for name, solid, transform in parts:
        scene.add_geometry(canonical_mesh(solid), node_name=name, geom_name=name, transform=np.asarray(transform))
    try:
        # stored, not deflated: the package is rewritten below and deflated once, there
        raw = trimesh.exchange.threemf.export_3MF(scene, compression=zipfile.ZIP_STORED)
    except Exception as exc:  # trimesh or lxml refusing the scene
        raise ExportError(f"cannot write the 3MF assembly of {names}: {type(exc).__name__}: {exc}") from exc
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(raw)) as src, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename.endswith(".model"):
                data = _core_only(data)
            member = zipfile.ZipInfo(info.filename, date_time=(1980, 1, 1, 0, 0, 0))
            member.compress_type = zipfile.ZIP_DEFLATED
            dst.writestr(member, data)
    return out.getvalue()


def _core_only(model: bytes) -> bytes:
    """A trimesh 3MF model part kept to the core specification (module docstring)."""
    model = re.sub(rb' p:UUID="[^"]*"', b"", model)
    model = re.sub(rb' xmlns(?::\w+)?="[^"]*"', b"", model)
    return model.replace(b"<model ", b'<model xmlns="' + CORE + b'" ', 1)


def read_assembly(data: bytes) -> dict[str, trimesh.Trimesh]:
    """The bodies of a 3MF package by part name (its object's name), each moved to its assembled
    position by its build item: read by the 3MF Consortium's lib3mf in strict mode (a warning is an
    error), as a trimesh mesh each. Issue 46: trimesh's own reader parsed each object as one lxml
    tree, ~240 MB more for a moment for the seed-004 ring's 147 000 vertices and triangles; lib3mf
    holds its model in ~60 MB and reads it as fast. lib3mf keeps coordinates and transforms in
    single precision: our vertices are written in it (the canonical mesh), a placement is read to
    6e-8 of its distance (3e-5 mm at 500 mm)."""
    import tempfile

    import lib3mf

    try:
        model = lib3mf.get_wrapper().CreateModel()
        reader = model.QueryReader("3mf")
        reader.SetStrictModeActive(True)
        # (from a file: its buffer call passes every byte as an argument of its own)
        with tempfile.TemporaryDirectory(prefix="transplanter-3mf-") as folder:
            path = f"{folder}/assembly.3mf"
            with open(path, "wb") as f:
                f.write(data)
            reader.ReadFromFile(path)
        bodies = {}
        items = model.GetBuildItems()
        while items.MoveNext():
            item = items.GetCurrent()
            mesh = model.GetMeshObjectByID(item.GetObjectResource().GetResourceID())
            name = mesh.GetName()
            if name in bodies:
                raise ExportError(f"the 3MF places the body {name} twice")
            bodies[name] = _placed_mesh(mesh, item)
    except lib3mf.ELib3MFException as exc:  # damaged bytes, or a file strict mode refuses
        raise ExportError(f"the 3MF cannot be read: {exc}") from exc
    return bodies


def _placed_mesh(mesh, item) -> trimesh.Trimesh:
    """A lib3mf mesh object as a trimesh mesh, moved by its build item's transform (lib3mf's 4
    rows of 3: a row vector times it)."""
    vertices, triangles = mesh.GetVertices(), mesh.GetTriangleIndices()
    if not vertices or not triangles:
        raise ExportError(f"the 3MF body {mesh.GetName()} has no triangle")
    # (each struct is a view of the array lib3mf filled: its ``_b_base_``, read as one buffer)
    xyz = np.frombuffer(bytes(vertices[0]._b_base_), dtype=np.float32).reshape(-1, 3)
    faces = np.frombuffer(bytes(triangles[0]._b_base_), dtype=np.uint32).reshape(-1, 3)
    fields = item.GetObjectTransform().Fields
    transform = np.eye(4)
    transform[:3, :4] = np.array([fields[r][:] for r in range(4)], dtype=np.float64).T
    body = trimesh.Trimesh(xyz.astype(np.float64), faces.astype(np.int64), process=False)
    return body.apply_transform(transform)


def _manifold(mesh: trimesh.Trimesh) -> manifold3d.Manifold:
    m = manifold3d.Manifold(
        manifold3d.Mesh(
            vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
            tri_verts=np.asarray(mesh.faces, dtype=np.uint32),
        )
    )
    if m.status() != manifold3d.Error.NoError:
        raise GeometryError(f"a 3MF body is not a closed manifold: {m.status()}")
    return m


def overlaps(bodies: dict[str, trimesh.Trimesh]) -> list[tuple[str, str, float]]:
    """``(a, b, volume mm³)`` for every two bodies whose bounding boxes meet, their common volume."""
    solids = {k: _manifold(v) for k, v in sorted(bodies.items())}
    boxes = {k: v.bounds for k, v in sorted(bodies.items())}
    out = []
    for a, b in itertools.combinations(sorted(solids), 2):
        (lo_a, hi_a), (lo_b, hi_b) = boxes[a], boxes[b]
        if np.any(lo_a > hi_b) or np.any(lo_b > hi_a):
            continue
        out.append((a, b, float((solids[a] ^ solids[b]).volume())))
    return out
