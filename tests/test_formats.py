"""The shop-format layer: STEP from exact arcs, 3MF assemblies, reading any section by its name."""

import math

import numpy as np
import pytest
import shapely
import trimesh

from transplanter.core.errors import ExportError, GeometryError
from transplanter.core.tolerances import SOLID_VOLUME_REL
from transplanter.families.builder.making import Making, manufacture
from transplanter.shop import dxf, formats, step, threemf
from transplanter.shop.export import csv_bytes
from transplanter.shop.solids import Features, circle_polygon


def _plate() -> shapely.Polygon:
    """A slotted link plate: two bosses, their hull, a long straight side (a near-flat arc fit)."""
    return shapely.convex_hull(shapely.union(circle_polygon(0, 0, 10.0), circle_polygon(260.0, 0, 6.0)))


@pytest.fixture(scope="module")
def made():
    res, files, part = manufacture(
        "plate",
        _plate(),
        shapely.Polygon(),
        Making(6.0, Features(holes=((0, 0, 8.05), (260, 0, 6.05))), material="S235JR"),
        (),
        str,
    )
    return res, files, part


def test_step_is_the_dxf_section_extruded_and_rebuilds_byte_identical(made):
    res, files, part = made
    data = files["plate.step"]
    assert data.startswith(b"ISO-10303-21;") and b"FILE_NAME('plate','1970-01-01T00:00:00'" in data
    assert b"PRODUCT('plate','plate'" in data
    assert formats.STEP.write(part) == data  # no time stamp, no per-process counter
    assert res["step"]["solids"] == 1 and res["step"]["volume_rel_error"] < 1e-9
    # re-read by OCP's reader and checked against the DXF's own arcs × width
    rep = formats.STEP.verify("plate", data, files["plate.dxf"], 6.0)
    assert rep["valid"] is True and rep["checked_by"] == "BRepCheck_Analyzer"
    assert rep["volume_rel_error"] < SOLID_VOLUME_REL
    # the arcs' closed-form area is the section's to the one-sided fit's inset (0.3 µm × perimeter)
    area = step.arcs_area(dxf.bulge_contours(files["plate.dxf"]))
    assert 0 < part.section.area - area < 0.5e-3 * part.section.boundary.length


def test_a_nearly_straight_arc_keeps_its_sagitta_in_the_step_file():
    # R = 1.7e8 mm: written as a circle with STEP's 13 digits its centre moves by ~1e-4 mm
    chord, sagitta = 262.0, 5e-5
    bulge = 2 * sagitta / chord
    verts = np.array([[0.0, 0.0, bulge], [chord, 0.0, 0.0], [chord, 20.0, 0.0], [0.0, 20.0, 0.0]])
    contours = [(verts, False)]
    shape = step.read_step(step.step_bytes("flat", step.prism(contours, 5.0)))
    rep = step.solid_report(shape)
    # the segment is 0.044 mm³ (1.7e-6 of the solid): kept to GProp's integration of the B-spline
    assert rep.valid and abs(rep.volume / (step.arcs_area(contours) * 5.0) - 1) < 1e-8


def test_the_closed_shell_check_used_above_the_brepcheck_limit(monkeypatch):
    circle = np.array([[10.0, 0.0, 1.0], [-10.0, 0.0, 1.0]])  # two half circles
    shape = step.prism([(circle, False)], 3.0)
    monkeypatch.setattr(step, "FULL_CHECK_FACES", 0)
    rep = step.solid_report(shape)
    assert rep.check == "closed shell" and rep.valid and abs(rep.volume - math.pi * 100 * 3) < 1e-9
    occ = step._occ()
    face = occ.TopExp_Explorer(shape, occ.TopAbs_ShapeEnum.TopAbs_FACE).Current()
    assert step.solid_report(face).valid is False  # an open face: edges bound one face


def test_damaged_files_are_named_not_tracebacks(made):
    _, files, _ = made
    with pytest.raises(ExportError, match="plate.step"):
        formats.STEP.verify("plate", files["plate.step"][:5000], files["plate.dxf"], 6.0)
    with pytest.raises(ExportError, match="cannot read plate.dxf"):
        formats.section_of("plate.dxf", b"0\nSECTION\n")
    with pytest.raises(ExportError, match="no section reader"):
        formats.section_of("plate.step", files["plate.step"])
    with pytest.raises(ExportError, match="3MF cannot be read"):
        formats.THREEMF.read(b"PK\x03\x04 not a zip")


