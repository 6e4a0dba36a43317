"""The assembly STEP (``shop.assembly_step``): every body a named solid at its placement, the same
bytes on every write, and read back by OCP and by gmsh — an independent importer — one volume per
body, of its volume, where it was placed."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
import shapely

from transplanter.core.errors import ExportError, GeometryError, SpecError
from transplanter.shop import formats
from transplanter.shop.assembly_read import read_bodies, verify
from transplanter.shop.assembly_step import Placed, Solid, frame, solid_of, step_bytes
from transplanter.shop.catalogue import bearing, circlip_for_shaft, key_for, nut, screw, washer

pytest.importorskip("gmsh")


def _plate_contours():
    """A made plate as a shop gets it: its DXF's lines and arcs, re-read (a 40 x 20 plate with a
    Ø10 bore and a round end)."""
    section = shapely.Polygon([(0, 0), (40, 0), (40, 20), (0, 20)]).union(shapely.Point(40, 10).buffer(10, 64))
    section = section.difference(shapely.Point(12, 10).buffer(5, 64))
    data = formats.DXF.write(formats.MadePart("plate", section, None, 6.0, ("a plate",)))
    return formats.DXF.arcs(data)


@pytest.fixture(scope="module")
def assembly():
    plate = Solid.prism(_plate_contours(), 6.0)
    ring = solid_of(bearing("6000"))  # 10 x 26 x 8
    placed = [
        Placed("plate_back", "plate", 1, plate, frame(0.0, 0.0, 0.0)),
        Placed("plate_middle", "plate", 1, plate, frame(5.0, -3.0, 7.0, math.radians(30))),
        # turned over (mounted face down): the same solid, its face at z 20
        Placed("plate_front", "plate", 1, plate, frame(0.0, 0.0, 20.0, 0.0, flip=True)),
        Placed("bearing_1", "6000-2Z", 2, ring, frame(12.0, 10.0, -9.0)),
        Placed("bearing_2", "6000-2Z", 2, ring, frame(12.0, 10.0, 21.0)),
    ]
    return placed, step_bytes("bench.assembly", placed)


def test_gmsh_opens_the_assembly_with_one_volume_per_body(assembly):
    placed, data = assembly
    checked = verify(data, placed, readers=("ocp", "gmsh"))
    assert checked["bodies"] == 5
    for reader in ("ocp", "gmsh"):
        assert checked[reader]["volumes"] == 5
        assert checked[reader]["volume_rel_error"] < 1e-9 and checked[reader]["centre_off_mm"] < 1e-6
    found = read_bodies(data, "gmsh")
    assert sorted(found) == ["1 plate_back", "1 plate_front", "1 plate_middle", "2 bearing_1", "2 bearing_2"]
    # a bearing is its ring d .. D x B, where it was put
    volume, centre, solids, _ = found["2 bearing_2"]
    assert solids == 1 and volume == pytest.approx(math.pi / 4 * (26**2 - 10**2) * 8, rel=1e-9)
    assert centre == pytest.approx([12.0, 10.0, 25.0], abs=1e-9)
    # the plate turned over lies below its placement, mirrored: its round end still on +x
    volume, centre, _, _ = found["1 plate_front"]
    back = found["1 plate_back"]
    assert centre[2] == pytest.approx(17.0) and centre[0] == pytest.approx(back[1][0])
    assert centre[1] == pytest.approx(-back[1][1])


def test_the_file_names_each_body_and_its_item_and_is_the_same_every_time(assembly):
    placed, data = assembly
    assert step_bytes("bench.assembly", placed) == data
    text = data.decode()
    assert "1970-01-01T00:00:00" in text and text.count("NEXT_ASSEMBLY_USAGE_OCCURRENCE(") == 5
    assert "PRODUCT('1 plate','1 plate'" in text and "PRODUCT('2 6000-2Z','2 6000-2Z'" in text
    assert text.count("PRODUCT('1 plate'") == 1  # the three plates are occurrences of one product


def test_a_body_moved_missing_or_of_another_size_fails(assembly):
    placed, data = assembly
    moved = [*placed[:-1], Placed("bearing_2", "6000-2Z", 2, placed[-1].solid, frame(12.0, 10.01, 21.0))]
    with pytest.raises(GeometryError, match="bearing_2"):
        verify(data, moved)
    with pytest.raises(GeometryError, match="not placed"):
        verify(data, placed[:-1])
    bigger = [*placed[:-1], Placed("bearing_2", "6000-2Z", 2, Solid.ring(10, 26, 8.01), placed[-1].at)]
    with pytest.raises(GeometryError, match="volume"):
        verify(data, bigger, readers=("gmsh",))
    # two occurrences by one name (a file edited, or written by another tool): OCP's reading says so
    renamed = data.replace(b"'2 bearing_2'", b"'2 bearing_1'")
    assert renamed != data
    with pytest.raises(ExportError, match="names two occurrences '2 bearing_1'"):
        verify(renamed, placed)


def test_bought_parts_are_simple_solids_of_their_catalogue_dimensions():
    k = key_for(12, 10)
    assert solid_of(k).volume == pytest.approx(k.b * k.h * k.length)
    s = screw("M4", 12)
    assert solid_of(s).volume == pytest.approx(math.pi / 4 * (s.head_diameter**2 * s.head_height + 4**2 * 12))
    w = washer("M4")
    assert solid_of(w).volume == pytest.approx(math.pi / 4 * (w.outer**2 - w.inner**2) * w.thickness)
    ring = circlip_for_shaft(12)
    g = ring.groove_diameter
    assert solid_of(ring).volume == pytest.approx(math.pi / 4 * ((g + 2 * ring.lug) ** 2 - g**2) * ring.s)
    n = nut("M4")
    hexagon = math.sqrt(3) / 2 * n.across_flats**2
    assert solid_of(n).volume == pytest.approx((hexagon - math.pi / 4 * n.d**2) * n.height)
    with pytest.raises(SpecError, match="no simple solid"):
        solid_of("a pin")


def test_bad_placements_and_names_are_refused():
    disc = Solid.ring(0.0, 10.0, 2.0)
    with pytest.raises(SpecError, match="rigid"):
        Placed("a", "p", 1, disc, np.diag([2.0, 1.0, 1.0, 1.0]))
    with pytest.raises(SpecError, match="without /"):
        Placed("a/b", "p", 1, disc, frame())
    with pytest.raises(SpecError, match="twice"):
        step_bytes("x", [Placed("a", "p", 1, disc, frame()), Placed("a", "p", 1, disc, frame(5.0))])
    with pytest.raises(SpecError, match="overlap"):
        Solid((*Solid.ring(0, 5, 2).slabs, *Solid.ring(0, 5, 2).slabs))


def test_the_lines_joined_are_the_file_opencascade_prints():
    """Issue 46: the assembly's STEP lines are joined in Python, a few thousand at a time, not
    printed by OpenCASCADE (which gathers the whole file in a C++ string first): the same bytes."""
    from transplanter.shop import step, step_writing

    occ = step._occ()
    step_writing.write_settings(occ)
    writer = occ.STEPControl_Writer()
    shape = step.prism(_plate_contours(), 6.0)
    assert writer.Transfer(shape, occ.STEPControl_StepModelType.STEPControl_AsIs, False) == occ.IFSelect_RetDone
    step_writing.fixed_header(occ, writer, "bench")
    lines = step_writing.sent(occ, writer)
    assert lines.NbLines() > 20
    joined = step_writing.joined(lines)
    assert joined == step_writing.printed(lines, "bench")
    assert joined.startswith(b"ISO-10303-21;\n") and joined.endswith(b"END-ISO-10303-21;\n")


#: a machine's assembly files (3MF and STEP) made in processes of their own and here (run in a
#: process of its own: the test workers' threads keep a fork from being made)
FORKED = """
import json, math, os
import shapely
from transplanter.families.machines.assembly import AssemblyFiles
from transplanter.families.machines.record import start_assembly
from transplanter.machine.bodies import Body, Link
from transplanter.shop.assembly_step import Placed, frame, solid_of, write_checked
from transplanter.shop.catalogue import bearing

