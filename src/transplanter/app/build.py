"""``transplanter build``: part scripts built into their family folders, a line per part as it is
done and a summary with the reports (:func:`transplanter.families.build_families`); a line for each
part that was not carried forward from the last build because something of it did not verify
(its file, its record, the manifest's seal), saying what.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from transplanter.app.options import default_jobs
from transplanter.core.text import shown

__all__ = ["run"]


def run(args: argparse.Namespace) -> int:
    """Build the part scripts ``args`` names (or every one in ``--parts``); the exit status."""
    import time

    from transplanter.families import build_families, discover, load_family

    scripts = [Path(s) for s in args.scripts] or discover(args.parts)
    if not scripts:
        print(shown(f"no part scripts found in {args.parts}"), file=sys.stderr)
        return 2
    start = time.perf_counter()
    families = [load_family(s, args.timeout) for s in scripts]
    total = sum(len(f.parts) for f in families)
    done = [0]

    def progress(label: str) -> None:  # a line per part as it is done, with the elapsed time
        done[0] += 1
        print(f"[{done[0]}/{total}] {label}  ({time.perf_counter() - start:.1f} s)", file=sys.stderr)

    jobs = args.jobs if args.jobs is not None else default_jobs()
    manifests = build_families(
        families, args.output, jobs=min(jobs, max(total, 1)), progress=progress, force=args.force
    )
    ok = True
    failed = withheld = 0
    kept = sum(len(m.get("build", {}).get("kept", ())) for m in manifests)
    for manifest in manifests:
        name = manifest["family"]
        print(shown(f"{name}: {'ok' if manifest['ok'] else 'FAILED'} -> {Path(args.output) / name}"))
        for part, why in manifest.get("build", {}).get("unverified", {}).items():  # a line each: not carried forward
            print(shown(f"  rebuilt {name}/{part}: {why}"))
        for part, rec in manifest["parts"].items():
            if "error" in rec:
                failed += 1
                print(shown(f"  error: {name}/{part}: {rec['error']}"), file=sys.stderr)
            elif "shop_files" in rec.get("results", {}):
                withheld += 1
        ok = ok and manifest["ok"]
    reports = shown(", ".join(str(Path(args.output) / m["family"] / "report.html") for m in manifests))
    print(
        f"built {total - failed} of {total} parts in {len(manifests)} "
        f"famil{'y' if len(manifests) == 1 else 'ies'} in {time.perf_counter() - start:.1f} s "
        f"({kept} kept unchanged since the last build, {failed} failed, {withheld} findings with shop files "
        f"withheld); reports: {reports}"
    )
    return 0 if ok else 1
