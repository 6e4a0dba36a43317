"""An assembly STEP (:mod:`~transplanter.shop.assembly_step`) read back, as a CAD system opens it.

:func:`read_bodies` finds every body of the file's top assembly with OCP's own XCAF reader (the
wire repairs :func:`~transplanter.shop.step.read_step` switches off, off here too) or with gmsh's
importer — an independent reader, on the test extra: each body by its occurrence's name
(``"<item> <body>"``), its volume, its centre of mass where the file places it, and how many solids
it holds. :func:`verify` holds them to the bodies placed: one volume per body, of the body's exact
volume within ``SOLID_VOLUME_REL``, its centre of mass where its placement puts its product's
within ``PLACEMENT_MM``.

OCP and gmsh are imported on first use.
"""

from __future__ import annotations

import os
import tempfile

import numpy as np

from transplanter.core.errors import ExportError, GeometryError, SpecError
from transplanter.core.precision import significant
from transplanter.core.tolerances import SOLID_VOLUME_REL
from transplanter.shop import step
from transplanter.shop.assembly_step import Placed, count_solids, mass_properties, xcaf_modules

__all__ = ["PLACEMENT_MM", "READERS", "read_bodies", "verify"]

#: a re-read body's centre of mass may lie this far from where its placement puts it, mm (STEP
#: writes 13 significant digits; the readers' volume integration is exact for these solids)
PLACEMENT_MM = 1e-6


def _temp_step(data: bytes):
    """A temporary file holding ``data`` (the readers read paths), removed by the caller."""
    d = tempfile.mkdtemp(prefix="transplanter-assembly-")
    path = os.path.join(d, "assembly.step")
    with open(path, "wb") as f:
        f.write(data)
    return d, path


#: what a reader finds of a body: volume mm³, centre of mass (mm, placed), solids; and, from OCP,
#: the centre of mass of its product in its own frame (None from gmsh)
Found = tuple[float, np.ndarray, int, "np.ndarray | None"]


def _ocp_bodies(data: bytes) -> dict[str, Found]:
    """Every occurrence of the file's top assembly as OCP's XCAF reader places it, by name."""
    occ, x = step._occ(), xcaf_modules()
    d, path = _temp_step(data)
    try:
        reader = x.STEPCAFControl_Reader()
        reader.SetNameMode(True)
        if reader.ReadFile(path) != x.IFSelect_RetDone:
            raise ExportError("the assembly STEP cannot be parsed")
        inner = reader.ChangeReader()
        params = inner.GetShapeFixParameters()  # the repairs step.read_step switches off (READ_REPAIR)
        for key, value in step.READ_REPAIR.items():
            params.Bind(occ.AString(key), occ.AString(value))
        inner.SetShapeFixParameters(params)
        doc = x.TDocStd_Document(x.TCollection_ExtendedString("XmlOcaf"))
        if not reader.Transfer(doc):
            raise ExportError("the assembly STEP holds no shape")
    finally:
        os.remove(path)
        os.rmdir(d)
    tool = x.XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    roots = x.TDF_LabelSequence()
    tool.GetFreeShapes(roots)
    if roots.Length() != 1:
        raise ExportError(f"the assembly STEP has {roots.Length()} top shapes, not one assembly")
    components = x.TDF_LabelSequence()
    tool.GetComponents_s(roots.Value(1), components, False)
    out: dict[str, Found] = {}
    products: dict[int, tuple[float, np.ndarray, int]] = {}
    for k in range(1, components.Length() + 1):
        label, product = components.Value(k), x.TDF_Label()
        name = x.TDataStd_Name()
        if not label.FindAttribute(x.TDataStd_Name.GetID_s(), name) or not tool.GetReferredShape_s(label, product):
            raise ExportError("an occurrence of the assembly STEP has no name or no product")
        tag = product.Tag()
        if tag not in products:  # each product measured once, in its own frame
            shape = tool.GetShape_s(product)
            products[tag] = (*mass_properties(occ, shape), count_solids(occ, shape))
        volume, own, solids = products[tag]
        # the occurrence's placement as the file states it, applied to its product's centre
        t = tool.GetLocation_s(label).Transformation()
        m = np.array([[t.Value(i, j) for j in range(1, 5)] for i in range(1, 4)])
        key = name.Get().ToExtString()
        if key in out:  # two bodies by one name: a bill or a CAD tree cannot tell them apart
            raise ExportError(f"the assembly STEP names two occurrences {key!r}")
        out[key] = (volume, m @ np.append(own, 1.0), solids, own)
    return out


