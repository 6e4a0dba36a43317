"""One call for a gear pair: from a transmission ratio to shop files, meshing proof and report.

For the designer who has a ratio and wants parts, :func:`gear_pair` (and ``transplanter pair``)
does in one step what a part script with a :class:`~transplanter.families.ToothedPairStudy`
does: the pitch pair of the spec (:func:`transplanter.geometry.pitch.transmission.transmission`),
sized by two of teeth, module and centre distance, teeth cut by a shaper cutter (the one
given, or the first of ``SCREEN_CUTTERS`` — 12 to 24 teeth — that cuts both gears), thinned
for the designed backlash, made as DXF / STL / STEP with bores and timing marks, a 3MF of the
pair in mesh, the assembly data, and the meshing check run on the re-read shop files — all in
``<out>/<name>/`` with ``manifest.json`` and ``report.html``, written as one transaction.

Choices it makes that a part script would state: each external gear gets a plain bore (no
keyway) of ``BORE_FRACTION`` of its smallest root radius, rounded down to 0.5 mm and at least
3 mm; a ring gets none (it is held by its rim). Face width 10 mm unless given.

The folder also receives the part script that states the call (``<name>.py``): rebuild it with
``transplanter build``, check the files with ``transplanter check``, or grow it into a family.

Example (CLI, then Python)::

    transplanter pair "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5 -o out
    gear_pair("ellipse:0.05:2", "out", internal=True, driven_lobes=4, teeth=24, module=1.5)
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from transplanter.core import inputs
from transplanter.core.errors import SpecError
from transplanter.core.files import FileRefused, read_regular
from transplanter.families.builder.build import build_family
from transplanter.families.builder.making import Making
from transplanter.families.builder.manifest import previous_manifest
from transplanter.families.builder.scripts import Family
from transplanter.families.pairs.incomplete_pair import LOCKING_PLAY_DEG
from transplanter.families.pairs.pair_options import INTERNAL_RING_ADDENDUM as INTERNAL_RING_ADDENDUM
from transplanter.families.pairs.pair_options import check_options, chosen_cutter
from transplanter.families.pairs.toothed import ToothedPairStudy
from transplanter.geometry.cutter_choice import first_cutter
from transplanter.geometry.pair_gate import per_gear
from transplanter.geometry.pitch import GearPair
from transplanter.shop.solids import Features

__all__ = ["gear_pair", "pair_family", "BORE_FRACTION", "DEFAULT_WIDTH", "PAIR_MATERIAL"]

#: an external gear's bore: this fraction of its smallest root radius (room for the timing mark
#: between bore and roots)
BORE_FRACTION = 0.4
#: face width when none is given, mm
DEFAULT_WIDTH = 10.0
#: the material a pair's drawings name (``transplanter.shop.catalogue``): C45 quenched and tempered,
#: a gear steel that holds its shape when cut by wire EDM
PAIR_MATERIAL = "C45"


def _bore(pair: GearPair, k: int, cutter) -> float:
    curve = (pair.driver, pair.driven)[k]
    # the gear's dedendum is the cutter's addendum
    return _bore_of(curve.min_radius().value - cutter.addendum * cutter.module)


def _bore_of(root: float) -> float:
    """The plain bore (mm) of a gear whose smallest root radius is ``root`` (mm)."""
    return max(3.0, math.floor(2 * BORE_FRACTION * root) / 2)


_chosen_cutter = chosen_cutter  # the cutter the user chose (pair_options)


def pair_family(
    spec: str,
    *,
    internal: bool = False,
    teeth: int | None = None,
    module: float | None = None,
    centre_distance: float | None = None,
    driven_lobes: int | None = None,
    ring: str | None = None,
    backlash: float | None = None,
    cutter_teeth: int | None = None,
    rack: bool = False,
    width: float = DEFAULT_WIDTH,
    name: str = "pair",
    scale_to_close: bool = False,
    addendum: float | tuple[float, float] = 1.0,
    shift: float | tuple[float, float] = 0.0,
    trim_ring_tips: bool = True,
    allow_undercut: bool = False,
    lock_clearance: float | None = None,
    lock_depth: float | None = None,
    locking_play: float = LOCKING_PLAY_DEG,
    names: Mapping[str, str] | None = None,
) -> Family:
    """The family of one toothed pair of ``spec`` (the design; :func:`gear_pair` builds it).

    Parameters
    ----------
    spec : str
        The transmission: an expression in ``phi`` (the driven angle ψ(φ), rad), the path of a
        ratio CSV (driver angle in deg, ω2/ω1), or a named driver curve ``ellipse:E[:LOBES]`` /
        ``eccentric:E`` (see :mod:`transplanter.geometry.pitch.transmission`).
    internal : bool
        An internal pair (a ring gear and its planet).
    teeth, module, centre_distance
        Two of them: the driver's tooth count, the module (mm), the centre distance (mm).
    driven_lobes : int or None
        Named curves: lobes of the mate (default: as many for external, one more for a ring).
    ring : str or None
        Internal pairs from a ratio: which gear is the ring, ``"driven"`` (None: the default) or
        ``"driver"``; refused for other pairs.
    backlash : float or None
        Circumferential backlash at the pitch point, mm; None: the ISO/TR 10064-2 default.
    cutter_teeth : int or None
        Teeth of the shaper cutter; None: the first of ``SCREEN_CUTTERS`` that cuts both gears.
    rack : bool
        Cut with a rack cutter (hob) instead: external pairs whose pitch curves have no concave
        part.
    width : float
        Face width, mm.
    name : str
        The family's (folder's) and the part's name.
    scale_to_close : bool
        A ratio that does not close is scaled by the factor that closes it (samples never quite
        close) instead of refused; the description says by how much. A constant ratio is built
        as its pair of circles either way.
    addendum, shift : float or (driver, driven)
        Addendum and profile-shift coefficients (the remedies for pointed teeth and undercut the
        errors name; ``--addendum``, ``--shift``).
    trim_ring_tips : bool
        Internal pairs: shorten the ring's tips to the closed-form interference limit (default);
        False refuses the pair instead (``--no-trim-ring-tips``).
    allow_undercut : bool
        Accept an undercut flank instead of refusing it (``--allow-undercut``).
    lock_clearance, lock_depth, locking_play
        Incomplete pairs (a law with dwells, :mod:`transplanter.geometry.pitch.intermittent`): the locks'
        radial clearance (mm; default 0.4 of the backlash), how deep the driver's locking arc reaches
        into the driven's tips (modules; default 0.3 for an external pair, 0.3 short of the planet's
        tips for an internal one) and the locking play the proof holds the
        dwells and transitions to (deg, default 2).
    names : mapping or None
        How the errors name the options (default: as here; ``transplanter pair`` passes its flags).

    Notes
    -----
    **Incomplete pairs.** A ``spec`` of segments (``"0..60: dwell; 60..360: EXPR"``) or a ratio
    CSV with zero rows (the dwells) makes an incomplete pair
    (:class:`~transplanter.families.pairs.incomplete_pair.IncompletePairStudy`): the module and one of
    ``teeth`` (the driver's on the first motion's sector) or ``centre_distance``; a shaper cutter
    (``cutter_teeth``, default 16) or ``rack``; ``internal`` for a planet driving its ring (ring
    addendum 0.8 unless ``addendum`` is given, as full rings are trimmed for tip interference).
    The options of full pairs that do not apply (``driven_lobes``, ``ring``,
    ``scale_to_close``, ``shift``, ``trim_ring_tips=False``, ``allow_undercut``) are refused.

    Every option is checked before anything is cut (:func:`~transplanter.families.pairs.pair_options.check_options`:
    ranges, options that do not apply, and the sizes the pair makes — for a law with dwells every lock
    and sector at those sizes), each error naming the option as ``names`` says.
    """
    stated = {k: v for k, v in locals().items() if k not in ("spec", "names")}
    checked = check_options(spec, names, **stated)  # every option, before anything is cut or written
    if checked.law is not None:
        return _incomplete_family(spec, checked, internal=internal, width=width, name=name, module=module)
    gate = {"addendum": per_gear("addendum", addendum), "shift": per_gear("shift", shift)}
    gate |= {"trim_ring_tips": trim_ring_tips, "allow_undercut": allow_undercut}
    mesh = "internal" if internal else "external"
    found, pair, sizing = checked.found, checked.pair, checked.sizing
    cutter = _chosen_cutter(rack, cutter_teeth, sizing.module)
    if cutter is None:
        cutter = first_cutter(pair, sizing.teeth, sizing.module, backlash, **gate)
    making = tuple(
        Making(
            width,
            Features() if pair.ring == role else Features(_bore(pair, k, cutter), keyway=False),
            material=PAIR_MATERIAL,
        )
        for k, role in enumerate(("driver", "driven"))
    )
    study = ToothedPairStudy(name, pair, cutter, sizing.teeth[0], making=making, backlash=backlash, **gate)
    scaled = "" if found.closure_scale == 1.0 else f"; ratio scaled by {found.closure_scale:.9g} to close"
    adjusted = ""
    if centre_distance is not None and abs(pair.centre_distance - centre_distance) > 1e-9 * centre_distance:
        adjusted = f" (ADJUSTED from the {centre_distance:g} mm asked: the nearest that carries whole teeth)"
    description = (
        f"{mesh} pair of {spec!r}: {sizing.teeth[0]}/{sizing.teeth[1]} teeth, m = {sizing.module:.6g} mm, "
        f"a = {pair.centre_distance:.6g} mm{adjusted}, {cutter.label}{scaled}"
    )
    return Family(name, description, (study,))


def _incomplete_family(spec, checked, *, internal, width, name, module) -> Family:
    """The family of one incomplete pair (see :func:`pair_family`): the study ``checked`` sized and
    fitted (:func:`~transplanter.families.pairs.pair_options.check_options`), made."""
    law, study = checked.law, checked.study
    mesh = "internal" if internal else "external"
    pair = study.pair
    making = (
        Making(width, Features(_sector_bore(pair, "driver", module), keyway=False), material=PAIR_MATERIAL),
        Making(
            width,
            Features() if internal else Features(_sector_bore(pair, "driven", module), keyway=False),
            material=PAIR_MATERIAL,
        ),
    )
    study = dataclasses.replace(study, making=making)
    description = (
        f"{mesh} incomplete pair of {spec!r}: {law.describe()}; m = {module:g} mm, a = {pair.centre_distance:.6g} mm, "
        f"{study.tool.label}"
    )
    return Family(name, description, (study,))


def _sector_bore(pair, role: str, module: float) -> float:
    """A sector gear's plain bore: ``BORE_FRACTION`` of its smallest root radius (the pitch radii
    of its sectors less a dedendum), rounded down to 0.5 mm, at least 3 mm — as for full gears."""
    radii = []
    for motion in pair.law.motions:
        phi = np.linspace(math.radians(motion.start), math.radians(motion.end), 721)
        radii.append(float((pair.r1(phi, motion=motion) if role == "driver" else pair.r2(phi, motion=motion)).min()))
    return _bore_of(min(radii) - 1.25 * module)


#: how a part script written by :func:`gear_pair` says so (it replaces only such a script)
SCRIPT_MARK = "Written by `transplanter pair`"
#: the largest ``pair.py`` read to see whether ``pair`` wrote it, bytes (it writes a few hundred)
SCRIPT_LIMIT = 1 << 20
#: the part script :func:`gear_pair` leaves beside the folder: the call, stated once
SCRIPT = '''"""{description}

