"""The slow judgement of a design (``DesignView.later``) off the server's process.

It runs in a child process, so it neither holds up the server's answers to the next change
(Python's lock) nor outlives its design: a change kills the child of the design it replaces.

* :class:`ScriptJudge` — a page served for a part script: the child is forked by a forkserver
  that imported the library once (``PRELOAD``), loads the script's ``problem()`` itself and judges
  ``problem.view(x).later()``. The server forks nothing: a fork of the server's own heap cost the
  page's next answer ~25 ms and its browser ~80 ms (``benchmarks/studio.py``, seed 002's
  intermediate points: 338 ms with it, 278 with a process that costs the server nothing).
  A script edited on disk while its page is open reaches the slow judgement first: reload the page.
* :func:`judge_later` — any ``later`` callable: a forked child inherits the design's closure
  (nothing is pickled but the rows it returns). Where a process cannot be forked (not Linux or
  macOS), a thread runs it and its result is dropped if its design is gone.
"""

from __future__ import annotations

import multiprocessing
import multiprocessing.forkserver
import os
import threading
from collections.abc import Callable
from pathlib import Path

from transplanter.core.errors import PartScriptError, TransplanterError
from transplanter.design.views import DesignView, Row

__all__ = ["NICENESS", "PRELOAD", "ScriptJudge", "judge_later"]

#: the forked child's niceness: it yields the cores to the server's answers and the browser
NICENESS = 19


def _judged(later) -> tuple[str, object]:
    """``("rows", rows)`` or ``("view", DesignView(panels, rows, notes))`` of ``later()``, or why not."""
    try:
        out = later()
        if isinstance(out, DesignView):
            return "view", DesignView(panels=out.panels, rows=tuple(out.rows), notes=tuple(map(str, out.notes)))
        rows = tuple(out)
        if not all(isinstance(r, Row) for r in rows):
            raise PartScriptError("later() must return Rows or a DesignView")
        return "rows", rows
    except TransplanterError as exc:
        return ("bug" if isinstance(exc, PartScriptError) else "error"), str(exc)
    except Exception as exc:  # the part script's own code
        return "bug", f"{type(exc).__name__}: {exc}"


def _child(later, conn) -> None:
    try:
        os.nice(NICENESS)  # the page's next change and the browser's drawing come first
        conn.send(_judged(later))
    finally:
        conn.close()


def _script_child(script: str, settings: dict, timeout: float | None, x: tuple, conn) -> None:
    """A :class:`ScriptJudge`'s child: the script's problem loaded here, its view's later judged."""
    try:
        os.nice(NICENESS)

        def later():
            import numpy as np

            from transplanter.app.optimise import script_problem

            problem, _ = script_problem(Path(script), settings, timeout)
            view = problem.view(np.asarray(x, dtype=float)) if problem.view is not None else None
            if not isinstance(view, DesignView) or view.later is None:
                raise PartScriptError(f"{script}: the view of this design has no later judgement here")
            return view.later()

        conn.send(_judged(later))
    finally:
        conn.close()


def _waited(child, receive, done: Callable[[str, object], None]) -> Callable[[], None]:
    """Wait for ``child``'s answer on ``receive`` in a thread and call ``done`` with it unless
    cancelled; the cancel (which kills the child)."""
    cancelled = threading.Event()

    def wait() -> None:
        try:
            kind, payload = receive.recv()
        except (EOFError, OSError):  # killed: its design was replaced
            return
        finally:
            receive.close()
            child.join()
        if not cancelled.is_set():
            done(kind, payload)

    threading.Thread(target=wait, daemon=True).start()

    def cancel() -> None:
        cancelled.set()
        if child.is_alive():
            child.kill()

    return cancel


def judge_later(later: Callable, done: Callable[[str, object], None]) -> Callable[[], None]:
    """Run ``later()`` away from the server and call ``done(kind, payload)`` from a waiting
    thread — ``("rows", rows)``, ``("view", DesignView)`` (panels to draw after the quick
    view's, rows and notes), ``("error", message)`` (the model refused the design) or ``("bug",
    message)`` (the script's code failed); never if cancelled. Returns the cancel."""
    if "fork" not in multiprocessing.get_all_start_methods():
        cancelled = threading.Event()

        def run() -> None:
            out = _judged(later)
            if not cancelled.is_set():
                done(*out)

        threading.Thread(target=run, daemon=True).start()
        return cancelled.set

    ctx = multiprocessing.get_context("fork")
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_child, args=(later, send), daemon=True)
    child.start()
    send.close()
    return _waited(child, receive, done)


#: what the forkserver imports before it forks a judging child (once per server)
PRELOAD = ("numpy", "scipy.optimize", "shapely", "transplanter.app.optimise", "transplanter.families", __name__)


class ScriptJudge:
    """The slow judgement of the designs of the part script ``script`` (``problem(**settings)``,
    run within ``timeout`` s as the studio ran it), each in a child of a forkserver: see the
    module docstring. Called with a design vector and ``done`` as :func:`judge_later`'s; returns
    the cancel. Without a forkserver (not Linux or macOS), :func:`judge_later` of ``later``."""

    def __init__(self, script: Path, settings: dict[str, float], timeout: float | None) -> None:
        self.job = (str(Path(script).resolve()), dict(settings), timeout)
        self.ctx = None
        self.warmed = False
        if "forkserver" in multiprocessing.get_all_start_methods():
            self.ctx = multiprocessing.get_context("forkserver")
            self.ctx.set_forkserver_preload(list(PRELOAD))

    def warm(self) -> None:
        """Start the forkserver (its imports take seconds) in the background, once: the page calls
        it when it draws the first view that has a slow judgement, not for a problem without one."""
        if self.ctx is not None and not self.warmed:
            self.warmed = True
            threading.Thread(target=multiprocessing.forkserver.ensure_running, daemon=True).start()

    def __call__(self, x, later: Callable, done: Callable[[str, object], None]) -> Callable[[], None]:
        if self.ctx is None:
            return judge_later(later, done)
        receive, send = self.ctx.Pipe(duplex=False)
        child = self.ctx.Process(target=_script_child, args=(*self.job, tuple(map(float, x)), send), daemon=True)
        child.start()
        send.close()
        return _waited(child, receive, done)
