"""Gear pairs a shop can cut and assemble: backlash by design, one-sided DXF, internal-pair
interference before cutting, and the assembly data — checked on the files as a shop gets them.

Tolerances: a shipped pair must not overlap at any step (SHOP_OVERLAP_MM2, round-off of the
polygon Booleans) and keep its smallest backlash above the wire-EDM tolerance budget; the
independent reader below rebuilds ezdxf's exact ARC entities, so its backlash agrees with the
manifest's within the 1 µm read-back budget plus its own bisection step (0.1 µm).
"""

import csv
import functools
import json
import math
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import ezdxf
import numpy as np
import pytest
import shapely
from shapely import affinity

from transplanter.core.errors import GeometryError, SpecError
from transplanter.core.tolerances import SHOP_OVERLAP_MM2, WIRE_EDM_TOLERANCE
from transplanter.families import Making, ToothedPairStudy
from transplanter.geometry.backlash import backlash_band, design_backlash, resolve_backlash, tolerance_budget
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.interference import circular_internal
from transplanter.geometry.pair_gate import generate_pair
from transplanter.geometry.pitch import GearPair, PitchCurve
from transplanter.proof.validate import mesh_check
from transplanter.shop.solids import Features

# -- an independent reader: ezdxf's own exact ARC/LINE entities, nothing of transplanter.shop.dxf --


def _exact_contours(path, layer="CUT", sagitta=2e-5):
    doc = ezdxf.readfile(path)
    out = []
    for poly in doc.modelspace().query(f"LWPOLYLINE[layer=='{layer}']"):
        pts = []
        here = np.array(poly.get_points("xy")[0])  # the polyline runs from its first vertex
        for e in poly.virtual_entities():  # LINE and ARC entities with centre, radius, angles
            if e.dxftype() == "LINE":
                a, b = np.array(e.dxf.start)[:2], np.array(e.dxf.end)[:2]
                seg = [a, b] if np.hypot(*(a - here)) <= np.hypot(*(b - here)) else [b, a]
                pts.append(tuple(seg[0]))
                here = seg[1]
                continue
            c, r = e.dxf.center, e.dxf.radius
            a0, a1 = math.radians(e.dxf.start_angle), math.radians(e.dxf.end_angle)
            sweep = (a1 - a0) % (2 * math.pi)
            n = max(2, math.ceil(sweep / (2 * math.acos(max(-1.0, 1 - sagitta / r)))))
            ang = a0 + sweep * np.arange(n + 1) / n
            arc = np.stack([c.x + r * np.cos(ang), c.y + r * np.sin(ang)], axis=1)
            # an ARC runs counter-clockwise; a clockwise polyline segment runs it backwards
            if np.hypot(*(arc[-1] - here)) < np.hypot(*(arc[0] - here)):
                arc = arc[::-1]
            pts.extend(map(tuple, arc[:-1]))
            here = arc[-1]
        pts = np.array(pts)
        keep = np.linalg.norm(pts - np.roll(pts, 1, axis=0), axis=1) > 1e-9  # arc ends meet the next start
        out.append(shapely.Polygon(pts[keep]))
    return out


def _ogr_contours(path, layer="CUT"):
    """GDAL/ogr's reading of the outline's layer (arcs stepped every 0.2°: sagitta < 5e-5 mm at R = 30 mm)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "cut.geojson"
        env = {**os.environ, "OGR_ARC_STEPSIZE": "0.2"}
        where = f"Layer='{layer}'"
        subprocess.run(["ogr2ogr", "-f", "GeoJSON", str(out), str(path), "-where", where], env=env, check=True)
        features = json.loads(out.read_text())["features"]
    lines = [np.array(f["geometry"]["coordinates"])[:, :2] for f in features]
    assert all(np.allclose(c[0], c[-1]) for c in lines), "ogr reads an open contour"
    # ogr repeats the vertex where an arc meets the next segment: drop the zero-length edges
    return [shapely.Polygon(c[1:][np.linalg.norm(np.diff(c, axis=0), axis=1) > 1e-9]) for c in lines]


READERS = ["ezdxf"] + (["ogr"] if shutil.which("ogr2ogr") else [])


@functools.cache  # the shared build's files are read, never written, by this module's tests (call it positionally)
def _section(path: str, reader="ezdxf", layer="CUT"):
    """The section on the drawing's outline layer (``layer``: CUT for a part to cut, REFERENCE for
    a drawing marked do not cut, as the manifest's ``dxf_layer`` says)."""
    contours = _exact_contours(path, layer) if reader == "ezdxf" else _ogr_contours(path, layer)
    polys = sorted(contours, key=lambda p: -p.area)
    body = polys[0]
    for p in polys[1:]:
        body = body.symmetric_difference(p)
    return body


