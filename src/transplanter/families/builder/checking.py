"""``transplanter check``: a built family's files re-read and its parts' checks re-run, as found on
disk.

**Trust.** A folder being checked may come from anyone, so checking it runs no code from it and
reads nothing outside it:

- by default nothing is executed: the manifest is read (by the one reader,
  :func:`transplanter.core.files.read_regular`: a regular file — a FIFO, device or link is never
  opened —, size- and depth-limited; checked against its schema field by field, its file names
  plain names inside the folder; its seal against hand edits), every file it lists is read the
  same way and hashed against its SHA-256, and the shop files are re-read by their readers (data
  only);
- with ``run_script`` (``--run-script``) the design is loaded from its part script to re-run the
  proofs on the files — only a script inside the project (the working folder) whose SHA-256, and
  that of every module beside it that it imported, is the manifest's; anything else is refused
  before a line of it runs.
"""

from __future__ import annotations

import os
from pathlib import Path

from transplanter.core.errors import ExportError, PartScriptError, SpecError
from transplanter.core.files import FileRefused, read_regular
from transplanter.families.builder import workers
from transplanter.families.builder.manifest import (
    MAX_SCRIPT_BYTES,
    listed_file,
    plain_name,
    read_manifest,
    seal_matches,
    sha256,
)
from transplanter.families.builder.scripts import Family, load_family
from transplanter.families.builder.study import Checked
from transplanter.shop import formats
from transplanter.shop.export import interrupted_swap, leftovers

__all__ = ["check_families", "check_family", "trusted_script"]

#: shop files re-read by their readers when no script is run
READABLE = (".dxf", ".stl")


def trusted_script(root: Path, recorded: dict, script: str | Path | None) -> Path:
    """The part script ``check --run-script`` may run for the family in ``root``: ``script`` (or the
    one the manifest records) if it lies inside the project (the working folder, links resolved)
    and it and every module beside it that the build imported have the SHA-256 the manifest
    records; PartScriptError saying which rule it breaks otherwise — before any of it runs."""
    path = Path(script) if script is not None else Path(str(recorded.get("path", "")))
    if not str(path) or str(path) == "." or not path.is_file():
        raise PartScriptError(
            f"{root}: the part script {str(path) or '(not recorded)'} is not found; pass it with --script"
        )
    project = Path.cwd().resolve()
    real = path.resolve()
    if not real.is_relative_to(project):
        raise PartScriptError(
            f"{root}: refusing to run {path}: it lies outside the project ({project}); a checked folder never "
            "runs code from elsewhere — copy the script into the project and pass it with --script"
        )
    if "sha256" not in recorded:
        raise PartScriptError(f"{root}: refusing to run {path}: the manifest records no SHA-256 of its script")
    if sha256(_script_bytes(root, real)) != recorded["sha256"]:
        raise PartScriptError(
            f"{root}: refusing to run {path}: its SHA-256 is not the one the manifest records (the script changed "
            "since the build, or it is not the script the folder was built from) — rebuild, or check without "
            "--run-script"
        )
    for name, digest in sorted(recorded.get("modules", {}).items()):
        module = real.parent / str(name)
        if not plain_name(name) or not module.is_file() or sha256(_script_bytes(root, module)) != digest:
            raise PartScriptError(
                f"{root}: refusing to run {path}: the module {name!r} beside it is missing or is not the one the "
                "build imported (SHA-256 differs)"
            )
    return path


def _script_bytes(root: Path, path: Path) -> bytes:
    """A script or design module hashed before it may run, through the one reader (a regular file,
    at most ``MAX_SCRIPT_BYTES``); PartScriptError if it cannot be."""
    try:
        return read_regular(path, "the part script", MAX_SCRIPT_BYTES, follow_links=True)
    except FileRefused as exc:
        raise PartScriptError(f"{root}: refusing to run it: {exc}") from exc


def _read_files(root: Path, listed: dict, out: dict) -> dict[str, bytes]:
    """The listed files' bytes (``{name: sha256}``), each problem into ``out["files"]``."""
    files = {}
    for fname, digest in listed.items():
        data, problem = listed_file(root, fname, digest)
        if problem:
            out["files"][fname] = problem
        if data is not None:  # a changed file is still checked
            files[fname] = data
    return files


def _reread(files: dict[str, bytes]) -> tuple[dict, list[str]]:
    """The shop files re-read by their readers (data only): what was read, what could not be."""
    read, problems = 0, []
    for fname, data in sorted(files.items()):
        if fname.endswith(READABLE) and not fname.endswith(".assembly.dxf"):
            try:
                formats.section_of(fname, data)
                read += 1
            except ExportError as exc:
                if fname.endswith(".dxf") and _turned(fname, data):  # a lathe's drawing: no section to cut
                    read += 1
                else:
                    problems.append(str(exc))
    return {"shop_files_reread": read}, problems


def _turned(fname: str, data: bytes) -> bool:
    """Whether ``data`` is a turned part's drawing that re-reads as a part
    (:func:`transplanter.machine.hardware.read_turned`: its side view on layer ``TURN``)."""
    from transplanter.core.errors import GeometryError
    from transplanter.machine.hardware import read_turned

    try:
        read_turned(data, fname)
    except (GeometryError, SpecError):
        return False
    return True


