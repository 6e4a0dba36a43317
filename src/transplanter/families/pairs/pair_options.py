"""The options of a one-call gear pair checked before anything is made or written.

:func:`check_options` takes what :func:`~transplanter.families.pairs.gear_pair.pair_family` (and so
``transplanter pair``) is given and refuses — in one :class:`~transplanter.core.errors.SpecError`
naming the parameter **as the user gave it** (``names``: the Python keywords by default, the
command line's flags for ``transplanter pair``), its value and its limit — every option that

* is out of its range: a number that is not finite, not positive where it must be, beyond its
  limit (``MIN_MODULE``..``MAX_MODULE``, the tooth counts, ``MAX_ADDENDUM``, ``SHIFT_LIMIT``, ...);
* does not apply to the pair the transmission states: ``ring`` for an external pair or a named
  curve, ``driven_lobes`` for a ratio, ``scale_to_close`` for a named curve (it closes by
  construction), ``trim_ring_tips=False`` for an external pair, ``rack`` for a ring, the full
  pairs' options for a law with dwells and the locks' options for a full pair;
* does not fit the pair at the sizes given, derived from the inputs before anything is cut: the
  ISO/TR 10064-2 default backlash grows with the centre distance and must stay below the module
  (so the centre distance and the teeth have an upper limit at each module, unless the backlash is
  given); both gears carry ``MIN_GEAR_TEETH`` to ``MAX_TEETH`` teeth; for a law with dwells, the
  working depth must exceed the locking arc's depth, and every dwell's lock and every motion's
  sector must fit at that size (:func:`transplanter.geometry.incomplete.check_fit`: the cut's own
  computations, run without cutting) — an error there names the law's segment (its number and
  text, or its angles in the ratio CSV) and the sizes the user gave.

It returns what it found (the law, the pitch pair, the sized study) so that nothing is read or
solved twice.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from transplanter.core import inputs
from transplanter.core.errors import SpecError, check_int, check_number
from transplanter.families.builder.making import MIN_FACE_WIDTH_MM
from transplanter.families.pairs.incomplete_pair import LOCKING_PLAY_DEG, IncompletePairStudy
from transplanter.geometry.backlash import design_backlash
from transplanter.geometry.cutter import RackCutter, ShaperCutter
from transplanter.geometry.incomplete import INTERNAL_LOCK_SHORT_OF_TIPS, LOCK_DEPTH, LockFitError, check_fit
from transplanter.geometry.pitch.intermittent import Dwell, IntermittentLaw, is_segmented
from transplanter.geometry.pitch.transmission import (
    NAMED_CURVES,
    Transmission,
    csv_table,
    is_named_curve,
    transmission,
)
from transplanter.geometry.toothed_sectors import SectorFitError

__all__ = [
    "Checked",
    "INTERNAL_RING_ADDENDUM",
    "MAX_ADDENDUM",
    "MAX_MODULE",
    "MIN_GEAR_TEETH",
    "MIN_MODULE",
    "PYTHON_NAMES",
    "SHIFT_LIMIT",
    "check_options",
    "chosen_cutter",
]

#: the options of :func:`~transplanter.families.pairs.gear_pair.pair_family`, named as in Python
PYTHON_NAMES: Mapping[str, str] = {"spec": "the transmission"} | {
    k: k
    for k in (
        "internal",
        "teeth",
        "module",
        "centre_distance",
        "driven_lobes",
        "ring",
        "backlash",
        "cutter_teeth",
        "rack",
        "width",
        "name",
        "scale_to_close",
        "addendum",
        "shift",
        "trim_ring_tips",
        "allow_undercut",
        "lock_clearance",
        "lock_depth",
        "locking_play",
    )
}
#: the module range a pair is made in, mm: below 0.05 mm a tooth is finer than the wire that cuts
#: it (0.25 mm) can follow; above 100 mm no plate is cut
MIN_MODULE, MAX_MODULE = 0.05, 100.0
#: the fewest teeth a gear of a full pair is cut with (``teeth.generate``'s limit: fewer do not
#: make a gear whose flanks the cutter generates)
MIN_GEAR_TEETH = 6
#: the fewest teeth on the first motion's sector of an incomplete pair (``--teeth``)
MIN_SECTOR_TEETH = 3
#: the largest addendum coefficient, modules (``teeth.generate``'s); it must be > 0
MAX_ADDENDUM = 2.0
#: the largest profile shift either way, modules (``teeth.generate``'s)
SHIFT_LIMIT = 1.5
#: the widest face, mm
MAX_WIDTH = 1000.0
#: the most locking play asked for, deg
MAX_LOCKING_PLAY = 45.0
#: an internal incomplete pair's ring addendum when none is given (modules): its tips clear the
#: planet's as a full ring's are trimmed to the closed-form interference limit
INTERNAL_RING_ADDENDUM = 0.8


@dataclass(frozen=True, eq=False)
class Checked:
    """What :func:`check_options` found: for a law with dwells its ``law`` and ``study`` (sized,
    not made); for a full pair its ``found`` transmission and the ``pair`` and ``sizing`` of it."""

    law: IntermittentLaw | None = None
    study: IncompletePairStudy | None = None
    found: Transmission | None = None
    pair: object = None
    sizing: object = None


def chosen_cutter(rack, cutter_teeth, module: float | None, names: Mapping[str, str] = PYTHON_NAMES):
    """The cutter the user chose at ``module`` (mm; None: its study's): the rack, a shaper of
    ``cutter_teeth``, or None (neither given); both given is refused."""
    inputs.boolean(names["rack"], rack)  # a truthy string ('no') must not select the rack cutter
    if rack:
        if cutter_teeth is not None:
            raise SpecError(
                f"give either {names['rack']} or {names['cutter_teeth']} (a shaper cutter's teeth), not both"
            )
        return RackCutter(module)
    if cutter_teeth is None:
        return None
    return ShaperCutter(check_int(names["cutter_teeth"], cutter_teeth, 8, 200), module)


def _per_gear(name: str, value, low: float, high: float, **open_ends) -> tuple[float, float]:
    """``value``: one number for both gears or a (driver, driven) pair, each in [low, high]."""
    pair = value if isinstance(value, tuple | list) else (value, value)
    if len(pair) != 2:
        raise SpecError.out_of_range(name, value, "a number or a (driver, driven) pair of numbers")
    if isinstance(value, tuple | list):
        driver = check_number(f"{name} (driver)", pair[0], low, high, **open_ends)
        return driver, check_number(f"{name} (driven)", pair[1], low, high, **open_ends)
    v = check_number(name, value, low, high, **open_ends)
    return v, v


def check_options(spec, names: Mapping[str, str] | None = None, **options) -> Checked:
    """Every option of ``pair_family(spec, **options)`` checked (module docstring), each refusal
    naming the parameter by ``names`` (default :data:`PYTHON_NAMES`); what it found."""
    n = {**PYTHON_NAMES, **(names or {})}
    o = {
        "internal": False,
        "teeth": None,
        "module": None,
        "centre_distance": None,
        "driven_lobes": None,
        "ring": None,
        "backlash": None,
        "cutter_teeth": None,
        "rack": False,
        "width": 10.0,
        "name": "pair",
        "scale_to_close": False,
        "addendum": 1.0,
        "shift": 0.0,
        "trim_ring_tips": True,
        "allow_undercut": False,
        "lock_clearance": None,
        "lock_depth": None,
        "locking_play": LOCKING_PLAY_DEG,
        **options,
    }
    if not isinstance(spec, str) or not spec.strip():
        raise SpecError(
            f"{n['spec']} must be an expression in phi, a law of segments, a CSV file or a named curve, got {spec!r}"
        )
    for flag in ("internal", "rack", "scale_to_close", "trim_ring_tips", "allow_undercut"):
        inputs.boolean(n[flag], o[flag])
    if not isinstance(o["name"], str) or not _is_file_name(o["name"]):
        raise SpecError.out_of_range(
            n["name"], o["name"], "a file name: a letter or digit first, then letters, digits, '_', '-', '.'"
        )
    check_number(n["width"], o["width"], MIN_FACE_WIDTH_MM, MAX_WIDTH, unit="mm")
    if o["module"] is not None:
        check_number(n["module"], o["module"], MIN_MODULE, MAX_MODULE, unit="mm")
    if o["centre_distance"] is not None:
        check_number(n["centre_distance"], o["centre_distance"], 0.0, low_open=True, unit="mm")
    if o["backlash"] is not None:
        check_number(n["backlash"], o["backlash"], 0.0, MAX_MODULE, unit="mm")
    if o["cutter_teeth"] is not None:
        check_int(n["cutter_teeth"], o["cutter_teeth"], 8, 200)
    if o["rack"] and o["cutter_teeth"] is not None:
        chosen_cutter(True, o["cutter_teeth"], None, n)
    if o["rack"] and o["internal"]:
        raise SpecError(f"{n['rack']} with {n['internal']}: a rack cutter (hob) cannot cut a ring gear - leave it out")
    if o["internal"] is False and o["ring"] is not None:
        raise SpecError(f"{n['ring']} = {o['ring']!r} is for internal pairs ({n['internal']}): leave it out")
    law = _law(spec)
    if law is not None:
        return _check_incomplete(spec, law, o, n)
    for key in ("lock_clearance", "lock_depth"):
        if o[key] is not None:
            raise SpecError(f"{n[key]} is for incomplete pairs (a law with dwells): leave it out")
    if o["locking_play"] != LOCKING_PLAY_DEG:
        raise SpecError(f"{n['locking_play']} is for incomplete pairs (a law with dwells): leave it out")
    return _check_full(spec, o, n)


def _is_file_name(name: str) -> bool:
    """A family's (folder's) name: a letter or digit first, then letters, digits, '_', '-', '.'."""
    return re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", name) is not None


def _law(spec: str) -> IntermittentLaw | None:
    """The law with dwells ``spec`` states (segments, or a ratio CSV with zero rows), else None."""
    if is_segmented(spec):
        return IntermittentLaw.parse(spec)
    if inputs.is_csv_path(spec):
        deg, ratio = csv_table(inputs.read_data_file("ratio CSV", spec, inputs.MAX_CSV_BYTES))
        if np.any(ratio == 0):
            return IntermittentLaw.from_table(deg, ratio)
    return None


def _sizes(o: dict, n, a: float | None = None) -> str:
    """The sizes the user gave, as given (and the centre distance they make)."""
    given = [f"{n[k]} = {o[k]:g}" for k in ("teeth", "module", "centre_distance") if o[k] is not None]
    made = f" (centre distance {a:.6g} mm)" if a is not None and o["centre_distance"] is None else ""
    return " and ".join(given) + made


def _backlash_fits(o: dict, n, module: float, a: float, pressure_angle: float) -> None:
    """The ISO/TR 10064-2 default backlash, which grows with the centre distance, below the module
    (else the teeth would be thinned away): refused naming the sizes given and the largest centre
    distance at this module — unless the backlash is given."""
    if o["backlash"] is not None:
        return
    iso = design_backlash(module, a, pressure_angle)
    if iso < module:
        return
    per_mm = design_backlash(module, 2.0, pressure_angle) - design_backlash(module, 1.0, pressure_angle)
    a_max = (module - (design_backlash(module, 1.0, pressure_angle) - per_mm)) / per_mm
    raise SpecError(
        f"{_sizes(o, n, a)}: the ISO/TR 10064-2 default backlash at {a:.6g} mm between the axes, {iso:.4g} mm, is "
        f"not below the module ({module:g} mm): at this module the centre distance must stay below {a_max:.6g} mm "
        f"- or give {n['backlash']}"
    )


def _check_full(spec: str, o: dict, n) -> Checked:
    """A full pair's options: what applies to the transmission, the ranges, the sizes it makes."""
    named = is_named_curve(spec)
    if not named and o["driven_lobes"] is not None:
        raise SpecError(
            f"{n['driven_lobes']} is for named curves ({', '.join(NAMED_CURVES)}): a ratio fixes the driven gear's "
            "lobes itself - leave it out"
        )
    if named and o["scale_to_close"]:
        raise SpecError(
            f"{n['scale_to_close']} is for a ratio (an expression or a CSV): a named curve's mate closes by "
            "construction - leave it out"
        )
    if named and o["ring"] is not None:
        raise SpecError(
            f"{n['ring']} = {o['ring']!r} is for internal pairs from a ratio: a named curve is the planet, its mate "
            "the ring - leave it out"
        )
    if o["ring"] not in (None, "driven", "driver"):
        raise SpecError.out_of_range(n["ring"], o["ring"], "'driven' or 'driver'")
    if not o["internal"] and not o["trim_ring_tips"]:
        raise SpecError(f"{n['trim_ring_tips']} is for internal pairs (a ring's tips): leave it out")
    if o["driven_lobes"] is not None:
        check_int(n["driven_lobes"], o["driven_lobes"], 1, 100)
    _per_gear(n["addendum"], o["addendum"], 0.0, MAX_ADDENDUM, low_open=True, unit="modules")
    _per_gear(n["shift"], o["shift"], -SHIFT_LIMIT, SHIFT_LIMIT, unit="modules")
    if sum(o[k] is not None for k in ("teeth", "module", "centre_distance")) != 2:
        raise SpecError(
            f"give two of {n['teeth']}, {n['module']} and {n['centre_distance']} (teeth and module fix the size; "
            "with the centre distance, the other follows)"
        )
    if o["teeth"] is not None:
        check_int(n["teeth"], o["teeth"], 1, inputs.MAX_TEETH)
    mesh = "internal" if o["internal"] else "external"
    found = transmission(
        spec, mesh, driven_lobes=o["driven_lobes"], ring=o["ring"] or "driven", scale_to_close=o["scale_to_close"]
    )
    lobes = found.pair.lobes[0]
    if o["teeth"] is not None and o["teeth"] % lobes:
        raise SpecError.out_of_range(n["teeth"], o["teeth"], f"a positive multiple of the driver's {lobes} lobes")
    pair = found.pair
    if o["centre_distance"] is not None:
        pair = pair.scaled(o["centre_distance"] / pair.centre_distance)
        pair, sizing = pair.sized(teeth=o["teeth"]) if o["teeth"] is not None else pair.sized(module=o["module"])
    else:
        pair = pair.scaled(o["teeth"] * math.pi * o["module"] / pair.driver.perimeter)
        pair, sizing = pair.sized(teeth=o["teeth"])
    z1, z2 = (int(z) for z in sizing.teeth)
    if not (MIN_GEAR_TEETH <= min(z1, z2) and max(z1, z2) <= inputs.MAX_TEETH):
        raise SpecError(
            f"{_sizes(o, n)} make gears of {z1} and {z2} teeth: each must have {MIN_GEAR_TEETH} to "
            f"{inputs.MAX_TEETH} teeth"
        )
    if not MIN_MODULE <= sizing.module <= MAX_MODULE:
        raise SpecError(
            f"{_sizes(o, n)} make a module of {sizing.module:.4g} mm: it must be {MIN_MODULE:g} to {MAX_MODULE:g} mm"
        )
    if o["backlash"] is not None and not o["backlash"] < sizing.module:
        raise SpecError.out_of_range(n["backlash"], o["backlash"], f">= 0 mm and < the module, {sizing.module:.6g} mm")
    _backlash_fits(o, n, sizing.module, pair.centre_distance, ShaperCutter(12).pressure_angle)
    return Checked(found=found, pair=pair, sizing=sizing)


