from pathlib import Path

import pytest

from transplanter import cli
from transplanter.families import load_family

PARTS = Path(__file__).resolve().parents[1] / "parts"


@pytest.fixture(scope="session")
def parts_dir() -> Path:
    return PARTS


@pytest.fixture(scope="session")
def seed000_arms():
    fam = load_family(PARTS / "fourbar_seed000.py")
    return {p.name[-1]: p.arm for p in fam.parts}


@pytest.fixture(scope="session")
def built(tmp_path_factory, parts_dir) -> Path:
    """Every seed family built once (in two processes), for the tests that read exports."""
    out = tmp_path_factory.mktemp("exports")
    assert cli.main(["build", "--parts", str(parts_dir), "-o", str(out), "--jobs", "2"]) == 0
    return out
