"""Assembly drawings read true: a dimension shows the length it measures, in mm, in ezdxf and in
GDAL (a shop's reader) — regression for the "EZDXF" dimension style's DIMLFAC = 100, which made
LibreCAD show 4498.15 for a 44.98 mm centre distance."""

import io
import json
import shutil
import subprocess

import ezdxf
import pytest
import shapely

from transplanter.shop import dxf


def _drawing() -> bytes:
    part = dxf.dxf_bytes(dxf.DxfPart("disc", shapely.Point(0, 0).buffer(10.0, quad_segs=32)))
    return dxf.assembly_bytes("pair", [("a", part, (0.0, 0.0, 0.0)), ("b", part, (44.98147417, 0.0, 0.0))])


def test_dimension_text_is_the_measured_length_in_mm():
    doc = ezdxf.read(io.StringIO(_drawing().decode()))
    (dim,) = doc.modelspace().query("DIMENSION")
    texts = [e.plain_text() for e in doc.blocks[dim.dxf.geometry] if e.dxftype() == "MTEXT"]
    assert texts == ["44.9815"]
    assert dim.get_measurement() == pytest.approx(44.98147417)
    assert dim.override().get("dimlfac") == 1.0


@pytest.mark.skipif(shutil.which("ogr2ogr") is None, reason="GDAL (gdal-bin) is not installed")
def test_gdal_reads_the_dimension_true(tmp_path):
    path = tmp_path / "pair.assembly.dxf"
    path.write_bytes(_drawing())
    out = tmp_path / "pair.geojson"
    subprocess.run(["ogr2ogr", "-f", "GeoJSON", str(out), str(path)], check=True, capture_output=True)
    texts = [f["properties"].get("Text") for f in json.loads(out.read_text())["features"]]
    dims = [t for t in texts if t and t[0].isdigit()]
    assert dims == ["44.9815"], texts
