"""Issue 41 moved the flat modules into station packages: every former path still imports, as the
very module at its new home (one object: classes, caches and ``isinstance`` are shared), and a
part script written against the old paths still loads."""

from __future__ import annotations

import importlib
import sys

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


#: names that moved out of a module split by issue 41 (each checked at its former path)
SPLIT_NAMES = [
    ("incomplete", "entry_contacts"),
    ("incomplete", "TIP_BAND"),
    ("incomplete", "sector_pitches"),
    ("incomplete", "virtual_curve"),
    ("incomplete", "CURVE_SAMPLES_PER_DEG"),
    ("teeth", "SECTOR_RUN_OUT"),
    ("machine", "LEVELS_MM"),
    ("report", "OPEN_ROWS"),
    ("report", "ROUND_OFF"),
    ("report", "SLIDER_SUFFIX"),
    ("families.machine", "START_POSE_DEG"),
    ("families.incomplete_pair", "PHASE_GRID"),
]


@pytest.mark.parametrize("old, name", SPLIT_NAMES)
def test_a_name_that_moved_out_of_a_split_module_is_still_found_there(old, name):
    module = importlib.import_module(f"transplanter.{old}")
    assert getattr(module, name) is not None
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        module.no_such_name  # noqa: B018 - the lookup is the test


#: in a fresh interpreter: every former module path whose last part is also a name its package
#: gives (a function, a class), imported, then that name looked up again
CLASHES = """
import importlib, sys, types
import transplanter
found = []
for old in sorted(transplanter.MOVED):
    parent, _, name = f"transplanter.{old}".rpartition(".")
    before = getattr(importlib.import_module(parent), name, None)
    if before is not None and not isinstance(before, types.ModuleType):
        found.append((parent, name, before))
for parent, name, before in found:
    importlib.import_module(f"{parent}.{name}")
    after = getattr(sys.modules[parent], name)
    assert after is before, (parent, name, after)
print(len(found), *(f"{p}.{n}" for p, n, _ in found))
"""


def test_importing_a_former_module_path_keeps_the_name_it_shares():
    """``transplanter.families.gear_pair`` is the one-call function and the former path of
    ``families.pairs.gear_pair``: importing the path must not make ``from transplanter.families
    import gear_pair`` the module (it did, in that process, for every test run after it)."""
    import subprocess

    out = subprocess.run([sys.executable, "-c", CLASHES], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split()[:2] == ["1", "transplanter.families.gear_pair"]
    from transplanter.families.gear_pair import pair_family  # the former path still imports

    from transplanter.families.pairs.gear_pair import pair_family as here

    assert pair_family is here


def test_a_forwarding_module_pickles_by_name_as_any_module():
    """cloudpickle keys a part by what it holds and ships a search's cost function: a function of a
    part script that refers to a forwarding module (``transplanter.families``, ``geometry.teeth``)
    pickles to that module, not to a refusal (which had left such a part without a build key:
    rebuilt every time)."""
    import pickle

    import cloudpickle

    import transplanter.families
    import transplanter.geometry.teeth  # noqa: F401 - a forwarding module, imported
    from transplanter.core.forwarding import Forwarding
    from transplanter.families.builder.manifest import part_key

    forwarding = [m for m in list(sys.modules.values()) if isinstance(m, Forwarding)]
    assert {"transplanter.families", "transplanter.geometry.teeth"} <= {m.__name__ for m in forwarding}
    for module in forwarding:
        assert pickle.loads(cloudpickle.dumps(module)) is module
    code = {}
    exec("import transplanter.geometry.teeth as teeth\ndef cost(x):\n    return teeth, x\n", code)  # noqa: S102 - a part script's function
    assert pickle.loads(cloudpickle.dumps(code["cost"]))(1)[0] is sys.modules["transplanter.geometry.teeth"]

    class Held:
        def __init__(self):
            self.cost = code["cost"]

    assert part_key(Held()) is not None