def _segment(law: IntermittentLaw, k: int, spec: str) -> str:
    """Segment ``k`` (index) of the law as the user stated it: its number and text, or its angles
    in the ratio CSV."""
    seg = law.segments[k]
    kind = "dwell" if isinstance(seg, Dwell) else "motion"
    if inputs.is_csv_path(spec):
        return f"the {kind} {seg.start % 360:g}..{seg.end % 360:g} deg of the ratio CSV {spec!r}"
    text = f"{seg.start:g}..{seg.end:g}: {'dwell' if isinstance(seg, Dwell) else seg.law}"
    return f"the law's segment {k + 1} {text if len(text) <= 60 else text[:57] + '...'!r} (a {kind})"


def _check_incomplete(spec: str, law: IntermittentLaw, o: dict, n) -> Checked:
    """A law with dwells: the full pairs' options refused, the ranges, then the sizes and every lock
    and sector at them (module docstring)."""
    refused = {
        "driven_lobes": o["driven_lobes"] is not None,
        "ring": o["ring"] is not None,
        "scale_to_close": o["scale_to_close"] is not False,
        "shift": o["shift"] != 0.0,
        "trim_ring_tips": o["trim_ring_tips"] is not True,
        "allow_undercut": o["allow_undercut"] is not False,
    }
    for key, given in refused.items():
        if given:
            raise SpecError(f"{n[key]} does not apply to an incomplete pair (a law with dwells): leave it out")
    if o["module"] is None or (o["teeth"] is None) == (o["centre_distance"] is None):
        raise SpecError(
            f"an incomplete pair is sized by {n['module']} and one of {n['teeth']} (the driver's on the first "
            f"motion's sector) or {n['centre_distance']}"
        )
    m = o["module"]
    if o["teeth"] is not None:
        check_int(n["teeth"], o["teeth"], MIN_SECTOR_TEETH, inputs.MAX_TEETH)
    if o["centre_distance"] is not None:
        check_number(n["centre_distance"], o["centre_distance"], 0.0, 100_000.0, low_open=True, unit="mm")
    internal = o["internal"]
    addendum = (1.0, INTERNAL_RING_ADDENDUM) if internal and o["addendum"] == 1.0 else o["addendum"]
    add = _per_gear(n["addendum"], o["addendum"], 0.0, MAX_ADDENDUM, low_open=True, unit="modules")
    add = add if addendum is o["addendum"] else addendum
    work = add[0] + add[1]
    check_number(n["locking_play"], o["locking_play"], 0.0, MAX_LOCKING_PLAY, low_open=True, unit="deg")
    if o["lock_depth"] is not None:
        check_number(n["lock_depth"], o["lock_depth"], 0.0, work, low_open=True, high_open=True, unit="modules")
    elif not internal and not LOCK_DEPTH < work:
        raise SpecError.out_of_range(
            n["addendum"],
            o["addendum"],
            f"a working depth (driver + driven addendum, here {work:g} modules) beyond the locking arc's reach into "
            f"the driven's tips, {LOCK_DEPTH:g} modules ({n['lock_depth']}'s default)",
        )
    elif internal and not INTERNAL_LOCK_SHORT_OF_TIPS < work:
        raise SpecError.out_of_range(
            n["addendum"],
            o["addendum"],
            f"a working depth (driver + driven addendum, here {work:g} modules) beyond "
            f"{INTERNAL_LOCK_SHORT_OF_TIPS:g} modules, which the planet's locking arc stops short of its tips",
        )
    if o["lock_clearance"] is not None:
        check_number(n["lock_clearance"], o["lock_clearance"], 0.0, m, low_open=True, high_open=True, unit="mm")
    if o["backlash"] is not None:
        check_number(n["backlash"], o["backlash"], 0.0, m, low_open=True, high_open=True, unit="mm")
    if internal:
        for k, seg in enumerate(law.segments):
            if not isinstance(seg, Dwell):
                phi = np.linspace(math.radians(seg.start), math.radians(seg.end), 2001)
                top = float(seg.ratio(phi).max())
                if top >= 1 - 1e-6:
                    raise SpecError(
                        f"{_segment(law, k, spec)} reaches a ratio w2/w1 of {top:.4g}: with {n['internal']} (a planet "
                        "driving its ring) every motion's ratio must stay below 1"
                    )
    cutter = chosen_cutter(o["rack"], o["cutter_teeth"], None, n) or ShaperCutter(16)
    study = IncompletePairStudy(
        o["name"],
        law,
        m,
        mesh="internal" if internal else "external",
        teeth=o["teeth"],
        centre_distance=o["centre_distance"],
        cutter=cutter,
        backlash=o["backlash"],
        lock_clearance=o["lock_clearance"],
        lock_depth=o["lock_depth"],
        max_play_deg=o["locking_play"],
        addendum=addendum,
    )
    try:
        pair = study.pair
    except SpecError as exc:  # the sizing's root finder: no centre distance carries these teeth
        raise SpecError.out_of_range(
            n["teeth"], o["teeth"], f"a tooth count the law's first motion can carry at {n['module']} = {m:g}"
        ) from exc
    a = pair.centre_distance
    _backlash_fits(o, n, m, a, study.tool.pressure_angle)
    pitches = sum(pair.sector_lengths()) / (math.pi * m)
    if pitches > inputs.MAX_TEETH:
        raise SpecError(
            f"{_sizes(o, n, a)}: the driver's sectors would roll {pitches:.0f} pitches a turn - at most "
            f"{inputs.MAX_TEETH} teeth"
        )
    try:
        check_fit(
            pair,
            study.tool,
            study.design_backlash,
            addendum=addendum,
            lock_clearance=o["lock_clearance"],
            lock_depth=o["lock_depth"],
        )
    except LockFitError as exc:
        seg = law.segments.index(law.dwells[exc.dwell])
        where = _segment(law, seg, spec)
        raise SpecError(f"{where}: its lock does not fit at {_sizes(o, n, a)}: {exc.reason}") from exc
    except SectorFitError as exc:
        seg = law.segments.index(law.motions[exc.motion])
        raise SpecError(
            f"{_segment(law, seg, spec)}: its sector on the {exc.role} does not fit at {_sizes(o, n, a)}: {exc.reason}"
        ) from exc
    return Checked(law=law, study=study)
