"""Part scripts, the builder and the command line."""

import hashlib
import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

from transplanter.app import cli
from transplanter.app.testing import admesh_available, assert_admesh_clean
from transplanter.core.errors import ExportError, PartScriptError, SpecError
from transplanter.families import build_family, discover, load_family
from transplanter.shop.export import atomic_write


def _tree_hashes(root: Path) -> dict[str, str]:
    """Digests of every exported file (the families' hidden lock files beside them excluded)."""
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file() and not p.name.endswith(".lock")
    }


def test_build_all_families_twice_is_byte_identical(tmp_path, parts_dir, built):
    a, b = built, tmp_path / "b"  # built with --jobs 2; this one serially, so the order of work differs too
    # two four-bar families, analyses and plates (the gear families cost two thirds of a build; the
    # made parts of every kind go through the same writers, and STEP and 3MF rebuild byte-identical
    # in test_formats)
    scripts = [str(parts_dir / f"fourbar_seed00{k}.py") for k in (1, 3)]
    assert cli.main(["build", *scripts, "-o", str(b), "--jobs", "1"]) == 0
    ha = {k: v for k, v in _tree_hashes(a).items() if k.startswith(("fourbar_seed001", "fourbar_seed003"))}
    hb = {k: v for k, v in _tree_hashes(b).items() if not k.startswith(".")}  # the exports, not the build records
    assert ha == hb
    for fam in ("planetary_seed004", "potseedling_seed002"):
        assert "<img src=" in (a / fam / "report.html").read_text()
    assert ".dxf" in (a / "potseedling_seed002" / "report.html").read_text()
    stls = sorted(a.rglob("*.stl"))
    assert len(stls) >= 5 + 24  # seed-002 four gears and the cam, the four-bars' 24 plates, seed 004's parts
    if admesh_available():
        for path in stls:
            assert_admesh_clean(path)
    assert {Path(k).parts[0] for k in _tree_hashes(a) if not k.startswith(".")} == {
        "fourbar_seed000",
        "fourbar_seed001",
        "fourbar_seed003",
        "picking_dwell",
        "planetary_seed004",
        "potseedling_seed002",
    }
    manifest = json.loads((a / "fourbar_seed000" / "manifest.json").read_text())
    assert manifest["ok"] is True
    for part in manifest["parts"].values():
        for fname, digest in part["files"].items():
            assert hashlib.sha256((a / "fourbar_seed000" / fname).read_bytes()).hexdigest() == digest
    assert not list(a.rglob("*.tmp")), "no temporary files left behind"


def test_build_one_script_with_jobs(tmp_path, parts_dir):
    out = tmp_path / "o"
    scripts = [str(parts_dir / "fourbar_seed001.py"), str(parts_dir / "fourbar_seed003.py")]
    assert cli.main(["build", *scripts, "-o", str(out), "--jobs", "2"]) == 0
    # beside each family its lock file and the record of its build (hidden), nothing else
    assert sorted(p.name for p in out.iterdir()) == [
        ".fourbar_seed001.build.json",
        ".fourbar_seed001.lock",
        ".fourbar_seed003.build.json",
        ".fourbar_seed003.lock",
        "fourbar_seed001",
        "fourbar_seed003",
    ]


