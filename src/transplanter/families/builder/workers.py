"""Building parts in other processes: the parallel build forks a fresh process for each part
(:class:`Forks`, the families loaded once before), :class:`Beside` forks a step of a part beside
the rest of it, and ``transplanter check`` checks families in a pool (:func:`executor`); a part's
failure is its outcome, never the process's."""

from __future__ import annotations

import contextlib
import itertools
import signal
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from transplanter.core import heap
from transplanter.core.errors import TransplanterError
from transplanter.families.builder.scripts import Family
from transplanter.families.builder.study import Built, Study

__all__ = ["FAMILIES", "PRELOADED", "Beside", "Forks", "executor", "outcome", "part_outcome", "uses"]


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


#: this process's forks running while its objects are frozen (:func:`_freeze`): (pid, how many)
_FROZEN = {"pid": 0, "forks": 0}
_FREEZING = threading.Lock()  # (the design studio builds from its server's threads)


def _freeze() -> bool:
    """Before a fork: this process's objects moved to the garbage collector's permanent generation
    (``gc.freeze``, as Python's documentation advises before a fork), so that neither the forked
    process's collections nor this one's, while it runs, walk them — each walk writes to every
    object's header and copies the page it lies on, shared until then. True if this call froze
    (then :func:`_thaw` when the fork has ended); False in a process forked from one that froze
    (a build worker), whose inherited objects stay frozen and whose own are left as they are (a
    worker freezing its own for good would keep the cyclic garbage of every later part).

    ``transplanter pair``: 6.47 → 6.17 s of CPU, 4.27 → 4.06 s wall (medians of 7, interleaved);
    the build of every family ~1 % less CPU."""
    import gc
    import os

    # (asked before the lock: a fork may inherit it taken by another thread of its parent)
    if _FROZEN["pid"] != os.getpid() and gc.get_freeze_count():
        return False
    with _FREEZING:
        if _FROZEN["pid"] != os.getpid():
            _FROZEN.update(pid=os.getpid(), forks=0)
        gc.freeze()
        _FROZEN["forks"] += 1
    return True


def _thaw() -> None:
    """A fork :func:`_freeze` froze for has ended: the objects back to the collector when none runs."""
    import gc

    with _FREEZING:
        _FROZEN["forks"] -= 1
        if not _FROZEN["forks"]:
            gc.unfreeze()


