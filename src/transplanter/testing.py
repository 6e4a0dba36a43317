"""Helpers for tests of exported files (like ``shapely.testing``)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

__all__ = ["admesh_available", "assert_admesh_clean"]

_CLEAN = (
    "Number of parts       :     1",
    "Total disconnected facets        :     0",
    "Degenerate facets     :     0",
    "Facets reversed       :     0",
    "Backwards edges       :     0",
)


def admesh_available() -> bool:
    """True when Debian's admesh (an independent STL checker) is on the PATH."""
    return shutil.which("admesh") is not None


def assert_admesh_clean(path: str | Path) -> None:
    """Run admesh on an STL: one part, nothing disconnected, degenerate, reversed or backwards."""
    out = subprocess.run(["admesh", str(path)], capture_output=True, text=True, check=True).stdout
    for line in _CLEAN:
        assert line in out, f"{Path(path).name}: admesh does not report {line!r}"
