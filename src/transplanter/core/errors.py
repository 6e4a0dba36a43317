"""One small exception hierarchy for every error a user can cause.

Every message names the parameter, the value it had and the limit it broke, so a
designer can fix the input without reading a traceback. Each class also inherits
the matching built-in exception, so ``except ValueError`` keeps working.

Examples
--------
>>> from transplanter.core.errors import SpecError, TransplanterError
>>> err = SpecError.out_of_range("crank", -1.0, "> 0 mm")
>>> isinstance(err, TransplanterError) and isinstance(err, ValueError)
True
>>> str(err)
'crank = -1.0 is out of range: must be > 0 mm'
"""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = [
    "TransplanterError",
    "SpecError",
    "AssemblyError",
    "GeometryError",
    "PartScriptError",
    "ExportError",
    "finite_array",
    "finite_positive",
    "check_number",
    "check_int",
    "MAX_MAGNITUDE",
]

#: Largest magnitude any length (mm) or other size parameter may have: 1e6 mm is a kilometre,
#: beyond any machine part, and squares of larger values lose the precision the geometry
#: needs (near 1e308 they overflow).
MAX_MAGNITUDE = 1e6


class TransplanterError(Exception):
    """Base class of every error raised on purpose by transplanter."""


class SpecError(TransplanterError, ValueError):
    """A parameter is missing, not finite, or outside its allowed range."""

    @classmethod
    def out_of_range(cls, name: str, value: object, limit: str) -> SpecError:
        return cls(f"{name} = {value!r} is out of range: must be {limit}")


class AssemblyError(SpecError):
    """A mechanism cannot be assembled, or its input link cannot turn fully."""


class GeometryError(TransplanterError, ValueError):
    """Geometry that cannot be made: a curve that does not close, an undercut, ..."""


class PartScriptError(TransplanterError, ValueError):
    """A part script in ``parts/`` is malformed or returns the wrong thing."""


class ExportError(TransplanterError, OSError):
    """A file could not be written; nothing half-written is left behind."""


def finite_array(name: str, values, ndim: int = 1) -> np.ndarray:
    """``values`` as a float array; SpecError naming ``name`` if it is not numbers (text such as
    ``"40"`` is refused, not read as one) or not finite."""
    try:
        raw = np.asarray(values)
        if raw.dtype.kind in "USVb" or (
            raw.dtype.kind == "O" and any(isinstance(v, str | bytes | bool) for v in raw.ravel())
        ):
            raise TypeError("text or booleans")
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SpecError(f"{name} must be numbers, got {values!r}") from exc
    if arr.ndim != ndim:
        raise SpecError(f"{name} must be a {ndim}-d array of numbers, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.isfinite(arr.ravel()))[0])
        raise SpecError(f"{name} must be finite; item {bad} is {arr.ravel()[bad]!r}")
    return arr


def _real(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise SpecError(f"{name} must be a number, got {value!r}")
    try:
        v = float(value)
    except OverflowError:  # an integer beyond any float (10**400): said by its size, not its digits
        raise SpecError.out_of_range(name, f"an integer of {len(str(value).lstrip('-'))} digits", "finite") from None
    if not math.isfinite(v):
        raise SpecError.out_of_range(name, value, "finite")
    return v


def check_number(
    name: str,
    value,
    low: float | None = None,
    high: float | None = MAX_MAGNITUDE,
    *,
    low_open: bool = False,
    high_open: bool = False,
    unit: str = "",
) -> float:
    """``value`` as a finite float in [low, high] (open ends with ``low_open``/``high_open``),
    or SpecError naming the parameter, the value and the rule. The one validation path for the
    numeric parameters of public constructors."""
    v = _real(name, value)
    u = f" {unit}" if unit else ""
    lo_ok = low is None or (v > low if low_open else v >= low)
    hi_ok = high is None or (v < high if high_open else v <= high)
    if not (lo_ok and hi_ok):
        parts = []
        if low is not None:
            parts.append(f"{'>' if low_open else '>='} {low:g}{u}")
        if high is not None:
            parts.append(f"{'<' if high_open else '<='} {high:g}{u}")
        raise SpecError.out_of_range(name, value, " and ".join(parts))
    return v


def check_int(name: str, value, low: int, high: int) -> int:
    """``value`` as an int in [low, high], or SpecError naming it (bools and floats are refused)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise SpecError.out_of_range(name, value, f"an integer from {low} to {high}")
    v = int(value)
    if not low <= v <= high:
        raise SpecError.out_of_range(name, value, f"an integer from {low} to {high}")
    return v


def finite_positive(name: str, value: float, high: float = MAX_MAGNITUDE) -> float:
    """``value`` as a float > 0 and <= ``high``, or SpecError naming it."""
    v = _real(name, value)
    if v <= 0 or v > high:
        raise SpecError.out_of_range(name, value, f"finite, > 0 and <= {high:g}")
    return v
