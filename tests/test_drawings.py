"""Drawings a shop reads as they are (issue 42).

* Assembly drawings read true: a dimension shows the length it measures, in mm, in ezdxf, in GDAL
  and in LibreCAD — regression for the "EZDXF" dimension style's DIMLFAC = 100, which made
  LibreCAD (it ignores an entity's DSTYLE override) show 4498.15 for a 44.98 mm centre distance in
  0.25 mm text. The drawing's own dimension style carries everything, at scale 1.
* Only what is to be cut is on CUT: an obstacle, a bought part and a drawing marked "do not cut"
  have their outline on REFERENCE or BOUGHT, and the readers take it from there.
* Every made part's drawing names its material (from the catalogue) and its quantity.
* A drawing not to cut ships as a drawing only: no STL or STEP beside it (a printer, a CAM or a
  CAD import takes those as parts to make), and no 3MF of reference parts alone.
* What the shop does after the wire is a numbered list of operations: a tapped hole or a circlip
  groove turned in a bore is an operation, not only a note.
"""

import io
import json
import os
import re
import shutil
import subprocess

import ezdxf
import numpy as np
import pytest
import shapely

from transplanter.core.errors import ExportError, SpecError
from transplanter.families.builder.making import Making, manufacture
from transplanter.shop import catalogue, dxf


def _drawing() -> bytes:
    part = dxf.dxf_bytes(dxf.DxfPart("disc", shapely.Point(0, 0).buffer(10.0, quad_segs=32)))
    return dxf.assembly_bytes("pair", [("a", part, (0.0, 0.0, 0.0)), ("b", part, (44.98147417, 0.0, 0.0))])


def _three() -> bytes:
    """Three discs, two dimensions (one horizontal, one vertical), one of them a reference outline."""
    disc = shapely.Point(0, 0).buffer(10.0, quad_segs=32)
    part = dxf.dxf_bytes(dxf.DxfPart("disc", disc))
    ref = dxf.dxf_bytes(dxf.DxfPart("ring", disc.difference(shapely.Point(0, 0).buffer(3.0)), layer=dxf.REFERENCE))
    placed = [("a", part, (0.0, 0.0, 0.0)), ("b", ref, (44.98147417, 0.0, 0.0)), ("c", part, (0.0, 30.0, 0.0))]
    return dxf.assembly_bytes("three", placed)


def test_dimension_text_is_the_measured_length_in_mm():
    doc = ezdxf.read(io.StringIO(_drawing().decode()))
    (dim,) = doc.modelspace().query("DIMENSION")
    texts = [e.plain_text() for e in doc.blocks[dim.dxf.geometry] if e.dxftype() == "MTEXT"]
    assert texts == ["44.9815"]
    assert dim.get_measurement() == pytest.approx(44.98147417)
    # the style carries it all, the entity overrides nothing (LibreCAD would not see an override)
    assert dim.dxf.dimstyle == dxf.DIMSTYLE and not dim.has_xdata("ACAD")
    style = doc.dimstyles.get(dxf.DIMSTYLE)
    assert (style.dxf.dimscale, style.dxf.dimlfac, style.dxf.dimdsep) == (1.0, 1.0, ord("."))
    assert style.dxf.dimtxt == dxf.lettering(0.0) == 3.5  # ISO 3098, not 0.25
    assert doc.header["$DIMSTYLE"] == dxf.DIMSTYLE
    assert (doc.header["$DIMLFAC"], doc.header["$DIMSCALE"], doc.header["$DIMTXT"]) == (1.0, 1.0, 3.5)
    assert doc.header["$INSUNITS"] == 4


def test_lettering_follows_the_iso_3098_series():
    assert [dxf.lettering(s) for s in (10.0, 175.0, 200.0, 400.0, 2000.0)] == [3.5, 3.5, 5.0, 10.0, 20.0]


@pytest.mark.skipif(shutil.which("ogr2ogr") is None, reason="GDAL (gdal-bin) is not installed")
def test_gdal_reads_the_dimension_true(tmp_path):
    path = tmp_path / "pair.assembly.dxf"
    path.write_bytes(_drawing())
    out = tmp_path / "pair.geojson"
    subprocess.run(["ogr2ogr", "-f", "GeoJSON", str(out), str(path)], check=True, capture_output=True)
    texts = [f["properties"].get("Text") for f in json.loads(out.read_text())["features"]]
    dims = [t for t in texts if t and t[0].isdigit()]
    assert dims == ["44.9815"], texts


