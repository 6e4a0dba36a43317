"""Parameter optimisation of a mechanism with scipy's differential evolution.

A :class:`Problem` names its variables with bounds and maps a parameter vector to a scalar
cost (lower is better) in which constraints enter as penalties; a parameter set the model
rejects (a :class:`~transplanter.core.errors.TransplanterError`) costs ``infeasible``. The run is
reproducible (``seed``) and reports progress once per generation.

**Parallel evaluation.** ``workers=N`` evaluates each generation's candidates on N local
processes, ``scheduler="tcp://host:8786"`` on a Dask cluster (dask.distributed: a
``LocalCluster`` for the local case, the user's scheduler otherwise; the cost function is sent
with cloudpickle, so a part script's closures work, and scattered to every worker once per run:
:class:`ClusterMap`; a generation's candidates go out in batches that shrink to one candidate
(:func:`batch_bounds`); each local
worker process runs one BLAS thread). scipy then updates the population once
per generation (``updating="deferred"``), so a parallel run gives the same result for any
number of workers or cluster, for a given seed; the serial default updates immediately (the
classic scheme, and the one the recorded seed-002 optimum was found with).

Examples
--------
>>> from transplanter.design.optimise import Problem, optimise
>>> p = Problem("bowl", (("x", -2.0, 2.0), ("y", -2.0, 2.0)), lambda v: (v[0] - 1) ** 2 + (v[1] + 0.5) ** 2)
>>> r = optimise(p, seed=3, maxiter=60, popsize=10)
>>> [round(v, 3) for v in r.x], r.fun < 1e-6
([1.0, -0.5], True)
"""

from __future__ import annotations

import itertools
import math
import re
import time
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import PartScriptError, SpecError, TransplanterError, check_int

__all__ = [
    "MAX_MAXITER",
    "MAX_POPSIZE",
    "MAX_SEED",
    "MAX_WORKERS",
    "SCHEDULER_TIMEOUT_S",
    "batch_bounds",
    "ClusterMap",
    "Problem",
    "OptimisationResult",
    "misses",
    "optimise",
]

#: the largest seed: numpy's legacy generator, which scipy seeds from it, takes 32 bits
MAX_SEED = 2**32 - 1
#: candidates per variable and generation: 1000 × 12 variables is 12 000 designs a generation,
#: hours each for seed 004's model; more is a typo, not a search
MAX_POPSIZE = 1000
#: generations: seed 004's longest recorded search ran 150
MAX_MAXITER = 100_000
#: local evaluation processes (a LocalCluster): beyond the cores of any one machine
MAX_WORKERS = 256
#: seconds a Dask scheduler is given to connect, shake hands and say what it is
SCHEDULER_TIMEOUT_S = 10.0


