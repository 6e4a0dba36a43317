"""Building families into a folder: every part's files written in one transaction, the manifest
and the report beside them; parts in worker processes (:mod:`families.workers`)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from transplanter.core import inputs
from transplanter.core.errors import ExportError, PartScriptError
from transplanter.families.builder import workers
from transplanter.families.builder.manifest import (
    BUILD_RECORD,
    intact,
    part_key,
    plain_name,
    previous_manifest,
    read_build_record,
    script_record,
    seal,
    sha256,
)
from transplanter.families.builder.scripts import Family
from transplanter.families.builder.study import Built
from transplanter.report.pages import family_report
from transplanter.shop.export import Transaction, json_bytes, leftovers

__all__ = ["build_families", "build_family"]


def build_family(
    family: Family,
    out_dir: str | Path,
    progress: Callable[[str], None] | None = None,
    outcomes: dict[str, Built | str] | None = None,
    beside: dict[str, bytes] | None = None,
    force: bool = False,
    reuse: tuple[dict, dict, dict] | None = None,
) -> dict:
    """Build every part of ``family`` into ``out_dir/<family.name>/``; returns the manifest, with
    ``build`` (which parts were kept or rebuilt and why; not written into the file).

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

    **Only what changed is rebuilt** (unless ``force``): a part whose key (:func:`manifest.part_key`:
    the package's code and the part's own content) is the last build's, and whose files are all
    there with their digests, is kept — its files carried over, its record as it was; so the folder
    equals a full rebuild byte for byte. Nothing at all changed: nothing is written. Which parts
    were kept or rebuilt, and why, is recorded beside the folder (``.<family>.build.json``).
    ``reuse`` is that decision made already (:func:`_reusable`, by :func:`build_families` before it
    hands out the parts).
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
    old = previous_manifest(root)
    keys, kept, last = reuse or _reusable(family, root, old, force, manifest.get("script"))
    rebuilt = {p.name: _why(keys[p.name], last.get(p.name)) for p in family.parts if p.name not in kept}
    decided = {"kept": sorted(kept), "rebuilt": rebuilt, "forced": force}
    if not rebuilt and not beside and _unchanged(root, family, manifest, old):
        return {**old, "build": decided}  # nothing changed: nothing touched
    beside = {**(beside or {}), BUILD_RECORD.format(name=family.name): json_bytes({"keys": keys, **decided})}
    made: dict[str, dict[str, bytes] | str] = {}  # each part's files, for the parts that use them
    with Transaction(root, beside) as tx:
        for part in family.parts:
            if part.name in kept:
                for fname in kept[part.name]["files"]:
                    tx.keep(fname)
                manifest["parts"][part.name] = kept[part.name]
                made[part.name] = _kept_files(root, kept[part.name]) if _used_later(family, part.name) else {}
                continue
            if outcomes is None or part.name not in outcomes:  # (a kept part whose files changed meanwhile)
                outcome = _outcome(part, root, made)
                if progress is not None:
                    progress(f"{family.name}/{part.name}")
            else:
                outcome = outcomes[part.name]
            made[part.name] = outcome if isinstance(outcome, str) else outcome[1]
            if not isinstance(outcome, str):
                record, files = outcome
                for fname, data in sorted(files.items()):
                    tx.write(fname, data)
                record["files"] = {fname: sha256(data) for fname, data in sorted(files.items())}
                manifest["parts"][part.name] = record
                continue
            failed: dict = {"error": outcome}
            before = old.get("parts", {}).get(part.name, {})
            previous = before.get("files", before.get("previous_files", {}))
            previous = {f: h for f, h in sorted(previous.items()) if plain_name(f) and tx.keep(f)}
            if previous:
                failed["previous_files"] = previous
            manifest["parts"][part.name] = failed
            manifest["ok"] = False
        report = family_report(manifest)
        tx.write("report.html", report)
        manifest["report"] = {"report.html": sha256(report)}
        manifest = seal(manifest)
        tx.write("manifest.json", json_bytes(manifest))
    return {**manifest, "build": decided}


def _used_later(family: Family, name: str) -> bool:
    return any(name in workers.uses(p) for p in family.parts)


def _kept_files(root: Path, record: dict) -> dict[str, bytes]:
    """The files of a kept part, as its last build left them (digests checked by ``intact``)."""
    return {fname: (root / fname).read_bytes() for fname in record.get("files", {})}


def _used(part, made: dict) -> dict[str, bytes] | str:
    """The files of the parts ``part`` uses (``made``: part -> files, or its error), or why it
    cannot be built."""
    files: dict[str, bytes] = {}
    for name in workers.uses(part):
        got = made.get(name)
        if got is None or isinstance(got, str):
            return f"PartError: {part.name} is built from the files of {name}, which failed to build"
        files.update(got)
    return files


def _outcome(part, root: Path, made: dict):
    used = _used(part, made)
    return used if isinstance(used, str) else workers.part_outcome(part, root, used)


