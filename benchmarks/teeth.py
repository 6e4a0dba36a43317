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

Run: python benchmarks/teeth.py
"""

import statistics
import sys
import time
from pathlib import Path

from transplanter.cutter import ShaperCutter
from transplanter.pitch import GearPair, PitchCurve
from transplanter.teeth import generate

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


if __name__ == "__main__":
    main()
