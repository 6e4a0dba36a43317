"""A family's manifest: what a build records of its script, parts and files (SHA-256 each), and
the check that a manifest read from disk has that shape before anything trusts it."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

__all__ = ["check_manifest", "previous_manifest", "script_record", "sha256"]


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def script_record(script: str, modules: tuple[str, ...]) -> dict:
    """The design a family was built from: its script and the modules beside it that it imported
    (by file name), with SHA-256."""
    out: dict = {"path": script, "sha256": sha256(Path(script).read_bytes())}
    if modules:
        out["modules"] = {Path(m).name: sha256(Path(m).read_bytes()) for m in sorted(modules)}
    return out


def previous_manifest(root: Path) -> dict:
    """The current export's manifest, or {} if there is none or it is damaged (``_check_manifest``)."""
    try:
        data = json.loads((root / "manifest.json").read_text())
        check_manifest(data)
    except (OSError, ValueError):
        return {}
    return data


def check_manifest(manifest) -> None:
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
