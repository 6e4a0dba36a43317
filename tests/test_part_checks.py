"""Each seed part's ``check`` — what ``transplanter check --run-script`` runs on a shipped
folder — re-run on the shared build's files and passing: the machines re-posed and re-judged from
the files as found, the cam's follower, the trains, the plates and arms, the synthesis.

The parts' test items (``pytest_plugin``) hold every part's files to the digests the build proved
them under; the toothed pairs' checks (the meshing proof re-run on DXF and STL) are exercised on a
small pair, tampered and not, in ``test_build_cli`` and ``test_robustness``, and cost a build's
worth of time on the seed gears."""

from __future__ import annotations

import json

import pytest

from transplanter.families import load_family
from transplanter.families.pairs.toothed import ToothedPairStudy

SCRIPTS = ("fourbar_seed000", "fourbar_seed001", "fourbar_seed003", "planetary_seed004", "potseedling_seed002")


def _parts(parts_dir):
    for script in SCRIPTS:
        fam = load_family(parts_dir / f"{script}.py")
        for part in fam.parts:
            if not isinstance(part, ToothedPairStudy):
                yield script, fam.name, part


@pytest.fixture(scope="module")
def families(parts_dir):
    return {(fam, part.name): part for _, fam, part in _parts(parts_dir)}


CASES = [
    ("fourbar_seed000", ("mechanism_A", "mechanism_A_plates")),
    ("fourbar_seed001", ("eight_row_arm", "eight_row_arm_plates")),
    ("fourbar_seed003", ("type_I", "type_I_plates")),
    ("planetary_seed004", ("machine", "optimised_train", "transplanting_train", "optimised_pitch")),
    ("potseedling_seed002", ("carriers", "machine", "swing_cam", "open_chain_3R", "stage_2_3")),
]


@pytest.mark.parametrize(("family", "names"), CASES, ids=[c[0] for c in CASES])
def test_every_kind_of_part_passes_its_own_check_on_the_built_files(built, families, family, names):
    root = built / family
    manifest = json.loads((root / "manifest.json").read_text())
    for name in names:
        part = families[(family, name)]
        record = manifest["parts"][name]
        files = {n: (root / n).read_bytes() for n in record["files"]}
        for used in getattr(part, "uses", ()) or ():
            files = {**{n: (root / n).read_bytes() for n in manifest["parts"][used]["files"]}, **files}
        checked = part.check(files)
        assert checked is None or not checked.problems or checked.expected, (name, checked.problems)


def test_every_shipped_part_has_a_build_key(families):
    """A part the pickler refuses has no build key and is silently rebuilt by every incremental
    build (``manifest.part_key``): every part of the shipped scripts has one."""
    from transplanter.families.builder.manifest import part_key

    assert [name for name, part in families.items() if part_key(part) is None] == []
