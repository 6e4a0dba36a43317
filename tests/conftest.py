from pathlib import Path

import pytest

from transplanter.families import load_family

PARTS = Path(__file__).resolve().parents[1] / "parts"


@pytest.fixture(scope="session")
def parts_dir() -> Path:
    return PARTS


@pytest.fixture(scope="session")
def seed000_arms():
    from transplanter.families import ArmStudy

    fam = load_family(PARTS / "fourbar_seed000.py")
    return {p.name[-1]: p.arm for p in fam.parts if isinstance(p, ArmStudy)}


@pytest.fixture(scope="session")
def built(transplanter_built) -> Path:
    """Every seed family built once per test run, for the tests that read exports: the
    folder the pytest plugin built for the part items (``transplanter.pytest_plugin``; with
    pytest-xdist, one build shared by the workers)."""
    return transplanter_built
