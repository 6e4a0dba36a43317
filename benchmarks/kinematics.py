"""Four-bar kinematics speed: 3600 crank positions with velocity and acceleration.

Prints our time and, measured in the same run, a baseline a user would otherwise write:
the loop solved numerically per angle with scipy.optimize.fsolve and rates by central
differences. The figures of ../shared/ANCHORS.md (numpy closed form, positions only:
0.62 ms; pylinkage 1.3 step_fast_with_kinematics: 2.4-3.0 ms) are printed for reference.

Run: python benchmarks/kinematics.py
"""

import math
import time

import numpy as np
from scipy import optimize

from transplanter.design.linkage.fourbar import FourBar, Link

FB = FourBar(ground=125.0, crank=40.0, coupler=100.0, rocker=85.0, ground_angle=math.radians(142.0))
TIP = (-173.8, 63.3)
N = 3600


def ours(theta):
    m = FB.solve(theta, 8 * math.pi, 0.0)
    return m.point(Link.COUPLER, TIP)


def baseline(theta):
    o4 = np.array(FB.rocker_pivot)
    start = FB.solve(theta[:1])  # start on the same assembly branch, then track it
    guess = np.array([start.theta[Link.COUPLER][0], start.theta[Link.ROCKER][0]])

    def tip(t, g):
        def f(x):
            b = FB.crank * np.array([math.cos(t), math.sin(t)])
            c1 = b + FB.coupler * np.array([math.cos(x[0]), math.sin(x[0])])
            c2 = o4 + FB.rocker * np.array([math.cos(x[1]), math.sin(x[1])])
            return c1 - c2

        x = optimize.fsolve(f, g, xtol=1e-12)
        b = FB.crank * np.array([math.cos(t), math.sin(t)])
        r = np.array([math.cos(x[0]), math.sin(x[0])])
        n = np.array([-r[1], r[0]])
        return b + TIP[0] * r + TIP[1] * n, x

    h = 1e-4
    out = []
    for t in theta:
        p0, guess = tip(t, guess)
        pp, _ = tip(t + h, guess)
        pm, _ = tip(t - h, guess)
        w = 8 * math.pi
        out.append((p0, (pp - pm) / (2 * h) * w, (pp - 2 * p0 + pm) / h**2 * w**2))
    return out


def best_of(fn, arg, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn(arg)
        times.append(time.perf_counter() - t0)
    return min(times)


def main():
    theta = np.linspace(0, 2 * math.pi, N, endpoint=False)
    t_ours = best_of(ours, theta, 50)
    t_base = best_of(baseline, theta, 1)
    ref = ours(theta)
    base = baseline(theta[:50])
    err = max(float(np.max(np.abs(ref.position[i] - base[i][0]))) for i in range(50))
    print(f"four-bar, {N} crank positions with velocity and acceleration of the tip")
    print(f"  transplanter closed form + analytic rates: {t_ours * 1e3:8.2f} ms")
    print(f"  baseline fsolve per angle + differences:   {t_base * 1e3:8.2f} ms")
    print(f"  ratio baseline / ours:                     {t_base / t_ours:8.1f} x")
    print(f"  max position difference (first 50 angles): {err:.2e} mm")
    print("  anchors (ANCHORS.md): numpy positions only 0.62 ms; pylinkage with kinematics 2.4-3.0 ms")


if __name__ == "__main__":
    main()
