"""A family's manifest: what a build records of its script, parts and files (SHA-256 each), and
the check that a manifest read from disk has that shape before anything trusts it.

A manifest is *data from the folder*. It is read by the one reader of files
(:func:`transplanter.core.files.read_regular`: a regular file, not a link, a FIFO or a device, at
most ``MAX_MANIFEST_BYTES``, nesting Python's JSON reader can hold) and checked against its
schema field by field (:func:`check_manifest`) before any field is used: every file name in it a
plain name of a file in that folder (no path, no ``..``, no control character, at most 255
bytes), every digest 64 hex digits, ``parameters`` and ``results`` tables, the script a record.
It carries its own digest (``manifest_sha256``, over everything else in it), so results edited
by hand are told apart from the build's — a seal against edits, not a signature (whoever edits
can reseal; ``transplanter check --run-script`` recomputes the results themselves, and a build
keeps a part only if its record here is the one in the build's own record beside the folder,
:data:`BUILD_RECORD`).
"""

from __future__ import annotations

import functools
import hashlib
import json
import re
import unicodedata
from pathlib import Path

from transplanter.core.files import FileRefused, read_regular

__all__ = [
    "BUILD_RECORD",
    "MAX_BUILD_RECORD_BYTES",
    "MAX_LISTED_FILE_BYTES",
    "MAX_MANIFEST_BYTES",
    "MAX_NAME_BYTES",
    "MAX_SCRIPT_BYTES",
    "check_build_record",
    "check_manifest",
    "check_part_record",
    "listed_file",
    "package_digest",
    "part_key",
    "plain_name",
    "previous_manifest",
    "read_build_record",
    "read_manifest",
    "script_record",
    "seal",
    "seal_matches",
    "sha256",
]

#: the largest manifest read, bytes (the seed-004 family's is 0.1 MB)
MAX_MANIFEST_BYTES = 50_000_000
#: the largest build record read, bytes (it holds every part's record, as the manifest does)
MAX_BUILD_RECORD_BYTES = MAX_MANIFEST_BYTES
#: the largest file of an export read (hashed, kept, re-read), bytes: the largest shop file, the
#: seed-004 machine's 3MF assembly, is some tens of MB
MAX_LISTED_FILE_BYTES = 1 << 30
#: the largest part script or design module hashed, bytes (the seed scripts are under 0.1 MB)
MAX_SCRIPT_BYTES = 10_000_000
#: the longest file or part name, bytes of UTF-8 (what Linux, macOS and Windows file systems take)
MAX_NAME_BYTES = 255
#: the longest script path a manifest records, characters
MAX_PATH_CHARS = 4096
SEAL = "manifest_sha256"
_DIGEST = re.compile(r"[0-9a-f]{64}")


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def plain_name(name: object) -> bool:
    """True for the name of a file directly inside a folder: text, not empty, ``.`` or ``..``, no
    separator, NUL or other control character, at most ``MAX_NAME_BYTES`` bytes of UTF-8."""
    if not isinstance(name, str) or name in ("", ".", "..") or "/" in name or "\\" in name:
        return False
    try:
        size = len(name.encode())
    except UnicodeEncodeError:  # a lone surrogate (JSON "\ud800"): no file has that name
        return False
    return size <= MAX_NAME_BYTES and not any(unicodedata.category(c) == "Cc" for c in name)


def script_record(script: str, modules: tuple[str, ...], data: bytes | None = None) -> dict:
    """The design a family was built from: its script and the modules beside it that it imported
    (by file name), with SHA-256 (of ``data`` for a script written with the export)."""
    if data is None:
        data = read_regular(script, "the part script", MAX_SCRIPT_BYTES, follow_links=True)
    out: dict = {"path": script, "sha256": sha256(data)}
    if modules:
        out["modules"] = {
            Path(m).name: sha256(read_regular(m, "the design module", MAX_SCRIPT_BYTES, follow_links=True))
            for m in sorted(modules)
        }
    return out


def _body(manifest: dict) -> bytes:
    return json.dumps({k: v for k, v in manifest.items() if k != SEAL}, sort_keys=True).encode()


def seal(manifest: dict) -> dict:
    """``manifest`` with its digest over everything else in it (``manifest_sha256``); the build
    record is sealed the same way."""
    return {**manifest, SEAL: sha256(_body(manifest))}


def seal_matches(manifest: dict) -> bool | None:
    """Whether the manifest is as its build sealed it (None: it carries no seal, an older build)."""
    if SEAL not in manifest:
        return None
    return manifest[SEAL] == sha256(_body(manifest))


