"""One designer's session in the studio, without the browser: the design vector, its checks,
undo and redo, the view computed and timed, a saved design's JSON.

Every value the page sends goes through :func:`value_of` (the variable's name, range and unit:
:func:`transplanter.core.errors.check_number`), so a bad one is a message beside its variable,
never a traceback and never a silently different design.

Examples
--------
>>> from transplanter.design.optimise import Problem
>>> p = Problem("bowl", (("x_mm", -2.0, 2.0), ("y", 0.0, 1.0)), lambda v: float(v[0] ** 2))
>>> s = Session(p, (0.5, 0.5))
>>> s.set("x_mm", "1.25")
(1.25, 0.5)
>>> s.set("x_mm", "3")
Traceback (most recent call last):
...
transplanter.core.errors.SpecError: x_mm = 3.0 is out of range: must be >= -2 mm and <= 2 mm
>>> s.undo(), s.redo()
((0.5, 0.5), (1.25, 0.5))
>>> Session.load(p, s.saved()).x
(1.25, 0.5)
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import PartScriptError, SpecError, TransplanterError, check_number
from transplanter.design.optimise import Problem
from transplanter.design.views import DesignView, Row, rows_from_description

__all__ = ["FORMAT", "MAX_SAVED_BYTES", "Computed", "Session", "unit_of", "value_of"]

#: the saved design's format name and version (``save`` writes it, ``load`` requires it)
FORMAT = ("transplanter-design", 1)
#: a saved design is a few hundred bytes; a larger upload is not one
MAX_SAVED_BYTES = 100_000
#: undo steps kept
MAX_UNDO = 200

_UNITS = {"mm": "mm", "deg": "deg", "rad": "rad", "n": "N", "s": "s", "rpm": "r/min"}


def unit_of(name: str) -> str:
    """A variable's unit from its name's suffix (``carrier_radius_mm`` -> mm); '' if none."""
    tail = name.rsplit("_", 1)[-1].lower() if "_" in name else ""
    return _UNITS.get(tail, "")


def value_of(problem: Problem, name: str, text) -> float:
    """The value ``text`` (a number or its text) for variable ``name`` of ``problem``, checked
    against its range; SpecError naming the variable, the value and the range."""
    bounds = {n: (lo, hi) for n, lo, hi in problem.variables}
    if name not in bounds:
        raise SpecError.out_of_range("variable", name, f"one of {', '.join(bounds)}")
    lo, hi = bounds[name]
    if isinstance(text, str):
        try:
            number = float(text.strip())
        except ValueError:
            raise SpecError.out_of_range(name, text, "a number") from None
    else:
        number = text
    return check_number(name, number, lo, hi, unit=unit_of(name))


@dataclass(frozen=True)
class Computed:
    """A design's view (or why there is none) and the server's time for it, ms."""

    x: tuple[float, ...]
    view: DesignView | None
    error: str
    ms: float


class Session:
    """The design being edited: its vector, the undo and redo stacks."""

    def __init__(self, problem: Problem, x) -> None:
        self.problem = problem
        self.x = tuple(value_of(problem, n, float(v)) for (n, _, _), v in zip(problem.variables, x, strict=True))
        self._undo: list[tuple[float, ...]] = []
        self._redo: list[tuple[float, ...]] = []

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(n for n, _, _ in self.problem.variables)

    def _move(self, x: tuple[float, ...]) -> tuple[float, ...]:
        if x != self.x:
            self._undo = [*self._undo[-MAX_UNDO + 1 :], self.x]
            self._redo = []
            self.x = x
        return self.x

    def set(self, name: str, text) -> tuple[float, ...]:
        """The design with ``name`` set to ``text`` (checked: :func:`value_of`); one undo step."""
        v = value_of(self.problem, name, text)
        k = self.names.index(name)
        return self._move((*self.x[:k], v, *self.x[k + 1 :]))

    def adopt(self, x) -> tuple[float, ...]:
        """The design ``x`` (every value checked), e.g. an optimum or a loaded design; one undo step."""
        return self._move(tuple(value_of(self.problem, n, float(v)) for n, v in zip(self.names, x, strict=True)))

    def undo(self) -> tuple[float, ...]:
        if self._undo:
            self._redo.append(self.x)
            self.x = self._undo.pop()
        return self.x

    def redo(self) -> tuple[float, ...]:
        if self._redo:
            self._undo.append(self.x)
            self.x = self._redo.pop()
        return self.x

    def compute(self, x: tuple[float, ...] | None = None) -> Computed:
        """The view of ``x`` (default: the current design), timed: the problem's ``view``, or
        its cost and ``describe`` rows. A design the model rejects is said, not raised."""
        x = self.x if x is None else x
        v = np.asarray(x, dtype=float)
        start = time.perf_counter()
        try:
            view = self._view(v)
        except TransplanterError as exc:
            return Computed(x, None, f"this design cannot be built: {exc}", (time.perf_counter() - start) * 1e3)
        except Exception as exc:  # the part script's own code: said as such
            said = PartScriptError(f"the part script's view of this design failed: {type(exc).__name__}: {exc}")
            return Computed(x, None, str(said), (time.perf_counter() - start) * 1e3)
        return Computed(x, view, "", (time.perf_counter() - start) * 1e3)

    def _view(self, v: np.ndarray) -> DesignView:
        p = self.problem
        if p.view is not None:
            out = p.view(v)
            if not isinstance(out, DesignView):
                raise PartScriptError(
                    f"problem {p.name!r}: view() returned {type(out).__name__}, expected a DesignView"
                )
            return out
        cost = p(v)
        rows = (Row("cost (lower is better)", float(cost), "", "", 0.0, cost < p.infeasible),)
        if p.describe is not None:
            rows += rows_from_description(p.describe(v))
        return DesignView(rows=rows)

    def saved(self) -> str:
        """The design as a small versioned JSON document."""
        doc = {"format": FORMAT[0], "version": FORMAT[1], "problem": self.problem.name}
        doc["design"] = dict(zip(self.names, self.x, strict=True))
        return json.dumps(doc, indent=1)

    @classmethod
    def load(cls, problem: Problem, text: str | bytes) -> Session:
        """A session on the design saved in ``text`` (:meth:`saved`); SpecError saying what is
        wrong with it (its size, format, version, problem, a variable missing, unknown or out of range)."""
        if len(text) > MAX_SAVED_BYTES:
            raise SpecError.out_of_range("saved design", f"{len(text)} bytes", f"at most {MAX_SAVED_BYTES} bytes")
        try:
            doc = json.loads(text)
        except (ValueError, UnicodeDecodeError) as exc:
            raise SpecError(f"saved design: not JSON ({exc})") from None
        except RecursionError:  # brackets nested deeper than any design
            raise SpecError("saved design: not a design (nested deeper than Python reads)") from None
        if not isinstance(doc, dict) or doc.get("format") != FORMAT[0]:
            raise SpecError(f"saved design: not a {FORMAT[0]} document")
        if doc.get("version") != FORMAT[1]:
            raise SpecError.out_of_range("saved design version", doc.get("version"), f"{FORMAT[1]}")
        if doc.get("problem") != problem.name:
            raise SpecError.out_of_range("saved design problem", doc.get("problem"), repr(problem.name))
        design = doc.get("design")
        names = tuple(n for n, _, _ in problem.variables)
        if not isinstance(design, dict) or set(design) != set(names):
            got = sorted(design) if isinstance(design, dict) else design
            raise SpecError.out_of_range("saved design variables", got, ", ".join(names))
        return cls(problem, tuple(value_of(problem, n, design[n]) for n in names))
