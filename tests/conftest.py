import os
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
    from transplanter.families import ArmStudy

    fam = load_family(PARTS / "fourbar_seed000.py")
    return {p.name[-1]: p.arm for p in fam.parts if isinstance(p, ArmStudy)}


@pytest.fixture(scope="session")
def built(tmp_path_factory, parts_dir) -> Path:
    """Every seed family built once per test run, for the tests that read exports.

    With pytest-xdist the workers share one build: the first to get the lock builds (in two
    processes), the others wait for it and reuse the folder."""
    import fcntl

    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = shared.parent  # the run's folder, common to all workers
    out = shared / "exports"
    with open(shared / "exports.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (shared / "exports.done").exists():
            assert cli.main(["build", "--parts", str(parts_dir), "-o", str(out), "--jobs", "2"]) == 0
            (shared / "exports.done").touch()
    return out
