"""Building families into a folder: every part's files written in one transaction, the manifest
and the report beside them; parts in worker processes (:mod:`families.workers`).

**Nothing carried forward unverified.** A part is kept from the last build only if everything
about it verifies, under the family's lock (taken before anything is decided, so two builds of
one folder never interleave — the second is refused): its key is the last build's; the last
manifest reads, fits its schema and its seal verifies; the part's record there is the one in the
build's own record of what it made (:data:`~transplanter.families.builder.manifest.BUILD_RECORD`,
sealed, beside the folder); and each of its files, read once as it is taken, has its digest —
the bytes hashed are the bytes written. Anything else is rebuilt, and why is said
(``build["unverified"]``: part -> why, one line each in ``transplanter build``'s summary).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from contextlib import ExitStack, nullcontext
from dataclasses import dataclass
from pathlib import Path

from transplanter.core import inputs
from transplanter.core.errors import ExportError, PartScriptError
from transplanter.families.builder import workers
from transplanter.families.builder.manifest import (
    BUILD_RECORD,
    check_part_record,
    listed_file,
    part_key,
    read_build_record,
    read_manifest,
    script_record,
    seal,
    seal_matches,
    sha256,
)
from transplanter.families.builder.scripts import Family
from transplanter.families.builder.study import Built
from transplanter.report.pages import family_report
from transplanter.shop.export import Transaction, json_bytes

__all__ = ["build_families", "build_family"]


@dataclass(frozen=True)
class _Plan:
    """What a build of one family does, decided under its lock (:func:`_plan`)."""

    #: each part's key (:func:`manifest.part_key`, with the parts it uses)
    keys: dict
    #: the parts kept: their records, from the build record (each verified)
    kept: dict
    #: the parts rebuilt, and why
    rebuilt: dict
    #: those of them rebuilt because something of the last build did not verify, and why
    unverified: dict
    #: the last manifest ({} unless it reads and its seal verifies)
    old: dict
    #: the last records the manifest and the build record agree on (a failing part keeps its files)
    trusted: dict
    force: bool


def build_family(
    family: Family,
    out_dir: str | Path,
    progress: Callable[[str], None] | None = None,
    outcomes: dict[str, Built | str] | None = None,
    beside: dict[str, bytes] | None = None,
    force: bool = False,
) -> dict:
    """Build every part of ``family`` into ``out_dir/<family.name>/``; returns the manifest, with
    ``build`` (which parts were kept or rebuilt and why; not written into the file).

    The manifest (also written as ``manifest.json``) lists for each part its parameters,
    results, files with SHA-256, or its error (:func:`workers.part_outcome`). ``manifest["ok"]`` is
    False if any part failed. ``outcomes`` (part name → :func:`workers.part_outcome`) are parts built
    elsewhere, e.g. in other processes (:func:`build_families`); the parts are then only written.
    ``beside`` are files written next to the folder with it, in the same transaction
    (``transplanter pair``'s part script; the manifest records a script given there by those bytes).

    The folder is written as one transaction (``export.Transaction``): it is the old export
    until the new one is complete, then the new one, with the files beside it; a failing part
    keeps its previous files (listed under ``previous_files``, each verified as it is taken),
    files of parts no longer in the script are gone, and a second build of the same folder
    meanwhile is refused.

    **Only what changed is rebuilt** (unless ``force``), and only what verifies is kept (the
    module docstring): a part whose key (:func:`manifest.part_key`: the package's code and the
    part's own content) is the last build's is kept — its files carried over, its record as the
    build made it; so the folder equals a full rebuild byte for byte. Nothing at all changed:
    nothing is written. Which parts were kept or rebuilt, and why, is recorded beside the folder
    (``.<family>.build.json``, with each part's record).
    """
    root = inputs.folder("out_dir", out_dir) / family.name
    head = _head(family, root, beside)
    with Transaction(root, {**(beside or {}), BUILD_RECORD.format(name=family.name): b""}) as tx:
        plan = _plan(family, root, force, head.get("script"))
        return _write(family, root, tx, plan, head, outcomes, progress, bool(beside))


def _head(family: Family, root: Path, beside: dict[str, bytes] | None = None) -> dict:
    """The manifest of ``family`` before its parts: name, description, the script it came from."""
    head: dict = {"family": family.name, "description": family.description, "parts": {}, "ok": True}
    if family.script is not None:
        written = (
            (beside or {}).get(Path(family.script).name)
            if Path(family.script).parent == root.parent.resolve()
            else None
        )
        head["script"] = script_record(family.script, family.modules, written)
    return head


def _write(
    family: Family,
    root: Path,
    tx: Transaction,
    plan: _Plan,
    head: dict,
    outcomes: dict | None,
    progress: Callable[[str], None] | None,
    beside: bool,
) -> dict:
    """Write the family's new folder in ``tx`` as ``plan`` says and commit it (nothing, when
    nothing changed); the manifest, with ``build``."""
    manifest = {**head, "parts": {}}
    kept, rebuilt, unverified = dict(plan.kept), dict(plan.rebuilt), dict(plan.unverified)

    def decided() -> dict:
        return {"kept": sorted(kept), "rebuilt": rebuilt, "unverified": unverified, "forced": plan.force}

    if not rebuilt and not beside and _unchanged(root, family, manifest, plan.old):
        tx.cancel()
        return {**plan.old, "build": decided()}  # nothing changed: nothing touched
    made: dict[str, dict[str, bytes] | str] = {}  # each part's files, for the parts that use them
    for part in family.parts:
        if part.name in kept:
            taken = _take(root, kept[part.name])
            if isinstance(taken, dict):
                for fname, data in sorted(taken.items()):
                    tx.write(fname, data)
                manifest["parts"][part.name] = kept[part.name]
                made[part.name] = taken if _used_later(family, part.name) else {}
                continue
            del kept[part.name]  # a file changed while the build ran: built here after all
            rebuilt[part.name] = unverified[part.name] = f"its files changed while the build ran: {taken}"
        if outcomes is None or part.name not in outcomes:
            outcome = _outcome(part, root, made)
            if progress is not None:
                progress(f"{family.name}/{part.name}")
        else:
            outcome = outcomes[part.name]
        outcome = _checked(part.name, outcome)
        made[part.name] = outcome if isinstance(outcome, str) else outcome[1]
        if not isinstance(outcome, str):
            record, files = outcome
            for fname, data in sorted(files.items()):
                tx.write(fname, data)
            manifest["parts"][part.name] = record
            continue
        failed: dict = {"error": outcome}
        before = plan.trusted.get(part.name, {})
        previous = {}
        for fname, digest in sorted(before.get("files", before.get("previous_files", {})).items()):
            data, problem = listed_file(root, fname, digest)
            if not problem:  # only files that verify, as they were read
                tx.write(fname, data)
                previous[fname] = digest
        if previous:
            failed["previous_files"] = previous
        manifest["parts"][part.name] = failed
        manifest["ok"] = False
    report = family_report(manifest)
    tx.write("report.html", report)
    manifest["report"] = {"report.html": sha256(report)}
    manifest = seal(manifest)
    tx.write("manifest.json", json_bytes(manifest))
    record = seal({"keys": plan.keys, **decided(), "parts": manifest["parts"]})
    tx.put_beside(BUILD_RECORD.format(name=family.name), json_bytes(record))
    tx.commit()
    return {**manifest, "build": decided()}


def _checked(name: str, outcome):
    """A built part's outcome with its files' digests in its record, or its error: a record or a
    file name a manifest could not hold (:func:`manifest.check_part_record`) fails the part."""
    if isinstance(outcome, str):
        return outcome
    record, files = outcome
    try:
        if not isinstance(record, dict) or not isinstance(files, dict):
            raise ValueError(f"part {name!r}: a study's build must give (record: dict, files: dict)")
        record["files"] = {fname: sha256(data) for fname, data in sorted(files.items())}
        check_part_record(name, record)
    except (TypeError, ValueError) as exc:
        return f"PartScriptError: {exc}"
    return outcome


def _take(root: Path, record: dict) -> dict[str, bytes] | str:
    """The files of a kept part, each read once and checked against its digest (the bytes hashed
    are the bytes returned, to be written); or what is wrong with the first that is not."""
    taken = {}
    for fname, digest in sorted(record.get("files", {}).items()):
        data, problem = listed_file(root, fname, digest)
        if problem:
            return f"{fname}: {problem}"
        taken[fname] = data
    return taken


def _used_later(family: Family, name: str) -> bool:
    return any(name in workers.uses(p) for p in family.parts)


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


def _keys(family: Family, script: dict | None = None) -> dict:
    """Each part's key; a part built from others' files changes when they do. ``script``: the
    family's script record, as the manifest will hold it (default: read from disk)."""
    design = {}
    if family.script:  # the files that define a study kind a script brings: module name -> digest
        record = script or script_record(family.script, family.modules)
        design = {"transplanter_part_script": record["sha256"]}
        design |= {Path(m).stem: d for m, d in record.get("modules", {}).items()}
    keys = {p.name: part_key(p, design) for p in family.parts}
    for p in family.parts:
        deps = [keys[u] for u in workers.uses(p)]
        if deps:
            key = keys[p.name]
            keys[p.name] = None if key is None or None in deps else sha256("\0".join([key, *deps]).encode())
    return keys


def _last_manifest(root: Path) -> tuple[dict, str]:
    """The last build's manifest if it reads, fits its schema and its seal verifies; else ``{}``
    and why not ("" when there is none)."""
    if not os.path.lexists(root / "manifest.json"):
        return {}, ""
    try:
        old = read_manifest(root)
    except ValueError as exc:  # (FileRefused included: a FIFO, a link, too large)
        return {}, f"the last manifest.json cannot be used ({exc})"
    sealed = seal_matches(old)
    if sealed is None:
        return {}, "the last manifest.json carries no seal"
    if not sealed:
        return {}, "the last manifest.json was edited since the build (its seal, manifest_sha256, does not verify)"
    return old, ""


def _plan(family: Family, root: Path, force: bool, script: dict | None = None) -> _Plan:
    """What to keep and what to rebuild, and why (the module docstring), decided under the lock."""
    keys = _keys(family, script)
    old, why_all = _last_manifest(root)
    record, why_record = read_build_record(root)
    why_all = why_all or why_record
    last, made = record.get("keys", {}), record.get("parts", {})
    listed = old.get("parts", {})
    trusted = {n: r for n, r in made.items() if listed.get(n) == r} if not why_all else {}
    kept, rebuilt, unverified = {}, {}, {}
    for p in family.parts:
        name, key = p.name, keys[p.name]
        why, alarm = _verdict(root, name, key, last.get(name), made.get(name), listed.get(name), force, why_all)
        busy = next((u for u in workers.uses(p) if u in rebuilt), None)
        if not why and busy is not None:
            why = f"it is built from the files of {busy}, which is rebuilt"
        if not why:
            kept[name] = made[name]
            continue
        rebuilt[name] = why
        if alarm:
            unverified[name] = why
    return _Plan(keys, kept, rebuilt, unverified, old, trusted, force)


def _verdict(root: Path, name: str, key, last, made, listed, force: bool, why_all: str) -> tuple[str, bool]:
    """Why the part ``name`` (``key``; ``last``: its key at the last build, ``made``: its record in
    the build record, ``listed``: in the last manifest) is rebuilt — "" if it is kept — and whether
    that is because something did not verify."""
    if key is None:
        return "its content cannot be keyed (always rebuilt)", False
    if force:
        return "rebuilt on request (--force)", False
    if why_all:
        return f"nothing of the last build is kept: {why_all}", True
    if last is None or made is None:
        return "new, or no record of its last build", False
    if last != key:
        return "changed (its content or the package's code)", False
    if "error" in made:
        return "its last build failed", False
    if listed != made:
        what = "is missing from" if listed is None else "differs from the one the build made in"
        return f"its record in manifest.json {what} {BUILD_RECORD.format(name=root.name)}", True
    taken = _take(root, made)  # (read and hashed now, and again as they are taken)
    if isinstance(taken, str):
        return f"its files do not verify: {taken}", True
    return "", False


def _unchanged(root: Path, family: Family, manifest: dict, old: dict) -> bool:
    """Every part kept, the manifest the same but for its parts (script, description) and the
    folder holding exactly its files (what an interrupted build left was put back when the lock
    was taken): it would be rewritten byte for byte, so it is not written at all."""
    head = {k: v for k, v in manifest.items() if k != "parts"}
    if not old or any(old.get(k) != v for k, v in head.items()):
        return False
    if set(old.get("parts", {})) != {p.name for p in family.parts}:
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

    The parts are handed out longest kind first (gear pairs, trains, cams, ...), each built in a
    process of its own forked from this one as it was before the first (:class:`workers.Forks`),
    up to ``jobs`` at once, and each family is written (:func:`build_family`) as soon as its last
    part is done, by this process, in the family's own part order — so the files are
    byte-identical to a serial build. ``progress`` gets ``family/part`` as each part finishes.
    """
    names = [f.name for f in families]
    if len(set(names)) != len(names):  # serial or not: the last would replace the first's export
        raise PartScriptError(f"two part scripts define the same family name: {sorted(names)}")
    if jobs <= 1:
        return [build_family(f, out_dir, progress, force=force) for f in families]

    out = inputs.folder("out_dir", out_dir)
    roots = {f.name: out / f.name for f in families}
    heads = {f.name: _head(f, roots[f.name]) for f in families}
    outcomes: dict[str, dict] = {f.name: {} for f in families}
    manifests: dict[str, dict] = {}
    with ExitStack() as held:  # every family's lock, taken before anything is decided
        txs = {
            f.name: held.enter_context(Transaction(roots[f.name], {BUILD_RECORD.format(name=f.name): b""}))
            for f in families
        }
        plans = {f.name: _plan(f, roots[f.name], force, heads[f.name].get("script")) for f in families}
        keep = {name: plan.kept for name, plan in plans.items()}  # the parts not handed out
        tasks = [(f, p) for f in families for p in f.parts if p.name not in keep[f.name]]
        tasks.sort(key=lambda t: -t[1].cost)  # the longest first; stable: script order within a cost

        def files_of(f: Family, name: str):  # a part's files, or its error, for a part that uses them
            if name in keep[f.name]:
                taken = _take(roots[f.name], keep[f.name][name])
                return taken if isinstance(taken, dict) else f"PartError: the files of {name} changed: {taken}"
            got = outcomes[f.name][name]
            return got if isinstance(got, str) else got[1]

        def waiting(f: Family, p) -> bool:
            return any(u not in keep[f.name] and u not in outcomes[f.name] for u in workers.uses(p))

        def write(f: Family) -> None:
            manifests[f.name] = _write(
                f, roots[f.name], txs[f.name], plans[f.name], heads[f.name], outcomes[f.name], None, False
            )

        workers.FAMILIES.clear()
        workers.FAMILIES.update((f.name, f) for f in families)
        try:
            # (no fork server where every part is kept: its imports are a second of a rebuild's CPU)
            with workers.Forks(jobs) if tasks else nullcontext() as pool:
                pending: dict = {}

                def hand_out() -> None:  # every task whose used parts are done, longest first
                    for f, p in [t for t in tasks if not waiting(*t)]:
                        tasks.remove((f, p))
                        used = _used(p, {u: files_of(f, u) for u in workers.uses(p)}) if workers.uses(p) else None
                        if isinstance(used, str):
                            outcomes[f.name][p.name] = used
                            continue
                        pending[pool.submit(workers.outcome, f.name, p.name, used)] = (f, p)

                hand_out()
                for f in families:  # a family without parts to build is written at once
                    if len(keep[f.name]) == len(f.parts):
                        write(f)
                while pending or tasks:
                    if not pending:  # (cannot happen: a part uses only parts listed before it)
                        raise ExportError(f"parts wait for parts that are not built: {[p.name for _, p in tasks]}")
                    ticket, kind, value = pool.next()
                    f, p = pending.pop(ticket)
                    if kind == "died":  # a process killed (out of memory, a signal)
                        raise ExportError(
                            f"a build process died while building {f.name}/{p.name} ({value}); the exports of the "
                            "families not yet written are unchanged — run the build again, or with --jobs 1"
                        )
                    if kind == "error":
                        raise value
                    outcomes[f.name][p.name] = value
                    if progress is not None:
                        progress(f"{f.name}/{p.name}")
                    hand_out()
                    for f in families:
                        if f.name not in manifests and len(outcomes[f.name]) + len(keep[f.name]) == len(f.parts):
                            write(f)
        finally:
            workers.FAMILIES.clear()
    return [manifests[n] for n in names]
