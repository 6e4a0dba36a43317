"""The exports a shop receives are byte-identical to the recorded ones.

A refactor (issue 28 moved the gear pair's journey into stations and split ``teeth``) must not
change one byte of a DXF, STL, STEP, 3MF, CSV or JSON: ``golden/exports.sha256`` holds the
SHA-256 of each, recorded from the default build before the change. A manifest is compared
without its ``script`` entry (the digests of the part scripts, which a refactor of their imports
changes by design), its seal (``manifest_sha256``, which covers them) and the digests it lists of
figures and reports (PNG, SVG, GIF, HTML): their bytes follow the matplotlib version and the
report's layout, not the design, and are left to the golden records.

A change that *means* to change an export rewrites the record with ``pytest --update-golden``
and says why in its commit.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

RECORD = Path(__file__).parent / "golden" / "exports.sha256"
#: the files whose bytes are the design: shop files and data
COMPARED = {".dxf", ".stl", ".step", ".3mf", ".csv", ".json"}
#: what a manifest lists that is a picture or a page (compared by the golden records, not here)
PICTURES = (".png", ".svg", ".gif", ".html")


def _design_of(manifest: dict) -> dict:
    """A manifest less what a refactor or a report's layout changes by design (module docstring)."""
    manifest = {k: v for k, v in manifest.items() if k not in ("script", "manifest_sha256", "report")}
    parts = manifest.get("parts")
    if isinstance(parts, dict):
        manifest["parts"] = {
            name: {
                **record,
                "files": {f: d for f, d in record.get("files", {}).items() if not f.endswith(PICTURES)},
            }
            if isinstance(record, dict)
            else record
            for name, record in parts.items()
        }
    return manifest


def export_digests(folder: Path) -> dict[str, str]:
    """``{family/file: sha256}`` of the compared files under ``folder`` (a build's output)."""
    out = {}
    for path in sorted(folder.rglob("*")):
        if path.suffix not in COMPARED or not path.is_file() or path.relative_to(folder).parts[0].startswith("."):
            continue  # the build's own records beside the families (.<family>.build.json) are no export
        data = path.read_bytes()
        if path.name == "manifest.json":
            data = json.dumps(_design_of(json.loads(data)), sort_keys=True).encode()
        out[path.relative_to(folder).as_posix()] = hashlib.sha256(data).hexdigest()
    return out


def test_exports_are_byte_identical_to_the_record(built, request):
    found = export_digests(built)
    if request.config.getoption("--update-golden"):
        RECORD.write_text("".join(f"{digest}  {name}\n" for name, digest in found.items()))
        return
    recorded = dict(line.split("  ")[::-1] for line in RECORD.read_text().splitlines())
    assert len(recorded) > 150  # every family's shop files, not an empty record
    changed = sorted(n for n in recorded.keys() & found.keys() if recorded[n] != found[n])
    assert not changed, f"{len(changed)} exports changed: {changed[:8]}"
    assert sorted(found.keys() - recorded.keys()) == [] and sorted(recorded.keys() - found.keys()) == []
