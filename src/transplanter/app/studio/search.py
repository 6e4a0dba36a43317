"""Optimise from the page: the problem's own search (:func:`transplanter.design.optimise.optimise`,
the one ``transplanter optimise`` runs, on the workers or the Dask cluster the command line gave)
started from the design on the page, on a background thread, its progress streamed to the page
each generation (best cost, what ``describe`` says of the best design, time left), stoppable; a
finished search's optimum goes into the sliders (one undo step), a stopped one's best design on
"adopt".
"""

from __future__ import annotations

import html
import threading
import time
from collections.abc import Callable
from functools import partial

import numpy as np

from transplanter.core.errors import TransplanterError, check_int
from transplanter.design.optimise import MAX_MAXITER, MAX_POPSIZE, optimise

__all__ = ["Stopped", "search_panel"]


class Stopped(Exception):
    """Raised from the search's progress callback when the designer stops it."""


def _int(name: str, text: str, low: int, high: int) -> int:
    try:
        number = int(text.strip())
    except ValueError:
        raise TransplanterError(f"{name} = {text!r} is out of range: must be a whole number") from None
    return check_int(name, number, low, high)


def search_panel(doc, session, on_adopt: Callable, workers: int = 1, scheduler: str | None = None):
    """The search's widgets for ``doc`` (a Bokeh layout); ``on_adopt(x)`` puts a design in the
    sliders. One search at a time per page."""
    from bokeh.layouts import column, row
    from bokeh.models import Button, Div, TextInput, Toggle

    problem = session.problem
    generations = TextInput(value="10", title="generations", name="search-generations", width=95)
    popsize = TextInput(value="8", title="population per variable", name="search-popsize", width=150)
    seed = TextInput(value="0", title="seed", name="search-seed", width=70)
    run = Toggle(label="optimise from here", name="search-run", width=160, button_type="primary")
    adopt = Button(label="adopt its best", name="search-adopt", width=120, disabled=True)
    said = Div(text="", name="search-progress", width=330, styles={"font-size": "12px"})
    held: dict = {"best": None, "stop": threading.Event(), "thread": None}

    def show(text: str) -> None:
        said.text = text

    def finish(x, text: str, done: bool) -> None:
        said.text = text
        run.active = False
        adopt.disabled = x is None
        if done and x is not None:
            on_adopt(x)

    def progress(start: float, total: int, gen: int, best: float, x) -> None:
        if held["stop"].is_set():
            raise Stopped
        held["best"] = np.asarray(x, dtype=float)
        left = (time.perf_counter() - start) / gen * (total - gen)
        lines = [f"generation {gen}/{total}: best cost {best:.6g}; about {left:.0f} s left"]
        if problem.describe is not None:
            try:
                lines += [f"{k}: {v}" for k, v in problem.describe(held["best"]).items()]
            except Exception as exc:  # the problem's own code: said, the search goes on
                lines.append(f"(its objectives cannot be described: {type(exc).__name__}: {exc})")
        doc.add_next_tick_callback(partial(show, "<br>".join(html.escape(s) for s in lines)))

    def search(x0, gens: int, pop: int, sd: int) -> None:
        start = time.perf_counter()
        try:
            res = optimise(
                problem,
                seed=sd,
                maxiter=gens,
                popsize=pop,
                x0=np.asarray(x0, dtype=float),
                progress=partial(progress, start, gens),
                workers=workers,
                scheduler=scheduler,
            )
        except Stopped:
            text = "stopped: its best design so far can be adopted"
            doc.add_next_tick_callback(partial(finish, held["best"], text, False))
            return
        except TransplanterError as exc:
            doc.add_next_tick_callback(partial(finish, None, html.escape(str(exc)), False))
            return
        except Exception as exc:  # the problem's own code
            text = html.escape(f"the search failed in the part script: {type(exc).__name__}: {exc}")
            doc.add_next_tick_callback(partial(finish, None, text, False))
            return
        held["best"] = np.asarray(res.x, dtype=float)
        text = (
            f"done: cost {res.fun:.6g} after {res.generations} generations, {res.evaluations} designs, "
            f"{time.perf_counter() - start:.0f} s; its optimum is in the sliders (undo goes back)"
        )
        doc.add_next_tick_callback(partial(finish, held["best"], html.escape(text), True))

    def on_run(attr, old, new) -> None:
        if not new:  # stopped by the designer (or finished)
            held["stop"].set()
            return
        if held["thread"] is not None and held["thread"].is_alive():
            return
        try:
            gens = _int("generations", generations.value, 1, MAX_MAXITER)
            pop = _int("population per variable", popsize.value, 1, MAX_POPSIZE)
            sd = _int("seed", seed.value, 0, 2**32 - 1)
        except TransplanterError as exc:
            said.text = f'<b style="color:#b00020">{html.escape(str(exc))}</b>'
            run.active = False
            return
        held["stop"] = threading.Event()
        adopt.disabled = True
        said.text = f"searching from this design: {gens} generations of {pop * len(problem.variables)} designs…"
        held["thread"] = threading.Thread(target=search, args=(session.x, gens, pop, sd), daemon=True)
        held["thread"].start()

    def on_adopt_click() -> None:
        if held["best"] is not None:
            on_adopt(held["best"])

    run.on_change("active", on_run)
    adopt.on_click(on_adopt_click)
    doc.on_session_destroyed(lambda ctx: held["stop"].set())
    return column(
        Div(text="<b>optimise from here</b>", width=330), row(generations, popsize, seed), row(run, adopt), said
    )
