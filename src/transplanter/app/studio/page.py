"""The studio's page: a Bokeh document for one problem (one per browser tab).

Left, a slider and a number box per design variable, the error beside it, undo/redo, the named
designs of the part script, save and load. Right, the view's panels (Bokeh figures: a curve per
:class:`~transplanter.design.views.Curve`, obstacles filled grey), the crank-angle scrubber and
its play button (the poses are all in the browser: scrubbing asks nothing of the server), the
objectives table and, once the slow judgement is in, its table.

A change is coalesced: while one design is computed the later changes only replace the design to
compute next, so a dragged slider never queues a backlog. The slow judgement (``later``) runs on a
worker thread and is shown only if its design is still the one on the page.
"""

from __future__ import annotations

import base64
import html
import itertools
import time
from collections.abc import Callable
from functools import partial

from transplanter.app.studio.later import judge_later
from transplanter.app.studio.making import making_panel
from transplanter.app.studio.plots import SLOTS, Drawing
from transplanter.app.studio.search import search_panel
from transplanter.app.studio.session import Computed, Session
from transplanter.core.errors import TransplanterError
from transplanter.design.views import Row

__all__ = ["LATER_AFTER_MS", "build_page", "rows_html"]

#: the slow judgement (:mod:`.later`, a forked child) starts this long after its design is drawn
#: (ms), and only if no other design has been asked for since: the drawing's messages go out
#: first, and while a slider is dragged no child is forked for designs already gone
LATER_AFTER_MS = 250

#: "save design": the server's ``Session.saved()`` (the one writer of the format) arrives in the
#: button's tags (with a count, so saving the same design twice downloads it twice) and is downloaded
_SAVE_JS = """
const blob = new Blob([save.tags[1]], {type: 'application/json'});
const a = document.createElement('a');
a.href = URL.createObjectURL(blob); a.download = 'design.json'; a.click();
"""


def rows_html(rows: tuple[Row, ...], name: str, against: tuple[Row, ...] = ()) -> str:
    """The objectives as an HTML table (text escaped), a row green when met, red when not; each
    row's value in full precision in ``data-value`` (what a test reads back). With ``against`` (the
    pinned design B's rows): B's value and the difference, by objective."""
    other = {r.name: r for r in against}
    extra = "<th>B</th><th>this - B</th>" if against else ""
    out = [
        f'<table class="objectives" id="{name}" style="border-collapse:collapse;font-size:13px">',
        f"<tr><th align=left>objective</th><th>value</th><th>limit</th><th>margin</th><th></th>{extra}</tr>",
    ]
    for r in rows:
        colour = "#e3f4e3" if r.ok else "#f9dddd"
        b = other.get(r.name)
        more = ""
        if against:
            more = "<td></td><td></td>" if b is None else f"<td align=right>{b.value:.4g}</td>"
            more += "" if b is None else f"<td align=right>{r.value - b.value:+.3g}</td>"
        out.append(
            f'<tr style="background:{colour}" data-name="{html.escape(r.name)}" data-value="{r.value!r}" '
            f'data-ok="{int(r.ok)}"><td>{html.escape(r.name)}</td>'
            f"<td align=right>{r.value:.4g} {html.escape(r.unit)}</td><td>{html.escape(r.limit)}</td>"
            f"<td align=right>{r.margin:+.3g}</td><td>{'pass' if r.ok else 'FAIL'}</td>{more}</tr>"
        )
    out.append("</table>")
    return "".join(out)


#: the page: the controls on the left, the drawing and what is judged of it on the right
_TEMPLATE_TEXT = """{% extends base %}
{% block contents %}
<div style="display: flex; align-items: flex-start; gap: 8px">
  <div>{{ embed(roots.controls) }}</div>
  <div>
    <div style="display: grid; grid-template-columns: auto auto; align-items: start">
      {% for i in range(slots) %}<div>{{ embed(roots["slot%d" % i]) }}</div>{% endfor %}
    </div>
    {{ embed(roots.drawing) }}{{ embed(roots.judged) }}
  </div>
</div>
{% endblock %}
"""


def _template():
    from jinja2 import Template

    return Template(_TEMPLATE_TEXT.replace("range(slots)", f"range({SLOTS})"))


