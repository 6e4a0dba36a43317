"""Cutter choice: the searches that cut trial pairs to find the cutter and module to make.

:func:`coarsest_cut` walks the fouling screen's tooth counts from coarse to fine and cuts each
as it will be shipped; :func:`first_cutter` takes the first standard shaper cutter (fewest
teeth first) that cuts both gears at a given module. The closed-form remedy the pair gate
names when it refuses a pair (which cutters clear its limits, nothing cut) is
:func:`pair_gate.clearing_cutters`.
"""

from __future__ import annotations

from transplanter.core.errors import GeometryError
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.interference import SCREEN_CUTTERS, ScreenResult, screen_module
from transplanter.geometry.pair_gate import generate_pair

__all__ = ["coarsest_cut", "first_cutter"]


def coarsest_cut(pair, *, max_module: float = 8.0, min_module: float = 0.5, **screen) -> ScreenResult | None:
    """The coarsest tooth count of an internal ``pair`` that passes the fouling screen
    (:func:`interference.screen_module`) *and* that the cutter can make: each screen result is
    cut as it will be shipped (:func:`generate_pair`, default backlash and chord tolerance —
    a trial at a coarser chord missed a 3 µm undercut); one the cutter refuses (undercut,
    secondary cutting, cutter fit) moves the search to the next finer tooth count. None if no
    module >= ``min_module`` passes both."""
    limit = max_module
    while True:
        found = screen_module(pair, max_module=limit, min_module=min_module, **screen)
        if found is None:
            return None
        sized, _ = pair.sized(teeth=found.teeth[0])
        try:
            generate_pair(
                sized,
                ShaperCutter(found.cutter_teeth, found.module),
                found.teeth,
                addendum=(found.ring_addendum, found.pinion_addendum)
                if pair.ring == "driver"
                else (found.pinion_addendum, found.ring_addendum),
                check_interference=False,
            )
        except GeometryError:
            limit = found.module * (1 - 1e-9)
            continue
        return found


def first_cutter(pair, teeth: tuple[int, int], module: float, backlash: float | None, **gate) -> ShaperCutter:
    """The first standard shaper cutter (``interference.SCREEN_CUTTERS``, fewest teeth first)
    that cuts both gears of the sized ``pair`` with ``teeth`` at ``module`` (mm), ring tips
    trimmed where the gate asks (``gate``: ``addendum``, ``shift``, ``trim_ring_tips``,
    ``allow_undercut`` as :func:`pair_gate.generate_pair` takes them); GeometryError with the last
    two refusals when none does."""
    reasons = []
    gate = {"trim_ring_tips": True} | gate
    for z0 in SCREEN_CUTTERS:
        cutter = ShaperCutter(z0, module)
        try:
            generate_pair(pair, cutter, teeth, backlash=backlash, **gate)
        except GeometryError as exc:
            reasons.append(f"z0 = {z0}: {exc}")
            continue
        return cutter
    raise GeometryError(
        f"no shaper cutter of {', '.join(map(str, SCREEN_CUTTERS))} teeth cuts this pair at m = {module:g} mm: "
        + " | ".join(reasons[-2:])
    )