Written by `transplanter pair`: edit it and rebuild with `transplanter build {script} -o .`
(from this folder); `transplanter check --run-script {folder}` re-runs the meshing proof on the files.
"""

from transplanter.families.pairs.gear_pair import pair_family


def family():
    return pair_family({call})
'''


def gear_pair(spec: str, out: str | Path, names: Mapping[str, str] | None = None, **options) -> dict:
    """Make the pair of ``spec`` (options as :func:`pair_family`) in ``out``: the part script
    ``<out>/<name>.py`` that states the call (rebuild or grow it like any part script), and the
    family built from it into ``<out>/<name>/`` — shop files, meshing proof, ``report.html``,
    ``manifest.json``. Returns the manifest."""
    out = inputs.folder((names or {}).get("out", "out"), out)
    family = pair_family(spec, names=names, **options)  # bad input fails here, before anything is written
    if inputs.is_csv_path(spec):  # the file as given ('r.csv ' is not 'r.csv'), from anywhere
        spec = str(Path(spec).resolve())
    defaults = {k: p.default for k, p in inspect.signature(pair_family).parameters.items()}
    stated = {k: v for k, v in sorted(options.items()) if v != defaults.get(k)}
    call = "".join(f"\n        {a}," for a in [repr(spec), *(f"{k}={v!r}" for k, v in stated.items())]) + "\n    "
    script = out / f"{family.name}.py"
    _refuse_foreign(out, family.name, script)
    description = family.description.replace('"""', "'''").replace("\\", "/")
    text = SCRIPT.format(description=description, script=script.name, folder=family.name, call=call)
    # the script is written with the export, under its lock: never one without the other
    fam = dataclasses.replace(family, script=str(script.resolve()))
    return build_family(fam, out, beside={script.name: text.encode()})


def _refuse_foreign(out: Path, name: str, script: Path) -> None:
    """SpecError when ``out/<name>.py`` or ``out/<name>/`` belongs to something other than an earlier
    ``transplanter pair`` of that name: a user's own script, another family's export."""
    try:  # a FIFO, device or link there is refused without opening it: a read never blocks
        written = read_regular(script, "the pair's script", SCRIPT_LIMIT, missing_ok=True)
    except FileRefused:
        written = b""
    if written is not None and SCRIPT_MARK.encode() not in written:
        raise SpecError(
            f"{script} exists and was not written by transplanter pair: it is not replaced - choose another --name "
            "or output folder"
        )
    folder = out / name
    if folder.is_symlink() or (folder.exists() and not (folder / "manifest.json").is_file()):
        raise SpecError(f"{folder} exists and is not an export of transplanter pair: choose another --name or folder")
    if folder.exists():
        recorded = Path(str(previous_manifest(folder).get("script", {}).get("path", "")))
        if recorded.name != script.name or recorded.parent != out.resolve():
            raise SpecError(
                f"{folder} holds the export of {recorded.name or 'another family'}, not of an earlier transplanter "
                f"pair {name!r}: it is not replaced - choose another --name or output folder"
            )