plate = shapely.Polygon([(0, 0), (40, 0), (40, 20), (0, 20)]).difference(shapely.Point(12, 10).buffer(5, 64))
bodies = [Body("plate", plate, (0.0, 6.0), "fixed"), Body("arm", plate, (7.0, 13.0), "arm")]
links = {"fixed": Link.fixed(), "arm": Link("arm", lambda t: (0 * t + 5.0, 0 * t - 3.0, 0 * t + math.radians(30)))}
ring = solid_of(bearing("6000"))
placed = [Placed("bearing_1", "6000-2Z", 2, ring, frame(12.0, 10.0, -9.0)),
          Placed("bearing_2", "6000-2Z", 2, ring, frame(12.0, 10.0, 21.0))]
with AssemblyFiles() as files:
    forked = [p._proc.pid for p in (files.threemf, files.step) if p._proc is not None]
    files.start_assembly("bench", bodies, links, {})
    files.step.send(("bench.assembly", placed))
    step = files.step.result()
    three = files.start_assembly_made()
here_step = write_checked("bench.assembly", placed)
here_three = start_assembly("bench", bodies, links, {})
print(json.dumps({
    "forked": forked, "me": os.getpid(),
    "same_step": step[0] == here_step[0] and step[1] == here_step[1],
    "same_3mf": three[0] == here_three[0] and three[1] == here_three[1],
    "bodies": three[0]["bodies"],
}))
"""


@pytest.mark.skipif(not hasattr(os, "fork"), reason="no fork on this platform")
def test_a_machine_s_assembly_files_made_in_processes_of_their_own_are_the_ones_made_here():
    """Issue 46: a machine's assembly 3MF and STEP are made in two processes forked before it is
    posed (``AssemblyFiles``), handed their bodies later — the same records and bytes as made in
    the machine's own process."""
    import json
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", FORKED], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert len(out["forked"]) == 2 and out["me"] not in out["forked"]
    assert out["same_step"] and out["same_3mf"] and out["bodies"] == 2
