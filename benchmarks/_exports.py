"""What the benchmarks share: transplanter's modules compiled as an installed copy has them, a
build to read, and a study's files from it."""

import compileall
import json
import sys
import tempfile
from pathlib import Path


def as_installed() -> None:
    """transplanter's modules byte-compiled, as ``pip install .`` leaves them (it compiles every
    module it installs), before a benchmark times processes that import them.

    Run from a source checkout (an editable install) in an environment with
    ``PYTHONDONTWRITEBYTECODE`` set, as this project's development machines have it, no ``.pyc``
    is ever written: every process — the command timed, each of its forks' imports, each search
    worker — compiled transplanter's ~250 modules from source again (0.1-0.2 s of CPU per process,
    not spent by a user's install nor by the peer's, installed from PyPI). Only stale or missing
    files are written, under the checkout's ``__pycache__`` folders (ignored by git)."""
    import transplanter

    for folder in transplanter.__path__:
        compileall.compile_dir(folder, quiet=1)


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