def _read_json(path: Path, what: str, limit: int, missing_ok: bool = False):
    """The JSON value in the file ``path`` (through the one reader; None if it is missing and
    ``missing_ok``); ValueError saying what is wrong (FileRefused: not a regular file, too large,
    unreadable)."""
    data = read_regular(path, what, limit, missing_ok=missing_ok)
    if data is None:
        return None
    try:
        return json.loads(data)
    except RecursionError as exc:
        raise ValueError(f"{path.name} is nested deeper than its reader can follow") from exc
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path.name} is not UTF-8 text ({exc.reason})") from exc
    except ValueError as exc:  # JSONDecodeError; an integer of more digits than Python converts
        raise ValueError(f"{path.name} is not JSON ({str(exc).splitlines()[0][:120]})") from exc


def read_manifest(root: Path) -> dict:
    """``root/manifest.json`` read (:func:`transplanter.core.files.read_regular`: a regular file —
    not a link, FIFO or device —, at most ``MAX_MANIFEST_BYTES``) and checked against its schema
    (:func:`check_manifest`); ValueError saying what is wrong with it (a
    :class:`~transplanter.core.files.FileRefused` when it cannot be read)."""
    manifest = _read_json(root / "manifest.json", "the manifest", MAX_MANIFEST_BYTES)
    check_manifest(manifest)
    return manifest


def previous_manifest(root: Path) -> dict:
    """The current export's manifest, or {} if there is none or it is damaged (:func:`read_manifest`)."""
    try:
        return read_manifest(root)
    except (OSError, ValueError):
        return {}


# -- the schema: every field checked before it is used ------------------------------------------


def _shown(value) -> str:
    """A value from a file, quoted in a message: its repr (control characters escaped), cut short."""
    text = repr(value)
    return text if len(text) <= 60 else text[:56] + "...'"


def _json_kind(value) -> str:
    kinds = ((bool, "true/false"), (dict, "a table"), (list, "a list"), (str, "text"), ((int, float), "a number"))
    return next((said for t, said in kinds if isinstance(value, t)), "null")


def _need(ok: bool, where: str, rule: str, value) -> None:
    if not ok:
        raise ValueError(f"{where} must be {rule}, got {_json_kind(value)} {_shown(value)}")


def _digest_field(where: str, value) -> None:
    _need(isinstance(value, str) and _DIGEST.fullmatch(value) is not None, where, "a SHA-256 (64 hex digits)", value)


def _files_field(where: str, value) -> None:
    """A table of plain file names inside the folder to SHA-256 digests."""
    _need(isinstance(value, dict), where, "a table of file names to SHA-256 digests", value)
    for fname, digest in value.items():
        if not plain_name(fname):
            raise ValueError(
                f"{where} names {_shown(fname)}, not a plain file name inside the folder (it lists plain file names "
                f"only: at most {MAX_NAME_BYTES} bytes, no separator or control character; nothing outside an export "
                "is read through its manifest)"
            )
        _digest_field(f"{where}[{fname!r}]", digest)


def _script_field(where: str, value) -> None:
    _need(isinstance(value, dict), where, "a record (path, sha256, modules)", value)
    path = value.get("path")
    _need(
        isinstance(path, str) and 0 < len(path) <= MAX_PATH_CHARS and "\0" not in path,
        f"{where}.path",
        f"a path (text of 1 to {MAX_PATH_CHARS} characters)",
        path,
    )
    _digest_field(f"{where}.sha256", value.get("sha256"))
    if "modules" in value:
        _files_field(f"{where}.modules", value["modules"])


def _type_field(kind: type, rule: str):
    def check(where: str, value) -> None:
        _need(isinstance(value, kind) and (kind is not int or not isinstance(value, bool)), where, rule, value)

    return check


def _name_field(where: str, value) -> None:
    rule = f"a plain name (at most {MAX_NAME_BYTES} bytes, no separator or control character)"
    _need(plain_name(value), where, rule, value)


#: the manifest's own fields (beside ``parts``), each with its rule; other fields are not used
_MANIFEST_FIELDS = {
    "family": _name_field,
    "description": _type_field(str, "text"),
    "ok": _type_field(bool, "true or false"),
    "report": _files_field,
    "script": _script_field,
    SEAL: _digest_field,
}
#: a part record's fields, each with its rule (a study may add others; they are not used)
_PART_FIELDS = {
    "files": _files_field,
    "previous_files": _files_field,
    "error": _type_field(str, "text"),
    "kind": _type_field(str, "text"),
    "parameters": _type_field(dict, "a table"),
    "results": _type_field(dict, "a table"),
}


