"""Building families into a folder: every part's files written in one transaction, the manifest
and the report beside them; parts in worker processes (:mod:`families.workers`)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from transplanter import inputs
from transplanter.errors import ExportError, PartScriptError
from transplanter.export import Transaction, json_bytes
from transplanter.families import workers
from transplanter.families.manifest import plain_name, previous_manifest, script_record, seal, sha256
from transplanter.families.scripts import Family
from transplanter.families.study import Built
from transplanter.report import family_report

__all__ = ["build_families", "build_family"]


def build_family(
    family: Family,
    out_dir: str | Path,
    progress: Callable[[str], None] | None = None,
    outcomes: dict[str, Built | str] | None = None,
    beside: dict[str, bytes] | None = None,
) -> dict:
    """Build every part of ``family`` into ``out_dir/<family.name>/``; returns the manifest.

    The manifest (also written as ``manifest.json``) lists for each part its parameters,
    results, files with SHA-256, or its error (:func:`workers.part_outcome`). ``manifest["ok"]`` is
    False if any part failed. ``outcomes`` (part name → :func:`workers.part_outcome`) are parts built
    elsewhere, e.g. in other processes (:func:`build_families`); the parts are then only written.
    ``beside`` are files written next to the folder with it, under its lock (``transplanter pair``'s
    part script; the manifest records a script given there by those bytes).

    The folder is written as one transaction (``export.Transaction``): it is the old export
    until the new one is complete, then the new one; a failing part keeps its previous files
    (listed under ``previous_files``), files of parts no longer in the script are gone, and a
    second build of the same folder meanwhile is refused.
    """
    root = inputs.folder("out_dir", out_dir) / family.name
    manifest: dict = {"family": family.name, "description": family.description, "parts": {}, "ok": True}
    if family.script is not None:
        written = (
            (beside or {}).get(Path(family.script).name)
            if Path(family.script).parent == root.parent.resolve()
            else None
        )
        manifest["script"] = script_record(family.script, family.modules, written)
    with Transaction(root, beside) as tx:
        old = previous_manifest(root)
        for part in family.parts:
            if outcomes is None:
                outcome = workers.part_outcome(part, root)
                if progress is not None:
                    progress(f"{family.name}/{part.name}")
            else:
                outcome = outcomes[part.name]
            if not isinstance(outcome, str):
                record, files = outcome
                for fname, data in sorted(files.items()):
                    tx.write(fname, data)
                record["files"] = {fname: sha256(data) for fname, data in sorted(files.items())}
                manifest["parts"][part.name] = record
                continue
            failed: dict = {"error": outcome}
            before = old.get("parts", {}).get(part.name, {})
            kept = before.get("files", before.get("previous_files", {}))
            kept = {f: h for f, h in sorted(kept.items()) if plain_name(f) and tx.keep(f)}
            if kept:
                failed["previous_files"] = kept
            manifest["parts"][part.name] = failed
            manifest["ok"] = False
        report = family_report(manifest)
        tx.write("report.html", report)
        manifest["report"] = {"report.html": sha256(report)}
        manifest = seal(manifest)
        tx.write("manifest.json", json_bytes(manifest))
    return manifest


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

    workers.FAMILIES.clear()
    workers.FAMILIES.update((f.name, f) for f in families)
    tasks = [(f, p) for f in families for p in f.parts]
    tasks.sort(key=lambda t: -t[1].cost)  # the longest first; stable: script order within a cost
    outcomes: dict[str, dict] = {f.name: {} for f in families}
    manifests: dict[str, dict] = {}
    try:
        with workers.executor(jobs) as pool:
            pending = {pool.submit(workers.outcome, f.name, f.script, p.name): (f, p) for f, p in tasks}
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
        workers.FAMILIES.clear()
    return [manifests[n] for n in names]
