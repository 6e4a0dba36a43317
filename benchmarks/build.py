"""Wall time and peak memory of the full default build, against the serial build, same run.

Runs ``transplanter build`` (every part script in ``parts/``) twice into temporary folders: as a
user runs it (parts spread over one process per available core) and with ``--jobs 1`` (one
process, the baseline: the same work, nothing shared), checks the two exports are
byte-identical, and prints both wall times, the ratio, each run's peak memory (the largest
resident set of the builder or any of its workers), and the slowest parts of the serial run.
Goal: <= 10 s wall on 2 cores, <= 300 MB peak.

Run: python benchmarks/build.py
"""

import filecmp
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# the build in a child process that reports its own and its workers' peak resident set (kB)
RUN = """
import resource, sys
from transplanter import cli
code = cli.main(sys.argv[1:])
peak = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
print(f"PEAK_KB {peak}", file=sys.stderr)
sys.exit(code)
"""


def build(out: Path, *extra: str) -> tuple[float, float, str]:
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-c", RUN, "build", "--parts", str(ROOT / "parts"), "-o", str(out), *extra],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"build failed:\n{proc.stderr}")
    peak = int(re.search(r"PEAK_KB (\d+)", proc.stderr).group(1)) / 1024
    return wall, peak, proc.stderr


def same(a: Path, b: Path) -> bool:
    cmp = filecmp.dircmp(a, b)
    if cmp.left_only or cmp.right_only or cmp.diff_files or cmp.funny_files:
        return False
    return all(same(a / d, b / d) for d in cmp.common_dirs) and all(
        (a / f).read_bytes() == (b / f).read_bytes() for f in cmp.common_files
    )


def main() -> None:
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    with tempfile.TemporaryDirectory() as tmp:
        t_par, m_par, _ = build(Path(tmp) / "default")
        t_ser, m_ser, log = build(Path(tmp) / "serial", "--jobs", "1")
        identical = same(Path(tmp) / "default", Path(tmp) / "serial")
    stamps = [(m.group(1), float(m.group(2))) for m in re.finditer(r"\] (\S+)  \((\d+\.\d+) s\)", log)]
    parts = sorted(
        ((name, t - (stamps[k - 1][1] if k else 0.0)) for k, (name, t) in enumerate(stamps)), key=lambda p: -p[1]
    )
    print(f"default build ({cores} cores): {t_par:6.2f} s wall, peak {m_par:5.0f} MB   (goal <= 10 s, <= 300 MB)")
    print(f"serial build (--jobs 1):     {t_ser:6.2f} s wall, peak {m_ser:5.0f} MB")
    print(f"ratio: {t_ser / t_par:.2f}x; exports byte-identical: {identical}")
    print("slowest parts (serial):")
    for name, t in parts[:6]:
        print(f"    {name:42s} {t:6.2f} s")


if __name__ == "__main__":
    main()