def test_section_of_reads_every_section_format_alike(made):
    _, files, part = made
    for name in ("plate.dxf", "plate.stl"):  # the DXF's arcs lie 0.05-0.55 µm inside the section
        sec = formats.section_of(name, files[name])
        assert abs(sec.area - part.section.area) < 0.6e-3 * part.section.boundary.length, name
    csv = formats.CSV.write(np.asarray(part.section.exterior.coords)[:-1])
    assert abs(formats.section_of("plate.outline.csv", csv).area - shapely.Polygon(part.section.exterior).area) < 1e-6
    ring = formats.CSV.read(csv, internal=True)  # a ring's material lies outside its outline
    assert ring.interiors and ring.contains(shapely.Point(0, 40.0))


def test_the_csv_writer_writes_the_rows_csv_bytes_would():
    """CSV.write formats each row in one go; the reference is the csv module (``csv_bytes``)."""
    rng = np.random.default_rng(15)
    contour = rng.normal(scale=60.0, size=(500, 2))
    leading = {"theta_deg": rng.uniform(0, 360, 500), "s_mm": rng.normal(size=500)}
    for cols in ({}, leading):
        rows = [[*(f"{c[k]:.6f}" for c in cols.values()), f"{x:.9f}", f"{y:.9f}"] for k, (x, y) in enumerate(contour)]
        assert formats.CSV.write(contour, cols) == csv_bytes([*cols, "x_mm", "y_mm"], rows)


def test_3mf_assembly_names_its_bodies_places_them_and_finds_overlaps(made):
    _, _, part = made
    placed = [("a", part.solid, threemf.placement()), ("b", part.solid, threemf.placement(z=6.5))]
    data = formats.THREEMF.write(placed)
    assert formats.THREEMF.write(placed) == data  # UUIDs from the names, fixed zip dates
    rep = formats.THREEMF.verify(data, ["a", "b"], {"a": part.volume, "b": part.volume})
    assert rep == {"bodies": 2, "pairs_checked": 0, "max_overlap_mm3": 0.0}
    bodies = formats.THREEMF.read(data)
    assert bodies["b"].bounds[0][2] == pytest.approx(6.5) and bodies["a"].is_watertight
    with pytest.raises(GeometryError, match="expected one body per part"):
        formats.THREEMF.verify(data, ["a", "c"])
    turned = [("a", part.solid, threemf.placement()), ("b", part.solid, threemf.placement(angle=0.1))]
    with pytest.raises(GeometryError, match=r"a and b overlap by [0-9.]+ mm³"):
        formats.THREEMF.verify(formats.THREEMF.write(turned), ["a", "b"])
    with pytest.raises(ExportError, match="names two parts alike"):
        formats.THREEMF.write([("a", part.solid, np.eye(4))] * 2)


def test_an_open_manifold_is_refused_in_an_assembly():
    with pytest.raises(GeometryError, match="not a closed manifold"):
        threemf._manifold(trimesh.Trimesh(np.eye(3), [[0, 1, 2]]))


