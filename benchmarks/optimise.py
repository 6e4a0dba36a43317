"""Evaluations per second of a design search on 1, 2 and all cores, its overheads, and the speed-up they predict.

Runs a script's ``problem()`` (default: seed 004's differential train, ``parts/_seed004.py``, 0-0.2 s per
candidate; seed 002's takes ~70 ms) for a few generations of differential evolution: once serially, timing
every candidate, then on 2 and on all local cores (a dask ``LocalCluster``, as ``transplanter optimise
--workers N``), with the same seed. Every run uses deferred updating (one population update per generation),
so all evaluate exactly the same candidates and reach the same best cost — equal accuracy by construction.
The baseline is the serial run of the same search in the same run.

It then measures, on a cluster of all cores, what a parallel generation costs beyond its candidates: the
cluster's start, a generation's round trip (a map of one empty batch per worker) and each task's share
(a map of many empty tasks: the dispatcher's time per task), and predicts the time of a generation on ``w``
workers as the makespan of the measured candidates' times dealt out in the search's batches
(:func:`~transplanter.design.cluster.batch_bounds`: shrinking to one candidate; the worker free first takes
the next batch, once the one dispatcher has sent the batches before it), plus a generation's round trip —
printed beside what was measured for 2 and all cores, and for 16 workers (a 16-core machine) as the
prediction; beside it, the more pessimistic figure were every task's dispatch to hold up every worker.

The second run on 2 workers is the baseline: the same search as issue 46's second pass ran it, with 4 equal
batches per worker and dask's own housekeeping on the workers (``--no-before`` skips it).

Each run's rate is printed in all (the cluster's start and the workers' first imports included: what a short
search pays once) and after its first generation (what every further generation costs).

    python benchmarks/optimise.py [parts/_seed002.py] [--generations 4] [--popsize 4]
"""

import argparse
import heapq
import os
import time

import numpy as np

from transplanter.design import cluster as search
from transplanter.design.cluster import batch_bounds
from transplanter.design.optimise import optimise
from transplanter.families import run_script


def _timed(problem):
    """``problem`` with each candidate's evaluation time recorded (in the order scipy asks)."""
    times: list[float] = []
    cost = problem.cost

    def timed(x):
        t = time.perf_counter()
        try:
            return cost(x)
        finally:
            times.append(time.perf_counter() - t)

    import dataclasses

    return dataclasses.replace(problem, cost=timed), times


#: the workers' settings of the second pass (the rest dask's defaults)
SECOND_PASS_CONFIG = ("distributed.nanny.pre-spawn-environ", "distributed.worker.profile.enabled")


def equal_batches(n: int, workers: int, per_worker: int = 4) -> list[tuple[int, int]]:
    """The schedule before issue 46's third pass: ``per_worker`` equal batches per worker (the baseline)."""
    k = max(1, min(n, workers * per_worker))
    bounds = np.linspace(0, n, k + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in zip(bounds, bounds[1:], strict=False) if b > a]


def makespan(times, workers: int, schedule=batch_bounds, per_task: float = 0.0) -> float:
    """A generation's candidates (``times`` s, in order) in the search's batches, the free worker first.

    Every task passes through one dispatcher (the client and the scheduler, one process), which
    spends ``per_task`` on each in turn while the workers compute: a batch starts when its worker
    is free and the dispatcher has sent the batches before it."""
    free = [0.0] * workers
    sent = 0.0
    for a, b in schedule(len(times), workers):
        sent = max(heapq.heappop(free), sent) + per_task
        heapq.heappush(free, sent + float(sum(times[a:b])))
    return max(free)


def _noop(x):
    return 0.0


def overheads(workers: int, tasks: int = 400) -> tuple[float, float, float]:
    """(cluster start s, a generation's round trip s, per task s) on ``workers`` local processes."""
    t = time.perf_counter()
    with search._evaluator(workers, None) as run:
        start = time.perf_counter() - t
        xs = [np.zeros(1)] * workers
        run(_noop, xs)  # the scatter and the first round trip (imports on the workers)
        t = time.perf_counter()
        for _ in range(10):
            run(_noop, xs)
        per_generation = (time.perf_counter() - t) / 10
        run.client.map(_noop, range(10), pure=False)
        t = time.perf_counter()
        run.client.gather(run.client.map(_noop, range(tasks), pure=False))
        per_task = (time.perf_counter() - t) / tasks
    return start, per_generation, per_task


