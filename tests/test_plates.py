"""Four-bar link plates: made, re-read by an independent reader, rebuilt into the designed arm."""

import json
import shutil
import subprocess

import ezdxf
import numpy as np
import pytest

from transplanter.app import cli
from transplanter.core.errors import SpecError
from transplanter.families import Joint, LinkPlatesStudy, load_family
from transplanter.families.mechanisms.plates import TIP_PATH_TOL_MM, finger_for_centre_of_mass

FOURBARS = {
    "fourbar_seed000": ("mechanism_A_plates", "mechanism_B_plates", "mechanism_C_plates"),
    "fourbar_seed001": ("eight_row_arm_plates",),
    "fourbar_seed003": ("type_I_plates", "type_II_plates"),
}
LINKS = ("frame", "crank", "coupler", "rocker")


def test_every_four_bar_ships_its_plates_with_the_tip_path_rebuilt(built):
    for family, names in FOURBARS.items():
        manifest = json.loads((built / family / "manifest.json").read_text())
        for name in names:
            part = manifest["parts"][name]
            res = part["results"]
            assert res["tip_path"]["max_deviation_mm"] < TIP_PATH_TOL_MM, name
            assert res["assembly"]["bodies"] == 4 and res["assembly"]["max_overlap_mm3"] == 0.0
            for link in LINKS:
                for ext in (".dxf", ".stl", ".step"):
                    assert f"{name}.{link}{ext}" in part["files"], (name, link, ext)
                assert res[link]["step"]["solids"] == 1 and res[link]["step"]["volume_rel_error"] < 1e-6
                assert res[link]["dxf_R2000"]["material_added_mm"] == 0.0
            assert f"{name}.assembly.3mf" in part["files"]
    # the rebuilt link lengths are the seed's
    seed001 = json.loads((built / "fourbar_seed001" / "manifest.json").read_text())
    links = seed001["parts"]["eight_row_arm_plates"]["results"]["tip_path"]["links_from_holes_mm"]
    assert links == pytest.approx({"ground": 330.0, "crank": 60.0, "coupler": 200.0, "rocker": 213.0}, abs=1e-6)


@pytest.mark.skipif(shutil.which("ogrinfo") is None, reason="GDAL's ogrinfo is not installed")
def test_plate_dxfs_open_in_gdal_as_closed_mm_contours_with_the_tip_path(built):
    for family, names in FOURBARS.items():
        for name in names:
            for link in LINKS:
                path = built / family / f"{name}.{link}.dxf"
                out = subprocess.run(
                    ["ogrinfo", "-ro", "-al", "-q", "-where", "Layer='CUT'", str(path)],
                    capture_output=True,
                    text=True,
                    check=True,
                ).stdout
                rings = [line for line in out.splitlines() if line.strip().startswith(("LINESTRING", "POLYGON"))]
                assert rings, (path, out[:500])
                for ring in rings:  # GDAL flattens the arcs: every CUT contour closes on itself
                    coords = ring.split("(")[-1].rstrip(")").split(",")
                    first, last = (np.array(c.split()[:2], dtype=float) for c in (coords[0], coords[-1]))
                    assert np.abs(first - last).max() < 1e-9, path
            frame = subprocess.run(
                [
                    "ogrinfo",
                    "-ro",
                    "-al",
                    "-q",
                    "-where",
                    "Layer='ANNOTATION'",
                    str(built / family / f"{name}.frame.dxf"),
                ],
                capture_output=True,
                text=True,
                check=True,
            ).stdout
            assert "LINESTRING" in frame  # the tip path
    header = (built / "fourbar_seed000" / "mechanism_A_plates.frame.dxf").read_text()
    assert "$INSUNITS\n 70\n4\n" in header  # millimetres


def test_the_tip_path_drawn_on_the_frame_is_the_designed_one(built, parts_dir):
    fam = load_family(parts_dir / "fourbar_seed000.py")
    plates = next(p for p in fam.parts if p.name == "mechanism_B_plates")
    doc = ezdxf.readfile(built / "fourbar_seed000" / "mechanism_B_plates.frame.dxf")
    (path,) = [e for e in doc.modelspace().query("LWPOLYLINE[layer=='ANNOTATION']")]
    drawn = np.array([p[:2] for p in path.get_points("xy")])
    design = plates.tip_path()
    assert len(drawn) == len(design) + 1 and np.abs(drawn[:-1] - design).max() < 1e-9


def test_check_catches_a_moved_hole(tmp_path, built, capsys):
    folder = tmp_path / "fourbar_seed001"
    shutil.copytree(built / "fourbar_seed001", folder)
    # as built it passes (test_build_cli's check of every family says so, with these lines:
    # "eight_row_arm_plates [tip_path]: tip path of the four-bar rebuilt from the plates: ...")
    # the shop's coupler with its C hole 0.01 mm further out: the arm it builds misses the path
    path = folder / "eight_row_arm_plates.coupler.dxf"
    doc = ezdxf.readfile(path)
    holes = [e for e in doc.modelspace().query("LWPOLYLINE[layer=='CUT']") if len(e) < 6]  # arcs of a circle
    hole = max(holes, key=lambda e: np.mean([p[0] for p in e.get_points("xy")]))  # C, 200 mm from B
    hole.set_points([(x + 0.01, y, b) for x, y, b in hole.get_points("xyb")], format="xyb")
    doc.saveas(path)
    assert cli.main(["check", "--run-script", str(folder)]) == 1
    text = capsys.readouterr().out
    assert "PROBLEM: the four-bar rebuilt from the plates leaves the designed tip path by" in text


def test_a_finger_from_a_published_centre_of_mass():
    # seed 003 type I: a uniform coupler plate (bar B->C and finger B->T) whose centre of mass is (-50, -20)
    tip = np.array(finger_for_centre_of_mass(71.5, (-50.0, -20.0)))
    c, length = 71.5, float(np.linalg.norm(tip))
    com = (c * np.array([c / 2, 0.0]) + length * tip / 2) / (c + length)
    assert np.abs(com - [-50.0, -20.0]).max() < 1e-9 and 170 < length < 190
    with pytest.raises(SpecError, match="coupler = nan"):
        finger_for_centre_of_mass(float("nan"), (-50.0, -20.0))


def test_plates_refuse_holes_that_do_not_fit(seed000_arms):
    pin = Joint("pin 8", 8.05, 20.0)
    with pytest.raises(SpecError, match="joint boss"):
        Joint("pin 8", 8.05, 9.0)
    with pytest.raises(SpecError, match="crank length = 35.0 is out of range"):
        LinkPlatesStudy("a", seed000_arms["A"], pin, Joint("shaft 60", 60.0, 70.0), 6.0, 5.0)
