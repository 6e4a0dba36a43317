from pathlib import Path

import pytest

from transplanter.families import load_family

PARTS = Path(__file__).resolve().parents[1] / "parts"


@pytest.fixture(scope="session")
def parts_dir() -> Path:
    return PARTS


@pytest.fixture(scope="session")
def seed000_arms():
    fam = load_family(PARTS / "fourbar_seed000.py")
    return {p.name[-1]: p.arm for p in fam.parts}
