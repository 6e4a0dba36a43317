"""A family's manifest: what a build records of its script, parts and files (SHA-256 each), and
the check that a manifest read from disk has that shape before anything trusts it.

A manifest is *data from the folder*: every file name in it must be a plain name of a file in
that folder (no path, no ``..``, not absolute) before anything reads, hashes or keeps it; it is
read only up to ``MAX_MANIFEST_BYTES`` and nesting Python's JSON reader can hold; and it carries
its own digest (``manifest_sha256``, over everything else in it), so results edited by hand are
told apart from the build's — a seal against edits, not a signature (whoever edits can reseal;
``transplanter check --run-script`` recomputes the results themselves).
"""

from __future__ import annotations

import functools
import hashlib
import json
from pathlib import Path

__all__ = [
    "BUILD_RECORD",
    "MAX_MANIFEST_BYTES",
    "intact",
    "listed_file",
    "package_digest",
    "part_key",
    "read_build_record",
    "check_manifest",
    "plain_name",
    "previous_manifest",
    "read_manifest",
    "script_record",
    "seal",
    "seal_matches",
    "sha256",
]

#: the largest manifest read, bytes (the seed-004 family's is 0.1 MB)
MAX_MANIFEST_BYTES = 50_000_000
SEAL = "manifest_sha256"


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def plain_name(name: object) -> bool:
    """True for the name of a file directly inside a folder: no separator, not ``.``/``..``,
    not empty, no NUL."""
    return (
        isinstance(name, str)
        and name not in ("", ".", "..")
        and "/" not in name
        and "\\" not in name
        and "\0" not in name
    )


def script_record(script: str, modules: tuple[str, ...], data: bytes | None = None) -> dict:
    """The design a family was built from: its script and the modules beside it that it imported
    (by file name), with SHA-256 (of ``data`` for a script written with the export)."""
    out: dict = {"path": script, "sha256": sha256(Path(script).read_bytes() if data is None else data)}
    if modules:
        out["modules"] = {Path(m).name: sha256(Path(m).read_bytes()) for m in sorted(modules)}
    return out


def _body(manifest: dict) -> bytes:
    return json.dumps({k: v for k, v in manifest.items() if k != SEAL}, sort_keys=True).encode()


def seal(manifest: dict) -> dict:
    """``manifest`` with its digest over everything else in it (``manifest_sha256``)."""
    return {**manifest, SEAL: sha256(_body(manifest))}


def seal_matches(manifest: dict) -> bool | None:
    """Whether the manifest is as its build sealed it (None: it carries no seal, an older build)."""
    if SEAL not in manifest:
        return None
    return manifest[SEAL] == sha256(_body(manifest))


def read_manifest(root: Path) -> dict:
    """``root/manifest.json`` read and checked (:func:`check_manifest`); ValueError saying what is
    wrong with it (too large, not JSON, nested too deep, not a family manifest), OSError if it
    cannot be read. A manifest that is a symbolic link is not followed."""
    path = root / "manifest.json"
    if path.is_symlink():
        raise ValueError("manifest.json is a symbolic link: not followed")
    with open(path, "rb") as f:
        data = f.read(MAX_MANIFEST_BYTES + 1)
    if len(data) > MAX_MANIFEST_BYTES:
        raise ValueError(f"manifest.json is larger than {MAX_MANIFEST_BYTES} bytes (limit)")
    try:
        manifest = json.loads(data)
    except RecursionError as exc:
        raise ValueError("manifest.json is nested deeper than its reader can follow") from exc
    except UnicodeDecodeError as exc:
        raise ValueError(f"manifest.json is not UTF-8 text ({exc.reason})") from exc
    check_manifest(manifest)
    return manifest


def previous_manifest(root: Path) -> dict:
    """The current export's manifest, or {} if there is none or it is damaged (:func:`read_manifest`)."""
    try:
        return read_manifest(root)
    except (OSError, ValueError):
        return {}


