"""Issue 41 moved the flat modules into station packages: every former path still imports, as the
very module at its new home (one object: classes, caches and ``isinstance`` are shared), and a
part script written against the old paths still loads."""

from __future__ import annotations

import importlib

import pytest

import transplanter


@pytest.mark.parametrize("old", sorted(transplanter.MOVED))
def test_a_former_path_is_the_module_at_its_new_home(old):
    new = importlib.import_module(f"transplanter.{transplanter.MOVED[old]}")
    assert importlib.import_module(f"transplanter.{old}") is new


def test_submodules_of_a_moved_package_move_with_it():
    from transplanter.pitch.intermittent import IntermittentLaw  # the former path

    from transplanter.geometry.pitch import intermittent

    assert IntermittentLaw is intermittent.IntermittentLaw
    assert importlib.import_module("transplanter.linkage.fourbar") is importlib.import_module(
        "transplanter.design.linkage.fourbar"
    )


def test_the_former_modules_that_became_packages_keep_their_names():
    from transplanter.machine import Body, bodies
    from transplanter.report import family_report, pages

    assert Body is bodies.Body and family_report is pages.family_report


def test_a_part_script_on_the_old_paths_loads(tmp_path):
    script = tmp_path / "old_paths.py"
    script.write_text(
        "from transplanter.families import Family, PitchPairStudy\n"
        "from transplanter.pitch import GearPair, PitchCurve\n\n\n"
        "def family():\n"
        "    pair = GearPair.from_driver(PitchCurve.ellipse(20.0, 0.1, 1), 'external', 1)\n"
        "    return Family('old_paths', 'a script on the former paths', (PitchPairStudy('p', pair),))\n"
    )
    from transplanter.families import load_family

    fam = load_family(script)
    assert [p.name for p in fam.parts] == ["p"]


def test_a_family_given_its_parts_for_a_description_is_refused():
    """Found writing the test above: ``Family(name, (parts,))`` took the parts as the description
    and built a family of no parts, silently."""
    from transplanter.core.errors import PartScriptError
    from transplanter.families import Family

    with pytest.raises(PartScriptError, match="description must be text"):
        Family("f", ())
