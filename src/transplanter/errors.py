"""One small exception hierarchy for every error a user can cause.

Every message names the parameter, the value it had and the limit it broke, so a
designer can fix the input without reading a traceback. Each class also inherits
the matching built-in exception, so ``except ValueError`` keeps working.

Examples
--------
>>> from transplanter.errors import SpecError, TransplanterError
>>> err = SpecError.out_of_range("crank", -1.0, "> 0 mm")
>>> isinstance(err, TransplanterError) and isinstance(err, ValueError)
True
>>> str(err)
'crank = -1.0 is out of range: must be > 0 mm'
"""

from __future__ import annotations

import math

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
]


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
    """``values`` as a float array; SpecError naming ``name`` if it is not finite."""
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SpecError(f"{name} must be numbers, got {values!r}") from exc
    if arr.ndim != ndim:
        raise SpecError(f"{name} must be a {ndim}-d array of numbers, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.isfinite(arr.ravel()))[0])
        raise SpecError(f"{name} must be finite; item {bad} is {arr.ravel()[bad]!r}")
    return arr


def finite_positive(name: str, value: float) -> float:
    """``value`` as a float > 0, or SpecError naming it."""
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise SpecError(f"{name} must be a number, got {value!r}") from exc
    if not math.isfinite(v) or v <= 0:
        raise SpecError.out_of_range(name, value, "finite and > 0")
    return v
