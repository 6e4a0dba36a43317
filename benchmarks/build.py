"""Time of the full default build (every family in parts/) and of each part.

Builds into a temporary folder, one family after another in this process (what
``transplanter build`` does with --jobs 1), and prints each part's time and the total.

Run: python benchmarks/build.py
"""

import tempfile
import time
from pathlib import Path

from transplanter.families import build_family, discover, load_family

PARTS = Path(__file__).resolve().parents[1] / "parts"


def main() -> None:
    total_start = time.perf_counter()
    with tempfile.TemporaryDirectory() as out:
        for script in discover(PARTS):
            fam = load_family(script)
            marks = []

            def progress(label, marks=marks):
                marks.append((label, time.perf_counter()))

            start = time.perf_counter()
            manifest = build_family(fam, out, progress)
            end = time.perf_counter()
            print(f"{fam.name}: {end - start:.2f} s{'' if manifest['ok'] else '  (FAILED)'}")
            stamps = [t for _, t in marks] + [end]
            for (label, t0), t1 in zip(marks, stamps[1:], strict=True):
                print(f"    {label.split('/', 1)[1]:28s} {t1 - t0:7.2f} s")
    print(f"full default build: {time.perf_counter() - total_start:.2f} s")


if __name__ == "__main__":
    main()