def _spelled_out(data: bytes, scale: float = 1.0) -> bytes:
    """The drawing with every dimension's text given outright: its measurement x ``scale`` as the
    style writes it (4 decimals, no trailing zeros)."""
    doc = ezdxf.read(io.StringIO(data.decode()))
    for dim in doc.modelspace().query("DIMENSION"):
        dim.dxf.text = f"{dim.get_measurement() * scale:.4f}".rstrip("0").rstrip(".")
    buf = io.StringIO()
    doc.write(buf)
    return buf.getvalue().encode()


def _librecad_pixels(data: bytes, folder, stem: str) -> np.ndarray:
    """The drawing as LibreCAD prints it (``librecad dxf2pdf``, fitted to the page), rasterised."""
    from PIL import Image

    path = folder / f"{stem}.dxf"
    path.write_bytes(data)
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    pdf = folder / f"{stem}.pdf"
    subprocess.run(["librecad", "dxf2pdf", "-a", "-o", str(pdf), str(path)], env=env, capture_output=True, timeout=120)
    assert pdf.is_file(), f"librecad dxf2pdf wrote no {pdf.name}"
    subprocess.run(["pdftoppm", "-r", "100", "-gray", "-singlefile", str(pdf), str(folder / stem)], check=True)
    with Image.open(folder / f"{stem}.pgm") as im:
        return np.asarray(im)


@pytest.mark.skipif(
    shutil.which("librecad") is None or shutil.which("pdftoppm") is None,
    reason="LibreCAD (librecad) or poppler-utils (pdftoppm) is not installed",
)
def test_librecad_renders_every_dimension_at_its_true_value(tmp_path):
    """LibreCAD draws its text as strokes (its own fonts: nothing for pdftotext to read), so the
    drawing is compared with itself where every dimension's text is spelled out as the true value
    (44.9815 and 30): LibreCAD must print the two alike. Spelled out x100 — what it showed before —
    the print differs, so the comparison sees a wrong value."""
    drawing = _three()
    shown = _librecad_pixels(drawing, tmp_path, "shown")
    true = _librecad_pixels(_spelled_out(drawing), tmp_path, "true")
    wrong = _librecad_pixels(_spelled_out(drawing, 100.0), tmp_path, "wrong")
    assert (shown < 128).sum() > 1000  # it drew something
    assert shown.shape == true.shape and int((shown != true).sum()) == 0
    assert shown.shape != wrong.shape or int((shown != wrong).sum()) > 100


def _layers(data) -> dict[str, int]:
    """Entities per layer of a DXF (its bytes, or the document already read)."""
    doc = ezdxf.read(io.StringIO(data.decode())) if isinstance(data, bytes) else data
    found: dict[str, int] = {}
    for e in doc.modelspace():
        found[e.dxf.layer] = found.get(e.dxf.layer, 0) + 1
    return found


def test_an_outline_not_to_cut_is_off_the_cut_layer_and_read_from_its_own():
    ring = shapely.Point(0, 0).buffer(10.0, quad_segs=32).difference(shapely.Point(0, 0).buffer(4.0, quad_segs=32))
    cut = dxf.dxf_bytes(dxf.DxfPart("ring", ring))
    for layer in (dxf.REFERENCE, dxf.BOUGHT):
        data = dxf.dxf_bytes(dxf.DxfPart("ring", ring, layer=layer))
        on = _layers(data)
        assert dxf.CUT not in on and "START_HOLES" not in on and on[layer] == 2, on  # no start hole either
        assert dxf.outline_layer(data) == layer
        assert dxf.read_section(data).equals_exact(dxf.read_section(cut), 1e-9)
        assert dxf.read_section(data, layer=layer).area == pytest.approx(ring.area, rel=1e-3)
        with pytest.raises(ExportError, match="no closed contour on its CUT layer"):
            dxf.read_section(data, layer=dxf.CUT)
    assert dxf.outline_layer(cut) == dxf.CUT and _layers(cut)["START_HOLES"] == 1
    with pytest.raises(SpecError, match="layer = 'WIRE'"):
        dxf.DxfPart("ring", ring, layer="WIRE")
    with pytest.raises(SpecError, match="only a part to cut"):
        dxf.DxfPart("ring", ring, layer=dxf.REFERENCE, wire_offset=0.145)
    # contours on two outline layers: which is the part? refused, not guessed
    doc = ezdxf.read(io.StringIO(cut.decode()))
    doc.modelspace().add_lwpolyline([(0, 0), (5, 0), (5, 5)], close=True, dxfattribs={"layer": dxf.REFERENCE})
    buf = io.StringIO()
    doc.write(buf)
    with pytest.raises(ExportError, match="on CUT and REFERENCE"):
        dxf.read_section(buf.getvalue().encode())


