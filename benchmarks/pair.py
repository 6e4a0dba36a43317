"""`transplanter pair` as a user runs it, against the time its answer's core takes, same run.

Runs the README's example, ``transplanter pair "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5``,
as a child process (wall clock and CPU, as a user waits for it), three times into fresh folders,
and checks the three exports are byte-identical (all but the manifests, which record the folder
their part script lies in). Then, in this process, the part of it that is the design's own
answer: cutting both gears' teeth (the exact envelope of the shaper cutter,
:meth:`ToothedPairStudy.cut_teeth`, median of 5) — and where the rest of the call goes,
from one profiled in-process run: imports, the meshing proof (once, on the re-read DXF, carried
to the outlines and the STL), making the shop files (DXF, STL, 3MF); the STEP (OpenCASCADE) and
the plots are made in forked processes beside the proof and the assembly (issue 46: the plots'
forks as soon as the teeth are cut, the meshing plot sent to it once proved), so the profile
cannot see them: their CPU is given as the profiled call's child processes' (with the profiler's
overhead, which a fork inherits).

transplanter is timed byte-compiled, as ``pip install`` leaves it and as the peer is
(``_exports.as_installed``).

Then the peer a user would pick instead, in the same run: ncgears 0.3.1's one-liner with the same
expression (``ncgears "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5``), installed from PyPI into
a virtual environment of its own under ``~/.cache/transplanter-benchmarks`` (``--no-peer`` skips it),
three times, wall and CPU — and the ratio of the CPU medians.

Goals: issue 30, the call <= 1.5 s wall on an idle 2-core machine, files unchanged; issue 46, its CPU
below the peer's for the same command in the same run, <= 3.5 s wall idle.

Run: python benchmarks/pair.py [--no-peer]
"""

import argparse
import cProfile
import filecmp
import os
import pstats
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

EXAMPLE = ["phi - 0.08*sin(2*phi)", "--teeth", "24", "--module", "1.5"]
#: where the profiled call's time goes: (label, the functions whose cumulative time it is)
STAGES = (
    # the DXF meshed, carried to the outline and STL (issue 46; a source it cannot be carried to is meshed)
    ("meshing proof (DXF, carried to outline, STL)", ("pair_proof.py", "mesh_once")),
    ("shop files made (DXF, STL, wire checks)", ("pair_assembly.py", "make")),
    ("assembly (3MF made and re-read, drawing)", ("pair_assembly.py", "assemble")),  # with the STEP's wait
    ("teeth cut", ("toothed.py", "cut_teeth")),
)


PEER = "ncgears==0.3.1"
#: the environment as the user's shell gave it, before this process runs transplanter's command in
#: itself (``app.cli`` sets ``OPENBLAS_NUM_THREADS`` where unset): both commands are timed in it
USER_ENV = dict(os.environ)


def timed(command: list[str], cwd: Path | None = None) -> tuple[float, float]:
    """(wall s, CPU s of the child and its children) of ``command``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, cwd=cwd, env=USER_ENV)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def child(out: Path) -> tuple[float, float]:
    return timed([sys.executable, "-m", "transplanter", "pair", *EXAMPLE, "-o", str(out)])


def peer() -> Path:
    """The peer's command, installed once into its own virtual environment."""
    env = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "transplanter-benchmarks" / "ncgears-0.3.1"
    exe = env / "bin" / "ncgears"
    if not exe.exists():
        subprocess.run([sys.executable, "-m", "venv", str(env)], check=True)
        subprocess.run([str(env / "bin" / "pip"), "install", "-q", PEER], check=True)
    return exe


def same(a: Path, b: Path) -> bool:
    cmp = filecmp.dircmp(a, b)
    if cmp.left_only or cmp.right_only:
        return False
    # (the manifest records where its part script lies: the folders differ by that path only)
    return all(filecmp.cmp(a / f, b / f, shallow=False) for f in cmp.common_files if f != "manifest.json") and all(
        same(a / d, b / d) for d in cmp.common_dirs
    )


def teeth_time() -> float:
    from transplanter.families.pairs.gear_pair import pair_family

    study = pair_family(EXAMPLE[0], teeth=24, module=1.5).parts[0]  # the call's own pair and cutter
    assert study.sized.sizing.teeth[0] == 24  # sized once, as the call does before it cuts
    times = []
    for _ in range(5):
        start = time.perf_counter()
        study.cut_teeth()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    from _exports import as_installed

    ap = argparse.ArgumentParser()
    ap.add_argument("--no-peer", action="store_true", help="skip installing and running ncgears")
    args = ap.parse_args()
    as_installed()  # transplanter's modules compiled, as pip installs them (the peer's are)
    with tempfile.TemporaryDirectory() as tmp:
        exe = None if args.no_peer else peer()
        runs, theirs = [], []
        for k in range(3):  # interleaved: a busy spell of a shared machine falls on both
            runs.append(child(Path(tmp) / f"run{k}"))
            if exe is not None:
                (Path(tmp) / f"peer{k}").mkdir()
                theirs.append(timed([str(exe), *EXAMPLE], cwd=Path(tmp) / f"peer{k}"))
        identical = all(same(Path(tmp) / "run0" / "pair", Path(tmp) / f"run{k}" / "pair") for k in (1, 2))
        wall = statistics.median(w for w, _ in runs)
        cpu = statistics.median(c for _, c in runs)
        print(f"transplanter pair (README example): {wall:.2f} s wall, {cpu:.2f} s CPU (median of 3; goal 1.5 s wall)")
        if theirs:
            pw, pc = statistics.median(w for w, _ in theirs), statistics.median(c for _, c in theirs)
            print(f"ncgears 0.3.1, the same expression:  {pw:.2f} s wall, {pc:.2f} s CPU (median of 3)")
            print(f"  transplanter / ncgears: {cpu / pc:.2f}x the CPU, {wall / pw:.2f}x the wall (goal: CPU below 1x)")
        print(f"  exports byte-identical across the runs: {identical}")
        ours = teeth_time()
        print(f"  cutting both gears' teeth alone:   {ours * 1e3:.0f} ms  -> the call is {wall / ours:.0f}x that")
        # where the rest goes: one profiled in-process call (imports included)
        from transplanter.app import cli

        prof = cProfile.Profile()
        start = time.perf_counter()
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        prof.enable()
        cli.main(["pair", *EXAMPLE, "-o", str(Path(tmp) / "profiled")])
        prof.disable()
        total = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        beside = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        stats = pstats.Stats(prof).stats
        print(f"  one profiled call in this process: {total:.2f} s (profiler overhead included)")
        for label, (module, func) in STAGES:
            spent = sum(v[3] for (f, _, name), v in stats.items() if f.endswith(module) and name == func)
            print(f"    {label:42s} {spent:5.2f} s")
        print(f"    {'STEP and plots, forked beside (their CPU)':42s} {beside:5.2f} s")


if __name__ == "__main__":
    main()
