"""The package's stations and its import graph, read from the source (nothing is imported or run).

One reader for the layout test (``tests/test_layout.py`` holds the layers) and the documentation's
module table (``docs/gen_pages.py`` loads this file by its path): the stations and what each module
imports are stated once.
"""

from __future__ import annotations

import ast
from pathlib import Path

__all__ = ["LAYERS", "MODULES", "SRC", "imports", "modules"]

SRC = Path(__file__).resolve().parents[1] / "src" / "transplanter"

#: the stations, lowest first: a module imports only from its own station or one below it (the
#: package ``__init__`` docstrings say the same; docs/layout.md draws it). An entry names a package
#: (every module under it) or a module; the longest entry that contains a module is its layer.
LAYERS = (
    ("core",),
    ("geometry",),
    ("design",),
    ("shop",),
    ("proof",),
    ("machine",),
    ("report",),
    ("families.builder",),
    ("families.pairs", "families.mechanisms"),
    ("families.machines",),
    ("families",),
    ("app", "__init__", "__main__"),
)

def modules() -> dict[str, Path]:
    return {
        ".".join(p.relative_to(SRC).with_suffix("").parts): p
        for p in sorted(SRC.rglob("*.py"))
        if "egg-info" not in str(p)
    }


MODULES = modules()


def imports(name: str, path: Path) -> tuple[set[str], set[str]]:
    """(project modules, outside top-level packages) that ``name`` imports."""
    tree = ast.parse(path.read_text())
    inner, outer = set(), set()
    package = name.rsplit(".", 1)[0] if "." in name and not path.name == "__init__.py" else name
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                (inner if a.name.startswith("transplanter") else outer).add(a.name)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                mod = ".".join(["transplanter", *base, *([node.module] if node.module else [])])
            else:
                mod = node.module or ""
            if not mod.startswith("transplanter"):
                outer.add(mod)
                continue
            for a in node.names:  # `from transplanter import dxf` imports the module dxf
                sub = f"{mod}.{a.name}"
                inner.add(sub if sub.removeprefix("transplanter.") in MODULES else mod)
    inner = {m.removeprefix("transplanter.").removeprefix("transplanter") for m in inner}
    return {m for m in inner if m}, {m.split(".")[0] for m in outer}
