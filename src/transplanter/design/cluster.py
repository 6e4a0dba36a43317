"""A search's generations evaluated on a Dask cluster (dask.distributed): a ``LocalCluster`` of
``workers`` processes, or the user's scheduler at an address (probed first: :func:`_reach`).

The cost function is sent with cloudpickle, so a part script's closures work, as bytes scattered
to every worker once per run and opened by each in its first batch (:class:`Shipped`); a
generation's candidates go out in batches that shrink to one candidate (:func:`batch_bounds`), one
in flight per worker (:class:`ClusterMap`); each local worker process runs one BLAS thread and
little housekeeping (:data:`WORKER_CONFIG`). :func:`transplanter.design.optimise.optimise` asks
for it with ``workers`` or ``scheduler``.

Examples
--------
>>> [b - a for a, b in batch_bounds(10, 2)]
[3, 3, 1, 1, 1, 1]
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass

from transplanter.core.errors import SpecError

__all__ = ["BLAS_THREADS", "SCHEDULER_TIMEOUT_S", "WORKER_CONFIG", "ClusterMap", "Shipped", "batch_bounds"]

#: seconds a Dask scheduler is given to connect, shake hands and say what it is
SCHEDULER_TIMEOUT_S = 10.0


def _reach(address: str, timeout: float) -> None:
    """SpecError unless a Dask scheduler at ``address`` connects, shakes hands and says it is one
    within ``timeout`` s. dask's own connect timeout does not bound the handshake (a peer that
    accepts and never answers holds it for ever), and a peer that answers garbage makes its reader
    fail in any way (a frame of 3 EiB, a msgpack error): both are said here as the address's fault."""
    import asyncio
    import queue
    import threading

    from distributed.comm import connect
    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, where = parse_address(address)
        if scheme in ("tcp", "tls", "ws", "wss") and not 0 < parse_host_port(where)[1] < 65536:
            raise ValueError(f"port {parse_host_port(where)[1]} is not 1..65535")
    except ValueError as exc:
        raise SpecError(f"scheduler = {address!r}: not an address like 'tcp://host:8786' ({exc})") from None

    async def ask():
        comm = await connect(address, timeout=timeout)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    answer: queue.Queue = queue.Queue()

    def probe() -> None:  # its own loop and thread: the caller may be inside an event loop
        try:
            answer.put((True, asyncio.run(asyncio.wait_for(ask(), timeout))))
        except BaseException as exc:  # a peer's bytes can fail the reader in any way; said below
            answer.put((False, exc))

    start = time.monotonic()
    threading.Thread(target=probe, name="transplanter-scheduler-probe", daemon=True).start()
    try:
        ok, reply = answer.get(timeout=timeout + 1.0)
    except queue.Empty:  # stuck outside the loop (a name lookup): left behind, a daemon thread
        ok, reply = False, TimeoutError()
    if not ok:
        if isinstance(reply, KeyboardInterrupt):
            raise reply
        # what failed once the time was up failed for the time: a reader cancelled in the middle of
        # its wait may raise anything (seen under a sampling profiler: a silent peer was said to send
        # garbage), while a peer's own bytes fail it at once
        if isinstance(reply, TimeoutError | asyncio.TimeoutError | asyncio.CancelledError) or (
            time.monotonic() - start >= timeout
        ):
            why = f"no Dask scheduler answered within {timeout:g} s"
        elif isinstance(reply, OSError):  # reset or closed before the deadline (dask retries a refusal until it)
            why = f"cannot reach it ({type(reply).__name__}: {reply})"
        else:  # its bytes, not ours: the reader's own words (a frame of 3 EiB to allocate) say nothing useful
            why = "it is not a Dask scheduler: its reply does not decode as Dask's protocol"
        raise SpecError(f"scheduler = {address!r}: {why}") from None
    kind = reply.get("type") if isinstance(reply, dict) else None
    if kind != "Scheduler":
        said = repr(kind)[:80] if kind is not None else f"a {type(reply).__name__}"
        raise SpecError(f"scheduler = {address!r}: it answered, but not as a Dask scheduler (it says {said})")