# -- closed-form interference of internal pairs ---------------------------------------------


def ring_pinion(module=2.0):
    """Circular ring z = 60 driving a pinion z = 30 (a 2-lobed 'circle' and its 1-lobed conjugate)."""
    return GearPair.from_driver(PitchCurve.ellipse(30 * module, 0.0, 2), "internal", 1).sized(module=module)


def test_ring60_pinion30_cutter20_is_refused_then_trimmed_and_meshes():
    """The issue's case: standard proportions jam (the ring's tips in the pinion's fillet); the
    closed-form limit is refused by default, ring-tip trimming fixes it, and the meshing check on
    the cut teeth agrees with both verdicts."""
    pair, sizing = ring_pinion()
    cutter = ShaperCutter(20, 2.0)
    with pytest.raises(GeometryError, match=r"fillet interference.*ring addendum 1 m must be <= 0\.785 m"):
        generate_pair(pair, cutter, sizing.teeth)
    # the other remedy, a cutter whose form circle sits lower on the pinion, is proposed with numbers
    with pytest.raises(GeometryError, match=r"cutters that clear it at these addenda: 24 to 60 teeth"):
        generate_pair(pair, cutter, sizing.teeth, addendum=(0.8, 1.0))
    j = design_backlash(2.0, pair.centre_distance)
    band = backlash_band(pair, j)
    ring, planet = generate_pair(pair, cutter, sizing.teeth, trim_ring_tips=True)
    assert ring.addendum == pytest.approx(0.76) and planet.addendum == 1.0
    r = mesh_check(pair, ring.polygon, planet.polygon, 2.0, steps=24, teeth=60)
    assert r.problems(max_penetration=SHOP_OVERLAP_MM2, backlash=band, names=("ring", "pinion")) == []
    assert r.backlash.min() > tolerance_budget()
    # the same teeth with the standard ring addendum (cut anyway) do jam: the limit is real
    ring1, planet1 = generate_pair(pair, cutter, sizing.teeth, check_interference=False)
    r1 = mesh_check(pair, ring1.polygon, planet1.polygon, 2.0, steps=24, teeth=60)
    assert r1.backlash.min() < tolerance_budget() and r1.max_penetration > SHOP_OVERLAP_MM2


def test_interference_limits_follow_circular_theory():
    """Involute interference is the limit of fillet interference for a sharp cutter; trochoid
    interference appears as the tooth-count difference shrinks; trimming forbids radial assembly."""
    lim = circular_internal(60, 30, 2.0, cutter_teeth=20, tip_fillet=0.0)
    # ring tip limit of the fillet check >= the textbook involute limit sqrt(rb2² + (a sin α)²)
    a, rb2 = 30.0, 60.0 * math.cos(math.radians(20))
    involute_limit = (60.0 - math.hypot(rb2, a * math.sin(math.radians(20)))) / 2.0
    assert lim.max_ring_addendum < involute_limit
    wide = circular_internal(60, 40, 2.0, cutter_teeth=12, ring_addendum=0.7)
    narrow = circular_internal(60, 56, 2.0, cutter_teeth=12, ring_addendum=0.7)
    assert wide.trochoid[0] > 0 > narrow.trochoid[0]
    assert any(p.startswith("trochoid interference") for p in narrow.problems())
    assert wide.radial_assembly and not narrow.radial_assembly
    assert 1.1 < wide.contact_ratio[0] < 2.5


# -- backlash by design ------------------------------------------------------------------------


