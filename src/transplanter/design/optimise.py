"""Parameter optimisation of a mechanism with scipy's differential evolution.

A :class:`Problem` names its variables with bounds and maps a parameter vector to a scalar
cost (lower is better) in which constraints enter as penalties; a parameter set the model
rejects (a :class:`~transplanter.core.errors.TransplanterError`) costs ``infeasible``. The run is
reproducible (``seed``) and reports progress once per generation.

**Parallel evaluation.** ``workers=N`` evaluates each generation's candidates on N local
processes, ``scheduler="tcp://host:8786"`` on a Dask cluster (dask.distributed: a
``LocalCluster`` for the local case, the user's scheduler otherwise; the cost function is sent
with cloudpickle, so a part script's closures work, and scattered to every worker once per run:
:mod:`~transplanter.design.cluster`; a generation's candidates go out in batches that shrink to
one candidate; each local worker process runs one BLAS thread). scipy then updates the population once
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

import math
import re
import time
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import PartScriptError, SpecError, TransplanterError, check_int
from transplanter.design.cluster import SCHEDULER_TIMEOUT_S, ClusterMap, _evaluator, batch_bounds

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
