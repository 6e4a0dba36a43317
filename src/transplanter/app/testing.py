"""Helpers for tests of exported files (like ``shapely.testing``)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

__all__ = ["SQUARE_SCRIPT", "admesh_available", "assert_admesh_clean"]

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


#: the smallest part script with a study of its own kind (a square plate: ``sq.txt``, its area; a
#: check that re-reads it), for tests of what the builder and ``check`` do with any family
SQUARE_SCRIPT = """
from dataclasses import dataclass

from transplanter.families import Built, Checked, Family, StudyDefaults


@dataclass(frozen=True)
class Square(StudyDefaults):
    name: str
    side: float
    cost = 1

    def build(self, out):
        data = f"{self.side ** 2:.6f}\\n".encode()
        return Built({"kind": "square", "parameters": {"side": self.side}, "results": {"area": self.side ** 2}},
                     {f"{self.name}.txt": data})

    def check(self, files):
        area = float(files[f"{self.name}.txt"])
        return Checked({"area": area}, [] if area == self.side ** 2 else [f"area {area}"])


def family():
    return Family("squares", "a square", (Square("sq", 3.0),))
"""
