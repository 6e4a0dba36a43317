"""One call for a gear pair (``transplanter pair``): spec parsing, and pairs made and proved from the CLI."""

import json
import math

import numpy as np
import pytest

from transplanter.app import cli
from transplanter.core.errors import SpecError
from transplanter.geometry.pitch.transmission import ratio_from_expression, size_pair, transmission


def _files(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file() and p.name != "manifest.json"}


def test_an_elliptical_pair_from_the_cli_meshes_on_its_exports(tmp_path, capsys):
    """Cut by a rack cutter (hob), with a profile shift from the command line (the remedies an
    error names are options); the ring below by a shaper cutter the call chooses."""
    args = ["pair", "ellipse:0.1:2", "--teeth", "30", "--module", "2", "--rack", "--shift", "0.05,-0.05"]
    args += ["-o", str(tmp_path)]
    assert cli.main(args) == 0
    out = capsys.readouterr().out
    assert "30/30 teeth, m = 2 mm" in out and "rack cutter (hob)" in out and "ok ->" in out
    folder = tmp_path / "pair"
    manifest = json.loads((folder / "manifest.json").read_text())
    rec = manifest["parts"]["pair"]
    for ext in (".dxf", ".stl", ".step"):
        assert {f"pair.driver{ext}", f"pair.driven{ext}"} <= set(rec["files"])
    assert "pair.assembly.3mf" in rec["files"]
    # the proof: the pair meshed once, from its DXF re-read from the bytes written, and carried to
    # the STL and the outlines, whose teeth lie within a µm of it (the ring test below re-runs it
    # on the files with transplanter check)
    line = next(x for x in out.splitlines() if "meshing [dxf]: " in x)
    assert "overlap 0 mm² (fouling 0)" in line
    for source in ("outline", "stl"):
        line = next(x for x in out.splitlines() if f"meshing [{source}]: " in x)
        assert "the dxf's proof carried: teeth within 1 µm/1 µm" in line
        carried = rec["results"]["meshing"][source]
        assert carried["problems"] == [] and carried["carried_from"] == "dxf"
        assert carried["clearance_at_least_mm"] >= rec["results"]["meshing"]["min_clearance_mm"]
    assert rec["results"]["meshing"]["dxf"]["problems"] == []
    mesh = rec["results"]["meshing"]["dxf"]
    low, high = rec["results"]["meshing"]["backlash_band_mm"]
    assert low <= mesh["backlash_mm"][0] and mesh["backlash_mm"][1] <= high and mesh["contact_ratio"] > 1
    # the part script left beside the folder states the call: building it where the call wrote
    # keeps the part — its key (the code and every value the part holds, manifest.part_key) is the
    # one the call built under — and leaves the files as they were (that a part's files rebuild
    # byte-identical is test_build_cli's and the golden export digests')
    script = tmp_path / "pair.py"
    assert "pair_family(" in script.read_text() and "'ellipse:0.1:2'" in script.read_text()
    assert "rack=True" in script.read_text() and "shift=(0.05, -0.05)" in script.read_text()
    assert manifest["parts"]["pair"]["parameters"]["shift"] == [0.05, -0.05]
    made = _files(folder)
    assert cli.main(["build", str(script), "-o", str(tmp_path)]) == 0
    assert _files(folder) == made
    summary = capsys.readouterr().out.splitlines()[-1]  # the build's summary
    assert summary.startswith("built 1 of 1 parts in 1 family in ")
    assert "(1 kept unchanged since the last build" in summary


def test_the_remedies_errors_name_are_options():
    """An error's remedies are the call's options (and the CLI's: --allow-undercut, --shift,
    --addendum, --no-trim-ring-tips), and a centre distance the teeth cannot carry exactly is said
    as adjusted."""
    from transplanter.core.errors import GeometryError
    from transplanter.families import pair_family

    with pytest.raises(GeometryError, match=r"undercut .* allow_undercut=True \(--allow-undercut\)"):
        pair_family("phi", teeth=12, module=1.5, cutter_teeth=18).parts[0].build(None)
    study = pair_family("phi", teeth=12, module=1.5, cutter_teeth=18, allow_undercut=True, shift=(0.1, -0.1)).parts[0]
    assert study.allow_undercut is True and study.shift == (0.1, -0.1) and study.trim_ring_tips is True
    family = pair_family("phi", module=1.5, centre_distance=40.0, addendum=0.9)
    assert "a = 40.5 mm (ADJUSTED from the 40 mm asked: the nearest that carries whole teeth)" in family.description
    assert family.parts[0].addendum == (0.9, 0.9)