def _edges_per_planar_face(shape) -> list[int]:
    """Edges bounding each face of ``shape`` that lies in a plane z = const (its top and bottom)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Plane
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    faces = TopExp_Explorer(shape, TopAbs_FACE)
    while faces.More():
        face = TopoDS.Face(faces.Current())
        surface = BRepAdaptor_Surface(face)
        if surface.GetType() == GeomAbs_Plane and abs(surface.Plane().Axis().Direction().Z()) > 0.5:  # top, bottom
            edges, n = TopExp_Explorer(face, TopAbs_EDGE), 0
            while edges.More():
                n += 1
                edges.Next()
            out.append(n)
        faces.Next()
    return out


@pytest.mark.parametrize(
    ("family", "stem", "width", "edges"),
    [
        ("planetary_seed004", "optimised_ring_planet.driver", 12.0, 5000),
        ("potseedling_seed002", "carriers.sector_8", 10.0, 1800),
    ],
)
def test_a_gears_step_has_no_face_of_thousands_of_edges(built, family, stem, width, edges):
    """OpenCASCADE's import grows with the square of a face's edge count: the seed-004 ring's two
    planar faces of 5744 edges took 56 s in gmsh. Its STEP splits them into sectors by straight
    cuts (the same arcs, no wall inside): re-read by OCP, one valid solid of the DXF's arcs × width
    (within 1e-6), its planar faces ~80 edges each (gmsh 4.15 imports the ring in ~4 s). A sector
    gear's edges crowd into its toothed third: cut at even angles its faces kept ~220 edges (gmsh
    8.8 s); cut by edge count ~90 on average (2.3 s)."""
    folder = built / family
    shape = formats.STEP.read((folder / f"{stem}.step").read_bytes())  # read once, checked as STEP.verify does
    expected = step.arcs_area(dxf.bulge_contours((folder / f"{stem}.dxf").read_bytes())) * width
    rep = formats.STEP.report(shape, expected, stem)
    assert rep["valid"] and rep["solids"] == 1 and rep["volume_rel_error"] < SOLID_VOLUME_REL
    per_face = np.array(_edges_per_planar_face(shape))
    # the import's work grows with the square of each face's edges: the edge-weighted mean face
    # (sum n² / sum n) is its measure — the plain prism's is its whole edge count
    assert len(per_face) > 40 and (per_face**2).sum() / per_face.sum() <= 2 * step.SECTOR_EDGES, per_face
    assert per_face.sum() > 2 * edges  # every arc of both contours is still there, on the sectors


def test_a_section_without_room_for_cuts_keeps_its_two_planar_faces():
    """A disc without a hole (nothing to cut to) is the plain prism, whatever its edge count."""
    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    verts = np.stack([40 * np.cos(t), 25 * np.sin(t), np.zeros_like(t)], axis=1)
    shape = step.prism([(verts, False)], 5.0)
    assert sorted(_edges_per_planar_face(shape)) == [2000, 2000]


def test_sector_cuts_follow_the_edges_where_they_crowd():
    """A sector gear's edges crowd into its toothed arc: the cuts are placed by edge count along the
    outline, not at even angles, so no planar face keeps hundreds of them (sectors 7 and 8 of seed
    002 had ~220 per face and took 5.4 and 8.8 s in gmsh; now 2.1 and 2.3 s); a bolt hole goes into
    the one sector that holds it, and the solid is the section's arcs × width."""
    t = np.concatenate(
        [np.linspace(0, 2 * np.pi / 3, 1800, endpoint=False), np.linspace(2 * np.pi / 3, 2 * np.pi, 30, endpoint=False)]
    )
    radius = 40 + 1.5 * np.sin(32 * t) * (t < 2 * np.pi / 3)  # teeth on a third of the turn
    outer = np.stack([radius * np.cos(t), radius * np.sin(t), np.zeros_like(t)], axis=1)
    b = np.linspace(0, 2 * np.pi, 186, endpoint=False)[::-1]  # the bore, clockwise
    bore = np.stack([6 * np.cos(b), 6 * np.sin(b), np.zeros_like(b)], axis=1)
    bolt = np.array([[-10.0, -9.0, -1.0], [-10.0, -5.0, -1.0]])  # a Ø4 circle of two half arcs, clockwise
    contours = [(outer, False), (bore, True), (bolt, True)]
    shape = step.prism(contours, 8.0)
    per_face = np.array(_edges_per_planar_face(shape))
    assert len(per_face) > 40 and (per_face**2).sum() / per_face.sum() <= 2 * step.SECTOR_EDGES, per_face
    rep = step.solid_report(shape)
    assert rep.solids == 1 and rep.valid
    assert abs(rep.volume / (step.arcs_area(contours) * 8.0) - 1) < 1e-9


def test_3mf_is_re_read_in_lib3mf_s_strict_mode_and_a_body_placed_twice_is_refused(made):
    """Issue 46: the build re-reads a 3MF with lib3mf in strict mode — a file its warnings would
    flag (trimesh's raw package, with the production extension's attributes) is refused, and so is
    one whose two build items place one object — each body where its build item puts it."""
    import io
    import re
    import zipfile

    from transplanter.shop.stl import canonical_mesh

    _, _, part = made
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box((10.0, 10.0, 10.0)), node_name="a", geom_name="a")
    with pytest.raises(ExportError, match="Invalid Attribute"):
        formats.THREEMF.read(trimesh.exchange.threemf.export_3MF(scene))
    at = threemf.placement(x=500.0, angle=0.3)
    data = formats.THREEMF.write([("a", part.solid, at)])
    model = zipfile.ZipFile(io.BytesIO(data)).read("3D/3dmodel.model")
    item = re.search(rb"<item [^>]*/>", model).group(0)
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as src, zipfile.ZipFile(out, "w") as dst:
        for info in src.infolist():
            dst.writestr(info, model.replace(item, item + item) if info.filename.endswith(".model") else src.read(info))
    with pytest.raises(ExportError, match="places the body a twice"):
        formats.THREEMF.read(out.getvalue())
    placed = formats.THREEMF.read(data)["a"]
    expected = canonical_mesh(part.solid).apply_transform(at)
    assert placed.faces.tolist() == expected.faces.tolist()
    assert np.abs(placed.vertices - expected.vertices).max() < 5e-5  # single precision at 500 mm