def test_backlash_is_stated_once_and_defaults_to_the_standard():
    assert resolve_backlash(None, 0.0, 1.5, 45.0, math.radians(20)) == pytest.approx(design_backlash(1.5, 45.0))
    assert resolve_backlash(None, 0.03, 1.5, 45.0, math.radians(20)) == pytest.approx(0.06)
    assert resolve_backlash(0.0, 0.0, 1.5, 45.0, math.radians(20)) == 0.0
    with pytest.raises(SpecError, match="state the play twice"):
        resolve_backlash(0.1, 0.03, 1.5, 45.0, math.radians(20))
    with pytest.raises(SpecError, match="backlash = -0.1"):
        resolve_backlash(-0.1, 0.0, 1.5, 45.0, math.radians(20))
    assert tolerance_budget(WIRE_EDM_TOLERANCE) == pytest.approx(0.0286, abs=1e-4)


def test_zero_backlash_shop_files_carry_a_note(tmp_path):
    """Zero backlash only when asked for, and then with a warning in the DXF and the manifest."""
    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(20.0, 0.1, 2), "external", 2).sized(module=2.0)
    study = ToothedPairStudy(
        "zero",
        pair,
        ShaperCutter(12, 2.0),
        sizing.teeth[0],
        making=(Making(6.0, Features(bore=6.5, keyway=False), step=False, material="C45"),) * 2,
        backlash=0.0,
        mesh_steps=24,
    )
    record, files = study.build(tmp_path)
    assert "zero backlash" in record["results"]["warning"]
    assert b"ZERO BACKLASH" in files["zero.driver.dxf"] and b"ZERO BACKLASH" in files["zero.driven.dxf"]
    assert record["results"]["meshing"]["dxf"]["max_penetration_mm2"] < 1e-3


# -- the shipped pairs, as a shop gets them ----------------------------------------------------


def _shipped(built):
    for family in sorted(p for p in built.iterdir() if p.is_dir()):
        manifest = json.loads((family / "manifest.json").read_text())
        for name, rec in sorted(manifest["parts"].items()):
            if rec.get("kind") == "toothed_pair" and "assembly" in rec.get("results", {}):
                yield family, name, rec


def test_every_shipped_pair_meshes_on_its_re_read_dxf(built):
    pairs = list(_shipped(built))
    assert len(pairs) >= 2  # the two seed-002 stages
    for _, name, rec in pairs:
        res = rec["results"]
        dxf = res["meshing"]["dxf"]
        assert dxf["max_penetration_mm2"] == 0.0, name
        assert dxf["backlash_mm"][0] > res["assembly"]["tolerance_budget_mm"], name
        assert dxf["backlash_mm"][1] < res["meshing"]["backlash_band_mm"][1], name
        for role in ("driver", "driven"):
            assert res[role]["made"]["dxf_R2000"]["material_added_mm"] == 0.0, (name, role)


def test_dxf_arcs_only_remove_material(built):
    """Re-read with ezdxf's exact arcs, every shipped tooth contour lies inside the generated outline."""
    for family, _, rec in _shipped(built):
        for role in ("driver", "driven"):
            stem = rec["results"]["assembly"][role]
            with open(family / f"{stem}.outline.csv") as f:
                rows = list(csv.reader(f))[1:]
            outline = shapely.Polygon(np.array(rows, dtype=float))
            body = _section(str(family / f"{stem}.dxf"), "ezdxf", rec["results"][role]["made"]["dxf_layer"])
            assert isinstance(body, shapely.Polygon)
            ring = rec["results"]["assembly"]["ring"] == role
            if ring:  # the toothed contour is the ring's largest hole; material lies outside it
                teeth = max((shapely.Polygon(r) for r in body.interiors), key=lambda p: p.area)
                pts = shapely.get_coordinates(teeth.exterior)
                wrong = shapely.contains_xy(outline, pts[:, 0], pts[:, 1])  # (a point on the outline is not in it)
                wrong[wrong] = shapely.distance(outline.exterior, shapely.points(pts[wrong])) > 1e-9
                assert not wrong.any(), stem
                lost = teeth.area - outline.area
            else:
                pts = shapely.get_coordinates(body.exterior)
                outside = ~shapely.contains_xy(outline, pts[:, 0], pts[:, 1])
                worst = float(shapely.distance(outline, shapely.points(pts[outside])).max()) if outside.any() else 0.0
                assert worst < 1e-9, (stem, worst)
                lost = outline.area - shapely.Polygon(body.exterior).area
            # and it removes no more than the fit's 0.55 µm band along the contour
            assert 0 <= lost < 0.6e-3 * outline.exterior.length, (stem, lost)


