"""Wall time and peak memory of the full default build, against the serial build, same run.

Runs ``transplanter build`` (every part script in ``parts/``) twice into temporary folders: as a
user runs it (parts spread over one process per available core) and with ``--jobs 1`` (one
process, the baseline: the same work, nothing shared), checks the two exports are
byte-identical, and prints both wall times, the ratio, each run's peak memory (the largest
resident set of the builder or any of its workers), and the slowest parts of the serial run.
Goal: <= 10 s wall on 2 cores, <= 300 MB peak.

Then the floor those goals meet: a third, serial build — in one process, with the work a part
otherwise forks beside itself (STEPs, plots, a machine's assembly files) — times every call into
the libraries the brief chose for the outputs (OpenCASCADE: the STEP solid, transfer, file and
volume, a part's and a machine's assembly; matplotlib: laying out and rendering each figure as
PNG and SVG; trimesh: writing the 3MF and STL, re-reading the STL; lib3mf: re-reading the 3MF;
manifold3d: the Boolean subtraction and the assembly's overlap check; ezdxf: writing and parsing
the DXF), and the imports and part-script loading the builder does before
any part starts. The wall time of a build on N cores is at least (library time)/N + that start:
what remains when our own code takes no time at all. And the peak of a process that only reads
the largest part's DXF (the seed-004 ring) and writes its STEP: the memory floor of a build that
writes it.

Run: python benchmarks/build.py
"""

import filecmp
import json
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
from transplanter.app import cli
code = cli.main(sys.argv[1:])
peak = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
print(f"PEAK_KB {peak}", file=sys.stderr)
sys.exit(code)
"""


# the same build, serial, with every call into the chosen libraries timed (a call inside another
# timed call counts once, for the outer one); prints "FLOOR <what>|<seconds>"
FLOOR = """
import collections, functools, sys, time
spent = collections.Counter()
inside = [False]
def timed(owner, name, label):
    fn = getattr(owner, name)
    @functools.wraps(fn)
    def wrapper(*a, **k):
        if inside[0]:
            return fn(*a, **k)
        inside[0] = True
        t = time.perf_counter()
        try:
            return fn(*a, **k)
        finally:
            spent[label] += time.perf_counter() - t
            inside[0] = False
    setattr(owner, name, wrapper)
# a thread kept alive: a part's work that would run beside it in a forked process (the STEPs, the
# plots, a machine's assembly files: workers.Beside) is done in this one, where its calls are timed
import threading
threading.Thread(target=threading.Event().wait, daemon=True).start()
t0 = time.perf_counter()
import ezdxf, matplotlib.figure, trimesh
from transplanter.app import cli
from transplanter.report import plots
from transplanter.shop import assembly_step, dxf, solids, step, threemf
import transplanter.families as families
spent["start: imports"] = time.perf_counter() - t0
CALLS = {
    "OpenCASCADE (STEP)": [(step, "_occ"), (step, "prism"), (step, "step_bytes"), (step, "solid_report"),
                           (assembly_step, "write_checked")],
    "matplotlib (PNG + SVG)": [(plots, "figure_files"), (matplotlib.figure.Figure, "tight_layout")],
    "trimesh, lib3mf (3MF, STL)": [(trimesh.exchange.threemf, "export_3MF"), (trimesh.exchange.stl, "export_stl"),
                                   (trimesh, "load"), (threemf, "read_assembly")],
    "manifold3d (Booleans)": [(solids, "check_solid"), (threemf, "overlaps")],
    "ezdxf (DXF)": [(ezdxf, "read"), (dxf, "_write")],
}
for label, calls in CALLS.items():
    for owner, name in calls:
        timed(owner, name, label)
timed(families, "load_family", "start: part scripts")  # as the command line imports it
t1 = time.perf_counter()
code = cli.main(sys.argv[1:])
spent["build"] = time.perf_counter() - t1
for what, t in spent.items():
    print(f"FLOOR {what}|{t:.3f}")
sys.exit(code)
"""

# a process that only reads a part's DXF and writes its STEP (the build's steps for it):
# its peak resident set (kB)
STEP_ONLY = """
import resource, sys
from pathlib import Path
from transplanter.shop import dxf, step
dxf_file, width = Path(sys.argv[1]), float(sys.argv[2])
solid = step.prism(dxf.bulge_contours(dxf_file.read_bytes()), width)
step.step_bytes(dxf_file.stem, solid)
step.solid_report(solid, check=False)
print(f"PEAK_KB {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}")
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


def floor(out: Path) -> dict[str, float]:
    """Seconds spent in each chosen library, at the start and in all, in a serial build (``FLOOR``)."""
    proc = subprocess.run(
        [sys.executable, "-c", FLOOR, "build", "--parts", str(ROOT / "parts"), "-o", str(out), "--jobs", "1"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    if proc.returncode != 0:
        raise SystemExit(f"build failed:\n{proc.stderr}")
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"FLOOR (.+)\|(\S+)", proc.stdout)}


def largest_step_peak(exports: Path) -> tuple[str, float]:
    """The part with the largest DXF and the peak (MB) of a process writing only its STEP."""
    largest = max(exports.glob("*/*.dxf"), key=lambda f: f.stat().st_size if ".assembly." not in f.name else 0)
    manifest = json.loads((largest.parent / "manifest.json").read_text())
    stem = largest.stem
    widths = {
        f"{name}.{role}": rec["made"]["solid_volume_mm3"] / rec["made"]["section_area_mm2"]
        for name, part in manifest["parts"].items()
        for role, rec in part.get("results", {}).items()
        if isinstance(rec, dict) and "made" in rec
    }
    proc = subprocess.run(
        [sys.executable, "-c", STEP_ONLY, str(largest), str(widths[stem])], capture_output=True, text=True, cwd=ROOT
    )
    if proc.returncode != 0:
        raise SystemExit(f"STEP of {stem} failed:\n{proc.stderr}")
    return stem, int(re.search(r"PEAK_KB (\d+)", proc.stdout).group(1)) / 1024


def main() -> None:
    from _exports import as_installed

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    as_installed()  # transplanter's modules compiled, as pip installs them
    with tempfile.TemporaryDirectory() as tmp:
        t_par, m_par, _ = build(Path(tmp) / "default")
        t_ser, m_ser, log = build(Path(tmp) / "serial", "--jobs", "1")
        identical = same(Path(tmp) / "default", Path(tmp) / "serial")
        spent = floor(Path(tmp) / "floor")
        step_part, step_peak = largest_step_peak(Path(tmp) / "serial")
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
    start = sum(t for k, t in spent.items() if k.startswith("start"))
    libraries = {k: t for k, t in spent.items() if not k.startswith("start") and k != "build"}
    # the build's time includes loading the part scripts (counted in start)
    own = spent["build"] - sum(libraries.values()) - spent.get("start: part scripts", 0.0)
    print(f"the floor (serial build with every library call timed, {spent['build'] + spent['start: imports']:.1f} s):")
    print(f"    {'start (imports, part scripts)':42s} {start:6.2f} s")
    for what, t in sorted(libraries.items(), key=lambda kv: -kv[1]):
        print(f"    {what:42s} {t:6.2f} s")
    print(f"    {'our own code':42s} {own:6.2f} s")
    bound = start + sum(libraries.values()) / cores
    print(
        f"lower bound on {cores} cores were our own code free: {bound:.1f} s "
        f"(start + library time / {cores}); with it: {start + (sum(libraries.values()) + own) / cores:.1f} s"
    )
    print(f"peak of a process writing only the largest STEP ({step_part}): {step_peak:.0f} MB")


if __name__ == "__main__":
    main()
