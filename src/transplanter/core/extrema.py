"""Extremes of a function sampled on a uniform grid, refined with scipy, and the peaks of a signal.

A dense scan finds the best sample; scipy's bounded scalar minimiser then refines within one
grid step either side of it. The refinement is kept only when it beats the sample, so a flat
top or a kink never makes the answer worse than the scan. Used for the extreme radii and
curvatures of pitch curves, the lowest and highest tip positions of planting arms and trains,
and the fastest tip speeds. :func:`prominent_peaks` is ``scipy.signal.find_peaks`` with a
prominence, for the meshing proof's scan of tip passes (the reason it is here is in its docstring).

Examples
--------
>>> import numpy as np
>>> from transplanter.core.extrema import refine_extreme
>>> x = np.linspace(0.0, 2 * np.pi, 16, endpoint=False)
>>> t, v = refine_extreme(np.sin, x, np.sin(x), largest=True)
>>> round(t, 9), round(v, 12)
(1.570796327, 1.0)
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy import optimize

__all__ = ["prominent_peaks", "refine_extreme"]


def refine_extreme(
    fn: Callable[[float], float], grid, values, largest: bool = False, xtol: float = 1e-12
) -> tuple[float, float]:
    """``(x, fn(x))`` at the extreme of scalar ``fn`` near the best of ``values`` = fn(``grid``).

    ``grid`` is uniform (increasing or decreasing); the refinement searches one step either
    side of the best sample to ``xtol``.
    """
    grid = np.asarray(grid, dtype=float)
    values = np.asarray(values, dtype=float)
    k = int(np.argmax(values) if largest else np.argmin(values))
    h = abs(float(grid[1] - grid[0]))
    sign = -1.0 if largest else 1.0
    res = optimize.minimize_scalar(
        lambda t: sign * float(fn(t)),
        bounds=(grid[k] - h, grid[k] + h),
        method="bounded",
        options={"xatol": xtol},
    )
    if res.success and res.fun < sign * values[k]:
        return float(res.x), float(sign * res.fun)
    return float(grid[k]), float(values[k])


def prominent_peaks(x, prominence: float) -> np.ndarray:
    """The indices of the peaks of ``x`` (1-D, no NaN) that stand out by at least ``prominence``:
    ``scipy.signal.find_peaks(x, prominence=prominence)[0]``, the same indices.

    Written out because importing ``scipy.signal`` loads ``scipy.stats``, which parses hundreds
    of docstrings as it loads: 0.36 s of CPU, 6 % of a ``transplanter pair`` call that needs this
    one function of it (issue 46). scipy's definitions, as its ``_local_maxima_1d`` and
    ``_peak_prominences`` implement them: a peak is a sample, or the middle (rounded down) of a
    run of equal samples, with a lower sample on either side, the first and last samples never;
    its prominence is its height over the higher of the lowest samples either side of it before
    a higher sample or the end. ``tests/test_meshing.py`` holds it to scipy's on random and
    plateaued signals.

    >>> prominent_peaks(np.array([0.0, 2.0, 1.0, 1.0, 3.0, 3.0, 3.0, 0.5, 0.6, 0.4, 1.0]), 0.5)
    array([1, 5])
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    if n < 3:
        return np.zeros(0, dtype=np.intp)
    # runs of equal samples: a run between lower ones, touching neither end, is a peak at its middle
    start = np.flatnonzero(np.concatenate([[True], x[1:] != x[:-1]]))
    end = np.append(start[1:], n) - 1
    v = x[start]
    rise = np.concatenate([[False], v[1:] > v[:-1]])
    fall = np.append(v[:-1] > v[1:], False)
    peak = rise & fall & (start > 0) & (end < n - 1)
    peaks = (start[peak] + end[peak]) // 2
    kept = []
    for i in peaks:
        top = x[i]
        higher = np.flatnonzero(x[:i] > top)
        left = x[(higher[-1] + 1 if len(higher) else 0) : i + 1].min()
        higher = np.flatnonzero(x[i:] > top)
        right = x[i : i + higher[0] if len(higher) else n].min()
        if top - max(left, right) >= prominence:
            kept.append(i)
    return np.asarray(kept, dtype=np.intp)
