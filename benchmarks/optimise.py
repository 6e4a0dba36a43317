"""Evaluations per second of a design search: serial against ``--workers 2`` (dask LocalCluster).

Runs a script's ``problem()`` (default: seed 004's differential train, ``parts/_seed004.py``, 0.1-0.5 s per
candidate; seed 002's takes ~70 ms) for a few
generations of differential evolution, once evaluating serially and once on two local worker
processes, with the same seed, and prints evaluations per second and the ratio. Both runs use
deferred updating (one population update per generation), so they evaluate exactly the same
candidates and reach the same best cost — equal accuracy by construction; the parallel run's
time includes starting its cluster.

    python benchmarks/optimise.py [parts/_seed002.py] [--generations 4] [--popsize 4]
"""

import argparse
import time

from transplanter.design.optimise import optimise
from transplanter.families import run_script


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("script", nargs="?", default="parts/_seed004.py")
    ap.add_argument("--generations", type=int, default=4)
    ap.add_argument("--popsize", type=int, default=4)
    args = ap.parse_args()
    problem = run_script(args.script)["problem"]()
    rows = []
    for label, kwargs in (("serial (1 process)", {"workers": 1, "scheduler": None}), ("--workers 2", {"workers": 2})):
        start = time.perf_counter()
        res = optimise(problem, seed=1, maxiter=args.generations, popsize=args.popsize, updating="deferred", **kwargs)
        seconds = time.perf_counter() - start
        rows.append((label, res.evaluations, seconds, res.fun))
        print(
            f"{label:20s} {res.evaluations:5d} evaluations in {seconds:6.2f} s: {res.evaluations / seconds:6.2f} /s"
            f"  (best cost {res.fun:.6g})"
        )
    (_, n1, t1, f1), (_, n2, t2, f2) = rows
    assert n1 == n2 and f1 == f2, "the two runs must evaluate the same candidates"
    print(f"ratio --workers 2 / serial: {(n2 / t2) / (n1 / t1):.2f}x evaluations per second")


if __name__ == "__main__":
    main()
