"""Seed 002 (Sun et al. 2023) synthesised: the design model behind ``potseedling_seed002.py``.

Table 1 gives link 2's four poses; link 3 (the planting arm) is 125 mm long with attitudes
171, 130, 154 and 167 deg at the poses. §3.3 picks the circle point (70, 33.4092) with centre
point (3.9926, 0.4983) — mechanism ③ — which :func:`chain` reproduces.

What the paper does not publish, and what we chose (see README):

* its ten intermediate points of the relative-angle curves: we place one point per gap between
  poses for each curve and let differential evolution choose them (:func:`problem`;
  ``transplanter optimise parts/_seed002.py --seed 2 --maxiter 25 --popsize 8`` gives
  ``OPTIMUM``), minimising the swing cam's largest pressure angle while keeping both gear
  stages convex;
* the centre distances of the two non-circular stages (45 mm each) and the split of the
  two-stage ratio between them (``I^λ``, λ = ``EXPONENT`` = 0.492225, the largest convexity index:
  ``chain(*OPTIMUM[:2]).distribute(CENTRE_DISTANCES, exponent=None)`` searches it, and
  ``tests/test_seed002.py`` checks the search still lands there);
* the cam follower: an oscillating roller follower (8 mm roller) whose pivot distance, arm and
  base circle are optimised with the curves.

The leading ``_`` keeps the builder from taking this module for a part script.
"""

import math

import numpy as np

from transplanter.design.linkage.open_chain import OpenChain3R, seed002_poses
from transplanter.design.optimise import Problem
from transplanter.geometry.cams import OscillatingRollerFollower, disc_cam
from transplanter.geometry.pitch import PeriodicSpline

CIRCLE_X = 70.0  # mm, the circle point's x of mechanism ③
ARM_LENGTH = 125.0  # mm, link 3
CENTRE_DISTANCES = (45.0, 45.0)  # mm, stages 2-3 and 3-5
#: the split I^λ of the two-stage ratio with the largest convexity index (both stages 0.642)
EXPONENT = 0.492225
ROLLER = 8.0  # mm, the follower's roller radius
#: intermediate points: offsets of β2 and β3 from the straight line between the poses at the
#: middle of each gap (fractions of the gap's width, rad per rad), and the follower (pivot
#: distance, arm, base radius, mm), as found by problem() with seed 2
OPTIMUM = (
    (-0.0344, 0.0694, 0.0219, -0.0212),
    (0.0176, -0.0013, -0.0532, 0.0364),
    (152.21, 54.45, 103.67),
)
#: the best plain design (no intermediate points, follower found alone) starts the search
START = (0.0,) * 8 + (130.7, 30.05, 99.9)


def chain(link2_offsets=None, link3_offsets=None) -> OpenChain3R:
    """Mechanism ③ with one intermediate point per gap between poses for each relative angle.

    The offsets are from the straight line between the neighbouring poses' values at the middle
    of the gap, as fractions of the gap's width in τ (so short gaps get small offsets); None puts
    no intermediate points.
    """
    poses, attitudes = seed002_poses()
    y = min(poses.circle_points_at(CIRCLE_X), key=lambda v: abs(v - 33.4092))
    plain = OpenChain3R(poses, (CIRCLE_X, y), ARM_LENGTH, attitudes)
    tau = plain.pose_tau
    mids = 0.5 * (tau + np.append(tau[1:], 2 * math.pi))
    b2 = plain.beta2(tau)
    b3 = plain.beta3(tau)
    lin2 = 0.5 * (b2 + np.roll(b2, -1))
    lin3 = 0.5 * (b3 + np.append(b3[1:], b3[0] + 2 * math.pi))
    width = np.diff(np.append(tau, 2 * math.pi))
    extra2 = (
        tuple(zip(mids, lin2 + width * np.asarray(link2_offsets), strict=True)) if link2_offsets is not None else ()
    )
    extra3 = (
        tuple(zip(mids, lin3 + width * np.asarray(link3_offsets), strict=True)) if link3_offsets is not None else ()
    )
    return OpenChain3R(poses, (CIRCLE_X, y), ARM_LENGTH, attitudes, extra2, extra3)


def swing(ch: OpenChain3R):
    """Link 2's swing relative to link 1, from its smallest value (rad), as the cam's motion."""
    tau = 2 * math.pi * np.arange(720) / 720
    b = ch.beta2(tau)
    return PeriodicSpline(tau, b - b.min(), degree=5)


def follower(pivot, arm, base) -> OscillatingRollerFollower:
    return OscillatingRollerFollower(pivot_distance=pivot, arm_length=arm, roller_radius=ROLLER, base_radius=base)


def problem() -> Problem:
    """Minimise the swing cam's largest pressure angle (deg) with both gear stages convex.

    Penalties are graded so the search can climb out of infeasible corners: the arm must keep
    turning relative to carrier 1 (β2' + β3' >= 0.05), the follower must reach the cam, and the
    smaller convexity index should be >= 0.3. The swing spans at least the poses' 84 deg, and an
    oscillating follower's pressure angle cannot stay below about half its swing, so a large
    cam with a short arm is what gets under 45 deg.
    """
    tau = 2 * math.pi * np.arange(720) / 720

    def cost(x):
        ch = chain(x[0:4], x[4:8])
        rel = ch.beta2(tau, 1) + ch.beta3(tau, 1)
        if rel.min() < 0.05:
            return 1000.0 + 1000.0 * (0.05 - rel.min())
        pivot, arm, base = x[8:11]
        prime = base + ROLLER
        if not abs(pivot - arm) + 1 < prime < pivot + arm - 1:
            return 500.0 + abs(prime - 0.5 * (abs(pivot - arm) + pivot + arm))
        dist = ch.distribute(CENTRE_DISTANCES, exponent=0.5, samples=720)
        cam = disc_cam(swing(ch), follower(pivot, arm, base), n=720, max_pressure_angle=math.radians(89))
        return math.degrees(cam.max_pressure_angle) + 50 * max(0.0, 0.3 - dist.p)

    names = [f"beta2_offset_gap{k}" for k in range(1, 5)] + [f"beta3_offset_gap{k}" for k in range(1, 5)]
    bounds = [(-0.1, 0.1)] * 8 + [(100.0, 250.0), (25.0, 80.0), (60.0, 120.0)]
    variables = tuple(zip(names + ["pivot_mm", "arm_mm", "base_mm"], *zip(*bounds, strict=True), strict=True))
    return Problem("seed002 swing cam and gear stages", variables, cost, infeasible=2000.0, x0=START)