@dataclass(frozen=True)
class Problem:
    """Variables ``(name, low, high)``, a cost function of the parameter vector, and an optional
    starting point ``x0`` that joins the initial population (so a known design is never lost)."""

    name: str
    variables: tuple[tuple[str, float, float], ...]
    cost: Callable[[np.ndarray], float]
    infeasible: float = 1e6
    x0: tuple[float, ...] | None = None
    #: variables that are choices (their integer part is what the model uses): shown as integers
    choices: tuple[str, ...] = ()
    #: the best design's objectives in words, ``{objective: "value unit (margin M)"}``, shown
    #: with the progress (one evaluation per generation); an entry whose text holds
    #: ``(margin M)`` with M < 0 is an objective missed (:func:`misses`): ``--write`` records
    #: such a design only with ``--write-infeasible``
    describe: Callable[[np.ndarray], dict[str, str]] | None = None
    #: the module-level name of the design vector in the file that defines ``problem()``
    #: (``OPTIMUM``): ``transplanter optimise --write`` records the optimum there
    optimum: str | None = None
    #: with ``x0``: half the initial population is drawn around it (normal, this fraction of each
    #: variable's range as the standard deviation; choices kept as ``x0``'s), half uniformly — a
    #: search that refines a known design without losing sight of the whole range (0: Latin hypercube)
    spread: float = 0.0
    #: what the design studio draws of a design (``transplanter design``): ``x`` ->
    #: :class:`~transplanter.design.views.DesignView`; without it the page shows the variables,
    #: the cost and what ``describe`` says
    view: Callable[[np.ndarray], object] | None = None
    #: the design the part script makes of this problem, where it is not ``x0`` (the search's
    #: start): the studio opens on it
    design: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if not self.variables:
            raise SpecError("a Problem needs at least one variable")
        for name, lo, hi in self.variables:
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise SpecError.out_of_range(f"bounds of {name}", (lo, hi), "finite with low < high")
        unknown = set(self.choices) - {name for name, _, _ in self.variables}
        if unknown:
            raise SpecError(f"problem {self.name!r}: choices {sorted(unknown)} are not variables")
        if not (isinstance(self.spread, int | float) and 0.0 <= self.spread <= 1.0):
            raise SpecError.out_of_range("spread", self.spread, "a fraction of each range, 0..1")
        if self.spread and self.x0 is None:
            raise SpecError(f"problem {self.name!r}: spread draws the population around x0; give x0")
        for what, given in (("x0", self.x0), ("design", self.design)):
            if given is not None and len(given) != len(self.variables):
                raise SpecError.out_of_range(
                    f"{what} (its length)", len(given), f"{len(self.variables)}, a value per variable"
                )
        if self.optimum is not None and not (isinstance(self.optimum, str) and self.optimum.isidentifier()):
            raise SpecError.out_of_range("optimum", self.optimum, "a Python name (the design vector's variable)")

    def shown(self, x) -> dict[str, float | int]:
        """``x`` by variable name as a designer reads it: choices as the integers the model uses."""
        return {
            name: int(v) if name in self.choices else round(float(v), 6)
            for (name, _, _), v in zip(self.variables, x, strict=True)
        }

    def __call__(self, x: np.ndarray) -> float:
        """The cost of ``x``: a TransplanterError (a design that cannot be built) or a non-finite
        value is ``infeasible``; any other error, or a value that is not a number, is the cost
        function's fault, said as such (PartScriptError)."""
        at = [round(float(v), 6) for v in np.asarray(x, dtype=float)]
        try:
            raw = self.cost(np.asarray(x, dtype=float))
        except TransplanterError:
            return self.infeasible
        except Exception as exc:  # the user's cost function: said as its error, with where
            raise PartScriptError(
                f"problem {self.name!r}: its cost function raised {type(exc).__name__} at {at}: {exc}"
            ) from exc
        try:
            value = float(raw)
        except (TypeError, ValueError) as exc:
            raise PartScriptError(
                f"problem {self.name!r}: its cost function returned {raw!r} at {at}, not a number"
            ) from exc
        return value if math.isfinite(value) else self.infeasible


@dataclass(frozen=True)
class OptimisationResult:
    x: tuple[float, ...]
    fun: float
    generations: int
    evaluations: int
    seconds: float
    history: tuple[float, ...] = field(repr=False)


_MARGIN = re.compile(r"\(margin\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")


def misses(said: dict[str, str]) -> list[tuple[str, str, float]]:
    """The objectives a design misses, from :attr:`Problem.describe`'s words: ``(objective, its
    text — value, unit, margin —, margin)`` for each entry whose ``(margin M)`` is below 0.

    >>> misses({"xi nutation": "30.28 deg (margin -0.282)", "i module": "3.5 mm (margin +0.1)"})
    [('xi nutation', '30.28 deg (margin -0.282)', -0.282)]
    """
    out = []
    for objective, text in said.items():
        found = _MARGIN.search(str(text))
        if found and float(found.group(1)) < 0:
            out.append((str(objective), str(text), float(found.group(1))))
    return out


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

    threading.Thread(target=probe, name="transplanter-scheduler-probe", daemon=True).start()
    try:
        ok, reply = answer.get(timeout=timeout + 1.0)
    except queue.Empty:  # stuck outside the loop (a name lookup): left behind, a daemon thread
        ok, reply = False, TimeoutError()
    if not ok:
        if isinstance(reply, TimeoutError | asyncio.TimeoutError):
            why = f"no Dask scheduler answered within {timeout:g} s"
        elif isinstance(reply, KeyboardInterrupt):
            raise reply
        elif isinstance(reply, OSError):  # refused, reset, closed, no such host
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
                    n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40
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


def _run_batch(fn, xs: list) -> list[float]:
    """The costs of a batch of candidates, on a worker (``fn`` resolved from its scattered copy)."""
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
            self._scattered = self.client.scatter(fn, broadcast=True, hash=False)
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