def main() -> None:
    from _exports import as_installed

    ap = argparse.ArgumentParser()
    ap.add_argument("script", nargs="?", default="parts/_seed004.py")
    ap.add_argument("--generations", type=int, default=4)
    ap.add_argument("--popsize", type=int, default=4)
    ap.add_argument(
        "--no-before", action="store_true", help="skip the run on 2 workers as the second pass ran it (the baseline)"
    )
    args = ap.parse_args()
    as_installed()  # transplanter's modules compiled, as pip installs them (each worker imports them)
    problem, times = _timed(run_script(args.script)["problem"]())
    cores = os.cpu_count() or 1
    kwargs = {"seed": 1, "maxiter": args.generations, "popsize": args.popsize, "updating": "deferred"}

    def run(workers: int):
        """The search on ``workers``: (result, seconds in all, seconds of the generations after the first)."""
        stamps: list[float] = []
        t = time.perf_counter()
        res = optimise(problem, workers=workers, progress=lambda *_: stamps.append(time.perf_counter()), **kwargs)
        return res, time.perf_counter() - t, stamps[-1] - stamps[0]

    serial, t1, steady1 = run(1)
    population = serial.evaluations // (serial.generations + 1)  # the initial population, then one per generation
    later = population * (serial.generations - 1)  # evaluated after the first generation
    print(
        f"{'serial (1 process)':22s} {serial.evaluations:5d} evaluations in {t1:6.2f} s: "
        f"{serial.evaluations / t1:6.2f} /s"
        f"; after the first generation {later / steady1:6.2f} /s"
    )
    measured = {}
    runs = [(w, "") for w in sorted({2, cores})] + ([] if args.no_before else [(2, "before")])
    for w, before in runs:
        config = search.WORKER_CONFIG
        if before:  # the same search, the same run, as the second pass had it: 4 equal batches per worker,
            # dask's own housekeeping on the workers (only one BLAS thread and no profiler)
            search.batch_bounds = equal_batches
            search.WORKER_CONFIG = {k: config[k] for k in SECOND_PASS_CONFIG}
        try:
            res, tw, steady = run(w)
        finally:
            search.batch_bounds, search.WORKER_CONFIG = batch_bounds, config
        assert res.evaluations == serial.evaluations and res.fun == serial.fun, "the runs must evaluate alike"
        measured[w, before] = (tw, steady)
        name = f"--workers {w}" + (", second pass (before)" if before else "")
        print(
            f"{name:22s} {res.evaluations:5d} evaluations in {tw:6.2f} s: {res.evaluations / tw:6.2f} /s"
            f" {t1 / tw:5.2f}x serial (the cluster's start and the workers' first imports included);"
            f" after the first generation {later / steady:6.2f} /s, {steady1 / steady:5.2f}x serial"
        )

    start, per_gen, per_task = overheads(cores)
    gens = [times[k : k + population] for k in range(0, len(times), population)]
    print(
        f"\noverheads on {cores} local workers: cluster start {start:.2f} s, a generation's round trip "
        f"{per_gen * 1e3:.1f} ms, {per_task * 1e3:.2f} ms per task; {len(gens)} generations of {population}, "
        f"a candidate {np.mean(times) * 1e3:.0f} ms on average ({min(times) * 1e3:.0f}..{max(times) * 1e3:.0f})"
    )
    total = sum(times)
    for (w, before), schedule in [((w, ""), batch_bounds) for w in sorted({2, cores, 16})] + [
        ((2, "before"), equal_batches)
    ]:
        if before and (w, before) not in measured:
            continue

        def predicted(generations, w=w, schedule=schedule):
            return sum(makespan(g, w, schedule, per_task) + per_gen for g in generations)

        def serialised(generations, w=w, schedule=schedule):  # no task's dispatch overlapping any computation
            return sum(makespan(g, w, schedule) + per_gen + len(schedule(len(g), w)) * per_task for g in generations)

        run = predicted(gens)
        name = f"{w:2d} workers" + (", second pass (before)" if before else "")
        line = (
            f"  {name}: predicted {total / run:5.2f}x ({total / (run + start):5.2f}x with the start;"
            f" {total / serialised(gens):5.2f}x were every dispatch to hold up every worker)"
        )
        if (w, before) in measured:
            tw, steady = measured[w, before]
            line += (
                f"; measured {t1 / tw:5.2f}x with the start, after the first generation "
                f"{steady1 / steady:5.2f}x (predicted {sum(map(sum, gens[2:])) / predicted(gens[2:]):5.2f}x)"
            )
        print(line + ("" if w <= cores else f" — this machine has {cores} cores"))


if __name__ == "__main__":
    main()
