"""Tooth generation speed: a 60-tooth non-circular gear and its ring partner at <= 1 µm.

The pair: a 2-lobed planet (n-lobed ellipse, e = 0.12, m = 2 mm, 60 teeth) driving a
3-lobed ring (90 teeth); both cut by a z0 = 16 shaper cutter. Prints, in one run:

- our time (exact envelope, outline within 0.25 µm of it), median of 5;
- the brute-force Boolean reference the ANCHORS describe (shapely: union of the whole
  cutter outline at N roll positions per pitch, then one difference from the blank), at
  increasing N until its flanks are within 1 µm of the exact envelope, with its time and
  error; and the ratio of the two at that accuracy.

ANCHORS (circular stand-ins, 2 cores): Boolean envelope, external z = 30, 1000 positions,
0.53 s at 0.79 µm; ring z = 60, 1000 positions, 0.55 s at 1.26 µm.

Then the issue-15 goal, circular gears at z = 60 and z = 600 (m = 2, z0 = 20 cutter, outline
within 0.25 µm), external and ring: ours against the general path measured in the same run —
every tooth space computed and the spaces unioned by GEOS, which is what ``generate`` falls
back to when spaces fold or touch (same outline to 1e-9 mm, tests/test_teeth.py) — and the
ANCHORS' compiled exact tool (GearCutter, C++: 4.6 ms at 0.43 µm for z = 60; not installable
here, quoted). Goal: <= 10 ms at z = 60 (within 2x of it), linear to z = 600.

Run: python benchmarks/teeth.py
"""

import statistics
import sys
import time
from pathlib import Path
from unittest import mock

from transplanter.geometry import teeth
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pitch import GearPair, PitchCurve
from transplanter.geometry.teeth import generate

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from reference_teeth import boolean_reference, flank_deviation  # noqa: E402

MODULE = 2.0
TARGET = 1e-3  # mm


def the_pair():
    planet = PitchCurve.ellipse(60.0, 0.12, lobes=2)
    pair = GearPair.from_driver(planet, "internal", driven_lobes=3)
    pair, sizing = pair.sized(module=MODULE)
    assert sizing.teeth == (60, 90), sizing
    return pair, sizing


def timed(fn, repeat=5):
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def main() -> None:
    pair, sizing = the_pair()
    cutter = ShaperCutter(16, MODULE)
    jobs = (
        ("planet (external, 60 teeth)", pair.driver, sizing.teeth[0], False),
        ("ring (internal, 90 teeth)", pair.driven, sizing.teeth[1], True),
    )
    total_ours = total_ref = 0.0
    for label, curve, z, internal in jobs:
        t_ours, gear = timed(lambda c=curve, z=z, i=internal: generate(c, cutter, z, internal=i))
        print(f"{label}: ours {t_ours * 1000:.1f} ms, {len(gear.toothed_contour)} vertices")
        for per_pitch in (8, 16, 32, 64):
            t_ref, ref = timed(
                lambda c=curve, z=z, i=internal, n=per_pitch: boolean_reference(
                    c, cutter, z, n, internal=i, window=0.5, cutter_teeth=None
                ),
                repeat=1,
            )
            err = flank_deviation(gear, ref)
            print(f"  Boolean reference, {per_pitch:3d} positions/pitch: {t_ref:7.3f} s, error {err * 1e3:.3f} µm")
            if err <= TARGET:
                break
        print(f"  ratio at <= 1 µm: {t_ref / t_ours:.0f}x")
        total_ours += t_ours
        total_ref += t_ref
    print(f"pair: ours {total_ours:.3f} s, Boolean reference {total_ref:.2f} s, ratio {total_ref / total_ours:.0f}x")
    circular()


COMPILED_Z60_MS = 4.6  # ANCHORS.md: GearCutter (C++), external z = 60


def circular() -> None:
    """Circular gears, z = 60 and 600: ours against the general path (no symmetry, GEOS union)."""
    cutter = ShaperCutter(20, MODULE)
    print("circular gears, m = 2, z0 = 20, outline within 0.25 µm (median of 7):")
    for z in (60, 600):
        for internal in (False, True):
            curve = PitchCurve.circle(z * MODULE / 2)
            label = f"{'ring' if internal else 'external'} z = {z}"
            t_ours, gear = timed(lambda c=curve, z=z, i=internal: generate(c, cutter, z, internal=i), repeat=7)
            with (
                mock.patch.object(teeth, "_apart_spaces", lambda *a: None),
                mock.patch.object(teeth, "_symmetry", lambda curve, teeth: 1),
            ):
                t_gen, general = timed(lambda c=curve, z=z, i=internal: generate(c, cutter, z, internal=i), repeat=3)
            same = teeth.shapely.hausdorff_distance(gear.polygon, general.polygon)
            extra = f", {t_ours * 1000 / COMPILED_Z60_MS:.1f}x the compiled anchor" if z == 60 else ""
            print(
                f"  {label:17s}: ours {t_ours * 1000:6.1f} ms, general path {t_gen * 1000:6.1f} ms "
                f"(ratio {t_gen / t_ours:4.1f}x, outlines {same * 1e6:.2g} nm apart){extra}"
            )


if __name__ == "__main__":
    main()
