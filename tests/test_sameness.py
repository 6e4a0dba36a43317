"""One meshing proof per pair, carried to its other files by a certified distance (issue 46).

``proof.sameness.within`` bounds how far two files' teeth lie apart by containment in GEOS's
offset (never a sample); ``PairProof.mesh_once`` meshes the DXF and carries its proof to the
outline and the STL, or meshes a source on its own where nothing can be carried."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import shapely

from transplanter.families.pairs import pair_assembly
from transplanter.families.pairs.pair_proof import Carried
from transplanter.proof import sameness
from transplanter.proof.meshing import MeshReport
from transplanter.shop import formats


def _star(n: int = 12, r: float = 20.0, a: float = 2.0, k: int = 2000) -> shapely.Polygon:
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    rr = r + a * np.cos(n * t)
    return shapely.Polygon(np.c_[rr * np.cos(t), rr * np.sin(t)])


def test_the_distance_is_the_first_rung_that_holds_and_a_spike_between_vertices_is_caught():
    star = _star()
    grown = shapely.buffer(star, 0.3e-3, quad_segs=64)
    assert sameness.within(star, grown, False) == pytest.approx(0.5e-3)
    assert sameness.within(star, star, False) == sameness.LADDER_MM[0]
    # a narrow spike on one flank, pushed 5 µm out radially from a vertex: the rest of the two
    # outlines coincide, and the figure is the first rung at or past the spike's tip distance
    x, y = np.asarray(star.exterior.coords)[:-1].T
    i = 700
    tip = np.array([x[i], y[i]]) * (1 + 5e-3 / np.hypot(x[i], y[i]))
    spiked = shapely.Polygon(np.insert(np.c_[x, y], i + 1, tip, axis=0))
    d = star.distance(shapely.Point(tip))
    assert 3e-3 < d < 4e-3
    assert sameness.within(star, spiked, False) == pytest.approx(4e-3)
    assert sameness.within(star, shapely.buffer(star, 0.1), False) is None  # 100 µm: past the ladder


def test_a_ring_is_compared_on_its_toothed_hole_not_its_rim_or_bolt_holes():
    hole = _star(r=30.0)
    plate = shapely.Polygon(shapely.Point(0, 0).buffer(45.0, quad_segs=64).exterior.coords, [hole.exterior.coords])
    bolts = plate.difference(shapely.Point(40, 0).buffer(2.0))
    assert sameness.within(plate, bolts, True) == sameness.LADDER_MM[0]
    # the ring's material grown 0.7 µm into its hole (its teeth thicker): caught both ways
    thicker = shapely.Polygon(plate.exterior.coords, [shapely.buffer(hole, -0.7e-3, quad_segs=64).exterior.coords])
    assert sameness.within(plate, thicker, True) == pytest.approx(1e-3)
    with pytest.raises(ValueError, match="no toothed hole"):
        sameness.teeth_region(shapely.Polygon(plate.exterior), True)


@pytest.fixture(scope="module")
def made():
    from transplanter.families import pair_family

    study = pair_family("phi - 0.08*sin(2*phi)", teeth=24, module=1.5).parts[0]
    cut = study.cut_teeth()
    files = cut.outline_files() | pair_assembly.make(cut, study.making, study.train, tuple(study.notes)).files
    return study, files, study.proof.mesh_once(files)


def test_the_dxf_is_meshed_once_and_its_proof_carried_to_the_outline_and_the_stl(made):
    study, files, reports = made
    proof = study.proof
    assert isinstance(reports["dxf"], MeshReport) and not proof.problems(reports["dxf"])
    gap = reports["dxf"].clearance_min.value
    alone = proof.mesh(files, ("outline", "stl"))
    for source in ("outline", "stl"):
        carried = reports[source]
        assert isinstance(carried, Carried) and carried.within_mm == (1e-3, 1e-3)
        assert carried.clearance_at_least == pytest.approx(gap - 2e-3)
        assert carried.clearance_at_least >= proof.min_clearance
        # what the source's own proof finds is never below what is carried to it
        assert alone[source].clearance_min.value >= carried.clearance_at_least
    results, _, problems = proof.results(reports)
    assert problems == [] and results["stl"]["carried_from"] == "dxf"
    assert results["stl"]["teeth_within_mm"] == [0.001, 0.001] and "backlash_mm" in results["dxf"]


def _moved(data: bytes, dx: float) -> bytes:
    """An STL with every vertex moved ``dx`` mm along x."""
    import io

    import trimesh

    mesh = trimesh.load(io.BytesIO(data), file_type="stl")
    mesh.apply_translation([dx, 0.0, 0.0])
    return trimesh.exchange.stl.export_stl(mesh)


def test_a_source_nothing_can_be_carried_to_is_meshed_on_its_own(made):
    study, files, once = made
    # held to a tighter shop (±10 µm: a 28.6 µm gap required), the DXF still meshes in its band
    proof = dataclasses.replace(study.proof, tolerance=0.01)
    gap = once["dxf"].clearance_min.value
    assert gap - 2e-3 >= proof.min_clearance and not proof.problems(once["dxf"])
    # the driven STL moved 3 µm: its teeth within 4 µm, the gap carried (35 µm) still enough
    near = files | {"pair.driven.stl": _moved(files["pair.driven.stl"], 0.003)}
    sections = [formats.section_of(f"pair.driven.{s}", near[f"pair.driven.{s}"]) for s in ("stl", "dxf")]
    assert sameness.within(*sections, False) == pytest.approx(4e-3)
    reports = proof.mesh_once(near, ("dxf", "stl"))
    assert isinstance(reports["stl"], Carried) and reports["stl"].clearance_at_least == pytest.approx(gap - 5e-3)
    # moved 12 µm: within 16 µm, carried it would fall below the gap required — meshed on its own
    nearer = files | {"pair.driven.stl": _moved(files["pair.driven.stl"], 0.012)}
    reports = proof.mesh_once(nearer, ("dxf", "stl"))
    assert gap - 17e-3 < proof.min_clearance and isinstance(reports["stl"], MeshReport)
    # moved 0.1 mm (past the ladder): meshed on its own, and its own proof finds what that does
    far = files | {"pair.driven.stl": _moved(files["pair.driven.stl"], 0.1)}
    reports = proof.mesh_once(far, ("dxf", "stl"))
    assert isinstance(reports["stl"], MeshReport) and proof.problems(reports["stl"])
    # a pair cut without backlash keeps no gap to carry: every source is meshed
    tight = dataclasses.replace(proof, backlash=0.0)
    assert tight.min_clearance is None
    assert all(isinstance(r, MeshReport) for r in tight.mesh_once(files, ("dxf", "stl")).values())