@contextmanager
def _evaluator(workers: int, scheduler: str | None):
    """scipy's ``workers`` argument: 1 (serial), or a map over a dask.distributed client (a
    scheduler's address is probed first, within :data:`SCHEDULER_TIMEOUT_S`: :func:`_reach`)."""
    if workers == 1 and scheduler is None:
        yield 1
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError as exc:  # a declared dependency; only a broken install lacks it
        raise SpecError("parallel evaluation needs dask.distributed (pip install distributed)") from exc
    import dask

    cluster = None
    if scheduler is not None:
        _reach(scheduler, SCHEDULER_TIMEOUT_S)
    try:
        if scheduler is None:
            with dask.config.set(WORKER_CONFIG):
                cluster = LocalCluster(
                    n_workers=workers,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    silence_logs=40,
                    # no dashboard, and the HTTP server the scheduler keeps for its metrics on a free
                    # port of loopback: not dask's 8787, taken by any other cluster (the design
                    # studio's search, a notebook's), which it says in a warning before moving on
                    scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"},
                )
            client = Client(cluster)
        else:
            client = Client(scheduler, timeout=f"{SCHEDULER_TIMEOUT_S:g}s")
    except (OSError, TimeoutError, ValueError, TypeError, MemoryError) as exc:  # unreachable, not an address
        if cluster is not None:
            cluster.close()
        where = scheduler or f"{workers} local workers"
        raise SpecError(f"scheduler = {where!r}: cannot start or reach the Dask cluster ({exc})") from exc

    try:
        yield ClusterMap(client)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


#: the thread-count variables of the BLAS libraries numpy and scipy may be built on
BLAS_THREADS = ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS")
#: the local workers' settings (measured on seed 004's candidates, 2 cores): one BLAS thread per
#: process (N workers on N cores, not N × N threads); glibc's own malloc trimming, not dask's
#: MALLOC_TRIM_THRESHOLD_ of 64 KiB (set to hand memory back to the OS: a candidate ~1.5x slower);
#: no statistical profiler sampling the running task's stack every 10 ms; and the housekeeping each
#: worker's event loop does beside the running candidate, which takes the GIL from it, slowed: the
#: loop's 20 ms tick, the 0.5 s system monitor and the 0.1 s memory monitor with its spilling and
#: pausing (a search's tasks hold a few numbers). The nanny still ends a worker past 95 % of the
#: memory. 144 candidates in 3 generations, 4 runs each: 1.90x the serial rate on 2 workers
#: against 1.80x with dask's defaults. The local scheduler steals no work (issue 46's fourth
#: pass): :func:`batch_bounds` already deals the generation out so no worker waits on more than
#: one candidate, and stealing moved queued batches between busy workers — seed 004's search
#: after its first generation 1.86x → 1.99x the serial rate on 2 workers, what the benchmark's
#: model predicts (1.98x).
WORKER_CONFIG = {
    "distributed.nanny.pre-spawn-environ": dict.fromkeys(BLAS_THREADS, 1),
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.worker.memory.target": False,
    "distributed.worker.memory.spill": False,
    "distributed.worker.memory.pause": False,
    "distributed.worker.memory.terminate": 0.95,
    "distributed.scheduler.work-stealing": False,
}


