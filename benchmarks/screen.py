"""The fouling screen against the full meshing check it stands in for, on the same designs.

For a few of ``tests/screen_cases.py``'s designs, times the screen (``fouling_screen``: closed-form
limits on windowed radii of curvature) and the full check (cut the teeth, then
``validate.mesh_check`` over a whole ring turn at 360 steps), prints both verdicts and the ratio.
The verdicts are the ones ``tests/test_screen.py`` compares on all 31 designs.

    python benchmarks/screen.py
"""

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import screen_cases as sc  # noqa: E402

CASES = (("circular", 12, 12), ("mild", 13, 12), ("mild", 13, 12, 1.0), ("sharp", 24, 12))


def main() -> None:
    total_screen = total_full = 0.0
    for case in CASES:
        start = time.perf_counter()
        screen = not sc.screen_verdict(case)
        t_screen = time.perf_counter() - start
        start = time.perf_counter()
        full = sc.full_verdict(case)["meshes"]
        t_full = time.perf_counter() - start
        total_screen += t_screen
        total_full += t_full
        print(
            f"{str(case):32s} screen {'meshes' if screen else 'fouls '} in {t_screen * 1000:7.1f} ms   "
            f"full check {'meshes' if full else 'fouls '} in {t_full:6.2f} s"
        )
    print(f"ratio full check / screen: {total_full / total_screen:.0f}x")


if __name__ == "__main__":
    main()
