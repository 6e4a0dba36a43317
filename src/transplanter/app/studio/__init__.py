"""``transplanter design PART_SCRIPT``: the design studio — seed 004's live design software, open,
in the browser, for any part script whose ``problem()`` declares its variables.

A slider and a number box per variable; on every change the problem's ``view`` (the tip's path in
the frame and on the ground with the box, tray and soil, the arm's attitude, the pitch curves, the
mechanism at a crank angle one scrubs or plays, the objectives coloured by their margins) is
recomputed by the library and redrawn; its slow judgement (under play) follows. Built on Bokeh's
server (:mod:`.server`: loopback, a token in the URL); the page is :mod:`.page`, the design
state :mod:`.session`.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from transplanter.core.errors import SpecError, TransplanterError

__all__ = ["designable", "named_designs", "run"]


def named_designs(problem, names: dict) -> dict[str, tuple[float, ...]]:
    """The module-level designs beside ``problem()`` (UPPER_CASE tuples of as many numbers as it has
    variables, each within its range): the studio's "start from" menu."""
    out = {}
    for name, value in sorted(names.items()):
        if not (name.isupper() and isinstance(value, tuple) and len(value) == len(problem.variables)):
            continue
        if all(
            isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) and lo <= v <= hi
            for v, (_, lo, hi) in zip(value, problem.variables, strict=True)
        ):
            out[name] = tuple(float(v) for v in value)
    return out


def designable(folder: Path) -> list[Path]:
    """The part scripts in ``folder`` (not ``_``-prefixed) that define or import ``problem`` at
    their top level, read as syntax only: nothing in them is run to list them."""
    import ast

    from transplanter.core import inputs

    out = []
    for path in sorted(Path(folder).glob("*.py")):
        if path.name.startswith("_") or path.is_symlink() or not path.is_file():
            continue
        try:
            tree = ast.parse(inputs.read_data_file("part script", path, 10_000_000))
        except (TransplanterError, SyntaxError, ValueError):
            continue
        for node in tree.body:
            names = [node.name] if isinstance(node, ast.FunctionDef) else []
            if isinstance(node, ast.ImportFrom | ast.Import):
                names = [a.asname or a.name for a in node.names]
            if "problem" in names:
                out.append(path)
                break
    return out


def _opening(problem, designs: dict, start: str | None) -> tuple[float, ...]:
    """The design the page opens on: ``--start``'s, the problem's ``design``, its ``x0``, the middle."""
    if start is not None:
        if start not in designs:
            raise SpecError.out_of_range("--start", start, f"one of {', '.join(designs) or '(none in the script)'}")
        return designs[start]
    if problem.design is not None:
        return tuple(problem.design)
    if problem.x0 is not None:
        return tuple(problem.x0)
    return tuple(0.5 * (lo + hi) for _, lo, hi in problem.variables)


def _stamp(*paths: Path | None) -> tuple:
    """What says a file changed: each path's modification time and size (None: gone)."""
    out = []
    for p in paths:
        try:
            s = p.stat() if p is not None else None
        except OSError:
            s = None
        out.append(None if s is None else (s.st_mtime_ns, s.st_size))
    return tuple(out)


def _page_maker(args: argparse.Namespace, script: Path, settings: dict, start: str | None):
    """``make_document(doc)`` for ``script``'s page: the script loaded at its first use, and again
    for a new page once it or the file its ``problem()`` is in has changed (a design written by
    "make parts", an edit): a new page opens on what the files hold. A script that no longer
    loads is said on the page."""
    import html

    from bokeh.models import Div

    from transplanter.app.optimise import script_problem
    from transplanter.app.studio.later import ScriptJudge
    from transplanter.app.studio.page import build_page

    loaded: dict = {}

    def load() -> None:
        problem, names = script_problem(script, settings, args.timeout)
        designs = named_designs(problem, names)
        where = names.get("__file__")
        design_file = Path(where) if isinstance(where, str) else None
        loaded.update(
            problem=problem,
            designs=designs,
            start=_opening(problem, designs, start),
            making=(script, design_file, Path(args.output)),
            judge=loaded.get("judge") or ScriptJudge(script, settings, args.timeout),
            stamp=_stamp(script, design_file),
        )

    def make(doc) -> None:
        try:
            if not loaded or _stamp(script, loaded["making"][1]) != loaded["stamp"]:
                load()
        except TransplanterError as exc:
            if doc is None:
                raise
            doc.add_root(Div(text=f'<b style="color:#b00020">{html.escape(str(exc))}</b>'))
            return
        if doc is None:
            return
        title = f"{script.name}: {loaded['problem'].name}"
        build_page(
            doc,
            loaded["problem"],
            loaded["start"],
            loaded["designs"],
            title,
            args.workers,
            args.scheduler,
            loaded["making"],
            loaded["judge"],
        )

    return make


def _chooser(scripts: list[Path]):
    """The page at ``/`` when no script is named: a link to each designable script's page."""
    import html

    def make(doc) -> None:
        from bokeh.models import Div

        items = "".join(f'<li><a href="/{s.stem}">{html.escape(s.name)}</a></li>' for s in scripts)
        doc.add_root(Div(text=f"<h3>transplanter design</h3><p>Part scripts with a problem():</p><ul>{items}</ul>"))
        doc.title = "transplanter design"

    return make


def run(args: argparse.Namespace) -> int:
    """Serve the studio for ``args.script`` (or every designable script of ``args.parts``, from a
    page at ``/``) until interrupted; the exit status."""
    from transplanter.app.optimise import settings_of
    from transplanter.app.studio.server import serve

    settings = settings_of(args.set or [])
    if args.script is not None:
        make = _page_maker(args, Path(args.script), settings, args.start)
        make(None)  # loaded now: a script that cannot load, or a --start it lacks, is said before serving
        apps = {"/": make}
    else:
        scripts = designable(Path(args.parts))
        if not scripts:
            raise SpecError(f"--parts {args.parts}: no part script there defines or imports problem()")
        apps = {"/": _chooser(scripts)}
        apps.update({f"/{s.stem}": _page_maker(args, s, settings, None) for s in scripts})
    serve(apps, host=args.host, port=args.port, open_browser=not args.no_browser, files=Path(args.output))
    return 0