def batch_bounds(n: int, workers: int) -> list[tuple[int, int]]:
    """How a generation's ``n`` candidates go out to ``workers``: ``(start, stop)`` slices, largest first.

    Scheduling by factoring (Hummel, Schonberg & Flynn, "Factoring: a method for scheduling
    parallel loops", Comm. ACM 35(8), 1992): in each round, half of what is left is cut into
    ``workers`` equal batches, until the batches are single candidates. The early batches are
    large, so a task's cost (~3 ms of scheduling and round trip) is a small part of them; the last
    are one candidate each, so at the generation's barrier no worker waits on more than one
    candidate of another's. Candidates' times vary 0-0.8 s on seed 004's problem: with equal
    batches (48 candidates, 2 workers, 4 batches each: 6 candidates, ~2.6 s a batch) a worker
    idled on the other's last batch in every generation.

    Examples
    --------
    >>> [b - a for a, b in batch_bounds(48, 2)]
    [12, 12, 6, 6, 3, 3, 2, 2, 1, 1]
    >>> batch_bounds(3, 4)
    [(0, 1), (1, 2), (2, 3)]
    """
    bounds: list[tuple[int, int]] = []
    start = 0
    while start < n:
        size = math.ceil((n - start) / (2 * workers))
        for _ in range(workers):
            if start >= n:
                break
            stop = min(n, start + size)
            bounds.append((start, stop))
            start = stop
    return bounds


#: on a worker, the cost function of the run it serves, opened from its bytes: ``{token: fn}``
_OPENED: dict[str, Callable] = {}


@dataclass(frozen=True)
class Shipped:
    """A cost function as cloudpickle's bytes, scattered to every worker and opened by each at its
    first batch (:meth:`opened`, kept for the run's later batches).

    Scattered as the function itself, dask opens it as it arrives, and a broadcast reaches the
    workers one after another: each worker's imports of the model (0.4 s for seed 004's) were
    paid in turn before the first generation could start — 0.9 s of a 17 s search on 2 workers.
    As bytes, the copies arrive at once and the workers open them side by side, in their first
    batch."""

    token: str
    blob: bytes

    def opened(self) -> Callable:
        fn = _OPENED.get(self.token)
        if fn is None:
            import cloudpickle

            fn = cloudpickle.loads(self.blob)
            _OPENED.clear()  # one run's function at a time (a user's cluster serves many runs)
            _OPENED[self.token] = fn
        return fn


def _run_batch(fn, xs: list) -> list[float]:
    """The costs of a batch of candidates, on a worker (``fn`` its scattered :class:`Shipped` copy)."""
    if isinstance(fn, Shipped):
        fn = fn.opened()
    return [fn(x) for x in xs]


class ClusterMap:
    """scipy's map-like ``workers`` over a dask.distributed client: the cost function is scattered
    to every worker once (scipy passes the same function every generation: a problem's model is
    not pickled, shipped and unpickled per candidate) and a generation's candidates go out in
    batches that shrink to one candidate (:func:`batch_bounds`), one in flight per worker, the next
    sent to the worker that returns one (the results in the candidates' order)."""

    def __init__(self, client) -> None:
        self.client = client
        self._fn = None
        self._scattered = None
        #: tasks sent, for the benchmark's per-task overhead
        self.tasks = 0

    def workers(self) -> int:
        return max(1, sum(self.client.nthreads().values()))

    def __call__(self, fn, xs) -> list[float]:
        xs = list(xs)
        if fn is not self._fn:
            import uuid

            import cloudpickle

            shipped = Shipped(uuid.uuid4().hex, cloudpickle.dumps(fn))
            self._scattered = self.client.scatter(shipped, broadcast=True, hash=False)
            self._fn = fn
        from distributed import as_completed

        workers = self.workers()
        batches = [xs[a:b] for a, b in batch_bounds(len(xs), workers)]
        self.tasks += len(batches)
        costs: list = [None] * len(batches)
        which: dict = {}
        waiting = iter(enumerate(batches))

        def send(k: int, batch: list):
            future = self.client.submit(_run_batch, self._scattered, batch, pure=False)
            which[future.key] = k
            return future

        # one batch in flight per worker, the next sent as one comes back: a worker done early takes
        # the next batch instead of the tasks dealt to it up front waiting behind a slow one
        running = as_completed([send(k, b) for k, b in itertools.islice(waiting, workers)])
        for future in running:
            costs[which[future.key]] = future.result()
            for k, b in itertools.islice(waiting, 1):
                running.add(send(k, b))
        return [cost for batch in costs for cost in batch]
