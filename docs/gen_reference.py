"""Write the API reference: one page per public module of ``src/transplanter`` (mkdocs-gen-files).

Run by ``mkdocs build`` (the ``gen-files`` plugin in ``mkdocs.yml``), never by hand. The pages are
found by walking the package tree, so a module added or moved gets its page with no list to keep:
every ``*.py`` under ``src/transplanter`` whose name and whose packages' names do not start with an
underscore (``__init__.py`` gives its package's page; ``__main__.py`` is left out). A package's page
shows its docstring (what the station takes, gives and may import) and links to its modules; a
module's page shows everything mkdocstrings finds in it (numpy docstrings). The navigation of the
section is written to ``reference/SUMMARY.md`` for mkdocs-literate-nav.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import mkdocs_gen_files

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"


def _layout_graph():
    """``tests/layout_graph.py``, loaded by its path: the package's modules as the layout test reads them."""
    spec = importlib.util.spec_from_file_location("layout_graph", ROOT / "tests" / "layout_graph.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def public_modules() -> list[tuple[str, ...]]:
    """Dotted parts of every public module and package, sorted so a package precedes its modules."""
    found = []
    for name in _layout_graph().MODULES:
        parts = ("transplanter", *name.split("."))
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if any(p.startswith("_") for p in parts):
            continue
        found.append(parts)
    return sorted(set(found))


def page(parts: tuple[str, ...], is_package: bool) -> Path:
    """The reference page of a module: ``reference/transplanter/geometry/teeth.md``; a package's is
    its folder's ``index.md``."""
    return Path("reference", *parts, "index.md") if is_package else Path("reference", *parts).with_suffix(".md")


modules = public_modules()
packages = {p for p in modules if (SRC.joinpath(*p) / "__init__.py").exists()}
nav = mkdocs_gen_files.Nav()
lines = [
    "# API reference",
    "",
    "Generated from the docstrings (numpy style) of every public module, by `docs/gen_reference.py`.",
    "The packages are the stations a part passes through, lowest first (see [Stations](../stations/index.md)).",
    "",
]
for parts in modules:
    is_package = parts in packages
    target = page(parts, is_package)
    name = ".".join(parts)
    nav[parts] = target.relative_to("reference").as_posix()
    depth = len(parts) - 1
    lines.append(f"{'    ' * depth}- [`{name}`]({target.relative_to('reference').as_posix()})")
    with mkdocs_gen_files.open(target, "w") as fd:
        fd.write(f"# `{name}`\n\n")
        if is_package:
            # the package's docstring only: its names are documented on their modules' pages
            fd.write(f"::: {name}\n    options:\n      members: false\n      show_root_heading: false\n\n")
            children = [c for c in modules if len(c) == len(parts) + 1 and c[: len(parts)] == parts]
            if children:
                fd.write("## Modules\n\n")
                for child in children:
                    link = page(child, child in packages).relative_to(target.parent).as_posix()
                    fd.write(f"- [`{'.'.join(child)}`]({link})\n")
        else:
            fd.write(f"::: {name}\n    options:\n      show_root_heading: false\n")
    source = SRC.joinpath(*parts) / "__init__.py" if is_package else SRC.joinpath(*parts).with_suffix(".py")
    mkdocs_gen_files.set_edit_path(target, source.relative_to(ROOT))

with mkdocs_gen_files.open("reference/index.md", "w") as fd:
    fd.write("\n".join(lines) + "\n")
with mkdocs_gen_files.open("reference/SUMMARY.md", "w") as fd:
    fd.write("* [Overview](index.md)\n")
    fd.writelines(nav.build_literate_nav())
