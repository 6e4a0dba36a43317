"""The pytest plugin: a user's part scripts as test items held to golden records."""

import pytest

import transplanter.app.cli

ARM = """
from transplanter.families import ArmStudy, Family
from transplanter.design.linkage.fourbar import FourBar
from transplanter.design.linkage.planting import PlantingArm


def family():
    arm = PlantingArm(FourBar(125, {crank}, 100, 85), (-170.0, 60.0), 25.0, 600.0, name="arm")
    return Family("alpha", "a user's planting arm", (ArmStudy(arm, {depth}),))
"""

#: a user's own kind of study, with a proof of its own that re-reads its file
PLATE = """
from dataclasses import dataclass

from transplanter.families import Built, Checked, Family, StudyDefaults


@dataclass(frozen=True)
class PlateStudy(StudyDefaults):
    name: str
    side: float

    def build(self, out):
        data = f"{{self.side ** 2:.6f}}".encode()
        record = {{"kind": "plate", "parameters": {{"side_mm": self.side}}, "results": {{}}}}
        return Built(record, {{"plate.txt": data}})

    def check(self, files):
        area = float(files["plate.txt"])
        return Checked({{"area_mm2": area}}, [] if area == {area} else [f"the file says {{area}} mm²"])


def family():
    return Family("beta", "a user's plate", (PlateStudy("plate", {side}),))
"""


@pytest.fixture(autouse=True, scope="module")
def _a_build_s_modules_imported(tmp_path_factory):
    """The inner pytest runs (in this process) drop the modules they import, and some extension
    modules (numpy's, matplotlib's) cannot be imported twice in one process: a build of the arm
    here, once, imports everything a build imports, whatever ran before in this process."""
    parts = tmp_path_factory.mktemp("warm") / "parts"
    parts.mkdir()
    (parts / "alpha.py").write_text(ARM.format(crank=40, depth=40.0))
    out = parts.parent / "out"
    assert transplanter.app.cli.main(["build", "--parts", str(parts), "-o", str(out), "--jobs", "1"]) == 0


INI = """[pytest]
addopts = -p no:hypothesispytest -p no:cacheprovider
testpaths = parts
transplanter_parts = parts
transplanter_golden = golden
transplanter_jobs = 1
"""


def test_a_users_parts_are_held_to_their_golden_records(pytester):
    pytester.makefile(".ini", pytest=INI)
    parts = pytester.mkdir("parts")
    (parts / "alpha.py").write_text(ARM.format(crank=40, depth=40.0))
    (parts / "beta.py").write_text(PLATE.format(side=4.0, area=16.0))

    first = pytester.runpytest()  # no records yet
    first.assert_outcomes(failed=2)
    first.stdout.fnmatch_lines(["*alpha/arm: no golden record*run pytest --update-golden*"])
    pytester.runpytest("--update-golden").assert_outcomes(passed=2)
    assert (pytester.path / "golden" / "alpha" / "arm.json").is_file()

    (parts / "beta.py").write_text(PLATE.format(side=5.0, area=25.0))  # a changed design
    changed = pytester.runpytest()
    changed.assert_outcomes(passed=1, failed=1)
    changed.stdout.fnmatch_lines(["*beta/plate: the part left its golden record plate.json*", "*side_mm: 5.0*4.0*"])

    pytester.runpytest("--update-golden").assert_outcomes(passed=2)  # accepted
    pytester.runpytest().assert_outcomes(passed=2)


def test_failed_builds_proofs_and_scripts_fail_their_items(pytester):
    pytester.makefile(".ini", pytest=INI)
    parts = pytester.mkdir("parts")
    (parts / "alpha.py").write_text(ARM.format(crank=40, depth=400.0))  # planted below the tip's path
    (parts / "beta.py").write_text(PLATE.format(side=4.0, area=15.0))  # its proof fails on its file
    result = pytester.runpytest("--update-golden")
    result.assert_outcomes(failed=2)
    result.stdout.fnmatch_lines(["*alpha/arm: the part did not build: *"])
    result.stdout.fnmatch_lines(["*beta/plate: its proofs fail on its own files:*", "*the file says 16.0 mm²*"])
    assert not (pytester.path / "golden").exists()
    # without the re-check the item trusts the build's proofs of the bytes it holds to their digests
    trusted = pytester.runpytest("--update-golden", "-o", "transplanter_recheck=false")
    trusted.assert_outcomes(passed=1, failed=1)
    (pytester.path / "golden").rename(pytester.path / "golden.trusted")
    (parts / "alpha.py").write_text(ARM.format(crank=90, depth=40.0))  # the crank cannot turn
    broken = pytester.runpytest()
    broken.assert_outcomes(errors=1)  # collection stops at a script that does not load
    broken.stdout.fnmatch_lines(["*PartScriptError: *alpha.py: crank cannot turn fully*"])
