"""``transplanter optimise``: differential evolution on a script's ``problem()`` (``--set`` numbers
passed to it), a progress line per generation, the best parameters printed as JSON and, with
``--write``, recorded where the part script reads them (:mod:`transplanter.design.optimise`).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from transplanter.core.errors import SpecError

__all__ = ["run"]


def _settings(pairs: list[str]) -> dict[str, float]:
    """``--set NAME=VALUE`` options as keyword arguments (numbers) for a script's problem()."""
    out = {}
    for pair in pairs:
        name, sep, value = pair.partition("=")
        if not sep or not name.isidentifier():
            raise SpecError.out_of_range("--set", pair, "NAME=NUMBER, NAME a Python name")
        try:
            out[name] = float(value)
        except ValueError:
            raise SpecError.out_of_range(f"--set {name}", value, "a number") from None
        if not math.isfinite(out[name]):
            raise SpecError.out_of_range(f"--set {name}", value, "a finite number")
    return out


def run(args: argparse.Namespace) -> int:
    """Optimise the part script's ``problem()`` as ``args`` says and print the best design; the exit status."""
    import inspect
    import json
    import time

    import numpy as np

    from transplanter.core.errors import PartScriptError
    from transplanter.design.optimise import Problem, optimise
    from transplanter.families.builder.scripts import record_optimum, run_script

    path = Path(args.script)
    fn = run_script(path, timeout=args.timeout).get("problem")
    if not callable(fn):
        raise PartScriptError(
            f"{path}: an optimisable script (a part script or a design module beside one) must define "
            "problem() returning an optimise.Problem"
        )
    settings = _settings(args.set or [])
    try:
        inspect.signature(fn).bind(**settings)
    except TypeError as exc:
        raise SpecError(f"--set {', '.join(settings)}: {path}'s problem() does not take it ({exc})") from None
    problem = fn(**settings)
    if not isinstance(problem, Problem):
        raise PartScriptError(f"{path}: problem() returned {type(problem).__name__}, expected optimise.Problem")

    if args.write and problem.optimum is None:
        raise PartScriptError(
            f"{path}: --write records the optimum where the part script reads it, but problem() names no place: "
            "give Problem(..., optimum='OPTIMUM') (a module-level tuple of numbers in this file)"
        )
    start = time.perf_counter()

    def progress(gen: int, best: float, x) -> None:  # the best design so far, every generation
        design = json.dumps(problem.shown(x))
        left = (time.perf_counter() - start) / gen * (args.maxiter - gen)
        line = f"generation {gen:4d}/{args.maxiter}: best cost {best:.6g} at {design}; at most {left:.0f} s left"
        if problem.describe is not None:
            try:
                said = problem.describe(np.asarray(x, dtype=float))
                line += "\n  " + "; ".join(f"{k}: {v}" for k, v in said.items())
            except Exception as exc:  # the problem's own code: its failure is said, the run goes on
                line += f"\n  (its objectives cannot be described: {type(exc).__name__}: {exc})"
        print(line, file=sys.stderr, flush=True)

    res = optimise(
        problem,
        seed=args.seed,
        maxiter=args.maxiter,
        popsize=args.popsize,
        progress=progress,
        workers=args.workers,
        scheduler=args.scheduler,
    )
    out = {
        "problem": problem.name,
        "seed": args.seed,
        "cost": res.fun,
        "generations": res.generations,
        "evaluations": res.evaluations,
        "evaluation": "serial" if args.workers == 1 and args.scheduler is None else "parallel (deferred updating)",
        "parameters": problem.shown(res.x),
    }
    if args.write:
        where = record_optimum(path, problem.optimum, res.x)
        out["written"] = f"{problem.optimum} in {where}"
        print(f"the optimum is recorded as {problem.optimum} in {where}: a build follows it", file=sys.stderr)
    print(json.dumps(out, indent=2))
    return 0