@contextlib.contextmanager
def executor(jobs: int):
    """A pool of ``jobs`` worker processes, forked where the platform can (the workers then
    start with everything this process has imported and loaded, frozen: :func:`_freeze`)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    fork = "fork" in multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if fork else None)
    froze = fork and _freeze()  # the pool forks its workers at the first task
    try:
        with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
            yield pool
    finally:
        if froze:
            _thaw()


#: modules a build's parts import that :class:`Forks`'s fork server imports once (each part's
#: fork then starts with them, shared, instead of importing them again: a cold build of every
#: family took ~10 s more CPU without)
PRELOADED = ("OCP.BRepPrimAPI", "OCP.STEPControl", "matplotlib.pyplot", "trimesh")


class Forks:
    """Up to ``jobs`` processes, a fresh one for each task, each forked from one that holds only
    what this process held on entering — the families loaded — and :data:`PRELOADED`, imported
    there, all frozen (:func:`_freeze`): the fork server, forked on entering. A part built in one
    starts from that state, not from what the builder has gathered since (the files of every
    part built before it), and what it leaves behind — its garbage, its heap's holes, the caches
    of the libraries it used — ends with it, instead of staying in a pool worker under every part
    that worker builds next (issue 46).

    :meth:`submit` queues ``fn(*args)`` and returns its ticket; :meth:`next` hands the server what
    the limit allows and waits for the first task to end: ``(ticket, "value", value)``, ``(ticket,
    "error", exception)`` for an exception it raised, or ``(ticket, "died", why)`` when its process
    ended without answering (a signal, out of memory). A value or error comes back pickled, as a
    pool's does, in a file of a temporary folder that the task's process writes and this one reads
    and removes — no pipe carries it, so the builder handing out a large task (a machine's gear
    files) and the server passing on a large answer never wait on each other. No thread is
    started. Leaving the ``with`` block stops the server and the processes still running, and
    removes the folder; if this process is killed instead, the server, seeing it gone, stops them
    and removes the folder itself. Where no process can be forked, each task is done in this
    process when :meth:`next` is asked."""

    def __init__(self, jobs: int) -> None:
        import collections

        self.jobs = max(1, jobs)
        self._queue: collections.deque = collections.deque()
        self._running: set[int] = set()
        self._tickets = itertools.count()

    def __enter__(self) -> Forks:
        import os
        import tempfile
        from multiprocessing.connection import Pipe

        self._server = None  # no fork to be had: each task is done here, in turn, when waited for
        self._froze = False
        if not hasattr(os, "fork"):
            return self
        self._froze = _freeze()
        self._dir = tempfile.mkdtemp(prefix="transplanter-forks-")
        tasks, self._tasks = Pipe(duplex=False)
        self._results, results = Pipe(duplex=False)
        mask = signal.pthread_sigmask(signal.SIG_BLOCK, OUTLIVED)  # until the server ignores them
        try:
            self._server = os.fork()
        except OSError:  # no process to be had (limits)
            self._server = None
        if self._server == 0:  # the fork server: until this process says stop or goes
            _server(tasks, results, (self._tasks, self._results), self._dir, mask)
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        if self._server is None:
            for end in (tasks, self._tasks, self._results, results):
                end.close()
            os.rmdir(self._dir)
            return self
        tasks.close()
        results.close()
        return self

    def __exit__(self, *exc) -> None:
        import os
        import shutil

        if self._server is None:
            if self._froze:
                _thaw()
            return
        try:
            with contextlib.suppress(OSError):  # the server stops what still runs, and ends
                self._tasks.send(None)
            self._tasks.close()
            self._results.close()
            os.waitpid(self._server, 0)
            self._queue.clear()
            self._running.clear()
            shutil.rmtree(self._dir, ignore_errors=True)
        finally:
            if self._froze:
                _thaw()

    def submit(self, fn: Callable[..., Any], *args) -> int:
        ticket = next(self._tickets)
        self._queue.append((ticket, fn, args))
        return ticket

    def __len__(self) -> int:
        """Tasks queued or running."""
        return len(self._queue) + len(self._running)

    def next(self) -> tuple[int, str, Any]:
        """Hand out what the limit allows, wait for one task to end: ``(ticket, kind, value)``."""
        import os
        import pickle

        if self._server is None and self._queue:
            ticket, fn, args = self._queue.popleft()
            try:
                return ticket, "value", fn(*args)
            except Exception as exc:  # the task's error, raised by the caller
                return ticket, "error", exc
        while self._queue and len(self._running) < self.jobs:
            task = self._queue.popleft()
            self._tasks.send(task)
            self._running.add(task[0])
        if not self._running:
            raise ValueError("no task to wait for")
        try:
            ticket, state, said = self._results.recv()
        except (EOFError, OSError):  # the server itself is gone: every task it ran with it
            return min(self._running), "died", "the build's fork server ended"
        self._running.discard(ticket)
        if state == "died":
            return ticket, "died", said
        with open(said, "rb") as f:
            kind, value = pickle.load(f)
        os.remove(said)
        return ticket, kind, value


def _preload() -> None:
    """:data:`PRELOADED` imported here (the fork server: not the builder, which never uses them —
    OpenCASCADE's import alone is ~230 MB, which the builder would hold under every part's files
    it gathers), and frozen with the rest (:func:`_freeze`)."""
    import gc
    import importlib

    for name in PRELOADED:
        with contextlib.suppress(ImportError):
            importlib.import_module(name)
    gc.freeze()


#: signals sent to the builder's whole process group (``timeout``'s SIGTERM, a closed terminal's
#: SIGHUP) that the fork server outlives: it ends once it sees the builder gone (:func:`_server`)
OUTLIVED = (signal.SIGTERM, signal.SIGHUP)


def _server(tasks, results, theirs, folder: str, mask) -> None:
    """The fork server's life (:class:`Forks`), ended by ``os._exit``: it ignores :data:`OUTLIVED`
    (blocked from before the fork to here) and its children take them as the builder did; when the
    builder is gone — killed, its ends of the pipes closed mid-message or not — it stops what runs
    and removes ``folder``, which no one else will."""
    import os
    import shutil

    builder, code = os.getppid(), 0
    try:
        before = {s: signal.signal(s, signal.SIG_IGN) for s in OUTLIVED}
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        for end in theirs:
            end.close()
        _preload()
        _serve(tasks, results, folder, before)
    except BaseException as exc:
        code = 1
        if isinstance(exc, (EOFError, OSError)) or os.getppid() != builder:
            shutil.rmtree(folder, ignore_errors=True)
    finally:
        os._exit(code)


def _serve(tasks, results, folder: str, restore: dict) -> None:
    """The fork server of :class:`Forks`: each task received forked into a process of its own,
    which pickles its answer into ``folder``; where it is, or the process's death, is passed on.
    On ``None`` (or the builder gone) every process still running is stopped. ``restore``: the
    signal handlers its children take back (the builder's)."""
    import os
    from multiprocessing.connection import Pipe, wait

    running: dict = {}  # reading end -> (ticket, pid)
    try:
        while True:
            for conn in wait([tasks, *running]):
                if conn is tasks:
                    task = tasks.recv()
                    if task is None:
                        return
                    receive, send = Pipe(duplex=False)
                    pid = os.fork()
                    if pid == 0:
                        for number, handler in restore.items():
                            signal.signal(number, signal.SIG_DFL if handler is None else handler)
                        tasks.close()
                        results.close()
                        receive.close()
                        _answer(send, os.path.join(folder, f"{task[0]}.pickle"), *task[1:])
                    send.close()
                    running[receive] = (task[0], pid)
                    del task
                    continue
                ticket, pid = running.pop(conn)
                try:
                    path = conn.recv()
                except (EOFError, OSError):
                    path = None
                conn.close()
                _, status = os.waitpid(pid, 0)
                if path is None:
                    results.send((ticket, "died", f"its process ended without answering (wait status {status})"))
                else:
                    results.send((ticket, "done", path))
    finally:
        for conn, (_, pid) in running.items():
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
            conn.close()
            os.waitpid(pid, 0)


def _answer(send, path: str, fn: Callable[..., Any], args: tuple) -> None:
    """In a task's process: ``fn(*args)``, its value or error pickled into ``path`` and the path
    sent, then gone without clean-up."""
    import os
    import pickle

    code = 0
    try:
        try:
            out: tuple[str, Any] = ("value", fn(*args))
        except Exception as exc:  # the task's error, raised by the caller
            out = ("error", exc)
        with open(path, "wb") as f:
            try:
                pickle.dump(out, f, protocol=pickle.HIGHEST_PROTOCOL)
            except Exception as exc:  # a value or error that does not pickle: said, not lost
                f.seek(0)
                f.truncate()
                pickle.dump(("error", TransplanterError(f"a build process could not return: {exc}")), f)
        send.send(path)
    except BaseException:
        code = 1
    finally:
        os._exit(code)


def uses(part: Study) -> tuple[str, ...]:
    """The names of the parts whose files ``part`` is built from (its ``uses``; none for most)."""
    return tuple(getattr(part, "uses", ()) or ())


def outcome(family: str, part: str, used: dict[str, bytes] | None = None):
    """:func:`part_outcome` of ``part`` of the loaded ``family`` (:data:`FAMILIES`, which a
    :class:`Forks` process inherits, or reads here where it cannot fork)."""
    fam = FAMILIES[family]
    return part_outcome(next(p for p in fam.parts if p.name == part), Path("."), used)


#: the work a :class:`Beside` hands its forked process, by key: the fork inherits it (nothing
#: pickled), with the reading and writing ends of its inbox (None without one)
_BESIDE: dict[int, tuple[Callable[..., Any], tuple, Any, Any]] = {}
_KEYS = itertools.count()


def _run_beside(key: int, conn) -> None:
    fn, args, inbox, outbox = _BESIDE[key]
    if outbox is not None:  # its inbox's writing end is its parent's alone: the parent gone, the
        outbox.close()  # inbox ends (EOF) and so does this process, not waiting on it for ever
    try:
        out: tuple[str, Any] = ("value", fn(*args, inbox.recv) if inbox is not None else fn(*args))
    except BaseException as exc:  # the work's error, raised in the parent
        out = ("error", exc)
    try:
        conn.send(out)
    except OSError:  # the parent gone (stopped): no one to answer
        pass
    except Exception as exc:  # a value or error that does not pickle: said, not lost
        said = f"work beside the build could not return: {type(exc).__name__}: {exc}"
        with contextlib.suppress(OSError):
            conn.send(("error", TransplanterError(said)))
    finally:
        conn.close()


class Beside:
    """``fn(*args)`` run in a forked process beside what this one does next (issue 46: the STEP
    beside the meshing proofs, the plots beside the assembly); :meth:`result` waits for its value
    (pickled back through a pipe; an exception it raises is raised here). The arguments are
    inherited by the fork, not pickled (a part's solid is not picklable).

    The fork is a bare process and a pipe — no pool, so no thread is started here and another
    ``Beside`` may fork while this one runs (the plots beside the STEP). This process's objects
    are frozen while a fork runs (:func:`_freeze`).

    With ``inbox``, the work is ``fn(*args, receive)`` and may start before all it needs exists:
    ``receive()`` waits for the next value this process hands it by :meth:`send` (pickled; a pair's
    plots: the teeth drawn while the shop files are made, the meshing once the proof has been).

    The same call, the same value: the work runs in this process instead — when :meth:`result`
    is asked — where no fork can be made safely (no ``fork`` start method, other threads running,
    which a fork would copy mid-step, or this process a daemon, which may have no children: the
    design studio's slow judgement runs in one) or the forked process died before answering."""

    def __init__(self, fn: Callable[..., Any], *args, inbox: bool = False) -> None:
        import multiprocessing

        self._call = (fn, args)
        self._proc = self._conn = self._inbox = None
        self._froze = False  # this process's objects frozen for the fork (:func:`_freeze`)
        #: with an inbox, what was sent (the work done here receives it from this list)
        self._sent: list | None = [] if inbox else None
        if (
            "fork" not in multiprocessing.get_all_start_methods()
            or threading.active_count() > 1
            or multiprocessing.current_process().daemon  # a daemonic process may have no children
        ):
            return
        ctx = multiprocessing.get_context("fork")
        key = next(_KEYS)
        receive, send = ctx.Pipe(duplex=False)
        mail, post = ctx.Pipe(duplex=False) if inbox else (None, None)
        _BESIDE[key] = (fn, args, mail, post)
        try:  # a daemon: ended with this process, and itself without children
            proc = ctx.Process(target=_run_beside, args=(key, send), daemon=True)
            self._froze = _freeze()
            proc.start()  # forks here, with the work in _BESIDE
            self._proc, self._conn, self._inbox = proc, receive, post
        except OSError:  # no process to be had (limits): the work is done here, when asked
            receive.close()
            if post is not None:
                post.close()
            self._thaw()
        finally:
            send.close()  # the fork's ends; this process keeps the results' reading end and the inbox's writing end
            if mail is not None:
                mail.close()
            del _BESIDE[key]

    def __enter__(self) -> Beside:
        return self

    def __exit__(self, *exc) -> None:
        self._close(stop=True)  # a forked process not asked for its value (the caller failed) is stopped

    def send(self, value) -> None:
        """Hand ``value`` to the work's ``receive()`` (``inbox``). A value that cannot go to the
        forked process (it does not pickle) stops it: the work is then done here, when asked."""
        if self._sent is None:
            raise TypeError("send() needs a Beside made with inbox=True")
        self._sent.append(value)
        if self._inbox is not None:
            try:
                self._inbox.send(value)
            except Exception:  # noqa: BLE001 - unpicklable (any error of any object's reduce), or the fork gone
                self._close(stop=True)

    def result(self):
        """The work's value (waiting for the forked process, or doing it here)."""
        if self._conn is None:
            return self._here()
        try:
            kind, value = self._conn.recv()
        except (EOFError, OSError):  # the process died (memory, a signal): the same work, here
            return self._here()
        finally:
            self._close()
        if kind == "error":
            raise value
        return value

    def _here(self):
        """The work done in this process (with an inbox, receiving what was sent, in order)."""
        fn, args = self._call
        if self._sent is None:
            return fn(*args)
        sent = iter(list(self._sent))

        def receive():
            try:
                return next(sent)
            except StopIteration:  # asked its value before handing the work all it waits for
                raise RuntimeError("the work beside waits for a value that was never sent") from None

        return fn(*args, receive)

    def _close(self, stop: bool = False) -> None:
        if self._inbox is not None:
            self._inbox.close()
        if self._conn is not None:
            self._conn.close()
        if self._proc is not None:
            if stop:
                self._proc.kill()
            self._proc.join()  # answered (or died): on its way out
            self._proc.close()
            self._thaw()
        self._proc = self._conn = self._inbox = None

    def _thaw(self) -> None:
        if self._froze:
            self._froze = False
            _thaw()