def check_family(
    folder: str | Path, script: str | Path | None = None, run_script: bool = False, timeout: float | None = None
) -> dict:
    """Check a built family's files as found on disk (see the module docstring for what runs).

    Every file the manifest lists must be there with its SHA-256 and the manifest as its build
    sealed it; with ``run_script`` the family is loaded from ``script`` (default: the script
    recorded in the manifest; see :func:`trusted_script`) and every part that has checks (toothed
    pairs, cams, plates) re-runs them on its files, every analysis its data files. Returns
    ``{"family", "script", "script_run", "files": {name: problem}, "parts": {part: {"results",
    "problems", "expected"}}, "ok"}``; ``expected`` marks a part built as a finding
    (``must_mesh=False``), whose problems do not make the check fail.

    Raises
    ------
    ExportError
        If the folder has no readable manifest.
    PartScriptError
        If the script may not run (:func:`trusted_script`) or cannot be loaded.
    """
    root = Path(folder)
    if root.is_symlink():
        raise SpecError(f"{root} is a symbolic link (to {os.readlink(root)}): a checked folder is not followed")
    if not os.path.lexists(root / "manifest.json"):  # (one that is not a regular file: damaged, below)
        previous = interrupted_swap(root)
        if previous is not None:
            raise ExportError(
                f"{root}: a build was interrupted while swapping the export; the previous export is whole in "
                f"{previous.name} — run the build again (it restores or replaces it)"
            )
        raise SpecError(f"{root} is not a built family folder (no manifest.json)")
    out: dict = {"family": root.name, "script": "", "script_run": False, "files": {}, "parts": {}, "ok": False}
    try:
        manifest = read_manifest(root)
    except (OSError, ValueError) as exc:
        out["files"]["manifest.json"] = f"damaged, nothing else can be checked ({exc})"
        return out
    if seal_matches(manifest) is False:
        out["files"]["manifest.json"] = "edited since the build (its seal, manifest_sha256, differs)"
    fam: Family | None = None
    if run_script:
        path = trusted_script(root, manifest.get("script", {}), script)
        fam = load_family(path) if timeout is None else load_family(path, timeout)
        if fam.name != manifest.get("family"):
            raise PartScriptError(f"{path} defines family {fam.name!r}, but {root} holds {manifest.get('family')!r}")
        out.update(script=str(path), script_run=True)
    out.update(family=manifest.get("family", root.name), ok=True)
    for name in leftovers(root):
        out["files"][name] = "left by an interrupted build (the next build removes it)"
    listed = {"manifest.json", *manifest.get("report", {"report.html": ""})}
    for rec in manifest["parts"].values():
        listed.update(rec.get("files", {}), rec.get("previous_files", {}))
    for f in sorted(root.iterdir()):  # anything there: a file, a link, a FIFO, a folder
        if f.name not in listed and not f.name.endswith(".tmp"):
            out["files"][f.name] = "not in the manifest (a file of a part no longer built?)"
    _read_files(root, manifest.get("report", {}), out)
    parts = {p.name: p for p in fam.parts} if fam is not None else {}
    if fam is not None:
        for name in sorted(set(manifest["parts"]) - set(parts)):
            gone = ["in the manifest but no longer in the script"]
            out["parts"][name] = {"results": {}, "problems": gone, "expected": False}
            out["ok"] = False
    for name in parts or manifest["parts"]:
        rec = manifest["parts"].get(name)
        if rec is None or "error" in rec:
            why = "it is not in the manifest" if rec is None else f"its build failed: {rec['error']}"
            out["parts"][name] = {"results": {}, "problems": [f"nothing to check: {why}"], "expected": False}
            out["ok"] = False
            continue
        files = _read_files(root, rec.get("files", {}), out)
        part = parts.get(name)
        if part is None:  # no code run: the files' digests above, and the shop files re-read
            results, problems = _reread(files)
            expected = rec.get("parameters", {}).get("must_mesh") is False
        else:
            for used in workers.uses(part):  # a machine's checks read its gears' files too
                files = {**_read_files(root, manifest["parts"].get(used, {}).get("files", {}), out), **files}
            results, problems, expected = _proofs(part, root, files)
        out["parts"][name] = {"results": results, "problems": problems, "expected": expected}
        out["ok"] = out["ok"] and (expected or not problems)
    out["ok"] = out["ok"] and not out["files"]
    return out


def _proofs(part, root: Path, files: dict[str, bytes]) -> tuple[dict, list[str], bool]:
    """A part's own checks re-run on its files; an analysis's data files made again."""
    try:
        checked = part.check(files)
    except Exception as exc:  # a damaged file the readers choke on: a problem of this part, go on
        checked = Checked({}, [f"cannot check its files: {type(exc).__name__}: {exc}"])
    if checked is not None:
        return checked.results, checked.problems, checked.expected
    _, fresh = part.build(root)
    data = sorted(f for f in fresh if f.endswith((".json", ".csv")))
    problems = [f"{f} differs from what the part script gives now" for f in data if files.get(f) != fresh[f]]
    return {"data_files_reproduced": len(data) - len(problems)}, problems, False


def check_families(
    folders: list[Path],
    script: str | Path | None = None,
    jobs: int = 1,
    run_script: bool = False,
    timeout: float | None = None,
):
    """:func:`check_family` of each folder, in order, on up to ``jobs`` processes; each report
    is yielded as soon as it and those before it are done."""
    jobs = min(jobs, len(folders))
    if jobs <= 1:
        yield from (check_family(f, script, run_script, timeout) for f in folders)
        return
    n = len(folders)
    with workers.executor(jobs) as pool:
        yield from pool.map(check_family, folders, [script] * n, [run_script] * n, [timeout] * n)
