"""Make parts from the page: the design on the page written where the part script reads it — the
tuple ``Problem(optimum=...)`` names, by the in-place writer of ``transplanter optimise --write``
(:func:`transplanter.families.builder.optimum.rewritten`: only its numbers, checked by reading them
back), shown first as a diff — then ``transplanter build`` of the script named on the command
line, in the background, its progress (a line per part, its proofs and findings) streamed to the
page. Nothing else is run.
"""

from __future__ import annotations

import difflib
import html
import subprocess
import sys
import threading
import urllib.parse
from functools import partial
from pathlib import Path

from transplanter.core.errors import TransplanterError

__all__ = ["making_panel"]

#: said beside every diff: what the page judged, and what only the build proves
CAVEAT = (
    "<p><i>The page judged this design with its view; where the view's slow judgement is the build's own "
    "(seed 004: \u201cas the build makes it\u201d \u2014 the teeth cut, the objectives the build refuses a "
    "miss of), it says whether the build would refuse it. The build also proves the made parts (meshing, "
    "backlash, the machine's clearances), which the page does not: its report says why it refused. Writing "
    "the design changes the file; undo does not.</i></p>"
)
#: lines of the build's output the page keeps (the last ones)
SHOWN_LINES = 40


def _diff(module, new_text: str) -> str:
    lines = difflib.unified_diff(
        module.text.splitlines(keepends=True),
        new_text.splitlines(keepends=True),
        fromfile=str(module.path),
        tofile=f"{module.path} (this design)",
        n=1,
    )
    return "".join(lines)


def _links(lines: list[str], output: Path) -> str:
    """Links (served under ``/files/``) to the reports the build's last lines name inside ``output``."""
    out = []
    root = output.resolve()
    for line in lines:
        if "reports: " not in line:
            continue
        for name in line.split("reports: ", 1)[1].strip().split(", "):
            try:
                rel = Path(name).resolve().relative_to(root)
            except ValueError:
                continue
            out.append(
                f'<a href="/files/{urllib.parse.quote(rel.as_posix())}" target="_blank">{html.escape(str(rel))}</a>'
            )
    return "<p>the report: " + ", ".join(out) + "</p>" if out else ""


def making_panel(doc, session, script: Path, design_file: Path | None, output: Path):
    """The "make parts" widgets for ``doc``: a diff of the design file, then write and build."""
    from bokeh.layouts import column, row
    from bokeh.models import Button, Div

    from transplanter.families.builder.optimum import find_optimum, module_file, record_optimum, rewritten

    problem = session.problem
    show = Button(label="make parts…", name="make-show", width=110)
    go = Button(label="write and build", name="make-go", width=130, disabled=True, button_type="warning")
    said = Div(text="", name="make-progress", width=330, styles={"font-size": "12px"})
    held: dict = {"place": None, "x": None, "thread": None}
    choices = tuple(name in problem.choices for name, _, _ in problem.variables)

    def where():
        if problem.optimum is None or design_file is None:
            raise TransplanterError(
                f"problem {problem.name!r} names no tuple the part script reads (Problem(optimum=...)): "
                "nothing to write"
            )
        return find_optimum(module_file(design_file), problem.optimum, len(problem.variables))

    def on_show() -> None:
        try:
            place = where()
            new = rewritten(place, session.x, choices)
        except TransplanterError as exc:
            said.text = f'<b style="color:#b00020">{html.escape(str(exc))}</b>'
            return
        held["place"], held["x"] = place, session.x
        go.disabled = False
        if new is None:
            said.text = f"{html.escape(problem.optimum)} in {html.escape(str(design_file))} holds this design: build it"
            return
        text = _diff(*new)
        said.text = f"<pre style='font-size:11px;max-height:260px;overflow:auto'>{html.escape(text)}</pre>" + CAVEAT

    def lines_to_page(lines: list[str], links: str = "") -> None:
        said.text = "<pre style='font-size:11px'>" + html.escape("".join(lines[-SHOWN_LINES:])) + "</pre>" + links

    def build() -> None:
        cmd = [sys.executable, "-m", "transplanter", "build", str(script), "-o", str(output)]
        lines: list[str] = []
        with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace") as p:
            assert p.stdout is not None
            for line in p.stdout:
                lines.append(line)
                doc.add_next_tick_callback(partial(lines_to_page, list(lines)))
            code = p.wait()
        verdict = "built" if code == 0 else f"the build failed (exit status {code})"
        lines.append(f"{verdict}: {output}\n")
        doc.add_next_tick_callback(partial(lines_to_page, lines, _links(lines, output)))
        doc.add_next_tick_callback(partial(setattr, go, "disabled", False))

    def on_go() -> None:
        if held["thread"] is not None and held["thread"].is_alive():
            return
        if held["x"] != session.x:  # the design moved since its diff was shown
            said.text = "the design changed since its diff: show it again"
            go.disabled = True
            return
        try:
            target = record_optimum(held["place"], session.x, choices)
        except TransplanterError as exc:
            said.text = f'<b style="color:#b00020">{html.escape(str(exc))}</b>'
            return
        go.disabled = True
        said.text = html.escape(f"written to {target}; building…" if target else "building…")
        held["thread"] = threading.Thread(target=build, daemon=True)
        held["thread"].start()

    show.on_click(on_show)
    go.on_click(on_go)
    return column(Div(text="<b>make parts</b>", width=330), row(show, go), said)
