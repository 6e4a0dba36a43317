"""Extremes of a function sampled on a uniform grid, refined with scipy.

A dense scan finds the best sample; scipy's bounded scalar minimiser then refines within one
grid step either side of it. The refinement is kept only when it beats the sample, so a flat
top or a kink never makes the answer worse than the scan. Used for the extreme radii and
curvatures of pitch curves, the lowest and highest tip positions of planting arms and trains,
and the fastest tip speeds.

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

__all__ = ["refine_extreme"]


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