def _notes(data) -> list[str]:
    """The ANNOTATION texts of a DXF (its bytes, or the document already read)."""
    doc = ezdxf.read(io.StringIO(data.decode())) if isinstance(data, bytes) else data
    return [t.dxf.text for t in doc.modelspace().query("TEXT[layer=='ANNOTATION']")]


def test_a_made_part_names_its_material_and_quantity_and_a_drawing_not_to_cut_is_off_cut():
    with pytest.raises(SpecError, match="material: a made part names its material"):
        Making(width=5.0)
    with pytest.raises(SpecError, match="material = 'brass' is not in the catalogue"):
        Making(width=5.0, material="brass")
    plate = shapely.box(0.0, 0.0, 40.0, 20.0)
    for quantity, layer in ((2, dxf.CUT), (0, dxf.REFERENCE)):
        making = Making(width=5.0, step=False, quantity=quantity, material="S235JR")
        res, files, made = manufacture("p", plate, shapely.Polygon(), making, ("a plate",), str)
        assert (res["material"], res["quantity"], res["dxf_layer"], made.layer) == ("S235JR", quantity, layer, layer)
        data = files["p.dxf"]
        assert set(_layers(data)) & set(dxf.OUTLINES) == {layer}
        notes = _notes(data)
        assert catalogue.material("S235JR").note in notes
        assert any(t.startswith("make 2 from" if quantity else "do not cut this drawing") for t in notes), notes


# -- the built export ---------------------------------------------------------------------------

#: what a made part's drawing says it is: "make N; ..." or "do not cut this drawing ..."
_MAKE = re.compile(r"^make (\d+)[ ;]")


def check_layers(folder) -> dict[str, int]:
    """Every DXF of a built export against what it is: a part to make ("make N", N >= 1) has its
    outline on CUT alone and names a catalogue material; a drawing marked do not cut, an obstacle
    and a bought part have nothing on CUT (their outline on REFERENCE or BOUGHT); an assembly
    drawing nothing on CUT (its bought parts may be drawn on BOUGHT). The manifests' made parts
    agree (``quantity`` >= 1 on CUT). Returns the count of each kind."""
    notes_of_material = {m.note for m in catalogue.materials().values()}
    kinds = {"cut": 0, "not cut": 0, "obstacle": 0, "bought": 0, "assembly": 0, "turned": 0}
    for path in sorted(folder.rglob("*.dxf")):
        data = path.read_bytes()
        assert data.isascii(), f"{path.name} is not ASCII"
        doc = ezdxf.read(io.StringIO(data.decode()))  # read once for its layers and its notes
        on = _layers(doc)
        outline = set(on) & set(dxf.OUTLINES)
        if path.name.endswith("assembly.dxf"):
            kind, want = "assembly", outline - {dxf.CUT}
        elif path.name.endswith(".obstacle.dxf"):
            kind, want = "obstacle", {dxf.REFERENCE}
        elif path.name.endswith(".bought.dxf"):
            kind, want = "bought", {dxf.BOUGHT}
        else:
            notes = _notes(doc)
            made = [int(m.group(1)) for t in notes if (m := _MAKE.match(t))]
            kind = "cut" if made and made[0] >= 1 else "not cut"
            want = {dxf.CUT} if kind == "cut" else {dxf.REFERENCE}
            if "TURN" in on:  # a lathe's part: its side view on TURN, nothing for the wire
                kind, want = "turned", set()
            assert made or any(t.startswith("do not cut this drawing") for t in notes), (path.name, notes)
            assert len(set(notes) & notes_of_material) == 1, (path.name, notes)
            solids = {path.with_suffix(s).name for s in (".stl", ".step")} & {p.name for p in path.parent.iterdir()}
            assert bool(solids) == bool(made and made[0] >= 1), (path.name, "a drawing not to make ships", solids)
            _operations(path.name, notes, kind)
        assert outline == want, (path.name, kind, on)
        kinds[kind] += 1
    for manifest in folder.glob("*/manifest.json"):
        parts = json.loads(manifest.read_text())["parts"]
        for found in _made_results(parts):
            if found["dxf_layer"] != "TURN":
                assert found["dxf_layer"] == (dxf.CUT if found["quantity"] >= 1 else dxf.REFERENCE), found
            catalogue.material(found["material"])
        for name, part in parts.items():  # a 3MF is a model to print: none of drawings not to make alone
            quantities = [r["quantity"] for r in _made_results(part)]
            if quantities and not any(quantities):
                assert not [f for f in part["files"] if f.endswith((".3mf", ".stl", ".step"))], name
    return kinds


