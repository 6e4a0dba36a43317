"""The exports a shop receives are byte-identical to the recorded ones.

A refactor (issue 28 moved the gear pair's journey into stations and split ``teeth``) must not
change one byte of a DXF, STL, STEP, 3MF, CSV or JSON: ``golden/exports.sha256`` holds the
SHA-256 of each, recorded from the default build before the change. A manifest is compared
without its ``script`` entry (the digests of the part scripts, which a refactor of their imports
changes by design) and its seal (``manifest_sha256``, which covers them); figures and reports
(PNG, SVG, HTML) are left to the golden records — their bytes follow the matplotlib version, not
the design.

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


def export_digests(folder: Path) -> dict[str, str]:
    """``{family/file: sha256}`` of the compared files under ``folder`` (a build's output)."""
    out = {}
    for path in sorted(folder.rglob("*")):
        if path.suffix not in COMPARED or not path.is_file() or path.relative_to(folder).parts[0].startswith("."):
            continue  # the build's own records beside the families (.<family>.build.json) are no export
        data = path.read_bytes()
        if path.name == "manifest.json":
            manifest = json.loads(data)
            manifest.pop("script", None)
            manifest.pop("manifest_sha256", None)  # its seal covers the script's digest too
            data = json.dumps(manifest, sort_keys=True).encode()
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
