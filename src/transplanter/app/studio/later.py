"""The slow judgement of a design (``DesignView.later``) off the server's process.

It runs in a forked child (the design's closure is inherited, nothing is pickled but the rows it
returns), so it neither holds up the server's answers to the next change (Python's lock) nor
outlives its design: a change kills the child of the design it replaces. Where a process cannot
be forked (not Linux or macOS), a thread runs it and its result is dropped if its design is gone.
"""

from __future__ import annotations

import multiprocessing
import threading
from collections.abc import Callable

from transplanter.core.errors import PartScriptError, TransplanterError
from transplanter.design.views import DesignView, Row

__all__ = ["judge_later"]


def _judged(later) -> tuple[str, object]:
    """``("rows", rows)`` or ``("view", DesignView(panels, rows))`` of ``later()``, or why not."""
    try:
        out = later()
        if isinstance(out, DesignView):
            return "view", DesignView(panels=out.panels, rows=tuple(out.rows))
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
        conn.send(_judged(later))
    finally:
        conn.close()


def judge_later(later: Callable, done: Callable[[str, object], None]) -> Callable[[], None]:
    """Run ``later()`` away from the server and call ``done(kind, payload)`` from a waiting
    thread — ``("rows", rows)``, ``("view", DesignView)`` (panels to draw after the quick
    view's, and rows), ``("error", message)`` (the model refused the design) or ``("bug",
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