#: an operation line of a drawing: "op 20: tap ..."
_OP = re.compile(r"^op (\d+): (.*)")


def _operations(name: str, notes: list[str], kind: str) -> None:
    """A made drawing's operations are numbered 10, 20, … in order; a tapped hole and a circlip
    groove turned in a plate's bore each have theirs; a wire-cut part's list starts with the wire."""
    ops = [m.groups() for t in notes if (m := _OP.match(t))]
    assert [int(n) for n, _ in ops] == [10 * k for k in range(1, len(ops) + 1)], (name, ops)
    said = " ".join(t for t in notes if not _OP.match(t))
    if re.search(r"\bM\d+ tapped", said):  # this part's threads ("3 x M5 tapped"), not its mate's
        assert any("tap" in text for _, text in ops), (name, "tapped holes without an operation", notes)
    if kind == "cut" and re.search(r"DIN 472 \S+ groove", said):
        assert any("groove" in text for _, text in ops), (name, "a bore's circlip groove without an operation")
    if kind == "cut" and ops:
        assert ops[0][1].startswith("wire-cut every contour on CUT"), (name, ops)


def _made_results(node):
    """Every made part's results in a manifest (the dicts ``manufacture`` returns)."""
    if isinstance(node, dict):
        if "dxf_layer" in node and "quantity" in node:
            yield node
        for v in node.values():
            yield from _made_results(v)
    elif isinstance(node, list):
        for v in node:
            yield from _made_results(v)


def test_a_drawing_is_ascii_whatever_its_text():
    """A note's Ø, ° and ± are DXF's own codes and anything else past ASCII its \\U+ escape: an
    R2000 file declares ANSI_1252, and raw UTF-8 there reads "Ã˜26 H7" in LibreCAD."""
    assert dxf.ascii_text("Ø26 H7 ± 0.01, 45° — ok") == "%%c26 H7 %%p 0.01, 45%%d \\U+2014 ok"
    doc = ezdxf.new("R2000")
    doc.modelspace().add_text("bore Ø20 H7")
    data = dxf._write(doc)
    assert data.isascii() and b"bore %%c20 H7" in data
    text = ezdxf.read(io.StringIO(data.decode())).modelspace().query("TEXT")[0]
    assert text.plain_text() == "bore Ø20 H7"


def test_only_what_is_to_be_cut_is_on_cut(built):
    kinds = check_layers(built)
    # seed 002's gears 7-8 (two drawings, do not cut), its roller; seed 004's box and soil, seed 002's soil
    assert kinds["not cut"] >= 2 and kinds["bought"] >= 1 and kinds["obstacle"] >= 3, kinds
    assert kinds["cut"] > 30 and kinds["assembly"] >= 3 and kinds["turned"] >= 8, kinds


def test_a_made_part_lists_what_the_shop_does_after_the_wire():
    plate = shapely.box(0.0, 0.0, 40.0, 20.0)
    ops = ("tap the 2 holes M4 through", "turn the DIN 472 22x1 groove 23 (+0.13/0) x 1.1 H13 in the bore")
    for quantity in (3, 0):
        making = Making(width=5.0, step=False, quantity=quantity, material="S235JR", operations=ops)
        res, files, _ = manufacture("p", plate, shapely.Polygon(), making, ("a plate (op 20)",), str)
        notes = _notes(files["p.dxf"])
        if quantity:
            want = [
                "op 10: wire-cut every contour on CUT (a hole to tap at its tap drill)",
                *(f"op {20 + 10 * k}: {o}" for k, o in enumerate(ops)),
            ]
            assert res["operations"] == want and [t for t in notes if t.startswith("op ")] == want
            assert set(files) == {"p.dxf", "p.stl"}
        else:  # a drawing not to cut has nothing to do after the wire, and ships as a drawing only
            assert "operations" not in res and not any(t.startswith("op ") for t in notes)
            assert set(files) == {"p.dxf"} and res["shipped"].startswith("DXF only")
    with pytest.raises(SpecError, match="operations"):
        Making(width=5.0, material="S235JR", operations=("",))