def _gmsh_bodies(data: bytes) -> dict[str, Found]:
    """Every volume gmsh's importer finds, by the occurrence's name (gmsh names a volume
    ``Shapes/<assembly>/<occurrence>/<product>``); an occurrence read as several volumes counts
    them."""
    import gmsh

    d, path = _temp_step(data)
    out: dict[str, Found] = {}
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.importShapes(path)
        gmsh.model.occ.synchronize()
        for dim, tag in gmsh.model.getEntities(3):
            parts = gmsh.model.getEntityName(dim, tag).split("/")
            name = parts[2] if len(parts) > 2 else f"volume {tag}"
            volume, centre = gmsh.model.occ.getMass(dim, tag), np.array(gmsh.model.occ.getCenterOfMass(dim, tag))
            if name in out:
                was = out[name]
                out[name] = (was[0] + volume, was[1], was[2] + 1, None)
            else:
                out[name] = (volume, centre, 1, None)
    finally:
        gmsh.finalize()
        os.remove(path)
        os.rmdir(d)
    return out


#: the readers :func:`verify` can ask: OCP's XCAF reader and gmsh's importer
READERS = {"ocp": _ocp_bodies, "gmsh": _gmsh_bodies}


def read_bodies(data: bytes, reader: str = "ocp") -> dict[str, Found]:
    """The bodies of an assembly STEP as ``reader`` (``"ocp"`` or ``"gmsh"``) finds them, by
    occurrence name: (volume mm³, centre of mass mm, solids, OCP only: the product's own centre
    of mass)."""
    if reader not in READERS:
        raise SpecError.out_of_range("reader", reader, " or ".join(repr(r) for r in READERS))
    return READERS[reader](data)


def verify(data: bytes, placed: list[Placed], readers: tuple[str, ...] = ("ocp",)) -> dict:
    """Read the assembly back — always with OCP, and with each other of ``readers`` — and check
    it against ``placed``: one volume per body, named by its occurrence, each of the body's
    exact volume (within ``SOLID_VOLUME_REL``) and with its centre of mass where the body's
    placement puts its product's (within ``PLACEMENT_MM``); GeometryError naming every body that
    fails. Returns per reader the volumes counted and the largest volume and placement errors."""
    found = {"ocp": read_bodies(data, "ocp")}
    for reader in readers:
        if reader not in found:
            found[reader] = read_bodies(data, reader)
    own = {name: f[3] for name, f in found["ocp"].items()}
    results: dict = {"bodies": len(placed)}
    for reader, bodies in found.items():
        problems = []
        missing = sorted({p.label for p in placed} - set(bodies))
        extra = sorted(set(bodies) - {p.label for p in placed})
        if missing or extra:
            problems.append(f"bodies missing {missing}, bodies not placed {extra}")
        worst_volume = worst_place = 0.0
        for p in placed:
            if p.label not in bodies or own.get(p.label) is None:
                continue
            volume, centre, solids, _ = bodies[p.label]
            err = abs(volume / p.solid.volume - 1.0)
            want = np.asarray(p.at, dtype=float)[:3] @ np.append(own[p.label], 1.0)
            off = float(np.linalg.norm(centre - want))
            worst_volume, worst_place = max(worst_volume, err), max(worst_place, off)
            if solids != 1 or err >= SOLID_VOLUME_REL or off > PLACEMENT_MM:
                problems.append(
                    f"{p.label}: {solids} solids, volume {volume:.6f} mm3 ({p.solid.volume:.6f} expected), "
                    f"centre {off:.3g} mm off"
                )
        if problems:
            raise GeometryError(f"the assembly STEP as {reader} reads it: " + "; ".join(problems))
        results[reader] = {
            "volumes": sum(f[2] for f in bodies.values()),
            "volume_rel_error": significant(worst_volume),
            "centre_off_mm": significant(worst_place),
        }
    return results