def test_analyse_prints_the_metrics_table(capsys, parts_dir, tmp_path):
    assert cli.main(["analyse", str(parts_dir / "fourbar_seed000.py"), "--plots", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "mechanism_B" in out and "loop height" in out and "max speed crank angle" in out
    assert (tmp_path / "mechanism_B.path.png").stat().st_size > 1000


def test_failing_part_keeps_the_others_and_previous_files(tmp_path):
    script = tmp_path / "two.py"
    script.write_text(
        "from transplanter.families import ArmStudy, Family\n"
        "from transplanter.design.linkage.fourbar import FourBar\n"
        "from transplanter.design.linkage.planting import PlantingArm\n"
        "DEPTH = {depth}\n"
        "def family():\n"
        "    good = PlantingArm(FourBar(125, 40, 100, 85), (-170.0, 60.0), 25.0, 600.0, name='good')\n"
        "    deep = PlantingArm(FourBar(125, 40, 100, 85), (-170.0, 60.0), 25.0, 600.0, name='deep')\n"
        "    return Family('two', 'test', (ArmStudy(good, 40.0), ArmStudy(deep, DEPTH)))\n"
    )
    out = tmp_path / "out"
    script.write_text(script.read_text().format(depth=30.0))
    assert cli.main(["build", str(script), "-o", str(out)]) == 0
    before = (out / "two" / "deep.metrics.json").read_bytes()
    # now the second part asks for a planting depth deeper than the whole loop
    script.write_text(script.read_text().replace("DEPTH = 30.0", "DEPTH = 5000.0"))
    assert cli.main(["build", str(script), "-o", str(out)]) == 1
    manifest = json.loads((out / "two" / "manifest.json").read_text())
    assert manifest["ok"] is False
    assert "planting_depth must be < loop height" in manifest["parts"]["deep"]["error"]
    assert "files" in manifest["parts"]["good"]
    assert (out / "two" / "deep.metrics.json").read_bytes() == before


@pytest.mark.parametrize(
    "source, match",
    [
        ("def family(:\n", r"bad.py:1: syntax error"),
        ("x = 1\n", r"must define family\(\)"),
        ("def family():\n    return 42\n", r"family\(\) returned int"),
        ("def family():\n    return 1 / 0\n", r"bad.py:2: family\(\) raised ZeroDivisionError"),
        (
            "from transplanter.design.linkage.fourbar import FourBar\n"
            "def family():\n    return FourBar(100, 65, 70, 90, branch=2)\n",
            r"branch = 2 is out of range",
        ),
        (
            "from transplanter.families import Family\ndef family():\n    return Family('bad name/x', 'd')\n",
            r"family name = 'bad name/x' is out of range",
        ),
    ],
)
def test_malformed_part_scripts(tmp_path, source, match):
    p = tmp_path / "bad.py"
    p.write_text(source)
    with pytest.raises(PartScriptError, match=match):
        load_family(p)


def test_cli_reports_bad_input_without_traceback(tmp_path, capsys):
    p = tmp_path / "bad.py"
    p.write_text("def family(:\n")
    assert cli.main(["build", str(p), "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "transplanter: error:" in err and "syntax error" in err and "Traceback" not in err
    assert cli.main(["build", "--parts", str(tmp_path / "nowhere")]) == 2


def test_discover_skips_private_scripts(tmp_path):
    (tmp_path / "_helper.py").write_text("")
    (tmp_path / "b.py").write_text("")
    (tmp_path / "a.py").write_text("")
    assert [p.name for p in discover(tmp_path)] == ["a.py", "b.py"]


def test_atomic_write_leaves_previous_file_on_failure(tmp_path, monkeypatch):
    target = atomic_write(tmp_path / "f.txt", b"old")

    def boom(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(ExportError, match="No space left on device"):
        atomic_write(target, b"new")
    assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["f.txt"]


def test_build_family_returns_manifest(tmp_path, parts_dir):
    fam = load_family(parts_dir / "fourbar_seed003.py")
    seen = []
    manifest = build_family(fam, tmp_path, progress=seen.append)
    assert seen == [f"fourbar_seed003/{n}" for n in ("type_I", "type_II", "type_I_plates", "type_II_plates")]
    cw = manifest["parts"]["type_I"]["results"]["counterweight"]["vertical"]
    assert abs(cw["radius_for_total_mass_mm"] - 35.7) < 0.05


def test_analyse_prints_planetary_metrics_beside_the_paper(parts_dir, capsys):
    assert cli.main(["analyse", str(parts_dir / "planetary_seed004.py")]) == 0
    out = capsys.readouterr().out
    assert "published" in out
    line = next(ln for ln in out.splitlines() if ln.strip().startswith("picking angle"))
    assert "337.30" in line and "342.00" in line


def test_optimise_command_is_reproducible(tmp_path, capsys):
    script = tmp_path / "bowl.py"
    script.write_text(
        "from transplanter.design.optimise import Problem\n"
        "def problem():\n"
        "    cost = lambda v: (v[0] - 0.5) ** 2 + (v[1] - 1) ** 2\n"
        "    return Problem('bowl', (('x', -2.0, 2.0), ('y', -1.0, 3.0)), cost)\n"
    )
    outs = []
    for _ in range(2):
        assert cli.main(["optimise", str(script), "--seed", "4", "--maxiter", "30", "--popsize", "8"]) == 0
        captured = capsys.readouterr()
        assert "generation    1/30" in captured.err
        outs.append(json.loads(captured.out))
    assert outs[0] == outs[1]
    assert outs[0]["parameters"]["x"] == pytest.approx(0.5, abs=1e-3)


def test_optimise_needs_a_problem(parts_dir, capsys):
    assert cli.main(["optimise", str(parts_dir / "fourbar_seed001.py")]) == 2
    assert "must define problem()" in capsys.readouterr().err


def test_every_gear_and_cam_family_carries_its_meshing_proof(built):
    seed002 = json.loads((built / "potseedling_seed002" / "manifest.json").read_text())
    for name in ("gears_2_3", "gears_3_5"):
        meshing = seed002["parts"][name]["results"]["meshing"]
        assert set(meshing) >= {"outline", "dxf", "stl"}
        r = meshing["dxf"]
        # designed backlash: only the driving flanks touch, and the play follows the pitch
        # curve's pressure deviation (the transmission error is a share of the backlash)
        assert r["problems"] == [] and r["min_contacts"] >= 1 and r["contact_ratio"] > 1.2
        assert r["max_penetration_mm2"] == 0.0
        assert r["max_transmission_error_mm"] < 0.1 * meshing["backlash_target_mm"]
        for source in ("outline", "stl"):  # the DXF's proof carried: the same teeth within a µm
            c = meshing[source]
            assert c["problems"] == [] and c["carried_from"] == "dxf" and max(c["teeth_within_mm"]) <= 1e-3
            assert meshing["min_clearance_mm"] <= c["clearance_at_least_mm"] < r["clearance_mm"]
        assert f"{name}.meshing.png" in seed002["parts"][name]["files"]
    cam = seed002["parts"]["swing_cam"]["results"]["follower_check"]
    assert set(cam) >= {"profile", "dxf", "stl"}
    assert all(cam[s]["max_error_mm"] < 5e-3 for s in ("profile", "dxf", "stl"))
    seed004 = json.loads((built / "planetary_seed004" / "manifest.json").read_text())
    teeth = seed004["parts"]["ring_planet_teeth"]
    assert teeth["results"]["shop_files"].startswith("withheld")
    assert not any(f.endswith((".dxf", ".stl")) for f in teeth["files"])
    outline = teeth["results"]["meshing"]["outline"]
    assert outline["problems"][0].startswith("the teeth foul") and outline["max_fouling_mm2"] > 0.1
    # rebuilt from the driving flanks with the designed 0.072 mm backlash: where the planet's pitch
    # radius falls to 3.84 mm that play turns the 150 mm arm by up to ~150 * 0.07 / 3.84 ≈ 3-5 mm
    assert 0.1 < outline["train"]["max_tip_deviation_mm"] < 6.0
    page = (built / "planetary_seed004" / "report.html").read_text()
    assert "ring_planet_teeth.meshing.png" in page and "max fouling</td>" in page


def test_check_command_reruns_the_checks_on_disk(built, capsys):
    """The CLI's report of ``check`` on a built family (every family's proofs are re-run on its
    files by its part items, ``transplanter.app.pytest_plugin``; gear pairs' lines below and in
    ``test_check_command_catches_a_tampered_part``)."""
    folder = built / "fourbar_seed001"
    assert cli.main(["check", "--run-script", str(folder)]) == 0
    out = capsys.readouterr().out
    assert "eight_row_arm: 2 data files reproduced by the script" in out
    assert "eight_row_arm_plates [tip_path]: tip path of the four-bar rebuilt from the plates: max deviation" in out
    assert "eight_row_arm_plates [eight_row_arm_plates.coupler.step]: 1 solid, 19 faces, valid (BRepCheck" in out
    assert out.endswith("  ok\n")
    # every STEP, re-read by OCP as a valid solid of its DXF's volume, and the 3MF re-read by
    # trimesh with one body per part and no overlap
    steps = {p.name for p in folder.glob("*.step")}
    lines = [line for line in out.splitlines() if ".step]: " in line]
    assert {line.split("[")[1].split("]")[0] for line in lines} == steps and len(steps) == 4
    assert all("1 solid" in line and ", valid (" in line for line in lines)
    models = [line for line in out.splitlines() if ".3mf]: " in line]
    assert len(models) == 1 and "4 bodies, largest overlap 0 mm³" in models[0]


def test_check_reports_a_rebuilt_train_and_an_expected_finding(monkeypatch, capsys, tmp_path):
    """How ``check`` words a pair that drives a train, a pair built as a finding (seed 004's
    published pair) and a cam's follower (the part items of seeds 002 and 004 run the real ones)."""
    import transplanter.families as families

    mesh = {
        "max_penetration_mm2": 0.0,
        "max_fouling_mm2": 0.0,
        "max_transmission_error_mm": 2e-3,
        "rms_transmission_error_mm": 1e-3,
        "backlash_mm": [0.07, 0.08],
        "contact_ratio": 1.4,
    }
    report = {
        "family": "planetary",
        "script": "",
        "script_run": True,
        "files": {},
        "parts": {
            "teeth": {
                "results": {"outline": {**mesh, "train": {"max_tip_deviation_mm": 3.2}}},
                "problems": ["outline: the teeth foul 2 mm from the pitch point"],
                "expected": True,
            }
        },
        "ok": True,
    }
    report["parts"]["cam"] = {
        "results": {"dxf": {"max_error_mm": 1.5e-3, "rms_error_mm": 4e-4}},
        "problems": [],
        "expected": False,
    }
    monkeypatch.setattr(families, "check_families", lambda folders, script, jobs, run_script, timeout: iter([report]))
    (tmp_path / "manifest.json").write_text("{}")
    assert cli.main(["check", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "teeth [outline]: overlap 0 mm² (fouling 0)" in out and "train tip deviation 3.2 mm" in out
    assert "teeth: finding (expected): outline: the teeth foul" in out and out.endswith("  ok\n")
    assert "cam [dxf]: follower error max 1.5 µm rms 0.4 µm" in out


SMALL_PAIR = """
from transplanter.geometry.cutter import ShaperCutter
from transplanter.families import Family, Making, ToothedPairStudy
from transplanter.geometry.pitch import GearPair, PitchCurve
from transplanter.shop.solids import Features


def family():
    pair, sizing = GearPair.from_driver(PitchCurve.ellipse(20.0, 0.15, 2), "external", 2).sized(module=2.0)
    making = (Making(6.0, Features(bore=8.0), step=False, material="C45"),) * 2  # the STEP is tested on its own
    study = ToothedPairStudy("pair", pair, ShaperCutter(12, 2.0), sizing.teeth[0], making=making, mesh_steps=36)
    return Family("small", "an elliptical pair", (study,))
"""


def test_check_command_catches_a_tampered_part(tmp_path, capsys, monkeypatch):
    from transplanter.shop import dxf

    monkeypatch.chdir(tmp_path)  # the project: --run-script runs scripts from inside it only
    script = tmp_path / "small.py"
    script.write_text(SMALL_PAIR)
    assert cli.main(["build", str(script), "-o", str(tmp_path / "out")]) == 0
    fam = tmp_path / "out" / "small"
    assert cli.main(["check", "--run-script", str(fam)]) == 0
    out = capsys.readouterr().out
    # the shop files re-proved: the DXF meshed, carried to the STL (the outline CSV is held to its digest)
    assert "pair [dxf]: overlap 0 mm² (fouling 0), TE max" in out
    assert "pair [stl]: the dxf's proof carried: teeth within" in out
    assert "pair [outline]" not in out
    path = fam / "pair.driven.dxf"
    moved = shapely.affinity.rotate(dxf.read_section(path.read_bytes()), 2.0, origin=(0, 0))  # 2 deg off
    path.write_bytes(dxf.dxf_bytes(dxf.DxfPart("pair.driven", moved)))
    assert cli.main(["check", "--run-script", str(fam)]) == 1
    out = capsys.readouterr().out
    assert "file pair.driven.dxf: changed since the build" in out
    assert "pair: PROBLEM: dxf: the teeth interfere at the pitch point" in out and "FAILED" in out
    assert "pair: PROBLEM: pair.driven.dxf: its contour is the design turned by 2.00 deg" in out
    manifest = json.loads((fam / "manifest.json").read_text())
    manifest["parts"]["pair"] = {"error": "GeometryError: made up"}
    (fam / "manifest.json").write_text(json.dumps(manifest))
    assert cli.main(["check", "--run-script", str(fam)]) == 1
    out = capsys.readouterr().out
    assert "pair: PROBLEM: nothing to check: its build failed: GeometryError: made up" in out
    assert "file manifest.json: edited since the build (its seal, manifest_sha256, differs)" in out
    (fam / "manifest.json").unlink()
    assert cli.main(["check", "--run-script", str(fam)]) == 2
    assert "is not a built family folder (no manifest.json)" in capsys.readouterr().err


def test_optimise_in_parallel_on_local_workers_and_a_dask_cluster(tmp_path, capsys):
    """--workers 2 (a LocalCluster made for the run) and --scheduler ADDRESS (a cluster the user
    runs; here a LocalCluster made by the test) evaluate the generations in parallel and give the
    same result for the same seed; the part script's closure travels to the workers."""
    from distributed import LocalCluster

    script = tmp_path / "bowl.py"
    script.write_text(
        "from transplanter.design.optimise import Problem\n"
        "OFFSET = 0.25\n"
        "def problem():\n"
        "    cost = lambda v: (v[0] - OFFSET) ** 2 + (v[1] - 1) ** 2\n"
        "    return Problem('bowl', (('x', -2.0, 2.0), ('y', -1.0, 3.0)), cost)\n"
    )
    args = ["optimise", str(script), "--seed", "4", "--maxiter", "12", "--popsize", "6"]
    assert cli.main([*args, "--workers", "2"]) == 0
    local = json.loads(capsys.readouterr().out)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=True, dashboard_address=None) as cluster:
        assert cli.main([*args, "--scheduler", cluster.scheduler_address]) == 0
    captured = capsys.readouterr()
    remote = json.loads(captured.out)
    assert local == remote and local["evaluation"] == "parallel (deferred updating)"
    assert local["parameters"]["x"] == pytest.approx(0.25, abs=0.05)
    assert 'at {"x":' in captured.err  # the best design so far, every generation


NEW_KIND = """
from dataclasses import dataclass

from transplanter.families import Built, Checked, Family, StudyDefaults, Table


@dataclass(frozen=True)
class PlateStudy(StudyDefaults):  # a kind of study the package does not know
    name: str
    side: float
    cost = 4

    def build(self, out):
        data = f"{self.side ** 2:.6f}\\n".encode()
        return Built({"kind": "plate", "parameters": {"side": self.side}, "results": {}}, {f"{self.name}.txt": data})

    def check(self, files):
        area = float(files[f"{self.name}.txt"])
        bad = [] if abs(area - self.side**2) < 1e-9 else [f"area {area} is not {self.side**2}"]
        return Checked({"area": area}, bad)

    def tables(self):
        return [Table(self.name, (("plate area", self.side**2, "mm²", 16.0),))]


def family():
    return Family("plates", "a new kind", (PlateStudy("square", 4.0),))
"""


def test_a_new_kind_of_study_needs_only_its_module_and_script(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    script = tmp_path / "plates.py"
    script.write_text(NEW_KIND)
    assert cli.main(["build", str(script), "-o", str(tmp_path / "out")]) == 0
    assert (tmp_path / "out" / "plates" / "square.txt").read_text() == "16.000000\n"
    assert cli.main(["check", "--run-script", str(tmp_path / "out" / "plates")]) == 0
    assert cli.main(["analyse", str(script)]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if "plate area" in x)
    assert "16.0000" in line and "16.00" in line.split("16.0000")[1]  # value, then the published value
    (tmp_path / "out" / "plates" / "square.txt").write_text("15.000000\n")  # a made file gone wrong
    assert cli.main(["check", "--run-script", str(tmp_path / "out" / "plates")]) == 1
    assert "area 15.0 is not 16.0" in capsys.readouterr().out
    script.write_text(NEW_KIND.replace('(PlateStudy("square", 4.0),)', '("square",)'))
    assert cli.main(["build", str(script), "-o", str(tmp_path / "out")]) == 2
    assert "parts must be studies (transplanter.families.Study" in capsys.readouterr().err


def test_a_part_script_imports_the_design_module_beside_it(tmp_path, capsys, monkeypatch):
    """Design models and problems live beside the part script in ``_*.py``: the script imports
    them (its folder is importable), the builder does not take them for part scripts, an edit
    is read afresh, and ``check --run-script`` refuses to run a design that changed since the build."""
    monkeypatch.chdir(tmp_path)
    parts = tmp_path / "parts"
    parts.mkdir()
    design = parts / "_plate.py"
    model = NEW_KIND.split("\n\ndef family():")[0]
    design.write_text(
        model
        + "\n\nSIDE = 4.0  # mm\n\n\ndef problem():\n"
        + "    from transplanter.design.optimise import Problem\n\n"
        + "    return Problem('side', (('side', 1.0, 9.0),), lambda v: (v[0] - SIDE) ** 2)\n"
    )
    (parts / "plates.py").write_text(
        "from _plate import SIDE, PlateStudy\n\nfrom transplanter.families import Family\n\n\n"
        "def family():\n    return Family('plates', 'from a design module', (PlateStudy('square', SIDE),))\n"
    )
    assert [p.name for p in discover(parts)] == ["plates.py"]
    fam = load_family(parts / "plates.py")
    assert fam.parts[0].side == 4.0 and fam.modules == (str(parts / "_plate.py"),)
    assert "_plate" not in sys.modules  # forgotten, so the next load reads it afresh
    out = tmp_path / "out"
    assert cli.main(["build", "--parts", str(parts), "-o", str(out), "--jobs", "2"]) == 0
    capsys.readouterr()
    manifest = json.loads((out / "plates" / "manifest.json").read_text())
    assert list(manifest["script"]["modules"]) == ["_plate.py"]
    assert cli.main(["optimise", str(design), "--seed", "1", "--maxiter", "5", "--popsize", "4"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"]["side"] == pytest.approx(4.0, abs=0.5)
    assert cli.main(["check", "--run-script", str(out / "plates")]) == 0
    assert "changed since the build" not in capsys.readouterr().out
    design.write_text(design.read_text().replace("SIDE = 4.0", "SIDE = 5.0"))
    assert load_family(parts / "plates.py").parts[0].side == 5.0
    # a copy imported beforehand (a notebook, pytest's doctest collection) is not served instead,
    # nor is a namesake from another folder (another copy of parts/, imported first)
    other = tmp_path / "elsewhere" / "_plate.py"
    other.parent.mkdir()
    other.write_text(design.read_text().replace("SIDE = 5.0", "SIDE = 7.0"))
    for where, side in ((design, 4.0), (other, 7.0)):
        held = type(sys)("_plate")
        held.__file__, held.SIDE = str(where), side
        sys.modules["_plate"] = held
        try:
            fam = load_family(parts / "plates.py")
            assert fam.parts[0].side == 5.0 and fam.modules == (str(parts / "_plate.py"),)
            assert sys.modules["_plate"] is held  # put back as it was
        finally:
            del sys.modules["_plate"]
    assert cli.main(["check", "--run-script", str(out / "plates")]) == 2
    assert "the module '_plate.py' beside it is missing or is not the one the build imported" in (
        capsys.readouterr().err
    )
    assert cli.main(["check", str(out / "plates")]) == 0  # its files are as built: no code needed for that
    (parts / "plates.py").write_text("from _missing import SIDE\n")
    with pytest.raises(PartScriptError, match=r"plates.py:1: ModuleNotFoundError: No module named '_missing'"):
        load_family(parts / "plates.py")


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_two_scripts_of_one_family_are_refused_whatever_the_jobs(tmp_path, capsys, jobs):
    """Regression (issue 31): with --jobs 1 the second script's export silently replaced the first's."""
    script = "from transplanter.families import Family\n\ndef family():\n    return Family('same', 'test', ())\n"
    (tmp_path / "a.py").write_text(script)
    (tmp_path / "b.py").write_text(script)
    out = tmp_path / "out"
    code = cli.main(["build", str(tmp_path / "a.py"), str(tmp_path / "b.py"), "-o", str(out), "--jobs", jobs])
    assert code == 2
    assert "two part scripts define the same family name" in capsys.readouterr().err
    assert not (out / "same").exists()


@pytest.mark.parametrize(
    "option, value", [("--maxiter", "-3"), ("--popsize", "0"), ("--workers", "0"), ("--seed", "-1")]
)
def test_optimiser_options_out_of_range_are_named_one_by_one(parts_dir, capsys, option, value):
    with pytest.raises(SystemExit) as exc:
        cli.main(["optimise", str(parts_dir / "_seed004.py"), option, value])
    assert exc.value.code == 2
    assert f"{option} = {value} is out of range" in capsys.readouterr().err


OPTIMISED = """
from transplanter.design.optimise import Problem

# the design the part script builds (written by transplanter optimise --write)
OPTIMUM = (
    0.0,
    1.5,
)
SIDES = (3, 4, 5, 6)


def problem():
    def cost(v):
        return (SIDES[int(v[0])] - 5) ** 2 + (v[1] - 0.25) ** 2

    return Problem(
        "polygon", (("sides_choice", 0.0, 3.999), ("x", -1.0, 2.0)), cost,
        choices=("sides_choice",), describe=lambda v: {"sides": f"{SIDES[int(v[0])]}"}, optimum="OPTIMUM",
    )
"""


def test_the_optimiser_records_its_optimum_where_the_script_reads_it(tmp_path, capsys):
    """Progress shows choices as integers, the objectives and the time left; --write replaces the
    script's OPTIMUM in place (nothing else in the file changes) so a build follows it."""
    script = tmp_path / "design.py"
    script.write_text(OPTIMISED)
    args = ["optimise", str(script), "--seed", "2", "--maxiter", "6", "--popsize", "8"]
    assert cli.main([*args, "--write"]) == 0
    captured = capsys.readouterr()
    result = json.loads(captured.out)
    assert result["parameters"]["sides_choice"] == 2 and isinstance(result["parameters"]["sides_choice"], int)
    assert '"sides_choice": 2' in captured.err and "s left" in captured.err and "  sides: 5" in captured.err
    text = script.read_text()
    assert text.startswith(OPTIMISED.split("OPTIMUM = (")[0]) and text.endswith(OPTIMISED.split("\n)\n", 1)[1])
    ns: dict = {}
    exec(compile(text, str(script), "exec"), ns)  # noqa: S102 - the test's own script
    assert int(ns["OPTIMUM"][0]) == result["parameters"]["sides_choice"]  # the choice the model uses
    assert abs(ns["OPTIMUM"][1] - result["parameters"]["x"]) < 1e-6
    script.write_text(OPTIMISED.replace(', optimum="OPTIMUM"', ""))
    assert cli.main([*args, "--write"]) == 2
    assert "names no place: give Problem(..., optimum='OPTIMUM')" in capsys.readouterr().err


SET_PROBLEM = """
from transplanter.design.optimise import Problem

BEST_1 = (0.0, 0.0)
START = (0.9, 0.9)


def problem(target=0.0):
    return Problem(
        f"bowl at {target:g}", (("x", -1.0, 2.0), ("y", -1.0, 2.0)), lambda v: (v[0] - target) ** 2 + v[1] ** 2,
        optimum=f"BEST_{round(target)}", x0=START, spread=0.05,
    )
"""


def test_set_passes_numbers_to_problem_and_spread_seeds_around_x0(tmp_path, capsys):
    """``--set NAME=VALUE`` reaches the script's problem() (a Pareto point per least module, issue
    27: ``--set min_module=2.5``) and --write records where that problem says; half the first
    population is drawn around x0 (``Problem.spread``), the rest uniform, reproducibly."""
    import numpy as np

    from transplanter.design.optimise import Problem, _initial

    script = tmp_path / "design.py"
    script.write_text(SET_PROBLEM)
    args = ["optimise", str(script), "--seed", "1", "--maxiter", "30", "--popsize", "8", "--set", "target=1"]
    assert cli.main([*args, "--write"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["problem"] == "bowl at 1" and abs(result["parameters"]["x"] - 1.0) < 0.05
    assert "BEST_1 = (0.0, 0.0)" not in script.read_text() and "START = (0.9, 0.9)" in script.read_text()
    for bad, said in (("target", "NAME=NUMBER"), ("target=abc", "a number"), ("size=2", "does not take it")):
        assert cli.main(["optimise", str(script), "--maxiter", "1", "--set", bad]) == 2
        assert said in capsys.readouterr().err
    p = Problem("p", (("x", 0.0, 10.0), ("c", 0.0, 2.999)), lambda v: 0.0, x0=(5.0, 1.5), spread=0.02, choices=("c",))
    first = _initial(p, 3, 10)
    assert first.shape == (20, 2) and list(first[0]) == [5.0, 1.5]
    assert np.all(np.abs(first[:10, 0] - 5.0) < 1.0) and np.all(first[:10, 1] == 1.5)  # around x0, choice kept
    assert np.ptp(first[10:, 0]) > 3.0  # the rest spread over the range
    assert np.array_equal(first, _initial(p, 3, 10))
    with pytest.raises(SpecError, match="give x0"):
        Problem("p", (("x", 0.0, 1.0),), lambda v: 0.0, spread=0.1)


PLATE_KIND = """
from dataclasses import dataclass

from transplanter.families import Built, StudyDefaults


@dataclass(frozen=True)
class Plate(StudyDefaults):
    name: str
    side: float
    cost = 1

    def build(self, out):
        data = f"{self.side ** 2:.6f}\\n".encode()
        return Built({"kind": "plate", "parameters": {"side": self.side}, "results": {}}, {f"{self.name}.txt": data})
"""
TWO_PLATES = """
from _plate_kind import Plate

from transplanter.families import Family


def family():
    return Family("plates", "two plates", (Plate("a", A_SIDE), Plate("b", 4.0)))
"""


def _files(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_only_what_changed_is_rebuilt_and_the_folder_equals_a_full_rebuild(tmp_path, capsys):
    script, out = tmp_path / "plates.py", tmp_path / "out"
    (tmp_path / "_plate_kind.py").write_text(PLATE_KIND)  # the kind of study, in a design module
    script.write_text(TWO_PLATES.replace("A_SIDE", "3.0"))
    assert cli.main(["build", str(script), "-o", str(out)]) == 0
    folder = out / "plates"
    stamps = {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}
    capsys.readouterr()
    assert cli.main(["build", str(script), "-o", str(out)]) == 0  # nothing changed: nothing touched
    assert "(2 kept unchanged since the last build" in capsys.readouterr().out
    assert {p.name: p.stat().st_mtime_ns for p in folder.iterdir()} == stamps
    script.write_text(TWO_PLATES.replace("A_SIDE", "5.0"))  # one part edited
    assert cli.main(["build", str(script), "-o", str(out)]) == 0
    record = json.loads((out / ".plates.build.json").read_text())
    assert record["kept"] == ["b"] and list(record["rebuilt"]) == ["a"] and "changed" in record["rebuilt"]["a"]
    assert (folder / "a.txt").read_text() == "25.000000\n"
    full = tmp_path / "full"
    assert cli.main(["build", str(script), "-o", str(full), "--force"]) == 0
    assert _files(full / "plates") == _files(folder)  # byte for byte
    (folder / "b.txt").write_text("tampered\n")  # a kept part whose file changed is rebuilt
    assert cli.main(["build", str(script), "-o", str(out)]) == 0
    record = json.loads((out / ".plates.build.json").read_text())
    assert (
        record["rebuilt"]
        == record["unverified"]
        == {"b": "its files do not verify: b.txt: changed since the build (SHA-256 differs)"}
    )
    assert (folder / "b.txt").read_text() == "16.000000\n"


class _CountedCost:
    """A cost function that counts how often it is pickled (in this process: the client's side)."""

    pickled = 0

    def __call__(self, v):
        return float((v[0] - 0.5) ** 2 + (v[1] + 0.25) ** 2)

    def __reduce__(self):
        type(self).pickled += 1
        return (_CountedCost, ())


def _opened() -> list[str]:
    from transplanter.design import cluster

    return list(cluster._OPENED)


def _worker_settings() -> dict:
    import os

    import dask

    keys = ("distributed.admin.tick.interval", "distributed.worker.memory.monitor-interval")
    keys += ("distributed.worker.memory.spill", "distributed.worker.profile.enabled")
    return {"OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS"), **{k: dask.config.get(k) for k in keys}}


def _steals(dask_scheduler) -> bool:
    return "stealing" in dask_scheduler.extensions


def test_a_parallel_search_ships_its_cost_function_once_and_batches_the_candidates():
    """Issue 46: the problem is scattered to the workers once per run, not pickled per task or per
    generation, and each generation goes out in batches shrinking to one candidate (the results in
    order); the local workers run with ``WORKER_CONFIG``'s settings (spawned, not forked: they get
    them from their nanny): one BLAS thread each, no profiler, the event loop's tick and memory
    monitor slowed, no spilling; the local scheduler steals no work (the batches balance it)."""
    from transplanter.design import optimise as search

    problem = search.Problem("bowl", (("x", -2.0, 2.0), ("y", -2.0, 2.0)), _CountedCost())
    with search._evaluator(2, None) as run:
        seen = run.client.run(_worker_settings)
        assert len(seen) == 2 and not run.client.run_on_scheduler(_steals)
        for settings in seen.values():
            assert settings == {
                "OMP_NUM_THREADS": "1",
                "distributed.admin.tick.interval": "1s",
                "distributed.worker.memory.monitor-interval": "1s",
                "distributed.worker.memory.spill": False,
                "distributed.worker.profile.enabled": False,
            }
        xs = [np.array([k / 10, 0.0]) for k in range(30)]
        assert run(problem, xs) == [problem(x) for x in xs]  # in the candidates' order
        assert run.tasks == len(search.batch_bounds(30, 2)) == 8  # 8, 8, 4, 4, 2, 2, 1, 1 candidates
        before = _CountedCost.pickled
        for _ in range(3):  # scipy passes the same function every generation: not shipped again
            assert run(problem, xs[:5]) == [problem(x) for x in xs[:5]]
        assert _CountedCost.pickled == before and run.tasks == 8 + 3 * 3  # 2, 2, 1 candidates
        # shipped as bytes, opened once by each worker in its first batch (side by side, not in turn)
        opened = run.client.run(_opened)
        assert len(opened) == 2 and len({tuple(t) for t in opened.values()}) == 1 and len(opened.popitem()[1]) == 1
        address = run.client.scheduler.address
        parallel = search.optimise(problem, seed=2, maxiter=6, popsize=5, scheduler=address)
    serial = search.optimise(problem, seed=2, maxiter=6, popsize=5, updating="deferred")
    assert (parallel.x, parallel.fun, parallel.evaluations) == (serial.x, serial.fun, serial.evaluations)


@pytest.mark.parametrize("workers", [1, 2, 3, 16])
def test_a_generation_goes_out_in_batches_that_shrink_to_one_candidate(workers):
    """Issue 46: factoring. The batches cover the candidates once, in order, never grow, and end in
    single candidates, at most one per worker: no worker waits at the barrier on more than one of
    another's candidates. The first round is half the generation, so a task's cost stays small."""
    from transplanter.design.optimise import batch_bounds

    assert batch_bounds(0, workers) == []
    for n in range(1, 200):
        bounds = batch_bounds(n, workers)
        assert [a for a, _ in bounds] == [0] + [b for _, b in bounds[:-1]] and bounds[-1][1] == n
        sizes = [b - a for a, b in bounds]
        assert all(s >= 1 for s in sizes) and sizes == sorted(sizes, reverse=True)
        assert sizes[-1] == 1
        assert sum(sizes[:workers]) >= n // 2  # the first round takes half the generation
        assert len(bounds) <= workers * (2 + n.bit_length())  # a round per halving