def build_page(
    doc,
    problem,
    start,
    designs: dict[str, tuple[float, ...]],
    title: str,
    workers: int = 1,
    scheduler: str | None = None,
    making: tuple | None = None,
    judge: Callable | None = None,
) -> None:
    """Fill Bokeh document ``doc`` with the studio for ``problem``, opening on design ``start``;
    ``designs``: the part script's named designs (a menu); ``workers``/``scheduler``: where its
    searches evaluate designs (:mod:`.search`); ``making``: (part script, the file ``problem()``
    is in, the build's output folder) for "make parts" (:mod:`.making`); ``judge(x, later, done)``:
    where a design's slow judgement runs (:class:`.later.ScriptJudge`; by default
    :func:`.later.judge_later`, a fork of the server)."""
    from bokeh.layouts import column, row
    from bokeh.models import (
        Button,
        CustomJS,
        Div,
        FileInput,
        Select,
        Slider,
        TextInput,
    )

    session = Session(problem, start)
    judge = judge or (lambda x, later, done: judge_later(later, done))
    names = session.names
    bounds = {n: (lo, hi) for n, lo, hi in problem.variables}
    sliders, boxes, errors = {}, {}, {}
    for n in names:
        lo, hi = bounds[n]
        sliders[n] = Slider(
            start=lo,
            end=hi,
            value=session.x[names.index(n)],
            step=(hi - lo) / 1000,
            title=f"{n}",
            name=f"slider-{n}",
            width=230,
            show_value=False,
        )
        boxes[n] = TextInput(value=f"{session.x[names.index(n)]:.6g}", name=f"box-{n}", width=95)
        errors[n] = Div(text="", name=f"error-{n}", styles={"color": "#b00020", "font-size": "12px"}, width=330)
    # one Div for the notes and both tables: every model changed is a message and, for a Div, a
    # layout of the page in the browser
    load_said = Div(text="", name="error-load", styles={"color": "#b00020", "font-size": "12px"}, width=330)
    results = Div(text="", name="results", width=900)
    undo, redo = Button(label="undo", name="undo", width=70), Button(label="redo", name="redo", width=70)
    save = Button(label="save design", name="save", width=100)
    pin = Button(label="pin as B", name="pin", width=80)
    load = FileInput(accept=".json", name="load", width=200)
    menu = Select(
        title="start from", options=["(this design)", *designs], value="(this design)", name="designs", width=200
    )
    save.js_on_change("tags", CustomJS(args={"save": save}, code=_SAVE_JS))

    drawing = Drawing()
    serial = itertools.count(1)
    state: dict = {
        "pending": None,
        "busy": False,
        "shown": 0,
        "pinned": None,
        "view": None,
        "cancel": lambda: None,
        "later_panels": (),
        "pinned_later": (),
    }

    def draw(computed: Computed) -> None:
        view = computed.view
        if view is None:
            said = html.escape(computed.error)
            results.text = (
                f'<p data-serial="{state["shown"]}"><b style="color:#b00020">{said}</b> ({computed.ms:.0f} ms)</p>'
            )
            return
        state["view"] = view
        drawing.ensure(view.panels, view.pose)
        drawing.draw(view.panels, 0, state["pinned"].panels if state["pinned"] else ())
        drawing.hide_from(len(view.panels))  # the slow judgement's panels: the design before's
        if view.pose is not None:
            drawing.pose(view.pose)
        met = sum(r.ok for r in view.rows)
        said = (
            f'<p data-serial="{state["shown"]}"><b>{met} of {len(view.rows)} objectives met</b>; '
            f"the library's view {computed.ms:.0f} ms, the server's answer "
            f'<span class="server-ms">{(time.perf_counter() - state["since"]) * 1e3:.1f}</span> ms</p>'
        )
        notes = "<br>".join(html.escape(s) for s in view.notes)
        against = state["pinned"].rows if state["pinned"] else ()
        state["quick"] = said + notes + rows_html(view.rows, "objectives-table", against)
        waiting = f"<p><i>{html.escape(view.later_title)}: computing…</i></p>" if view.later else ""
        results.text = state["quick"] + waiting
        if view.later is not None:  # once this design's messages are out, unless another follows
            if hasattr(judge, "warm"):
                judge.warm()
            doc.add_timeout_callback(partial(start_later, state["shown"], view, computed.x), LATER_AFTER_MS)

    def start_later(number: int, view, x) -> None:
        if number == state["shown"]:
            state["cancel"]()
            state["cancel"] = judge(x, view.later, partial(later_done, number, view.later_title))

    def later_done(number: int, title: str, kind: str, payload) -> None:
        notes: tuple[str, ...] = ()
        if kind == "view":  # panels drawn after the quick view's, rows and notes
            if payload.panels:
                doc.add_next_tick_callback(partial(show_later_panels, number, payload.panels))
            kind, payload, notes = "rows", payload.rows, payload.notes
        if kind == "rows":
            said = "".join(f'<br><span class="later-note">{html.escape(s)}</span>' for s in notes)
            text = f"<p><b>{html.escape(title)}</b>{said}</p>" + rows_html(tuple(payload), "later-table")
        elif kind == "error":
            text = f'<b style="color:#b00020">{html.escape(str(payload))}</b>'
        else:
            said = html.escape(f"the part script's judgement failed: {payload}")
            text = f'<b style="color:#b00020">{said}</b>'
        doc.add_next_tick_callback(partial(show_later, number, text))

    def show_later_panels(number: int, panels) -> None:
        if number == state["shown"] and state["view"] is not None:
            first = len(state["view"].panels)
            drawing.ensure((*state["view"].panels, *panels), None)
            pinned = state["pinned_later"] if state["pinned"] else ()
            drawing.draw(panels, first, pinned)
            state["later_panels"] = panels

    def show_later(number: int, text: str) -> None:
        if number == state["shown"]:
            results.text = state["quick"] + text

    def compute_pending() -> None:
        state["cancel"]()  # the judgement of the design being replaced
        x = state["pending"]
        state["pending"] = None
        state["since"] = state.pop("asked")
        computed = session.compute(x)
        state["shown"] = next(serial)
        doc.hold("combine")
        draw(computed)
        doc.unhold()
        if state["pending"] is not None:
            doc.add_next_tick_callback(compute_pending)
        else:
            state["busy"] = False

    def request(x) -> None:
        if state["pending"] is None:  # the server's time is counted from the first change it answers
            state["asked"] = time.perf_counter()
        state["pending"] = x
        if not state["busy"]:
            state["busy"] = True
            doc.add_next_tick_callback(compute_pending)

    def show_design(x) -> None:
        for n, v in zip(names, x, strict=True):
            sliders[n].value = v
            boxes[n].value = f"{v:.6g}"
            errors[n].text = ""
        request(x)

    syncing = {"on": False}

    def on_slider(name, attr, old, new) -> None:
        if syncing["on"]:
            return
        try:
            x = session.set(name, float(new))
        except TransplanterError as exc:  # only a page driven by script can send it past its ends
            errors[name].text = html.escape(str(exc))
            return
        syncing["on"] = True
        boxes[name].value = f"{new:.6g}"
        errors[name].text = ""
        syncing["on"] = False
        request(x)

    def on_box(name, attr, old, new) -> None:
        if syncing["on"]:
            return
        try:
            x = session.set(name, new)
        except TransplanterError as exc:
            errors[name].text = html.escape(str(exc))
            return
        errors[name].text = ""
        syncing["on"] = True
        sliders[name].value = x[names.index(name)]
        syncing["on"] = False
        request(x)

    def on_history(step) -> None:
        syncing["on"] = True
        show_design(step())
        syncing["on"] = False

    def on_save() -> None:  # to the browser, which downloads it (_SAVE_JS)
        save.tags = [save.tags[0] + 1 if save.tags else 1, session.saved()]

    def on_pin() -> None:  # the design on the page becomes B (unpin: none)
        state["pinned"] = state["view"] if state["pinned"] is None else None
        state["pinned_later"] = state["later_panels"]
        pin.label = "unpin B" if state["pinned"] is not None else "pin as B"
        request(session.x)

    def adopt_design(x) -> None:
        syncing["on"] = True
        show_design(session.adopt(x))
        syncing["on"] = False

    def on_menu(attr, old, new) -> None:
        if new in designs:
            syncing["on"] = True
            show_design(session.adopt(designs[new]))
            syncing["on"] = False
            menu.value = "(this design)"

    def on_load(attr, old, new) -> None:
        load_said.text = ""  # the last file's message is not this one's
        try:
            text = base64.b64decode(new, validate=True)
            loaded = Session.load(problem, text)
        except (TransplanterError, ValueError) as exc:
            load_said.text = html.escape(str(exc))
            return
        load_said.text = ""
        syncing["on"] = True
        show_design(session.adopt(loaded.x))
        syncing["on"] = False

    for n in names:
        sliders[n].on_change("value", partial(on_slider, n))
        boxes[n].on_change("value", partial(on_box, n))
    save.on_click(on_save)
    undo.on_click(lambda: on_history(session.undo))
    pin.on_click(on_pin)
    redo.on_click(lambda: on_history(session.redo))
    menu.on_change("value", on_menu)
    load.on_change("value", on_load)

    controls = [Div(text=f"<h3>{html.escape(title)}</h3>", width=340)]
    for n in names:
        controls += [row(sliders[n], boxes[n]), errors[n]]
    controls += [row(undo, redo, save, pin), row(menu), row(Div(text="load a design:", width=90), load), load_said]
    controls.append(search_panel(doc, session, adopt_design, workers, scheduler))
    if making is not None:
        controls.append(making_panel(doc, session, *making))
    # roots laid out each on its own by the browser (a Div's new text or a plot's new title lays out
    # its root again: in one root, every change would measure every plot's axes once more)
    doc.add_root(column(*controls, name="controls"))
    for slot in drawing.roots:
        doc.add_root(slot)
    doc.add_root(row(drawing.scrub, drawing.play, name="drawing"))
    doc.add_root(column(results, name="judged"))
    doc.template = _template()
    doc.title = f"transplanter design: {title}"
    doc.on_session_destroyed(lambda ctx: state["cancel"]())
    request(session.x)
