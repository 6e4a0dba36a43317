"""A pytest plugin: every part of a folder of part scripts becomes a test, held to a golden record.

The way gdsfactory's users regression-test their components: point pytest at your part
scripts and each part is built, its own proofs are re-run on the files it wrote (meshing of a
gear pair, the follower on a cam, the four-bar rebuilt from its plates, STEP and 3MF re-read —
``Study.check``), and its parameters and results are compared with a golden record kept in
your repository (metrics as JSON, never pictures). A changed design fails until you accept it
with ``--update-golden``.

Set-up (``pyproject.toml`` of your project; the plugin comes with transplanter)::

    [tool.pytest.ini_options]
    testpaths = ["tests", "parts"]
    transplanter_parts = "parts"          # the folder of part scripts
    transplanter_golden = "golden"        # where the records live (default: golden)
    transplanter_jobs = "2"               # processes of the shared build (default: 2)

    transplanter_recheck = "true"         # re-run each part's proofs on its files (default)

Then ``pytest`` runs ``parts/<script>.py::<part>`` items; ``pytest --update-golden`` writes or
rewrites the records (``golden/<family>/<part>.json``). Every family is built once per run —
with pytest-xdist, once for all workers — into the run's temporary folder; the
``transplanter_built`` fixture gives that folder to your own tests.

The shared build already ran every part's proofs on the bytes it wrote; each item holds the
files on disk to the digests the manifest records for them and, with ``transplanter_recheck``
(the default), re-runs the part's ``check`` on them as ``transplanter check --run-script`` would —
``false`` trusts the build's proofs of those very bytes (a suite that tests ``check`` on its
own).

Numbers compare within ``transplanter_golden_rtol`` (relative, default 1e-6) or 1e-9 absolute
(figures are written rounded, see :mod:`transplanter.core.precision`); everything else exactly.
"""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path

import pytest

__all__ = ["shared_build", "compare_records"]

#: numbers closer than this absolutely are equal whatever their relative difference
ABS_TOL = 1e-9


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("transplanter", "transplanter part scripts as tests")
    group.addoption("--update-golden", action="store_true", help="write the parts' golden records instead of comparing")
    parser.addini("transplanter_parts", "folder of part scripts whose parts become test items", default="")
    parser.addini("transplanter_golden", "folder of the parts' golden records", default="golden")
    parser.addini("transplanter_golden_rtol", "relative tolerance of numbers against the records", default="1e-6")
    parser.addini("transplanter_jobs", "processes the shared build uses", default="2")
    parser.addini(
        "transplanter_recheck",
        "re-run each part's proofs on its files after the shared build (false: hold the files to the digests "
        "the build proved them under)",
        default="true",
    )


def _parts_dir(config: pytest.Config) -> Path | None:
    value = config.getini("transplanter_parts")
    return (Path(config.rootpath) / value).resolve() if value else None


def pytest_collect_file(file_path: Path, parent: pytest.Collector):
    parts = _parts_dir(parent.config)
    if parts is None or file_path.suffix != ".py" or file_path.name.startswith("_"):
        return None
    if file_path.resolve().parent != parts:
        return None
    return PartScript.from_parent(parent, path=file_path)


