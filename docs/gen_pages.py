"""Append to two hand-written pages what the source says, so they cannot go stale (mkdocs-gen-files).

Run by ``mkdocs build`` (the ``gen-files`` plugin in ``mkdocs.yml``), never by hand:

- ``layout.md`` gets every module of ``src/transplanter``, station by station, with the modules of
  its own station that it imports (read from the source with :mod:`ast`, as ``tests/test_layout.py``
  reads them) and the first sentence of its docstring, linked to its API page;
- ``cli.md`` gets every command's ``--help``, from the installed ``transplanter`` command itself.
"""

from __future__ import annotations

import ast
import contextlib
import io
import re
from pathlib import Path

import mkdocs_gen_files

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "src" / "transplanter"
#: the stations, lowest first (as ``tests/test_layout.py`` orders them)
STATIONS = (
    "core",
    "geometry",
    "design",
    "shop",
    "proof",
    "machine",
    "report",
    "families.builder",
    "families.pairs",
    "families.mechanisms",
    "families.machines",
    "families",
    "app",
)


def modules() -> dict[str, Path]:
    """Every public module, by its dotted name below ``transplanter`` (a package by its own name)."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if not parts or any(p.startswith("_") for p in parts):
            continue
        found[".".join(parts)] = path
    return found


def station(name: str) -> str:
    return max((s for s in STATIONS if name == s or name.startswith(s + ".")), key=len, default="")


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The modules of the package that ``name`` imports (dotted below ``transplanter``)."""
    found = set()
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name.removeprefix("transplanter.") for a in node.names if a.name.startswith("transplanter.")]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1] if package else []
                module = ".".join([*base, *([node.module] if node.module else [])])
            elif (node.module or "").startswith("transplanter."):
                module = node.module.removeprefix("transplanter.")
            else:
                continue
            targets = [f"{module}.{a.name}" if f"{module}.{a.name}" in known else module for a in node.names]
        else:
            continue
        found |= {t for t in targets if t in known and t != name}
    return found


def summary(path: Path) -> str:
    """The first sentence of a module's docstring, its reStructuredText roles made plain."""
    doc = ast.get_docstring(ast.parse(path.read_text())) or ""
    text = " ".join(doc.split("\n\n")[0].split())
    text = re.sub(r":[a-z]+:`~?(?:[\w.]+\.)?([^`<]+?)`", r"`\1`", text)
    text = text.replace("``", "`").replace("|", "\\|")
    first = re.match(r"(.+?\.)(\s|$)", text)
    text = first.group(1) if first else text
    if len(text) > 240:
        text = text[:239].rsplit(" ", 1)[0] + ("`" if text[:239].rsplit(" ", 1)[0].count("`") % 2 else "") + " …"
    return text or "—"


def layout_table() -> str:
    known = modules()
    lines = [
        "",
        "## Every module, from the source",
        "",
        "Generated from the source on every build of this site (`docs/gen_pages.py`): each module of each",
        "station, the modules of its own station it imports, and the first sentence of its docstring.",
        "",
    ]
    for st in STATIONS:
        names = [n for n in known if station(n) == st and n != st]
        if not names:
            continue
        lines += [f"### {st}", "", "| Module | Imports from its station | What it holds |", "| --- | --- | --- |"]
        for name in names:
            page = "/".join(name.split(".")) + ("/index.md" if known[name].name == "__init__.py" else ".md")
            deps = sorted(d.removeprefix(st + ".") for d in imports(name, known[name], known) if station(d) == st)
            short = name.removeprefix(st + ".")
            lines.append(
                f"| [`{short}`](reference/transplanter/{page}) | {', '.join(f'`{d}`' for d in deps) or '—'} | "
                f"{summary(known[name])} |"
            )
        lines.append("")
    return "\n".join(lines)


def cli_help() -> str:
    from transplanter.app.cli import main

    def helptext(*argv: str) -> str:
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.suppress(SystemExit):
            main([*argv, "--help"])
        return out.getvalue().rstrip()

    top = helptext()
    commands = re.search(r"\{([^}]*)\}", top).group(1).split(",")
    aliases = {"analyze": "analyse", "optimize": "optimise"}
    lines = ["", "## Every option", "", "From each command's own `--help` (generated by `docs/gen_pages.py`).", ""]
    lines += ["```text", top, "```", ""]
    for command in commands:
        if command in aliases:
            continue
        lines += [f"### transplanter {command}", "", "```text", helptext(command), "```", ""]
    return "\n".join(lines)


with mkdocs_gen_files.open("layout.md", "a") as fd:
    fd.write(layout_table())
with mkdocs_gen_files.open("cli.md", "a") as fd:
    fd.write(cli_help())
