"""The fast fouling screen of the seed-004 search against the full meshing check of cut teeth.

``screen_cases.CASES`` are internal ring/planet pairs of seed-004-like trains (five ratio laws,
from circular to sharper than the optimised design, modules 1.4-4.1 mm, ring tips trimmed as the
screen does or standard); ``tests/data/screen_record.json`` holds their full verdicts, recorded by
``python tests/screen_cases.py`` (teeth cut, then ``validate.mesh_check`` over a whole ring turn,
3-6 s a case). Here the screen (milliseconds) is compared with every recorded verdict, and two
cases — one that meshes, one that fouls — are cut and meshed again live, so the record cannot go
stale unnoticed.
"""

import json

import pytest

import screen_cases as sc


def _key(case) -> str:
    return " | ".join(map(str, case))


@pytest.fixture(scope="module")
def record():
    return json.loads(sc.RECORD.read_text())


def test_every_case_is_recorded(record):
    assert set(record) == {_key(c) for c in sc.CASES}


def test_screen_verdict_agrees_with_the_full_meshing_check(record):
    agree, conservative, false_pass = [], [], []
    for case in sc.CASES:
        full = record[_key(case)]["meshes"]
        screen = not sc.screen_verdict(case)
        if screen == full:
            agree.append((case, full))
        elif full:
            conservative.append(case)
        else:
            false_pass.append(case)
    assert not false_pass, f"the screen passed pairs whose teeth foul: {false_pass}"
    assert len(agree) >= 20, (len(agree), conservative)
    assert sum(f for _, f in agree) >= 10 and sum(not f for _, f in agree) >= 5  # both verdicts
    assert len(conservative) <= len(sc.CASES) // 5, conservative


@pytest.mark.parametrize("case", [("mild", 13, 12), ("mild", 13, 12, 1.0)])
def test_recorded_verdicts_are_reproduced_live(record, case):
    full = sc.full_verdict(case)
    assert full["meshes"] == record[_key(case)]["meshes"]
    assert full["meshes"] == (not sc.screen_verdict(case))
