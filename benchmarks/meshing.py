"""Meshing-check speed: the closed-form check against the root-finding one it replaced, same run.

The pair: seed 002's first gear stage (30/30 teeth, m = 1.5 mm, the outlines the build
exports). Both checks give the same answers (overlap, transmission error, backlash, contacts,
fouling; ``tests/test_validate.py`` holds them to ``MESH_REFERENCE_MM``): the reference
(``tests/reference_meshing.py``, our check until 0.13 and the strongest baseline we know —
a user with shapely would rotate and intersect whole outlines, ~20x slower still) turns the
driven gear's clipped outline and searches first contact with ``brentq`` on the signed gap
(GEOS distance/intersection at every evaluation); ours takes every vertex–edge pair of the
window at once and solves for the turn at which they meet.

Prints the time per position of each (median of 3 runs of 24 positions) — ours with the
reference's own search window (3 modules beside the pitch point, no refinement: equal work) —
the ratio, the largest difference in contact arc and backlash, and the time of a full cycle at
0.25 deg (1440 positions) with ours. Goal: <= 1.4 ms per position, a 0.25-deg cycle <= 2 s.

Then what the shipped proof costs beyond that (the default ``mesh_check``: every gap in reach,
the mid-play clearance, the tip scan and the refinement between the samples), at the build's
180 steps, as a ratio to the windowed check at the same steps — and what the windowed check
misses that the proof finds (the free play's floor).

Run: python benchmarks/meshing.py
"""

import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from reference_meshing import mesh_check_reference  # noqa: E402
from transplanter.families import load_family  # noqa: E402
from transplanter.geometry.pair_gate import generate_pair  # noqa: E402
from transplanter.proof.validate import mesh_check  # noqa: E402

STEPS = 24


def main():
    fam = load_family(ROOT / "parts" / "potseedling_seed002.py")
    study = next(p for p in fam.parts if p.name == "gears_2_3")
    pair, sizing = study._sized()
    g1, g2 = generate_pair(pair, study.tool, sizing.teeth, backlash=study.design_backlash)
    args = (pair, g1.polygon, g2.polygon, sizing.module)
    ours, base = [], []
    for _ in range(3):
        t = time.perf_counter()
        rep = mesh_check(*args, steps=STEPS, window=3.0, refine=False)
        ours.append((time.perf_counter() - t) / STEPS)
        t = time.perf_counter()
        ref = mesh_check_reference(*args, steps=STEPS)
        base.append((time.perf_counter() - t) / STEPS)
    o, b = statistics.median(ours), statistics.median(base)
    r2 = pair.centre_distance - pair.driver.r(rep.driver_angle)
    arc = float(np.max(np.abs((rep.driven_error - ref.driven_error) * r2)))
    bl = float(np.max(np.abs(rep.backlash - ref.backlash)))
    t = time.perf_counter()
    cycle = mesh_check(*args, steps=1440, window=3.0, refine=False)
    t_cycle = time.perf_counter() - t
    t = time.perf_counter()
    windowed = mesh_check(*args, steps=180, teeth=int(sizing.teeth[0]), window=3.0, refine=False)
    t_windowed = time.perf_counter() - t
    t = time.perf_counter()
    proof = mesh_check(*args, steps=180, teeth=int(sizing.teeth[0]))
    t_proof = time.perf_counter() - t
    print(f"pair: {sizing.teeth[0]}/{sizing.teeth[1]} teeth, m = {sizing.module:g} mm, {STEPS} positions")
    print(f"ours (closed form, all pairs at once): {o * 1000:8.2f} ms per position   (goal <= 1.4 ms)")
    print(f"reference (brentq on GEOS gap):        {b * 1000:8.2f} ms per position")
    print(f"ratio: {b / o:.1f}x; contact arc within {arc * 1000:.2g} µm, backlash within {bl * 1000:.2g} µm")
    print(
        f"full cycle at 0.25 deg ({len(cycle.driver_angle)} positions): {t_cycle:.2f} s   (goal <= 2 s); "
        f"backlash {cycle.backlash.min():.4f}..{cycle.backlash.max():.4f} mm, contact ratio {cycle.contact_ratio:.3f}"
    )
    print(
        f"the proof at 180 steps (every gap, clearance, tip scan, {len(proof.refined[0])} refined samples): "
        f"{t_proof:.2f} s vs the windowed check {t_windowed:.2f} s ({t_proof / t_windowed:.1f}x); free play "
        f"{1000 * proof.backlash_min.value:.3f}..{1000 * proof.backlash_max.value:.3f} µm vs "
        f"{1000 * windowed.backlash.min():.3f}..{1000 * windowed.backlash.max():.3f} µm sampled, "
        f"clearance {1000 * proof.clearance_min.value:.2f} µm"
    )


if __name__ == "__main__":
    main()
