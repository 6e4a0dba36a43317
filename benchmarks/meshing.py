"""Meshing-check speed: our cycle check against the plain whole-outline approach, same run.

The pair: seed 002's first gear stage (30/30 teeth, m = 1.5 mm, the outlines the build
exports). For each driver position both checks place the driven gear at the design ratio
and find the overlap area and the first contact of the driving flanks (brentq on the signed
gap). The plain approach — what a user would write with shapely — rotates and compares the
whole outlines at every evaluation (GEOS distance is all-pairs); ours clips the driver to
the driven gear's extent for the overlap and works on a 3-module window around the pitch
point for the contact, with a bracket grown from the design angle. Prints the time per
position of each, the ratio, and that both find the same contact (max difference, mm).

Run: python benchmarks/meshing.py
"""

import math
import runpy
import statistics
import time
from pathlib import Path

import numpy as np
import shapely
from scipy import optimize

from transplanter.teeth import generate_pair
from transplanter.validate import _place, mesh_check

STEPS = 24


def plain(pair, drv_poly, drn_poly, module, steps):
    """Whole outlines at every evaluation: overlap area and driving-flank contact (arc, mm)."""
    a = pair.centre_distance
    phi = 2 * math.pi * np.arange(steps) / steps
    theta = pair.driven_rotation(phi)
    r2 = a - pair.driver.r(phi)
    arcs = []
    for k in range(steps):
        drv = _place(drv_poly, -phi[k], (0.0, 0.0))

        def gap(d, k=k, drv=drv):
            g = _place(drn_poly, math.pi + theta[k] + d, (a, 0.0))
            if shapely.intersects(drv, g):
                return -(shapely.intersection(drv, g).area ** (2 / 3))
            return float(shapely.distance(drv, g))

        span = 2 * module / r2[k]
        _ = shapely.intersection(drv, _place(drn_poly, math.pi + theta[k], (a, 0.0))).area  # the overlap
        g0 = gap(0.0)
        d = 0.0 if g0 <= 0 else optimize.brentq(gap, 0.0, -span, xtol=1e-8 / r2[k])
        arcs.append(d * r2[k])
    return np.array(arcs)


def main():
    ns = runpy.run_path(str(Path(__file__).resolve().parents[1] / "parts" / "potseedling_seed002.py"))
    fam = ns["family"]()
    study = next(p for p in fam.parts if p.name == "gears_2_3")
    pair, sizing = study._sized()
    g1, g2 = generate_pair(pair, study.cutter, sizing.teeth)
    ours, base = [], []
    for _ in range(3):
        t = time.perf_counter()
        rep = mesh_check(pair, g1.polygon, g2.polygon, sizing.module, steps=STEPS)
        ours.append((time.perf_counter() - t) / STEPS)
        t = time.perf_counter()
        arcs = plain(pair, g1.polygon, g2.polygon, sizing.module, STEPS)
        base.append((time.perf_counter() - t) / STEPS)
    o, b = statistics.median(ours), statistics.median(base)
    diff = float(np.max(np.abs(rep.driven_error * (pair.centre_distance - pair.driver.r(rep.driver_angle)) - arcs)))
    print(f"pair: {sizing.teeth[0]}/{sizing.teeth[1]} teeth, m = {sizing.module:g} mm, {STEPS} positions")
    print(f"ours  (clipped, windowed):      {o * 1000:8.1f} ms per position")
    print(f"plain (whole outlines, shapely): {b * 1000:8.1f} ms per position")
    print(f"ratio: {b / o:.1f}x; same driving-flank contact within {diff * 1000:.3g} µm")


if __name__ == "__main__":
    main()
