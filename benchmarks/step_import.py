"""STEP import speed: the seed-004 ring's solid with its planar faces in sectors against the plain
prism, re-read by OpenCASCADE's STEP reader, same run.

Both solids are the same lines and arcs (the DXF's one-sided fit) extruded by the face width, and
both re-read as one solid of the arcs' exact area × width (equal accuracy: the volume error of
each is printed). The baseline is the prism as shipped before (one planar face on each side,
bounded by all 5744 edges of the rim and the toothed contour): OpenCASCADE's import repairs and
orients a face's wires with searches that grow with the square of its edge count. The sectors
cut each planar face into ``step.SECTOR_EDGES``-edge pieces by straight cuts across the material.

Prints the time of each re-read (OCP's ``STEPControl_Reader`` as ``transplanter check`` runs it:
``step.read_step``, and the same reader with its default repairs — what gmsh, FreeCAD and other
OpenCASCADE front ends do) and the ratios. Goal: the ring <= 5 s in gmsh (measured with gmsh
4.15: 56 s plain, 4.8 s in sectors).

Run: python benchmarks/step_import.py [RING.dxf] (default: the ring of a fresh build of
parts/planetary_seed004.py)
"""

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
WIDTH = 12.0  # mm, the ring's face width in parts/planetary_seed004.py


def ring_dxf() -> bytes:
    if len(sys.argv) > 1:
        return Path(sys.argv[1]).read_bytes()
    from transplanter.families import build_family, load_family

    family = load_family(ROOT / "parts" / "planetary_seed004.py")
    ring = next(p for p in family.parts if p.name == "optimised_ring_planet")
    with tempfile.TemporaryDirectory() as out:
        from dataclasses import replace

        build_family(replace(family, parts=(ring,)), out)
        return (Path(out) / family.name / "optimised_ring_planet.driver.dxf").read_bytes()


def read_with_repairs(data: bytes):
    """OCP's reader with its default shape repairs (as gmsh and FreeCAD import)."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "part.step"
        path.write_bytes(data)
        reader = STEPControl_Reader()
        assert reader.ReadFile(str(path)) == IFSelect_RetDone
        reader.TransferRoots()
        return reader.OneShape()


def main() -> None:
    from transplanter.shop import dxf, step
    from transplanter.shop.arcs import bulge_area

    contours = []
    for verts, hole in dxf.bulge_contours(ring_dxf()):
        if (bulge_area(verts) < 0) != hole:  # the orientation section_arcs gives
            flipped = verts[::-1].copy()
            flipped[:, 2] = -np.roll(verts[::-1, 2], -1)
            verts = flipped
        contours.append((verts, hole))
    exact = step.arcs_area(contours) * WIDTH
    sectored = step.prism(contours, WIDTH)
    keep = step.SECTOR_EDGES
    step.SECTOR_EDGES = 10**9  # the plain prism: one planar face on each side
    plain = step.prism(contours, WIDTH)
    step.SECTOR_EDGES = keep
    times = {}
    for label, shape in (("plain prism", plain), ("sectors", sectored)):
        data = step.step_bytes("ring", shape)
        for reader, read in (("check's reader", step.read_step), ("default repairs", read_with_repairs)):
            start = time.perf_counter()
            back = read(data)
            times[label, reader] = time.perf_counter() - start
            rep = step.solid_report(back, check=False)
            print(
                f"{label:12s} {reader:16s} {times[label, reader]:7.2f} s  {rep.faces} faces, "
                f"volume error {(rep.volume - exact) / exact:+.1e}"
            )
    for reader in ("check's reader", "default repairs"):
        ratio = times["plain prism", reader] / times["sectors", reader]
        print(f"{reader}: sectors re-read {ratio:.1f}x faster than the plain prism")


if __name__ == "__main__":
    main()
