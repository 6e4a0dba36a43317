"""``transplanter check``: built family folders verified (digests, seal, the shop files re-read and,
with ``--run-script``, the proofs re-run; :func:`transplanter.families.check_families`) and each
part's figures and problems printed.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from transplanter.app.options import default_jobs
from transplanter.app.proof_lines import fmt_um, made_line, mesh_line, phases_line
from transplanter.core.text import shown

__all__ = ["run"]


def run(args: argparse.Namespace) -> int:
    """Check the built folders ``args`` names (default: ``exports``), print what each proof finds; the exit status."""
    from transplanter.families import check_families

    folders = []
    for folder in map(Path, args.folders or ["exports"]):
        if folder.is_symlink():
            print(
                shown(f"transplanter: error: {folder} is a symbolic link: a checked folder is not followed"),
                file=sys.stderr,
            )
            return 2
        if folder.is_dir() and not (folder / "manifest.json").exists():  # a folder of families
            inside = sorted(p for p in folder.iterdir() if not p.is_symlink() and (p / "manifest.json").is_file())
            if not inside:
                print(
                    shown(
                        f"transplanter: error: {folder} is not a built family folder (no manifest.json), "
                        "nor a folder of them"
                    ),
                    file=sys.stderr,
                )
                return 2
            folders += inside
        else:
            folders.append(folder)
    ok = True
    reports = check_families(
        folders, args.script, jobs=default_jobs(), run_script=args.run_script, timeout=args.timeout
    )
    for folder, rep in zip(folders, reports, strict=True):
        design = f", design from {rep['script']}" if rep["script"] else ""
        print(shown(f"{rep['family']}  ({folder}{design})"))
        if not rep["script_run"]:
            print(
                "  files and digests only: no code from the folder was run (--run-script re-runs the proofs with "
                "the part script, if its SHA-256 is the manifest's)"
            )
        for fname, problem in sorted(rep["files"].items()):
            print(shown(f"  file {fname}: {problem}"))
        for name, part in rep["parts"].items():
            res = part["results"]
            if res.get("shop_files_reread"):  # parts without shop files: nothing to say
                n = res["shop_files_reread"]
                print(shown(f"  {name}: {n} shop file{'s' if n != 1 else ''} re-read (DXF, STL)"))
            if "data_files_reproduced" in res:
                n = res["data_files_reproduced"]
                print(shown(f"  {name}: {n} data file{'s' if n != 1 else ''} reproduced by the script"))
            for source, r in sorted((k, v) for k, v in res.items() if isinstance(v, dict)):
                if "error" in r:  # an unreadable file: reported with the problems below
                    continue
                if "max_penetration_mm2" in r or "carried_from" in r:  # meshed, or the DXF's proof carried
                    line = phases_line(r) if "dwell" in r or "motion" in r else mesh_line(r)
                    if "train" in r:
                        line += f", train tip deviation {fmt_um(r['train']['max_tip_deviation_mm'])}"
                elif "max_error_mm" in r:
                    line = f"follower error max {fmt_um(r['max_error_mm'])} rms {fmt_um(r['rms_error_mm'])}"
                elif "pairs_judged" in r:
                    line = (
                        f"{r['pairs_judged']} pairs of bodies judged again over the cycle: nearest its "
                        f"requirement {r['smallest_mm']:.4g} mm ({r['between']}, "
                        f"at driver {r['at_driver_deg']:.1f} deg; "
                        f"required {r['required_mm']:g} mm)"
                    )
                elif "max_deviation_mm" in r:
                    dev = fmt_um(r["max_deviation_mm"])
                    line = f"tip path of the four-bar rebuilt from the plates: max deviation {dev}"
                else:  # the made files re-read: STEP solids, 3MF assemblies
                    for fname, f in sorted(r.items()):
                        print(shown(f"  {name} [{fname}]: {made_line(f)}"))
                    continue
                print(shown(f"  {name} [{source}]: {line}"))
            tag = "finding (expected)" if part["expected"] else "PROBLEM"
            for p in part["problems"]:
                print(shown(f"  {name}: {tag}: {p}"))
        print(f"  {'ok' if rep['ok'] else 'FAILED'}")
        ok = ok and rep["ok"]
    return 0 if ok else 1
