"""The pair gate: both gears of a sized pair cut to mesh, after the closed-form checks.

:func:`generate_pair` resolves the backlash the pair is cut for (the cutter thickened by half
of it), checks that the cutter rolls on both pitch curves and — for an internal pair — holds
it to the closed-form interference limits along the pitch curves
(:func:`interference.pair_limits`) *before* cutting: ring tips that reach into the pinion's
fillet are trimmed to the limit (``trim_ring_tips``) or refused with the cutters that would
clear them (:func:`clearing_cutters`). Then each gear is cut by :func:`teeth.generate`, the
driver with a space and the driven gear with a tooth at the start contact. The searches that
cut trial pairs (the coarsest module, the first cutter that cuts) are in :mod:`cutter_choice`.
"""

from __future__ import annotations

from dataclasses import replace

from transplanter.core.errors import GeometryError, SpecError, TransplanterError, check_number
from transplanter.geometry.backlash import resolve_backlash
from transplanter.geometry.cutter import Cutter, ShaperCutter
from transplanter.geometry.interference import pair_limits, trimmed_addendum
from transplanter.geometry.pitch.arcframe import ArcFrame
from transplanter.geometry.teeth import ToothedGear, generate, require_cutter

__all__ = ["MIN_TRIMMED_ADDENDUM", "clearing_cutters", "generate_pair", "per_gear"]

#: Ring tips are not trimmed below this addendum (modules): shorter teeth lose their contact
#: ratio, so the pair needs another remedy (cutter, tooth-count difference)
MIN_TRIMMED_ADDENDUM = 0.3


def per_gear(name: str, value) -> tuple[float, float]:
    """``value`` (one number for both gears, or a (driver, driven) pair) as a checked pair."""
    pair = value if isinstance(value, tuple | list) else (value, value)
    if len(pair) != 2:
        raise SpecError.out_of_range(name, value, "a number or a (driver, driven) pair of numbers")
    return (check_number(f"{name} (driver)", pair[0], -2.0, 2.0), check_number(f"{name} (driven)", pair[1], -2.0, 2.0))


def clearing_cutters(pair, cutter: ShaperCutter, addendum, shift) -> list[int]:
    """Tooth counts (8 to 60) of the shaper cutters like ``cutter`` that pass this gate with these
    ``addendum`` and ``shift`` (driver, driven) and still roll on both pitch curves — the gate's
    remedy; closed form only, nothing is cut (the searches that cut are :mod:`cutter_choice`)."""
    add, sh = addendum, shift
    r, p = (0, 1) if pair.ring == "driver" else (1, 0)
    frames = [ArcFrame.from_curve(c) for c in (pair.driver, pair.driven)]
    good = []
    for z in range(8, 61):
        try:
            other = replace(cutter, teeth=z)
            for k, frame in enumerate(frames):
                other.check_fits(frame, internal=k == r, shift=sh[k])
            lim = pair_limits(
                pair, other, ring_addendum=add[r], pinion_addendum=add[p], ring_shift=sh[r], pinion_shift=sh[p]
            )
        except TransplanterError:
            continue
        if not lim.problems():
            good.append(z)
    return good


def _remedy(pair, cutter: ShaperCutter, add, sh) -> str:
    """:func:`clearing_cutters` in words, for the gate's refusal."""
    good = clearing_cutters(pair, cutter, add, sh)
    if not good:
        return "; no shaper cutter of 8 to 60 teeth clears it at these addenda"
    return (
        f"; cutters that clear it at these addenda: {good[0]} to {good[-1]} teeth"
        if good[-1] - good[0] + 1 == len(good)
        else f"; cutters that clear it at these addenda: {', '.join(map(str, good))} teeth"
    )


def generate_pair(
    pair,
    cutter: Cutter,
    teeth: tuple[int, int],
    *,
    backlash: float | None = None,
    addendum: float | tuple[float, float] = 1.0,
    shift: float | tuple[float, float] = 0.0,
    trim_ring_tips: bool = False,
    check_interference: bool = True,
    **kwargs,
) -> tuple[ToothedGear, ToothedGear]:
    """Both gears of a sized ``pitch.GearPair``: the driver with a space, the driven with a tooth at
    the start contact, so they mesh in the pair's start position.

    Parameters
    ----------
    backlash : float or None
        Circumferential backlash the pair is cut for, mm at the pitch point: each gear's teeth
        are thinned by half of it (the cutter is made ``backlash/2`` thicker). None: twice the
        cutter's own ``thickening`` if it has one, else the ISO/TR 10064-2 default
        (``backlash.design_backlash``). 0 only when zero backlash is really wanted.
    addendum, shift : float or (driver, driven)
        Addendum and profile-shift coefficients, for both gears or per gear.
    trim_ring_tips : bool
        Internal pairs are checked against the closed-form interference limits along the pitch
        curves (``interference.pair_limits``) *before* cutting. When the ring's tips reach into
        the pinion's fillet (or beyond the cutter's involute), True shortens the ring's
        addendum to the limit (less 0.02 m); False raises GeometryError naming the limit.
    check_interference : bool
        False cuts an interfering internal pair anyway (to study it: a finding), without raising.
    kwargs
        Go to :func:`generate` (``allow_undercut``, ``min_land``, ``rim``, ...).
    """
    ring = getattr(pair, "ring", None)
    add = list(per_gear("addendum", addendum))
    sh = per_gear("shift", shift)
    require_cutter(cutter)
    j = resolve_backlash(backlash, cutter.thickening, cutter.module, pair.centre_distance, cutter.pressure_angle)
    cutter = replace(cutter, thickening=j / 2)
    if ring is not None:
        for k, curve in enumerate((pair.driver, pair.driven)):  # a cutter that cannot roll says so first
            cutter.check_fits(ArcFrame.from_curve(curve), internal=(k == 0) == (ring == "driver"), shift=sh[k])
        r, p = (0, 1) if ring == "driver" else (1, 0)
        names = ("ring", "planet")

        def limits():
            return pair_limits(
                pair, cutter, ring_addendum=add[r], pinion_addendum=add[p], ring_shift=sh[r], pinion_shift=sh[p]
            )

        lim = limits()
        if trim_ring_tips and lim.max_ring_addendum < add[r]:
            trimmed = trimmed_addendum(lim.max_ring_addendum)
            if trimmed > MIN_TRIMMED_ADDENDUM:
                add[r] = trimmed
                lim = limits()
            elif check_interference:
                raise GeometryError(
                    f"ring-tip trimming would leave an addendum of {trimmed:.2f} m (limit > {MIN_TRIMMED_ADDENDUM} m): "
                    + "; ".join(lim.problems(names, trochoid=False))
                )
        # KHK's trochoid limit, exact for circular gears, refuses non-circular pairs that mesh
        # (tests/test_screen.py): the cut teeth's meshing check judges tip fouling instead
        found = lim.problems(names, trochoid=False)
        if found and check_interference:
            raise GeometryError(
                "the internal pair interferes before cutting: " + "; ".join(found) + _remedy(pair, cutter, add, sh)
            )
    driver = generate(
        pair.driver, cutter, teeth[0], internal=ring == "driver", phase=0.0, addendum=add[0], shift=sh[0], **kwargs
    )
    driven = generate(
        pair.driven, cutter, teeth[1], internal=ring == "driven", phase=0.5, addendum=add[1], shift=sh[1], **kwargs
    )
    return driver, driven
