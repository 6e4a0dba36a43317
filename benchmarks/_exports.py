"""What the machine benchmarks share: a build to read, and a study's files from it."""

import json
import sys
import tempfile
from pathlib import Path


def built(families) -> Path:
    """The exports folder named on the command line, or a temporary one ``families`` are built into."""
    from transplanter.families import build_family

    named = [a for a in sys.argv[1:] if not a.startswith("--")]
    if named:
        return Path(named[0])
    out = Path(tempfile.mkdtemp())
    for fam in families:
        build_family(fam, out)
    return out


def study_files(root: Path, study) -> dict[str, bytes]:
    """The files ``study`` reads from its family's folder ``root``: its own and its ``uses``'."""
    manifest = json.loads((root / "manifest.json").read_text())
    files = {}
    for name in (*study.uses, study.name):
        files.update({f: (root / f).read_bytes() for f in manifest["parts"][name]["files"]})
    return files
