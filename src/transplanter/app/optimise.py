"""``transplanter optimise``: differential evolution on a script's ``problem()`` (``--set`` numbers
passed to it), a progress line per generation, the best parameters printed as JSON and, with
``--write``, recorded where the part script reads them (:mod:`transplanter.design.optimise`) —
only the tuple's numbers, only if better than the file's own, a design that misses an objective
only with ``--write-infeasible`` (:mod:`transplanter.families.builder.optimum`).
"""

from __future__ import annotations

import argparse
import inspect
import math
import sys
from pathlib import Path

from transplanter.core.errors import PartScriptError, SpecError

__all__ = ["run", "script_problem", "settings_of"]


def settings_of(pairs: list[str]) -> dict[str, float]:
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


def script_problem(path: Path, settings: dict[str, float], timeout: float | None):
    """(``problem(**settings)`` of the part script at ``path`` — or of a design module beside one —,
    the names of the module that defines it), run once; PartScriptError or SpecError saying why not."""
    from transplanter.design.optimise import Problem
    from transplanter.families.builder.scripts import run_script

    fn = run_script(path, timeout=timeout).get("problem")
    if not callable(fn):
        raise PartScriptError(
            f"{path}: an optimisable script (a part script or a design module beside one) must define "
            "problem() returning an optimise.Problem"
        )
    try:
        inspect.signature(fn).bind(**settings)
    except TypeError as exc:
        raise SpecError(f"--set {', '.join(settings)}: {path}'s problem() does not take it ({exc})") from None
    problem = fn(**settings)
    if not isinstance(problem, Problem):
        raise PartScriptError(f"{path}: problem() returned {type(problem).__name__}, expected optimise.Problem")
    return problem, dict(getattr(fn, "__globals__", {}))


def run(args: argparse.Namespace) -> int:
    """Optimise the part script's ``problem()`` as ``args`` says and print the best design; the exit status.

    With ``--write`` everything that could refuse the write is checked before the first generation
    (:mod:`transplanter.families.builder.optimum`: the file, its encoding, the tuple); after the run
    the optimum is written only if it costs less than the file's own tuple and, unless
    ``--write-infeasible``, misses no objective (:func:`transplanter.design.optimise.misses`)."""
    import json
    import time

    import numpy as np

    from transplanter.design.optimise import optimise
    from transplanter.families.builder.optimum import find_optimum, module_file

    path = Path(args.script)
    write = args.write or args.write_infeasible
    if write:  # before the script runs: a module that cannot be written is refused at once
        module_file(path)
    problem, _ = script_problem(path, settings_of(args.set or []), args.timeout)

    place = None
    if write:
        if problem.optimum is None:
            raise PartScriptError(
                f"{path}: --write records the optimum where the part script reads it, but problem() names no place: "
                "give Problem(..., optimum='OPTIMUM') (a module-level tuple of numbers in this file)"
            )
        place = find_optimum(module_file(path), problem.optimum, len(problem.variables))
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
    if place is not None:
        out.update(_write(problem, place, res, args.write_infeasible))
    print(json.dumps(out, indent=2))
    return 0


def _write(problem, place, res, infeasible: bool) -> dict:
    """Record ``res.x`` at ``place`` if it beats the file's own tuple and (unless ``infeasible``)
    misses no objective; what was done, for the JSON printed (``written`` or ``not_written``)."""
    import numpy as np

    from transplanter.design.optimise import misses
    from transplanter.families.builder.optimum import record_optimum

    where = place.module.path
    held = problem(np.asarray(place.values, dtype=float))  # the baseline: the design the file holds
    if not res.fun < held:
        why = (
            f"the optimum (cost {res.fun:.6g}) is no better than {place.name} in {where} (cost {held:.6g}): "
            "nothing written"
        )
        print(why, file=sys.stderr)
        return {"written": None, "not_written": why}
    missed, said = [], None
    if problem.describe is not None:
        try:
            missed = misses(problem.describe(np.asarray(res.x, dtype=float)))
        except Exception as exc:  # the problem's own code: a design that cannot be judged is not taken as met
            said = f"its objectives cannot be described ({type(exc).__name__}: {exc})"
    if missed:
        said = "it misses " + "; ".join(f"{objective}: {text}" for objective, text, _ in missed)
    if said and not infeasible:
        why = f"{said}: not written to {place.name} in {where} (--write-infeasible writes it anyway)"
        print(f"the optimum {why}", file=sys.stderr)
        return {"written": None, "not_written": why}
    choices = tuple(name in problem.choices for name, _, _ in problem.variables)
    target = record_optimum(place, res.x, choices)
    if target is None:
        why = f"the optimum is the design {place.name} in {where} already holds: nothing written"
        print(why, file=sys.stderr)
        return {"written": None, "not_written": why}
    shown_at = f"{where} (a link: written at its target {target})" if where.is_symlink() else where
    print(f"the optimum is recorded as {place.name} in {shown_at}: a build follows it", file=sys.stderr)
    if said:
        print(f"  written as asked (--write-infeasible), though {said}", file=sys.stderr)
    return {"written": f"{place.name} in {shown_at}", **({"misses": said} if said else {})}
