"""A family of parts from a part script: loading, building into a folder, checking a built folder."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import re
import runpy
import sys
import traceback
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from transplanter.errors import ExportError, PartScriptError, SpecError, TransplanterError
from transplanter.export import Transaction, interrupted_swap, json_bytes, leftovers
from transplanter.families.study import Built, Checked, Study
from transplanter.report import family_report

__all__ = [
    "Family",
    "load_family",
    "run_script",
    "discover",
    "part_outcome",
    "build_family",
    "build_families",
    "check_family",
    "check_families",
]


_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")


def _check_name(kind: str, name: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise SpecError.out_of_range(f"{kind} name", name, "letters, digits, '_', '-', '.' (a file name)")
    return name


@dataclass(frozen=True)
class Family:
    """A named set of parts defined by one part script."""

    name: str
    description: str
    parts: tuple[Study, ...] = field(default_factory=tuple)
    #: the part script it came from (set by :func:`load_family`)
    script: str | None = None
    #: the modules beside the script that it imported (``_*.py`` in its folder; set by
    #: :func:`load_family`), recorded with the script in the manifest
    modules: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        _check_name("family", self.name)
        object.__setattr__(self, "parts", tuple(self.parts))
        seen: set[str] = set()
        for p in self.parts:
            if not isinstance(p, Study):
                raise PartScriptError(
                    f"family {self.name!r}: parts must be studies (transplanter.families.Study: a name, cost, "
                    f"build, check, tables and analysis_files — e.g. ArmStudy, ToothedPairStudy, CamStudy), "
                    f"got {type(p).__name__}"
                )
            _check_name("part", p.name)
            if p.name in seen:
                raise PartScriptError(f"family {self.name!r}: part name {p.name!r} is used twice")
            seen.add(p.name)


@contextmanager
def _beside(folder: Path, imported: list[str]) -> Iterator[None]:
    """Run with ``folder`` first on ``sys.path``, as ``python script.py`` would: a part script
    imports the modules beside it (``_seed004.py`` → ``from _seed004 import ...``). Those modules
    are read afresh — any copy already imported (by a notebook, by pytest's doctest collection)
    is set aside for the run and put back after — listed in ``imported``, and forgotten again,
    so the next load reads them afresh too (an edited design module is never served from a cache)."""
    where = str(folder.resolve())
    files = {f.name for f in folder.glob("*.py")}

    def beside() -> dict:  # the imported modules whose file is in the folder (by name first: cheap)
        return {
            name: module
            for name, module in list(sys.modules.items())
            if os.path.basename(getattr(module, "__file__", None) or "") in files
            and os.path.dirname(os.path.realpath(module.__file__)) == where
        }

    held = beside()
    for name in held:
        del sys.modules[name]
    sys.path.insert(0, where)
    try:
        yield
    finally:
        sys.path.remove(where)
        for name, module in sorted(beside().items()):
            imported.append(str(folder / os.path.basename(module.__file__)))
            del sys.modules[name]
        sys.modules.update(held)


def run_script(path: str | Path, imported: list[str] | None = None) -> dict:
    """The namespace of a part script (or of a design module beside one), run with its folder
    importable (:func:`_beside`); ``imported`` collects the modules beside it that it imported.

    Raises
    ------
    PartScriptError
        If the file is missing or a folder, does not parse, or raises; the message names the
        script and the line.
    """
    p = Path(path)
    if p.is_dir():
        raise PartScriptError(f"{p} is a folder, not a part script (give a .py file, or --parts {p})")
    if not p.is_file():
        raise PartScriptError(f"part script {p} does not exist")
    try:
        with _beside(p.parent, imported if imported is not None else []):
            return runpy.run_path(str(p), run_name="transplanter_part_script")
    except SyntaxError as exc:
        raise PartScriptError(f"{exc.filename or p}:{exc.lineno}: syntax error: {exc.msg}") from exc
    except TransplanterError as exc:
        raise PartScriptError(f"{p}: {exc}") from exc
    except SystemExit as exc:
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: the script called sys.exit({exc.code!r})") from exc
    except Exception as exc:  # a user script can raise anything; report where
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: {type(exc).__name__}: {exc}") from exc


def load_family(path: str | Path) -> Family:
    """Run a part script and return the :class:`Family` its ``family()`` builds.

    The script runs with its folder importable, so its design models and optimisation problems
    can live beside it in modules named ``_*.py`` (which :func:`discover` skips).

    Raises
    ------
    PartScriptError
        If the file is missing, does not parse, lacks ``family()``, raises, or returns
        something that is not a Family. The message names the script (and line).
    """
    p = Path(path)
    imported: list[str] = []
    ns = run_script(p, imported)
    fn = ns.get("family")
    if not callable(fn):
        raise PartScriptError(f"{p}: a part script must define family() returning transplanter.families.Family")
    try:
        fam = fn()
    except TransplanterError as exc:
        raise PartScriptError(f"{p}: {exc}") from exc
    except SystemExit as exc:
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: family() called sys.exit({exc.code!r})") from exc
    except Exception as exc:
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: family() raised {type(exc).__name__}: {exc}") from exc
    if not isinstance(fam, Family):
        raise PartScriptError(f"{p}: family() returned {type(fam).__name__}, expected transplanter.families.Family")
    return dataclasses.replace(fam, script=str(p), modules=tuple(imported))


def _script_line(exc: BaseException, path: Path) -> str:
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if Path(f.filename).resolve() == path.resolve()]
    return str(frames[-1].lineno) if frames else "?"


def discover(parts_dir: str | Path) -> list[Path]:
    """Part scripts in ``parts_dir`` (``*.py`` not starting with ``_``: those are the modules the
    scripts import), sorted by name."""
    d = Path(parts_dir)
    if not d.is_dir():
        raise PartScriptError(f"parts folder {d} does not exist (run from the project root or pass scripts)")
    return sorted(p for p in d.glob("*.py") if not p.name.startswith("_"))


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _script_record(script: str, modules: tuple[str, ...]) -> dict:
    """The design a family was built from: its script and the modules beside it that it imported
    (by file name), with SHA-256."""
    out: dict = {"path": script, "sha256": _sha256(Path(script).read_bytes())}
    if modules:
        out["modules"] = {Path(m).name: _sha256(Path(m).read_bytes()) for m in sorted(modules)}
    return out


def _previous_manifest(root: Path) -> dict:
    """The current export's manifest, or {} if there is none or it is damaged (``_check_manifest``)."""
    try:
        data = json.loads((root / "manifest.json").read_text())
        _check_manifest(data)
    except (OSError, ValueError):
        return {}
    return data


def part_outcome(part: Study, root: Path) -> Built | str:
    """Build one part: its :class:`~transplanter.families.study.Built` (record, files), or the
    error the manifest records for it — any exception a part raises is its failure (a project
    error by its message; anything else with its type, as a bug to report)."""
    try:
        return Built(*part.build(root))
    except TransplanterError as exc:
        return f"{type(exc).__name__}: {exc}"
    except Exception as exc:  # a bug, or a library error that escaped: the part fails, the build goes on
        return f"{type(exc).__name__} (unexpected, please report): {exc}"


def build_family(
    family: Family,
    out_dir: str | Path,
    progress: Callable[[str], None] | None = None,
    outcomes: dict[str, Built | str] | None = None,
) -> dict:
    """Build every part of ``family`` into ``out_dir/<family.name>/``; returns the manifest.

    The manifest (also written as ``manifest.json``) lists for each part its parameters,
    results, files with SHA-256, or its error (:func:`part_outcome`). ``manifest["ok"]`` is
    False if any part failed. ``outcomes`` (part name → :func:`part_outcome`) are parts built
    elsewhere, e.g. in other processes (:func:`build_families`); the parts are then only written.

    The folder is written as one transaction (``export.Transaction``): it is the old export
    until the new one is complete, then the new one; a failing part keeps its previous files
    (listed under ``previous_files``), files of parts no longer in the script are gone, and a
    second build of the same folder meanwhile is refused.
    """
    root = Path(out_dir) / family.name
    manifest: dict = {"family": family.name, "description": family.description, "parts": {}, "ok": True}
    if family.script is not None:
        manifest["script"] = _script_record(family.script, family.modules)
    with Transaction(root) as tx:
        old = _previous_manifest(root)
        for part in family.parts:
            if outcomes is None:
                outcome = part_outcome(part, root)
                if progress is not None:
                    progress(f"{family.name}/{part.name}")
            else:
                outcome = outcomes[part.name]
            if not isinstance(outcome, str):
                record, files = outcome
                for fname, data in sorted(files.items()):
                    tx.write(fname, data)
                record["files"] = {fname: _sha256(data) for fname, data in sorted(files.items())}
                manifest["parts"][part.name] = record
                continue
            failed: dict = {"error": outcome}
            before = old.get("parts", {}).get(part.name, {})
            kept = before.get("files", before.get("previous_files", {}))
            kept = {f: h for f, h in sorted(kept.items()) if tx.keep(f)}
            if kept:
                failed["previous_files"] = kept
            manifest["parts"][part.name] = failed
            manifest["ok"] = False
        report = family_report(manifest)
        tx.write("report.html", report)
        manifest["report"] = {"report.html": _sha256(report)}
        tx.write("manifest.json", json_bytes(manifest))
    return manifest


#: families being built by :func:`build_families`, inherited by forked workers (by name)
_FAMILIES: dict[str, Family] = {}


def _pool(jobs: int):
    """A pool of ``jobs`` worker processes, forked where the platform can (the workers then
    start with everything this process has imported and loaded)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else None)
    return ProcessPoolExecutor(max_workers=jobs, mp_context=ctx)


def _outcome_in_worker(family: str, script: str | None, part: str):
    fam = _FAMILIES.get(family)
    if fam is None:  # a worker that was not forked from the builder: load the script itself
        fam = _FAMILIES[family] = load_family(script)
    return part_outcome(next(p for p in fam.parts if p.name == part), Path("."))


def build_families(
    families: list[Family],
    out_dir: str | Path,
    jobs: int = 1,
    progress: Callable[[str], None] | None = None,
) -> list[dict]:
    """Build ``families`` into ``out_dir``, their parts spread over ``jobs`` processes; returns
    their manifests in order.

    The parts are handed out longest kind first (gear pairs, trains, cams, ...) to whichever
    process is free, and each family is written (:func:`build_family`) as soon as its last part
    is done, by this process, in the family's own part order — so the files are byte-identical
    to a serial build. ``progress`` gets ``family/part`` as each part finishes.
    """
    names = [f.name for f in families]
    if len(set(names)) != len(names):  # serial or not: the last would replace the first's export
        raise PartScriptError(f"two part scripts define the same family name: {sorted(names)}")
    if jobs <= 1:
        return [build_family(f, out_dir, progress) for f in families]
    from concurrent.futures import FIRST_COMPLETED, wait
    from concurrent.futures.process import BrokenProcessPool

    _FAMILIES.clear()
    _FAMILIES.update((f.name, f) for f in families)
    tasks = [(f, p) for f in families for p in f.parts]
    tasks.sort(key=lambda t: -t[1].cost)  # the longest first; stable: script order within a cost
    outcomes: dict[str, dict] = {f.name: {} for f in families}
    manifests: dict[str, dict] = {}
    try:
        with _pool(jobs) as pool:
            pending = {pool.submit(_outcome_in_worker, f.name, f.script, p.name): (f, p) for f, p in tasks}
            for f in families:  # a family without parts is written at once
                if not f.parts:
                    manifests[f.name] = build_family(f, out_dir, outcomes={})
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    f, p = pending.pop(fut)
                    try:
                        outcomes[f.name][p.name] = fut.result()
                    except BrokenProcessPool as exc:  # a worker killed (out of memory, a signal)
                        raise ExportError(
                            f"a build process died while building {f.name}/{p.name} ({exc}); the exports of the "
                            "families not yet written are unchanged — run the build again, or with --jobs 1"
                        ) from exc
                    if progress is not None:
                        progress(f"{f.name}/{p.name}")
                    if len(outcomes[f.name]) == len(f.parts):
                        manifests[f.name] = build_family(f, out_dir, outcomes=outcomes[f.name])
    finally:
        _FAMILIES.clear()
    return [manifests[n] for n in names]


def _check_manifest(manifest) -> None:
    """ValueError naming what is wrong if ``manifest`` is not a family manifest."""
    if not isinstance(manifest, dict) or not isinstance(manifest.get("parts"), dict):
        raise ValueError("not a family manifest: no 'parts' table")
    for name, rec in manifest["parts"].items():
        if not isinstance(rec, dict):
            raise ValueError(f"part {name!r} is not a record")
        for key in ("files", "previous_files"):
            files = rec.get(key, {})
            if not isinstance(files, dict) or not all(isinstance(v, str) for v in files.values()):
                raise ValueError(f"part {name!r}: {key} is not a table of SHA-256 digests")
    if not isinstance(manifest.get("script", {}), dict):
        raise ValueError("'script' is not a record")


def check_family(folder: str | Path, script: str | Path | None = None) -> dict:
    """Re-run the checks on a built family's files as found on disk.

    Every file the manifest lists must be there with its SHA-256; the family is loaded from
    ``script`` (default: the script recorded in the manifest) for the design it was built
    from, and every part that has checks (toothed pairs, cams) re-runs them on its files.
    Returns ``{"family", "script", "script_changed", "files": {name: problem}, "parts":
    {part: {"results", "problems", "expected"}}, "ok"}``; ``expected`` marks a part built as
    a finding (``must_mesh=False``), whose problems do not make the check fail.

    Raises
    ------
    ExportError
        If the folder has no readable manifest.
    PartScriptError
        If the script cannot be found or loaded.
    """
    root = Path(folder)
    if not (root / "manifest.json").is_file():
        previous = interrupted_swap(root)
        if previous is not None:
            raise ExportError(
                f"{root}: a build was interrupted while swapping the export; the previous export is whole in "
                f"{previous.name} — run the build again (it restores or replaces it)"
            )
        raise SpecError(f"{root} is not a built family folder (no manifest.json)")
    out: dict = {"family": root.name, "script": "", "script_changed": False, "files": {}, "parts": {}, "ok": False}
    try:
        manifest = json.loads((root / "manifest.json").read_text())
        _check_manifest(manifest)
    except (OSError, ValueError) as exc:
        out["files"]["manifest.json"] = f"damaged, nothing else can be checked ({exc})"
        return out
    recorded = manifest.get("script", {})
    path = Path(script) if script is not None else Path(recorded.get("path", ""))
    if not str(path) or not path.is_file():
        raise PartScriptError(
            f"{root}: the part script {str(path) or '(not recorded)'} is not found; pass it with --script"
        )
    fam = load_family(path)
    now = _script_record(str(path), fam.modules)
    if fam.name != manifest.get("family"):
        raise PartScriptError(f"{path} defines family {fam.name!r}, but {root} holds {manifest.get('family')!r}")
    out.update(
        family=fam.name,
        script=str(path),
        script_changed="sha256" in recorded
        and (recorded["sha256"], recorded.get("modules", {})) != (now["sha256"], now.get("modules", {})),
        ok=True,
    )
    for name in leftovers(root):
        out["files"][name] = "left by an interrupted build (the next build removes it)"
    listed = {"manifest.json", "report.html"}
    for rec in manifest["parts"].values():
        listed.update(rec.get("files", {}), rec.get("previous_files", {}))
    for f in sorted(root.iterdir()):
        if f.is_file() and f.name not in listed and not f.name.endswith(".tmp"):
            out["files"][f.name] = "not in the manifest (a file of a part no longer built?)"
    for name in sorted(set(manifest["parts"]) - {p.name for p in fam.parts}):
        gone = ["in the manifest but no longer in the script"]
        out["parts"][name] = {"results": {}, "problems": gone, "expected": False}
        out["ok"] = False
    for part in fam.parts:
        rec = manifest["parts"].get(part.name)
        if rec is None or "error" in rec:
            why = "it is not in the manifest" if rec is None else f"its build failed: {rec['error']}"
            out["parts"][part.name] = {"results": {}, "problems": [f"nothing to check: {why}"], "expected": False}
            out["ok"] = False
            continue
        files = {}
        for fname, digest in rec.get("files", {}).items():
            f = root / fname
            if not f.is_file():
                out["files"][fname] = "missing"
                continue
            try:
                data = f.read_bytes()
            except OSError as exc:
                out["files"][fname] = f"cannot be read: {exc.strerror or exc}"
                continue
            if _sha256(data) != digest:
                out["files"][fname] = "changed since the build (SHA-256 differs)"
            files[fname] = data
        try:
            checked = part.check(files)
        except Exception as exc:  # a damaged file the readers choke on: a problem of this part, go on
            checked = Checked({}, [f"cannot check its files: {type(exc).__name__}: {exc}"])
        if checked is not None:
            results, problems, expected = checked
        else:  # an analysis: its data files must be what the design gives now
            _, fresh = part.build(root)
            data = sorted(f for f in fresh if f.endswith((".json", ".csv")))
            problems = [f"{f} differs from what the part script gives now" for f in data if files.get(f) != fresh[f]]
            results, expected = {"data_files_reproduced": len(data) - len(problems)}, False
        out["parts"][part.name] = {"results": results, "problems": problems, "expected": expected}
        out["ok"] = out["ok"] and (expected or not problems)
    out["ok"] = out["ok"] and not out["files"]
    return out


def check_families(folders: list[Path], script: str | Path | None = None, jobs: int = 1):
    """:func:`check_family` of each folder, in order, on up to ``jobs`` processes; each report
    is yielded as soon as it and those before it are done."""
    jobs = min(jobs, len(folders))
    if jobs <= 1:
        yield from (check_family(f, script) for f in folders)
        return
    with _pool(jobs) as pool:
        yield from pool.map(check_family, folders, [script] * len(folders))