def test_a_four_lobed_ring_and_its_planet_from_the_cli(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = ["pair", "ellipse:0.05:2", "--internal", "--driven-lobes", "4", "--teeth", "24", "--module", "1.5"]
    assert cli.main([*args, "-o", str(tmp_path)]) == 0
    assert "internal pair of 'ellipse:0.05:2': 24/48 teeth, m = 1.5 mm, a = 17.9438 mm, shaper cutter z0 = 14" in (
        capsys.readouterr().out
    )
    manifest = json.loads((tmp_path / "pair" / "manifest.json").read_text())
    asm = manifest["parts"]["pair"]["results"]["assembly"]
    assert asm["kind"] == "internal" and asm["ring"] == "driven" and asm["teeth"] == [24, 48]
    assert asm["model"]["max_overlap_mm3"] == 0.0
    # the files re-read as a shop gets them (the proofs re-run on them: test_build_cli's tampered part)
    assert cli.main(["check", str(tmp_path / "pair")]) == 0
    check = capsys.readouterr().out
    assert "pair: 4 shop files re-read (DXF, STL)" in check and check.endswith("  ok\n")


def test_the_ratio_of_a_transmission_function_is_its_exact_derivative():
    ratio = ratio_from_expression("phi - 0.08*sin(2*phi)")
    phi = np.linspace(0, 2 * math.pi, 1001)
    assert ratio.lobes == 2
    assert np.max(np.abs(ratio(phi) - (1 - 0.16 * np.cos(2 * phi)))) < 1e-12
    pair = transmission("0.5*phi + 0.03*sin(phi)").pair  # one driver turn turns the driven half a turn
    assert pair.lobes == (1, 2) and pair.closure_error < 1e-9
    assert abs(float(pair.ratio(0.0)) - 0.53) < 1e-12


def test_ratio_samples_are_scaled_to_close_only_when_asked_and_say_by_how_much(tmp_path):
    deg = np.arange(0, 360, 5.0)
    csv = tmp_path / "ratio.csv"
    rows = "\n".join(f"{d:g},{1.001 * (1 + 0.1 * math.cos(math.radians(d))):.12f}" for d in deg)
    csv.write_text("phi_deg,ratio\n" + rows + "\n")
    with pytest.raises(SpecError, match=r"does not close: it turns the driven gear 1\.001\d* turns per driver lobe"):
        transmission(str(csv))
    found = transmission(str(csv), scale_to_close=True)
    assert abs(found.closure_scale * 1.001 - 1) < 1e-4  # the samples' mean was 1.001
    assert found.pair.lobes == (1, 1) and found.pair.closure_error < 1e-9
    pair, sizing = size_pair(found.pair, 30, 2.0, None)
    assert sizing.teeth == (30, 30) and abs(pair.driver.perimeter - 30 * math.pi * 2.0) < 1e-9


@pytest.mark.parametrize(
    ("spec", "lobes", "ratio"),
    [
        ("3*phi", (3, 1), 3.0),  # a constant ratio: circles, 3 driver "lobes" to 1
        ("phi/4", (1, 4), 0.25),
        ("0.4*phi", (2, 5), 0.4),
        ("2*phi + 0.3*sin(2*phi)", (2, 1), 2.6),  # closes: the law repeats every half turn
    ],
)
def test_a_requested_ratio_is_built_exactly(spec, lobes, ratio):
    """A constant ratio is a circle pair at that ratio (was: 1:1, silently); a law that closes is
    taken as it is."""
    found = transmission(spec)
    assert found.pair.lobes == lobes and found.closure_scale == 1.0
    assert abs(float(found.pair.ratio(0.0)) - ratio) < 1e-12 and found.pair.closure_error < 1e-9


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("2*phi + 0.3*sin(phi)", r"turns the driven gear 2 turns per driver lobe .* scaled by 0\.5 it would close"),
        ("1.5*phi + 0.1*sin(phi)", r"turns the driven gear 1\.5 turns per driver lobe"),
        ("2.718281828459045*phi", r"not a fraction p/q with p, q <= 1000"),
    ],
)
def test_a_ratio_that_cannot_be_built_exactly_is_refused(spec, message):
    with pytest.raises(SpecError, match=message):
        transmission(spec)