@pytest.mark.parametrize("reader", READERS)
def test_a_shop_assembles_the_pair_from_the_assembly_object_and_the_dxfs(built, reader):
    """Only what the shop gets: the manifest's assembly object, the two DXFs (read by ezdxf's ARC
    entities, and by GDAL/ogr where it is installed) and the motion CSV.
    The driver sits unrotated at the origin, the driven gear on ``driven_centre_mm`` turned by
    ``driven_angle_at_start_deg``; at 24 driver angles the driven gear is placed by the motion
    table and turned both ways until it touches — the free play, as arc at the pitch point
    (located from the motion's ratio), must exceed the tolerance budget everywhere, and agree
    with the backlash the manifest states."""
    for family, name, rec in _shipped(built):
        a = rec["results"]["assembly"]
        layer = {role: rec["results"][role]["made"]["dxf_layer"] for role in ("driver", "driven")}
        driver = _section(str(family / f"{a['driver']}.dxf"), reader, layer["driver"])
        driven = _section(str(family / f"{a['driven']}.dxf"), reader, layer["driven"])
        with open(family / a["motion"]) as f:
            table = np.array(list(csv.reader(f))[1:], dtype=float)
        cx, cy = a["driven_centre_mm"]
        dist = math.hypot(cx, cy)
        internal = a["kind"] == "internal"
        m = a["module_mm"]
        start = math.radians(a["driven_angle_at_start_deg"])
        plays = []
        for phi in np.linspace(0.0, 360.0, 24, endpoint=False):
            psi = math.radians(float(np.interp(phi, table[:, 0], table[:, 1])))
            ratio = abs(float(np.interp(phi, table[:, 0], np.gradient(table[:, 1], table[:, 0]))))
            toward = np.array([cx, cy]) / dist
            if not internal:  # r1 + r2 = a, ratio = r1/r2
                r_driven = dist / (1 + ratio)
                pitch_point = toward * (dist - r_driven)
            elif ratio > 1:  # a ring driving its planet: r1 - r2 = a
                r_driven = dist / (ratio - 1)
                pitch_point = toward * (dist + r_driven)
            else:  # a planet driving its ring: r2 - r1 = a
                r_driven = dist / (1 - ratio)
                pitch_point = -toward * (r_driven - dist)
            box = shapely.box(*(pitch_point - 4 * m), *(pitch_point + 4 * m))
            gear1 = affinity.rotate(driver, -phi, origin=(0, 0)).intersection(box)
            placed = affinity.translate(affinity.rotate(driven, start + psi, origin=(0, 0), use_radians=True), cx, cy)
            local = placed.intersection(box.buffer(3 * m))

            def touches(delta, local=local, gear1=gear1, axis=(cx, cy)):
                return gear1.intersects(affinity.rotate(local, delta, origin=axis, use_radians=True))

            assert not touches(0.0), (name, phi)
            edges = []
            for sign in (-1.0, 1.0):
                lo, hi = 0.0, sign * 2 * m / r_driven
                assert touches(hi), (name, phi)
                while abs(hi - lo) * r_driven > 1e-4:
                    mid = 0.5 * (lo + hi)
                    lo, hi = (lo, mid) if touches(mid) else (mid, hi)
                edges.append(lo)
            plays.append((edges[1] - edges[0]) * r_driven)
        plays = np.array(plays)
        assert plays.min() > a["tolerance_budget_mm"], name
        assert plays.min() > a["backlash_mm"]["min"] - 2e-3 and plays.max() < a["backlash_mm"]["max"] + 2e-3, name