def _reusable(
    family: Family, root: Path, old: dict, force: bool, script: dict | None = None
) -> tuple[dict, dict, dict]:
    """Each part's key, the parts that may be kept (``{name: their last record}`` for those whose
    key is the last build's and whose files are intact; nothing when ``force``) and the last
    build's keys. ``script``: the family's script record, as the manifest will hold it (default:
    read from disk)."""
    design = {}
    if family.script:  # the files that define a study kind a script brings: module name -> digest
        record = script or script_record(family.script, family.modules)
        design = {"transplanter_part_script": record["sha256"]}
        design |= {Path(m).stem: d for m, d in record.get("modules", {}).items()}
    keys = {p.name: part_key(p, design) for p in family.parts}
    for p in family.parts:  # a part built from others' files changes when they do
        deps = [keys[u] for u in workers.uses(p)]
        if deps:
            key = keys[p.name]
            keys[p.name] = None if key is None or None in deps else sha256("\0".join([key, *deps]).encode())
    last = read_build_record(root).get("keys", {})
    if force or not old:
        return keys, {}, last
    kept = {}
    for name, key in keys.items():
        prev = old.get("parts", {}).get(name)
        if key is not None and last.get(name) == key and isinstance(prev, dict) and "error" not in prev:
            if intact(root, prev):
                kept[name] = prev
    return keys, kept, last


def _why(key: str | None, last: str | None) -> str:
    """Why a part with ``key`` is rebuilt (``last``: its key at the last build), in words."""
    if key is None:
        return "its content cannot be keyed (always rebuilt)"
    if last is None:
        return "new, or no record of its last build"
    return "changed (its content or the package's code)" if last != key else "its files changed"


def _unchanged(root: Path, family: Family, manifest: dict, old: dict) -> bool:
    """Every part kept, the manifest the same but for its parts (script, description) and the
    folder holding exactly its files, nothing left by an interrupted build: it would be rewritten
    byte for byte, so it is not written at all."""
    head = {k: v for k, v in manifest.items() if k != "parts"}
    if not old or any(old.get(k) != v for k, v in head.items()):
        return False
    if set(old.get("parts", {})) != {p.name for p in family.parts} or leftovers(root):
        return False
    listed = {"manifest.json", *old.get("report", {})}
    for rec in old["parts"].values():
        listed.update(rec.get("files", {}))
    return {p.name for p in root.iterdir()} == listed


def build_families(
    families: list[Family],
    out_dir: str | Path,
    jobs: int = 1,
    progress: Callable[[str], None] | None = None,
    force: bool = False,
) -> list[dict]:
    """Build ``families`` into ``out_dir``, their parts spread over ``jobs`` processes; returns
    their manifests in order. Parts that have not changed are kept (:func:`build_family`; all
    rebuilt with ``force``).

    The parts are handed out longest kind first (gear pairs, trains, cams, ...) to whichever
    process is free, and each family is written (:func:`build_family`) as soon as its last part
    is done, by this process, in the family's own part order — so the files are byte-identical
    to a serial build. ``progress`` gets ``family/part`` as each part finishes.
    """
    names = [f.name for f in families]
    if len(set(names)) != len(names):  # serial or not: the last would replace the first's export
        raise PartScriptError(f"two part scripts define the same family name: {sorted(names)}")
    if jobs <= 1:
        return [build_family(f, out_dir, progress, force=force) for f in families]
    from concurrent.futures import FIRST_COMPLETED, wait
    from concurrent.futures.process import BrokenProcessPool

    workers.FAMILIES.clear()
    workers.FAMILIES.update((f.name, f) for f in families)
    out = inputs.folder("out_dir", out_dir)
    reuse = {f.name: _reusable(f, out / f.name, previous_manifest(out / f.name), force) for f in families}
    keep = {name: decided[1] for name, decided in reuse.items()}  # the parts not handed out
    tasks = [(f, p) for f in families for p in f.parts if p.name not in keep[f.name]]
    tasks.sort(key=lambda t: -t[1].cost)  # the longest first; stable: script order within a cost
    outcomes: dict[str, dict] = {f.name: {} for f in families}
    manifests: dict[str, dict] = {}

    def files_of(f: Family, name: str):  # a part's files, or its error, for a part that uses them
        if name in keep[f.name]:
            return _kept_files(out / f.name, keep[f.name][name])
        got = outcomes[f.name][name]
        return got if isinstance(got, str) else got[1]

    def waiting(f: Family, p) -> bool:
        return any(u not in keep[f.name] and u not in outcomes[f.name] for u in workers.uses(p))

    try:
        with workers.executor(jobs) as pool:
            pending: dict = {}

            def hand_out() -> None:  # every task whose used parts are done, longest first
                for f, p in [t for t in tasks if not waiting(*t)]:
                    tasks.remove((f, p))
                    used = _used(p, {u: files_of(f, u) for u in workers.uses(p)}) if workers.uses(p) else None
                    if isinstance(used, str):
                        outcomes[f.name][p.name] = used
                        continue
                    pending[pool.submit(workers.outcome, f.name, f.script, p.name, used)] = (f, p)

            hand_out()
            for f in families:  # a family without parts to build is written at once
                if len(keep[f.name]) == len(f.parts):
                    manifests[f.name] = build_family(f, out_dir, outcomes={}, force=force, reuse=reuse[f.name])
            while pending or tasks:
                if not pending:  # (cannot happen: a part uses only parts listed before it)
                    raise ExportError(f"parts wait for parts that are not built: {[p.name for _, p in tasks]}")
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
                hand_out()
                for f in families:
                    if f.name not in manifests and len(outcomes[f.name]) + len(keep[f.name]) == len(f.parts):
                        manifests[f.name] = build_family(
                            f, out_dir, outcomes=outcomes[f.name], force=force, reuse=reuse[f.name]
                        )
    finally:
        workers.FAMILIES.clear()
    return [manifests[n] for n in names]
