"""The designer's loop: a rebuild after nothing changed and after one number changed, against the
cold builds they replace, same run.

Copies ``parts/`` to a temporary folder and times, each as ``transplanter build`` in a child
process (wall clock, as a designer waits for it):

1. the cold build of every family (``--force``) — the baseline of 2;
2. the same build again with nothing changed (every part kept, nothing written), and checks that
   no file in the export was touched;
3. seed 002's family cold (``--force``) — the baseline of 4;
4. that family after one edit (the first gear stage's backlash set to 0.15 mm): only that part and
   the machine built from its files are rebuilt; the folder is then compared byte for byte with a
   forced full rebuild of the edited script.

Prints each time and the ratios. Goals (issue 30): 2 <= 2 s; 4 <= 1.5 x the edited part's own time.

Run: python benchmarks/rebuild.py
"""

import filecmp
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def build(*args: str) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "transplanter", "build", *args], check=True, capture_output=True)
    return time.perf_counter() - start


def same_tree(a: Path, b: Path) -> bool:
    cmp = filecmp.dircmp(a, b)
    if cmp.left_only or cmp.right_only or cmp.diff_files or cmp.funny_files:
        return False
    return all(filecmp.cmp(a / f, b / f, shallow=False) for f in cmp.common_files)


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        parts, out = tmp / "parts", tmp / "out"
        shutil.copytree(ROOT / "parts", parts)
        cold = build("--parts", str(parts), "-o", str(out), "--force")
        stamps = {p: p.stat().st_mtime_ns for p in out.rglob("*") if p.is_file() and "/." not in str(p)}
        noop = build("--parts", str(parts), "-o", str(out))
        touched = sum(p.stat().st_mtime_ns != t for p, t in stamps.items())
        print(f"cold build, every family:        {cold:6.1f} s")
        print(f"rebuild with nothing changed:    {noop:6.1f} s  ({touched} files touched)  ratio {cold / noop:.0f}x")
        seed002 = parts / "potseedling_seed002.py"
        family_cold = build(str(seed002), "-o", str(tmp / "family"), "--force")
        text = seed002.read_text()
        edit = '        notes=(f"the sun 2 (driver'  # the first stage's keyword arguments
        assert edit in text, "the seed-002 script changed: update the benchmark's edit"
        seed002.write_text(text.replace(edit, "        backlash=0.15,\n" + edit, 1))
        one = build(str(seed002), "-o", str(tmp / "family"))
        full = build(str(seed002), "-o", str(tmp / "full"), "--force")
        same = same_tree(tmp / "family" / "potseedling_seed002", tmp / "full" / "potseedling_seed002")
        print(f"seed-002 family, cold:           {family_cold:6.1f} s")
        print(
            f"after one backlash edit:         {one:6.1f} s  ratio {family_cold / one:.1f}x faster; "
            f"folder {'equals' if same else 'DIFFERS from'} a full rebuild (that took {full:.1f} s)"
        )
        os.sync()


if __name__ == "__main__":
    main()