def test_timing_marks_are_in_the_dxf_and_the_solid(built):
    from transplanter.shop import stl

    for family, _, rec in _shipped(built):
        a = rec["results"]["assembly"]
        for role in ("driver", "driven"):
            x, y = a["timing_marks_mm"][role]
            doc = ezdxf.readfile(family / f"{a[role]}.dxf")
            texts = [e.dxf.text for e in doc.modelspace().query("TEXT[layer=='ANNOTATION']")]
            assert "TIMING" in texts
            assert any(a["driven" if role == "driver" else "driver"] in t for t in texts)  # the mate is named
            assert any(f"centre distance {a['centre_distance_mm']:.4f} mm" in t for t in texts)
            if not (family / f"{a[role]}.stl").exists():  # a drawing not to cut ships no solid (seed 002's 7-8)
                assert a["model"]["file"] is None and "DXF only" in a["model"]["shipped"], role
                continue
            section = stl.section((family / f"{a[role]}.stl").read_bytes())
            mark = shapely.Point(x, y)
            if a["ring"] == role:  # a notch in the ring's rim: no material there, at the outline
                assert not section.contains(mark) and section.exterior.distance(mark) < 1.0, (role, "no notch")
            else:
                holes = [shapely.Polygon(r) for r in section.interiors]
                assert any(h.contains(mark) for h in holes), (role, "no timing hole in the STL")
        drawing = ezdxf.readfile(family / a["drawing"])
        dims = drawing.modelspace().query("DIMENSION")
        assert len(dims) == 1 and abs(dims[0].get_measurement() - a["centre_distance_mm"]) < 1e-6
        assert not drawing.modelspace().query("*[layer=='CUT']")  # nothing on the wire's layer


def test_reports_say_built_withheld_or_failed_in_their_headlines(built):
    page = (built / "planetary_seed004" / "report.html").read_text()
    assert "all parts built" not in page and "1 withheld" in page
    assert "withheld as a finding" in page
    page = (built / "potseedling_seed002" / "report.html").read_text()
    assert "built — shop files: gears_2_3.assembly.3mf, gears_2_3.assembly.dxf" in page
    assert "1 withheld" not in page and not re.search(r"\d+ failed|failed:", page)
    # at most 4 significant digits in the tables (the manifest keeps the full figures)
    table = "".join(re.findall(r"<table.*?</table>", page, flags=re.S))  # the tables, not the notes' sentences
    digits = [m.lstrip("0.").replace(".", "") for m in re.findall(r"\d+\.\d+", table)]
    assert digits and max(len(d) for d in digits) <= 4


def test_a_metrics_table_is_one_table_with_its_units_in_their_own_column(built):
    """Seed 000's Table-2 metrics were one mini-table per metric (159 tables on the page) with
    noise such as -5.9e-08 m/s: now one table per part, name / value / unit, the units written
    as units, round-off shown as 0, and the parameters folded."""
    page = (built / "fourbar_seed000" / "report.html").read_text()
    parts = page.count("<h2>")
    assert page.count("<table>") <= 8 * parts and "<td class='u'>m/s²</td>" in page and "m/s^2" not in page
    assert not re.search(r"e-0[6-9]<", page) and "<details><summary><b>parameters</b></summary>" in page


def test_a_backlash_floor_is_held_at_every_position_and_names_its_remedy(tmp_path):
    """``min_backlash``: the smallest free play anywhere over the cycle must reach the floor; a pair
    cut for less is refused with the backlash to cut it for, and cut for that it passes."""
    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(20.0, 0.1, 2), "external", 2).sized(module=2.0)

    def study(**kw):
        return ToothedPairStudy("floor", pair, ShaperCutter(12, 2.0), sizing.teeth[0], mesh_steps=24, **kw)

    iso = study().proof.backlash
    held = study(min_backlash="iso")
    assert held.proof.min_backlash == pytest.approx(iso) and held.proof.band[0] == pytest.approx(iso)
    record, _ = held.build(tmp_path)  # this pair's free play never dips under what it is cut for
    low = record["results"]["meshing"]["outline"]["backlash_mm"][0]
    assert low >= iso and record["results"]["meshing"]["outline"]["problems"] == []
    floor = round(low + 0.02, 4)  # a floor 20 µm over its smallest free play
    with pytest.raises(GeometryError, match="this pair must keep at every position") as refused:
        study(min_backlash=floor).build(tmp_path)
    said = str(refused.value)
    assert f"below the {floor * 1e3:.1f} µm this pair must keep at every position" in said
    need = float(said.split("backlash of at least ")[1].split(" mm")[0])
    assert need == pytest.approx(iso + floor - low, abs=1.5e-3)
    record, _ = study(min_backlash=floor, backlash=need).build(tmp_path)
    assert record["results"]["meshing"]["outline"]["problems"] == []
    assert record["results"]["meshing"]["outline"]["backlash_mm"][0] >= floor
    with pytest.raises(SpecError, match="min_backlash"):
        study(min_backlash=-0.1)
