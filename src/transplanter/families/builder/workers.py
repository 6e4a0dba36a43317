"""Building parts in worker processes: each worker loads a family once and builds the parts it is
given; a part's failure is its outcome, never the worker's."""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from transplanter.core import heap
from transplanter.core.errors import TransplanterError
from transplanter.families.builder.scripts import Family, load_family
from transplanter.families.builder.study import Built, Study

__all__ = ["FAMILIES", "Beside", "executor", "outcome", "part_outcome", "uses"]


def part_outcome(part: Study, root: Path, used: dict[str, bytes] | None = None) -> Built | str:
    """Build one part: its :class:`~transplanter.families.builder.study.Built` (record, files), or the
    error the manifest records for it — any exception a part raises is its failure (a project
    error by its message; anything else with its type, as a bug to report). A part that uses
    others' files (``uses``) is given them, ``used`` (file name -> bytes)."""
    try:
        if uses(part):
            return Built(*part.build_using(root, used or {}))
        return Built(*part.build(root))
    except TransplanterError as exc:
        return f"{type(exc).__name__}: {exc}"
    except Exception as exc:  # a bug, or a library error that escaped: the part fails, the build goes on
        return f"{type(exc).__name__} (unexpected, please report): {exc}"
    finally:  # the part's freed heap handed back: the next part this process builds starts low
        heap.trim(1)


#: the families being built, by name: set by the builder before it forks its workers
FAMILIES: dict[str, Family] = {}


def executor(jobs: int):
    """A pool of ``jobs`` worker processes, forked where the platform can (the workers then
    start with everything this process has imported and loaded)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else None)
    return ProcessPoolExecutor(max_workers=jobs, mp_context=ctx)


def uses(part: Study) -> tuple[str, ...]:
    """The names of the parts whose files ``part`` is built from (its ``uses``; none for most)."""
    return tuple(getattr(part, "uses", ()) or ())


def outcome(family: str, script: str | None, part: str, used: dict[str, bytes] | None = None):
    fam = FAMILIES.get(family)
    if fam is None:  # a worker that was not forked from the builder: load the script itself
        fam = FAMILIES[family] = load_family(script)
    return part_outcome(next(p for p in fam.parts if p.name == part), Path("."), used)


#: the work a :class:`Beside` hands its forked process, by key: the fork inherits it (nothing pickled)
_BESIDE: dict[int, tuple[Callable[..., Any], tuple]] = {}
_KEYS = itertools.count()


def _run_beside(key: int):
    fn, args = _BESIDE[key]
    return fn(*args)


class Beside:
    """``fn(*args)`` run in a forked process beside what this one does next (issue 46: the STEP
    beside the meshing proofs); :meth:`result` waits for its value (pickled back; an exception it
    raises is raised here). The arguments are inherited by the fork, not pickled (a part's solid
    is not picklable).

    The same call, the same value: the work runs in this process instead — when :meth:`result`
    is asked — where no fork can be made safely (no ``fork`` start method, other threads running,
    which a fork would copy mid-step, or this process a daemon, which may have no children: the
    design studio's slow judgement runs in one) or the forked process died before answering."""

    def __init__(self, fn: Callable[..., Any], *args) -> None:
        import multiprocessing

        self._call = (fn, args)
        self._pool = self._future = None
        if (
            "fork" not in multiprocessing.get_all_start_methods()
            or threading.active_count() > 1
            or multiprocessing.current_process().daemon  # a daemonic process may have no children
        ):
            return
        key = next(_KEYS)
        _BESIDE[key] = self._call
        try:
            self._pool = executor(1)
            self._future = self._pool.submit(_run_beside, key)  # forks here, with the work in _BESIDE
        except OSError:  # no process to be had (limits): the work is done here, when asked
            self._close()
        finally:
            del _BESIDE[key]

    def __enter__(self) -> Beside:
        return self

    def __exit__(self, *exc) -> None:
        self._close()  # a forked process not asked for its value (the caller failed) is stopped

    def result(self):
        """The work's value (waiting for the forked process, or doing it here)."""
        from concurrent.futures.process import BrokenProcessPool

        fn, args = self._call
        if self._future is None:
            return fn(*args)
        try:
            return self._future.result()
        except BrokenProcessPool:  # the process died (memory, a signal): the same work, here
            return fn(*args)
        finally:
            self._close()

    def _close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
        self._pool = self._future = None