@contextmanager
def _cost_errors():
    """The cost function's own error as raised: scipy wraps a ValueError from it (ours are) in a
    RuntimeError about "the map-like callable"."""
    try:
        yield
    except RuntimeError as exc:
        if isinstance(exc.__cause__, TransplanterError):
            raise exc.__cause__ from None
        raise


def _initial(problem: Problem, seed: int, popsize: int, start=None):
    """scipy's ``init``: its Latin hypercube, or with ``problem.spread`` half the population around
    ``start`` (default ``problem.x0``; the first member is it) and half uniform, drawn reproducibly
    from ``seed``."""
    start = problem.x0 if start is None else start
    if not problem.spread or start is None:
        return "latinhypercube"
    lo = np.array([v[1] for v in problem.variables])
    hi = np.array([v[2] for v in problem.variables])
    x0 = np.clip(np.asarray(start, dtype=float), lo, hi)
    rng = np.random.default_rng(seed)
    n = max(5, popsize * len(lo))
    near = np.clip(x0 + rng.normal(0.0, problem.spread, (n // 2, len(lo))) * (hi - lo), lo, hi)
    for k, (name, _, _) in enumerate(problem.variables):
        if name in problem.choices:
            near[:, k] = x0[k]
    near[0] = x0
    return np.vstack([near, lo + rng.random((n - n // 2, len(lo))) * (hi - lo)])


def optimise(
    problem: Problem,
    seed: int = 0,
    maxiter: int = 50,
    popsize: int = 15,
    tol: float = 1e-8,
    progress: Callable[[int, float, np.ndarray], None] | None = None,
    x0: np.ndarray | None = None,
    workers: int = 1,
    scheduler: str | None = None,
    updating: str | None = None,
) -> OptimisationResult:
    """Minimise ``problem`` by differential evolution (scipy), reproducibly for a given ``seed``.

    ``progress(generation, best_cost, best_x)`` is called after every generation. ``workers``
    local processes or a Dask ``scheduler`` address evaluate the candidates in parallel (see
    the module docstring). ``updating`` ("immediate" or "deferred") overrides the scheme; a
    parallel run is always deferred.
    """
    from scipy import optimize

    if updating not in (None, "immediate", "deferred"):
        raise SpecError.out_of_range("updating", updating, "'immediate' or 'deferred'")
    seed = check_int("seed", seed, 0, MAX_SEED)
    maxiter = check_int("maxiter", maxiter, 1, MAX_MAXITER)
    popsize = check_int("popsize", popsize, 1, MAX_POPSIZE)
    workers = check_int("workers", workers, 1, MAX_WORKERS)
    if scheduler is not None and not isinstance(scheduler, str):
        raise SpecError(f"scheduler must be an address like 'tcp://host:8786', got {scheduler!r}")
    history: list[float] = []
    start = time.perf_counter()
    first = x0 if x0 is not None else problem.x0
    init = _initial(problem, seed, popsize, first)

    def callback(intermediate_result) -> None:
        history.append(float(intermediate_result.fun))
        if progress is not None:
            progress(len(history), float(intermediate_result.fun), np.asarray(intermediate_result.x))

    with _evaluator(workers, scheduler) as evaluate, _cost_errors():
        res = optimize.differential_evolution(
            problem,
            bounds=[(lo, hi) for _, lo, hi in problem.variables],
            seed=seed,
            maxiter=maxiter,
            popsize=popsize,
            tol=tol,
            polish=False,
            callback=callback,
            init=init,
            x0=None if first is None or not isinstance(init, str) else np.asarray(first, dtype=float),
            updating=(updating or "immediate") if evaluate == 1 else "deferred",
            workers=evaluate,
        )
    if not float(res.fun) < problem.infeasible:
        raise SpecError(
            f"problem {problem.name!r}: no feasible design in {int(res.nfev)} evaluations — every cost was NaN, "
            f"infinite, a design that cannot be built, or the infeasible value {problem.infeasible:g}"
        )
    return OptimisationResult(
        tuple(float(v) for v in res.x),
        float(res.fun),
        len(history),
        int(res.nfev),
        time.perf_counter() - start,
        tuple(history),
    )
