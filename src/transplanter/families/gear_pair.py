"""One call for a gear pair: from a transmission ratio to shop files, meshing proof and report.

For the designer who has a ratio and wants parts, :func:`gear_pair` (and ``transplanter pair``)
does in one step what a part script with a :class:`~transplanter.families.ToothedPairStudy`
does: the pitch pair of the spec (:func:`transplanter.pitch.transmission.transmission`),
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
from pathlib import Path

from transplanter import inputs
from transplanter.cutter import RackCutter, ShaperCutter
from transplanter.cutter_choice import first_cutter
from transplanter.errors import SpecError, check_int, check_number
from transplanter.families.build import build_family
from transplanter.families.gears import ToothedPairStudy
from transplanter.families.making import Making
from transplanter.families.manifest import previous_manifest
from transplanter.families.scripts import Family
from transplanter.pair_gate import per_gear
from transplanter.pitch import GearPair
from transplanter.pitch.transmission import size_pair, transmission
from transplanter.solids import Features

__all__ = ["gear_pair", "pair_family", "BORE_FRACTION", "DEFAULT_WIDTH"]

#: an external gear's bore: this fraction of its smallest root radius (room for the timing mark
#: between bore and roots)
BORE_FRACTION = 0.4
#: face width when none is given, mm
DEFAULT_WIDTH = 10.0


def _bore(pair: GearPair, k: int, cutter) -> float:
    curve = (pair.driver, pair.driven)[k]
    root = curve.min_radius().value - cutter.addendum * cutter.module  # the gear's dedendum is the cutter's addendum
    return max(3.0, math.floor(2 * BORE_FRACTION * root) / 2)


def pair_family(
    spec: str,
    *,
    internal: bool = False,
    teeth: int | None = None,
    module: float | None = None,
    centre_distance: float | None = None,
    driven_lobes: int | None = None,
    ring: str = "driven",
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
) -> Family:
    """The family of one toothed pair of ``spec`` (the design; :func:`gear_pair` builds it).

    Parameters
    ----------
    spec : str
        The transmission: an expression in ``phi`` (the driven angle ψ(φ), rad), the path of a
        ratio CSV (driver angle in deg, ω2/ω1), or a named driver curve ``ellipse:E[:LOBES]`` /
        ``eccentric:E`` (see :mod:`transplanter.pitch.transmission`).
    internal : bool
        An internal pair (a ring gear and its planet).
    teeth, module, centre_distance
        Two of them: the driver's tooth count, the module (mm), the centre distance (mm).
    driven_lobes : int or None
        Named curves: lobes of the mate (default: as many for external, one more for a ring).
    ring : str
        Internal pairs from a ratio: which gear is the ring, ``"driven"`` or ``"driver"``.
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
    """
    check_number("width", width, 0.0, 1000.0, low_open=True, unit="mm")
    inputs.boolean("internal", internal)
    inputs.boolean("rack", rack)  # a truthy string ('no') must not select the rack cutter
    inputs.boolean("scale_to_close", scale_to_close)
    inputs.boolean("trim_ring_tips", trim_ring_tips)
    inputs.boolean("allow_undercut", allow_undercut)
    gate = {"addendum": per_gear("addendum", addendum), "shift": per_gear("shift", shift)}
    gate |= {"trim_ring_tips": trim_ring_tips, "allow_undercut": allow_undercut}
    mesh = "internal" if internal else "external"
    found = transmission(spec, mesh, driven_lobes=driven_lobes, ring=ring, scale_to_close=scale_to_close)
    pair, sizing = size_pair(found.pair, teeth, module, centre_distance)
    if rack:
        if cutter_teeth is not None:
            raise SpecError("give either rack or cutter_teeth (a shaper cutter's teeth), not both")
        cutter = RackCutter(sizing.module)
    elif cutter_teeth is None:
        cutter = first_cutter(pair, sizing.teeth, sizing.module, backlash, **gate)
    else:
        cutter = ShaperCutter(check_int("cutter_teeth", cutter_teeth, 8, 200), sizing.module)
    making = tuple(
        Making(width, Features() if pair.ring == role else Features(_bore(pair, k, cutter), keyway=False))
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


#: how a part script written by :func:`gear_pair` says so (it replaces only such a script)
SCRIPT_MARK = "Written by `transplanter pair`"
#: the part script :func:`gear_pair` leaves beside the folder: the call, stated once
SCRIPT = '''"""{description}

Written by `transplanter pair`: edit it and rebuild with `transplanter build {script} -o .`
(from this folder); `transplanter check --run-script {folder}` re-runs the meshing proof on the files.
"""

from transplanter.families.gear_pair import pair_family


def family():
    return pair_family({call})
'''


def gear_pair(spec: str, out: str | Path, **options) -> dict:
    """Make the pair of ``spec`` (options as :func:`pair_family`) in ``out``: the part script
    ``<out>/<name>.py`` that states the call (rebuild or grow it like any part script), and the
    family built from it into ``<out>/<name>/`` — shop files, meshing proof, ``report.html``,
    ``manifest.json``. Returns the manifest."""
    out = inputs.folder("out", out)
    family = pair_family(spec, **options)  # bad input fails here, before anything is written
    if Path(spec).suffix.lower() == ".csv":
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
    if script.is_symlink() or (script.exists() and SCRIPT_MARK not in script.read_text(errors="replace")):
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