def check_part_record(name, record) -> None:
    """ValueError naming the field and what is wrong with it unless ``record`` is the record of a
    part named ``name``: a built part's files, or a failed part's error (and previous files)."""
    _name_field("a part name", name)
    where = f"part {name!r}"
    _need(isinstance(record, dict), where, "a record", record)
    for key, check in _PART_FIELDS.items():
        if key in record:
            check(f"{where}: {key}", record[key])
    if "files" not in record and "error" not in record:
        raise ValueError(f"{where} has neither 'files' nor 'error'")


def check_manifest(manifest) -> None:
    """ValueError naming the field and what is wrong with it if ``manifest`` is not a family
    manifest: a ``parts`` table of part records (:func:`check_part_record`), and beside it the
    family's name, description, ``ok``, ``report`` (file names to digests), ``script`` (``path``,
    ``sha256`` and ``modules``: design module file names to digests) and seal — each, when present,
    of its type, so nothing that reads a manifest meets a field it cannot use.

    >>> check_manifest({"parts": {"a": {"files": {}, "parameters": [1]}}})
    Traceback (most recent call last):
    ...
    ValueError: part 'a': parameters must be a table, got a list [1]
    """
    if not isinstance(manifest, dict) or not isinstance(manifest.get("parts"), dict):
        raise ValueError("not a family manifest: no 'parts' table")
    for key, check in _MANIFEST_FIELDS.items():
        if key in manifest:
            check(f"'{key}'", manifest[key])
    for name, record in manifest["parts"].items():
        check_part_record(name, record)


# -- what a part was built from: its key, for rebuilding only what changed ---------------------

#: the record of the last build beside a family folder (not in it: the export stays byte-identical
#: to a full rebuild): ``{"keys": {part: key}, "parts": {part: its record, as made}, "kept": [...],
#: "rebuilt": {part: why}, "unverified": {part: why}, "forced": bool}``, sealed like the manifest
BUILD_RECORD = ".{name}.build.json"


@functools.cache
def package_digest() -> str:
    """SHA-256 of the package's own code (every ``.py`` file under ``transplanter/``, by path)."""
    import transplanter

    root = Path(transplanter.__file__).resolve().parent  # (this module is two packages down: families/builder)
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


def check_build_record(record) -> None:
    """ValueError unless ``record`` is a build record (:data:`BUILD_RECORD`): ``keys`` (part name to
    its key, or null), ``parts`` (part name to its record as the manifest holds it) and a seal."""
    _need(isinstance(record, dict), "the build record", "a table", record)
    keys = record.get("keys")
    _need(isinstance(keys, dict), "the build record's keys", "a table of part names to keys", keys)
    for name, key in keys.items():
        _name_field("a part name", name)
        if key is not None:
            _digest_field(f"the key of {name!r}", key)
    _need(isinstance(record.get("parts"), dict), "the build record's parts", "a table", record.get("parts"))
    for name, rec in record["parts"].items():
        check_part_record(name, rec)
    _digest_field("the build record's seal", record.get(SEAL))


def read_build_record(root: Path) -> tuple[dict, str]:
    """The record of the last build of the family folder ``root`` and what is wrong with it: ``({},
    "")`` when there is none (or one of an older build, which recorded no parts); ``({}, why)``
    when it cannot be read, is not a build record or its seal does not verify."""
    path = root.parent / BUILD_RECORD.format(name=root.name)
    try:
        record = _read_json(path, "the build record", MAX_BUILD_RECORD_BYTES, missing_ok=True)
        if record is None or (isinstance(record, dict) and "parts" not in record):
            return {}, ""  # none, or an older build's record: it says nothing of what was made
        check_build_record(record)
    except FileRefused as exc:
        return {}, str(exc)
    except ValueError as exc:
        return {}, f"{path.name} is damaged ({exc})"
    if not seal_matches(record):
        return {}, f"{path.name} was edited since the build (its seal differs)"
    return record, ""


def listed_file(root: Path, name: str, digest: str) -> tuple[bytes | None, str]:
    """A file a manifest lists, as found in ``root``, read once (the one reader: a regular file,
    not a link, at most ``MAX_LISTED_FILE_BYTES``): its bytes (None when they cannot be had) and
    what is wrong with it ("" when nothing) — missing, a link (not followed), not a regular file,
    unreadable, or bytes that are not the listed digest's."""
    try:
        data = read_regular(root / name, name, MAX_LISTED_FILE_BYTES, missing_ok=True)
    except FileRefused as exc:
        return None, exc.reason
    if data is None:
        return None, "missing"
    return data, "" if sha256(data) == digest else "changed since the build (SHA-256 differs)"