def shared_build(config: pytest.Config) -> Path:
    """Every family of the configured parts folder (or, if none is set, of ``./parts``) built
    once per run into the run's temporary folder; with pytest-xdist the first worker to get the
    lock builds (on two processes) and the others reuse its folder."""
    import fcntl

    from transplanter.app import cli

    cached = getattr(config, "_transplanter_built", None)
    if cached is not None:
        return cached
    parts = _parts_dir(config) or (Path(config.rootpath) / "parts")
    shared = config._tmp_path_factory.getbasetemp()  # noqa: SLF001 - pytest's own temporary folder
    if hasattr(config, "workerinput"):  # a pytest-xdist worker
        shared = shared.parent  # the run's folder, common to all workers
    out = shared / "transplanter-exports"
    with open(shared / "transplanter-exports.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (shared / "transplanter-exports.done").exists():
            jobs = config.getini("transplanter_jobs")
            code = cli.main(["build", "--parts", str(parts), "-o", str(out), "--jobs", jobs])
            (shared / "transplanter-exports.done").write_text(str(code))
    config._transplanter_built = out
    return out


@pytest.fixture(scope="session")
def transplanter_built(request: pytest.FixtureRequest) -> Path:
    """The folder every family of the part scripts was built into for this run."""
    return shared_build(request.config)


def compare_records(found, golden, rtol: float, where: str = "") -> list[str]:
    """Where ``found`` differs from ``golden`` (nested JSON values): numbers beyond ``rtol``
    relative and ``ABS_TOL`` absolute, anything else by value; one line per difference."""
    if isinstance(golden, dict) and isinstance(found, dict):
        out = [f"{where}/{k}: gone (was {golden[k]!r})" for k in golden if k not in found]
        out += [f"{where}/{k}: new ({found[k]!r})" for k in found if k not in golden]
        for k in golden:
            if k in found:
                out += compare_records(found[k], golden[k], rtol, f"{where}/{k}")
        return out
    if isinstance(golden, list) and isinstance(found, list):
        if len(golden) != len(found):
            return [f"{where}: {len(found)} values, the record has {len(golden)}"]
        pairs = enumerate(zip(found, golden, strict=True))
        return [d for k, (a, b) in pairs for d in compare_records(a, b, rtol, f"{where}[{k}]")]
    numbers = (int, float)
    if isinstance(golden, numbers) and isinstance(found, numbers) and not isinstance(golden, bool):
        if math.isclose(found, golden, rel_tol=rtol, abs_tol=ABS_TOL):
            return []
        return [f"{where}: {found!r}, the record has {golden!r}"]
    return [] if found == golden else [f"{where}: {found!r}, the record has {golden!r}"]


class PartFailure(Exception):
    """A part that did not build, whose proofs failed, or that left its golden record."""


class PartScript(pytest.File):
    """A part script: one item per part of its family."""

    def collect(self):
        from transplanter.core.errors import TransplanterError
        from transplanter.families import load_family

        try:
            family = load_family(self.path)
        except TransplanterError as exc:  # the script's own message names the line and the problem
            raise self.CollectError(f"{type(exc).__name__}: {exc}") from exc
        for part in family.parts:
            yield PartItem.from_parent(self, name=part.name, family=family, part=part)


class PartItem(pytest.Item):
    """One part: built (shared), its proofs re-run on its files, held to its golden record."""

    def __init__(self, *, family, part, **kwargs) -> None:
        super().__init__(**kwargs)
        self.family = family
        self.part = part

    def runtest(self) -> None:
        root = shared_build(self.config) / self.family.name
        if not (root / "manifest.json").is_file():
            raise PartFailure(f"the family was not built (no {root / 'manifest.json'}): see the build's messages")
        manifest = json.loads((root / "manifest.json").read_text())
        record = manifest["parts"].get(self.part.name)
        if record is None or "error" in record:
            raise PartFailure(f"the part did not build: {record['error'] if record else 'not in the manifest'}")
        files = {name: (root / name).read_bytes() for name in record["files"]}
        changed = sorted(n for n, d in record["files"].items() if hashlib.sha256(files[n]).hexdigest() != d)
        if changed:
            raise PartFailure(f"its files are not the ones the build proved: {changed}")
        if self.config.getini("transplanter_recheck").strip().lower() in ("true", "1", "yes"):
            for used in getattr(self.part, "uses", ()) or ():  # a machine's proofs read its gears' files too
                files = {**{n: (root / n).read_bytes() for n in manifest["parts"][used].get("files", {})}, **files}
            checked = self.part.check(files)
            if checked is not None and checked.problems and not checked.expected:
                raise PartFailure("its proofs fail on its own files:\n  " + "\n  ".join(checked.problems))
        found = {k: v for k, v in record.items() if k != "files"}
        golden_dir = Path(self.config.rootpath) / self.config.getini("transplanter_golden") / self.family.name
        path = golden_dir / f"{self.part.name}.json"
        if self.config.getoption("update_golden"):
            from transplanter.shop.export import atomic_write, json_bytes

            atomic_write(path, json_bytes(found))
            return
        if not path.is_file():
            raise PartFailure(f"no golden record {path}: run pytest --update-golden to write it")
        rtol = float(self.config.getini("transplanter_golden_rtol"))
        diffs = compare_records(found, json.loads(path.read_text()), rtol)
        if diffs:
            shown = "\n  ".join(diffs[:20]) + (f"\n  ... {len(diffs) - 20} more" if len(diffs) > 20 else "")
            raise PartFailure(
                f"the part left its golden record {path.name} (rtol {rtol:g}):\n  {shown}\n"
                "if the change is intended, accept it with pytest --update-golden"
            )

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, PartFailure):
            return f"{self.family.name}/{self.part.name}: {excinfo.value}"
        return super().repr_failure(excinfo, style)

    def reportinfo(self):
        return self.path, None, f"{self.family.name}/{self.part.name}"