def test_a_constant_ratio_csv_is_its_circle_pair(tmp_path):
    csv = tmp_path / "five.csv"
    csv.write_text("".join(f"{d},5\n" for d in range(0, 360, 10)))
    found = transmission(str(csv))
    assert found.pair.lobes == (5, 1) and abs(float(found.pair.ratio(1.0)) - 5.0) < 1e-12
    pair, sizing = size_pair(found.pair, 50, 1.0, None)
    assert sizing.teeth == (50, 10)


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("phi +", "not an expression"),
        ("__import__('os')", "calls something other than"),
        ("phi * x", "uses 'x'"),
        ("phi.real", "uses Attribute"),
        ("-phi", "the driven gear turns on"),
        ("sqrt(phi) + phi", "not smooth and periodic"),
        ("ellipse:1.2", "ellipse eccentricity E = 1.2"),
        ("ellipse:0.1:2.5", "ellipse LOBES = 2.5"),
        ("hyperbola:1", "unknown curve 'hyperbola'"),
        ("missing.csv", "cannot be read"),
    ],
)
def test_a_bad_transmission_names_the_problem(spec, message):
    with pytest.raises(SpecError) as err:
        transmission(spec)
    assert message in str(err.value)


def test_the_cli_refuses_bad_input_with_exit_2_and_writes_nothing(tmp_path, capsys):
    assert cli.main(["pair", "phi - 0.08*sin(2*phi)", "--teeth", "24", "-o", str(tmp_path)]) == 2
    assert "give two of --teeth, --module and --centre-distance" in capsys.readouterr().err
    assert cli.main(["pair", "phi - 0.08*sin(2*phi)", "--teeth", "25", "--module", "1.5", "-o", str(tmp_path)]) == 2
    assert "multiple of the driver's 2 lobes" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_a_string_does_not_select_the_rack_cutter(tmp_path):
    """Regression (issue 31): ``rack='no'`` is truthy and cut the pair with a hob."""
    from transplanter.core.errors import SpecError
    from transplanter.families import gear_pair

    with pytest.raises(SpecError, match="rack"):
        gear_pair("ellipse:0.1:2", tmp_path, teeth=30, module=2.0, rack="no")


def test_a_ratio_csv_without_a_header_keeps_its_first_sample_and_radians_are_named(tmp_path):
    """Regressions (issue 31): the first row was always skipped as a header, losing a sample;
    angles in radians were refused only by an unrelated cutter message."""
    from transplanter.core.errors import SpecError
    from transplanter.geometry.pitch.transmission import ratio_from_csv

    deg = np.arange(0, 360, 10.0)
    ratio = 1 + 0.1 * np.cos(np.radians(deg))
    ratio[0] = 1.2  # a first sample that differs: losing it would show
    rows = "".join(f"{d:g},{r:.12f}\n" for d, r in zip(deg, ratio, strict=True))
    bare = ratio_from_csv(rows.encode())
    headed = ratio_from_csv(("phi_deg,ratio\n" + rows).encode())
    assert abs(float(bare(0.0)) - 1.2) < 1e-12 and abs(float(headed(0.0)) - 1.2) < 1e-12
    rad = "".join(f"{math.radians(d):.6f},{r:.12f}\n" for d, r in zip(deg, ratio, strict=True))
    with pytest.raises(SpecError, match="look like radians"):
        ratio_from_csv(rad.encode())