def check_manifest(manifest) -> None:
    """ValueError naming what is wrong if ``manifest`` is not a family manifest: parts are records,
    their files tables of plain file names to SHA-256 digests, the script a record."""
    if not isinstance(manifest, dict) or not isinstance(manifest.get("parts"), dict):
        raise ValueError("not a family manifest: no 'parts' table")
    for name, rec in manifest["parts"].items():
        if not isinstance(rec, dict):
            raise ValueError(f"part {name!r} is not a record")
        for key in ("files", "previous_files"):
            files = rec.get(key, {})
            if not isinstance(files, dict) or not all(isinstance(v, str) for v in files.values()):
                raise ValueError(f"part {name!r}: {key} is not a table of SHA-256 digests")
            bad = [f for f in files if not plain_name(f)]
            if bad:
                raise ValueError(
                    f"part {name!r}: {key} names {bad[0]!r}, not a plain file name inside the folder (nothing "
                    "outside an export is read through its manifest)"
                )
    report = manifest.get("report", {})
    if not isinstance(report, dict) or not all(plain_name(f) for f in report):
        raise ValueError("'report' is not a table of plain file names")
    if not isinstance(manifest.get("script", {}), dict):
        raise ValueError("'script' is not a record")


# -- what a part was built from: its key, for rebuilding only what changed ---------------------

#: the record of the last build beside a family folder (not in it: the export stays byte-identical
#: to a full rebuild): ``{"keys": {part: key}, "kept": [...], "rebuilt": {part: why}}``
BUILD_RECORD = ".{name}.build.json"


@functools.cache
def package_digest() -> str:
    """SHA-256 of the package's own code (every ``.py`` file under ``transplanter/``, by path)."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def part_key(part, design: dict[str, str] | None = None) -> str | None:
    """What a part's files follow from, as one digest: the package's code, the part's kind and
    everything it holds — every number, curve and option, pickled by value with cloudpickle
    (dask's pickler: functions the part's data refers to are pickled with their code) — so a part
    is rebuilt when any of them changed and kept otherwise. A kind defined outside the package (a
    study class in a part script or a design module beside it) is keyed by the digest of the file
    that defines it too (``design``: module name -> digest; its code is the kind's code; a kind
    from elsewhere is keyed by all of them). None when the part cannot be pickled (always rebuilt)."""
    import dataclasses

    import cloudpickle

    kind = type(part)
    ident = f"{kind.__module__}.{kind.__qualname__}"
    if not kind.__module__.startswith("transplanter."):
        design = design or {}
        ident += "@" + design.get(kind.__module__, sha256(json.dumps(design, sort_keys=True).encode()))
    try:
        held = (
            [getattr(part, f.name) for f in dataclasses.fields(part)] if dataclasses.is_dataclass(part) else vars(part)
        )
        data = cloudpickle.dumps(held, protocol=5)
    except Exception:  # an object the pickler refuses: no key, always rebuilt
        return None
    return sha256(package_digest().encode() + ident.encode() + b"\0" + data)


def read_build_record(root: Path) -> dict:
    """The record of the last build of the family folder ``root`` ({} if none or damaged)."""
    path = root.parent / BUILD_RECORD.format(name=root.name)
    try:
        if path.is_symlink():
            return {}
        record = json.loads(path.read_text())
        return record if isinstance(record, dict) and isinstance(record.get("keys"), dict) else {}
    except (OSError, ValueError, RecursionError):
        return {}


def listed_file(root: Path, name: str, digest: str) -> tuple[bytes | None, str]:
    """A file a manifest lists, as found in ``root``: its bytes (None when they cannot be had) and
    what is wrong with it ("" when nothing): a symbolic link is not followed, a missing or
    unreadable file is said, and bytes that are not the listed digest's."""
    path = root / name
    if path.is_symlink():
        return None, "a symbolic link: not followed"
    if not path.is_file():
        return None, "missing"
    try:
        data = path.read_bytes()
    except OSError as exc:
        return None, f"cannot be read: {exc.strerror or exc}"
    return data, "" if sha256(data) == digest else "changed since the build (SHA-256 differs)"


def intact(root: Path, record: dict) -> bool:
    """Every file a part record lists is in ``root`` as a regular file with its SHA-256."""
    files = record.get("files")
    if not isinstance(files, dict) or not files:
        return False
    return all(plain_name(name) and not listed_file(root, name, digest)[1] for name, digest in files.items())
