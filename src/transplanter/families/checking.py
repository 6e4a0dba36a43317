"""``transplanter check``: a built family's files re-read and its parts' checks re-run, as found on
disk."""

from __future__ import annotations

import json
from pathlib import Path

from transplanter.errors import ExportError, PartScriptError, SpecError
from transplanter.export import interrupted_swap, leftovers
from transplanter.families import workers
from transplanter.families.manifest import check_manifest, script_record, sha256
from transplanter.families.scripts import load_family
from transplanter.families.study import Checked

__all__ = ["check_families", "check_family"]


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
        check_manifest(manifest)
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
    now = script_record(str(path), fam.modules)
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
            if sha256(data) != digest:
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
    with workers.executor(jobs) as pool:
        yield from pool.map(check_family, folders, [script] * len(folders))
