"""Command line: ``transplanter build``, ``analyse``, ``optimise``, ``check`` and ``pair``.

``transplanter build`` with no arguments builds every part script in ``./parts`` into
``./exports/<family>/``; ``transplanter build parts/x.py -o DIR --jobs N`` builds the named scripts,
their parts spread over N processes (default: one per available core). ``transplanter analyse
parts/x.py`` prints the metrics tables of the four-bar arms (the seed-000 Table 2 layout) and
planetary trains (beside published values) in a script and, with ``--plots DIR``, writes the arms'
plots. ``transplanter optimise parts/x.py --seed S`` runs differential evolution on the script's
``problem()`` with a progress line per generation and prints the best parameters as JSON.
``transplanter check exports/<family>`` (or ``transplanter check`` for every family in ``exports/``)
verifies every file's SHA-256 against the manifest and the manifest's seal, and re-reads the shop
files — running no code from the folder; with ``--run-script`` it also re-runs the meshing,
follower and rebuild proofs on the files and recomputes the analyses, with the part script only if
it lies in the project and its SHA-256 is the manifest's. It exits 1 if a part that must mesh does
not, or a file is missing, changed or stale. Exit status: 0 on success, 1
if any part failed or a file could not be written (disk full, permissions, another build writing the
same folder), 2 on bad input (message on stderr). ``transplanter pair "phi - 0.08*sin(2*phi)" --teeth 24
--module 1.5 -o DIR`` makes one gear pair from its transmission (an expression in phi, a ratio CSV or
a named curve such as ``ellipse:0.15:2``; ``--internal`` for a ring and planet) into ``DIR/pair/``:
shop files, meshing proof on them, report (:mod:`transplanter.families.gear_pair`).
``transplanter --version`` prints the version; ``python -m transplanter`` is the same command.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

from transplanter import __version__, inputs
from transplanter.errors import ExportError, SpecError, TransplanterError

__all__ = ["main"]


def _default_jobs() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _cmd_build(args: argparse.Namespace) -> int:
    import time

    from transplanter.families import build_families, discover, load_family

    scripts = [Path(s) for s in args.scripts] or discover(args.parts)
    if not scripts:
        print(f"no part scripts found in {args.parts}", file=sys.stderr)
        return 2
    start = time.perf_counter()
    families = [load_family(s, args.timeout) for s in scripts]
    total = sum(len(f.parts) for f in families)
    done = [0]

    def progress(label: str) -> None:  # a line per part as it is done, with the elapsed time
        done[0] += 1
        print(f"[{done[0]}/{total}] {label}  ({time.perf_counter() - start:.1f} s)", file=sys.stderr)

    jobs = args.jobs if args.jobs is not None else _default_jobs()
    manifests = build_families(
        families, args.output, jobs=min(jobs, max(total, 1)), progress=progress, force=args.force
    )
    ok = True
    failed = withheld = 0
    kept = sum(len(m.get("build", {}).get("kept", ())) for m in manifests)
    for manifest in manifests:
        name = manifest["family"]
        print(f"{name}: {'ok' if manifest['ok'] else 'FAILED'} -> {Path(args.output) / name}")
        for part, rec in manifest["parts"].items():
            if "error" in rec:
                failed += 1
                print(f"  error: {name}/{part}: {rec['error']}", file=sys.stderr)
            elif "shop_files" in rec.get("results", {}):
                withheld += 1
        ok = ok and manifest["ok"]
    reports = ", ".join(str(Path(args.output) / m["family"] / "report.html") for m in manifests)
    print(
        f"built {total - failed} of {total} parts in {len(manifests)} "
        f"famil{'y' if len(manifests) == 1 else 'ies'} in {time.perf_counter() - start:.1f} s "
        f"({kept} kept unchanged since the last build, {failed} failed, {withheld} findings with shop files "
        f"withheld); reports: {reports}"
    )
    return 0 if ok else 1


def _cmd_analyse(args: argparse.Namespace) -> int:
    from transplanter.export import atomic_write
    from transplanter.families import load_family

    fam = load_family(args.script, args.timeout)
    tables = [(study, table) for study in fam.parts for table in study.tables()]
    if not tables:
        print(f"{args.script}: family {fam.name!r} has no study with a table to analyse", file=sys.stderr)
        return 2
    for _, table in tables:
        published = any(pub is not None for *_, pub in table.rows)
        print(f"\n{fam.name} / {table.title}")
        width = max(34, *(len(label) for label, *_ in table.rows))
        if published:
            print(f"  {'quantity':{width}s} {'value':>12s} {'published':>10s}")
        for label, value, unit, pub in table.rows:
            ref = (" " * 10 if pub is None else f"{pub:10.2f}") + " " if published else ""
            print(f"  {label:{width}s} {value:12.4f} {ref}{unit}")
    if args.plots:
        for study in fam.parts:
            for fname, data in study.analysis_files().items():
                atomic_write(Path(args.plots) / fname, data)
    return 0


def _settings(pairs: list[str]) -> dict[str, float]:
    """``--set NAME=VALUE`` options as keyword arguments (numbers) for a script's problem()."""
    out = {}
    for pair in pairs:
        name, sep, value = pair.partition("=")
        if not sep or not name.isidentifier():
            raise SpecError.out_of_range("--set", pair, "NAME=NUMBER, NAME a Python name")
        try:
            out[name] = float(value)
        except ValueError:
            raise SpecError.out_of_range(f"--set {name}", value, "a number") from None
        if not math.isfinite(out[name]):
            raise SpecError.out_of_range(f"--set {name}", value, "a finite number")
    return out


def _cmd_optimise(args: argparse.Namespace) -> int:
    import inspect
    import json
    import time

    import numpy as np

    from transplanter.errors import PartScriptError
    from transplanter.families.scripts import record_optimum, run_script
    from transplanter.optimise import Problem, optimise

    path = Path(args.script)
    fn = run_script(path, timeout=args.timeout).get("problem")
    if not callable(fn):
        raise PartScriptError(
            f"{path}: an optimisable script (a part script or a design module beside one) must define "
            "problem() returning an optimise.Problem"
        )
    settings = _settings(args.set or [])
    try:
        inspect.signature(fn).bind(**settings)
    except TypeError as exc:
        raise SpecError(f"--set {', '.join(settings)}: {path}'s problem() does not take it ({exc})") from None
    problem = fn(**settings)
    if not isinstance(problem, Problem):
        raise PartScriptError(f"{path}: problem() returned {type(problem).__name__}, expected optimise.Problem")

    if args.write and problem.optimum is None:
        raise PartScriptError(
            f"{path}: --write records the optimum where the part script reads it, but problem() names no place: "
            "give Problem(..., optimum='OPTIMUM') (a module-level tuple of numbers in this file)"
        )
    start = time.perf_counter()

    def progress(gen: int, best: float, x) -> None:  # the best design so far, every generation
        design = json.dumps(problem.shown(x))
        left = (time.perf_counter() - start) / gen * (args.maxiter - gen)
        line = f"generation {gen:4d}/{args.maxiter}: best cost {best:.6g} at {design}; at most {left:.0f} s left"
        if problem.describe is not None:
            try:
                said = problem.describe(np.asarray(x, dtype=float))
                line += "\n  " + "; ".join(f"{k}: {v}" for k, v in said.items())
            except Exception as exc:  # the problem's own code: its failure is said, the run goes on
                line += f"\n  (its objectives cannot be described: {type(exc).__name__}: {exc})"
        print(line, file=sys.stderr, flush=True)

    res = optimise(
        problem,
        seed=args.seed,
        maxiter=args.maxiter,
        popsize=args.popsize,
        progress=progress,
        workers=args.workers,
        scheduler=args.scheduler,
    )
    out = {
        "problem": problem.name,
        "seed": args.seed,
        "cost": res.fun,
        "generations": res.generations,
        "evaluations": res.evaluations,
        "evaluation": "serial" if args.workers == 1 and args.scheduler is None else "parallel (deferred updating)",
        "parameters": problem.shown(res.x),
    }
    if args.write:
        where = record_optimum(path, problem.optimum, res.x)
        out["written"] = f"{problem.optimum} in {where}"
        print(f"the optimum is recorded as {problem.optimum} in {where}: a build follows it", file=sys.stderr)
    print(json.dumps(out, indent=2))
    return 0


def _fmt_um(mm: float) -> str:
    """A length in µm, or in mm from 1 mm up (no "3.2e+03 µm")."""
    return f"{mm:.3g} mm" if abs(mm) >= 1 else f"{mm * 1000:.3g} µm"


def _cmd_check(args: argparse.Namespace) -> int:
    from transplanter.families import check_families

    folders = []
    for folder in map(Path, args.folders or ["exports"]):
        if folder.is_symlink():
            print(
                f"transplanter: error: {folder} is a symbolic link: a checked folder is not followed", file=sys.stderr
            )
            return 2
        if folder.is_dir() and not (folder / "manifest.json").exists():  # a folder of families
            inside = sorted(p for p in folder.iterdir() if not p.is_symlink() and (p / "manifest.json").is_file())
            if not inside:
                print(
                    f"transplanter: error: {folder} is not a built family folder (no manifest.json), "
                    "nor a folder of them",
                    file=sys.stderr,
                )
                return 2
            folders += inside
        else:
            folders.append(folder)
    ok = True
    reports = check_families(
        folders, args.script, jobs=_default_jobs(), run_script=args.run_script, timeout=args.timeout
    )
    for folder, rep in zip(folders, reports, strict=True):
        design = f", design from {rep['script']}" if rep["script"] else ""
        print(f"{rep['family']}  ({folder}{design})")
        if not rep["script_run"]:
            print(
                "  files and digests only: no code from the folder was run (--run-script re-runs the proofs with "
                "the part script, if its SHA-256 is the manifest's)"
            )
        for fname, problem in sorted(rep["files"].items()):
            print(f"  file {fname}: {problem}")
        for name, part in rep["parts"].items():
            res = part["results"]
            if res.get("shop_files_reread"):  # parts without shop files: nothing to say
                n = res["shop_files_reread"]
                print(f"  {name}: {n} shop file{'s' if n != 1 else ''} re-read (DXF, STL)")
            if "data_files_reproduced" in res:
                n = res["data_files_reproduced"]
                print(f"  {name}: {n} data file{'s' if n != 1 else ''} reproduced by the script")
            for source, r in sorted((k, v) for k, v in res.items() if isinstance(v, dict)):
                if "error" in r:  # an unreadable file: reported with the problems below
                    continue
                if "max_penetration_mm2" in r:
                    line = _phases_line(r) if "dwell" in r or "motion" in r else _mesh_line(r)
                    if "train" in r:
                        line += f", train tip deviation {_fmt_um(r['train']['max_tip_deviation_mm'])}"
                elif "max_error_mm" in r:
                    line = f"follower error max {_fmt_um(r['max_error_mm'])} rms {_fmt_um(r['rms_error_mm'])}"
                elif "pairs_judged" in r:
                    line = (
                        f"{r['pairs_judged']} pairs of bodies judged again over the cycle: nearest its "
                        f"requirement {r['smallest_mm']:.4g} mm ({r['between']}, "
                        f"at driver {r['at_driver_deg']:.1f} deg; "
                        f"required {r['required_mm']:g} mm)"
                    )
                elif "max_deviation_mm" in r:
                    dev = _fmt_um(r["max_deviation_mm"])
                    line = f"tip path of the four-bar rebuilt from the plates: max deviation {dev}"
                else:  # the made files re-read: STEP solids, 3MF assemblies
                    for fname, f in sorted(r.items()):
                        print(f"  {name} [{fname}]: {_made_line(f)}")
                    continue
                print(f"  {name} [{source}]: {line}")
            tag = "finding (expected)" if part["expected"] else "PROBLEM"
            for p in part["problems"]:
                print(f"  {name}: {tag}: {p}")
        print(f"  {'ok' if rep['ok'] else 'FAILED'}")
        ok = ok and rep["ok"]
    return 0 if ok else 1


def _mesh_line(r: dict) -> str:
    """One source's meshing check (``validate.mesh_check`` figures), in words."""
    clearance = ""
    if "clearance_mm" in r:
        clearance = f"clearance {_fmt_um(r['clearance_mm'])} at {r['clearance_at_driver_deg']:.1f} deg, "
    return (
        f"overlap {r['max_penetration_mm2']:.3g} mm² (fouling {r['max_fouling_mm2']:.3g}), "
        f"TE max {_fmt_um(r['max_transmission_error_mm'])} "
        f"rms {_fmt_um(r['rms_transmission_error_mm'])}, "
        f"backlash {_fmt_um(r['backlash_mm'][0])}..{_fmt_um(r['backlash_mm'][1])}, "
        f"{clearance}contact ratio {r['contact_ratio']:.3g}"
    )


def _cmd_pair(args: argparse.Namespace) -> int:
    from transplanter.families.gear_pair import gear_pair

    names = ("internal", "teeth", "module", "centre_distance", "driven_lobes", "ring", "backlash", "cutter_teeth")
    names += ("scale_to_close", "addendum", "shift", "trim_ring_tips", "allow_undercut")
    names += ("lock_clearance", "lock_depth", "locking_play")
    options = {k: getattr(args, k) for k in (*names, "rack", "width", "name")}
    options = {k: v for k, v in options.items() if v is not None or k != "locking_play"}
    manifest = gear_pair(args.transmission, args.output, **options)
    folder = Path(args.output) / manifest["family"]
    print(manifest["description"])
    rec = manifest["parts"][args.name]
    if "error" in rec:
        print(f"FAILED -> {folder}\n  error: {rec['error']}", file=sys.stderr)
        return 1
    if rec.get("kind") == "incomplete_pair":
        return _print_incomplete(rec, folder)
    asm = rec["results"]["assembly"]
    print(
        f"  centre distance {asm['centre_distance_mm']:.6f} mm; driven axis at {asm['driven_centre_mm']} mm in the "
        f"driver's DXF frame, turned {asm['driven_angle_at_start_deg']:g} deg at the start"
    )
    for source, r in sorted((k, v) for k, v in rec["results"]["meshing"].items() if isinstance(v, dict)):
        print(f"  meshing [{source}]: {_mesh_line(r)}")
    shop = [f for f in rec["files"] if f.endswith((".dxf", ".stl", ".step", ".3mf"))]
    print(f"  shop files: {', '.join(shop)}")
    print(f"ok -> {folder} (report.html)")
    return 0


def _phases_line(r: dict) -> str:
    """An incomplete pair's meshing figures (one source), per phase, in words."""
    parts = []
    if "motion" in r:
        lo, hi = r["motion"]["free_play_mm"]
        parts.append(f"motion free play {_fmt_um(lo)}..{_fmt_um(hi)}")
    for phase in ("dwell", "transition"):
        if phase in r:
            parts.append(f"{phase} play <= {r[phase]['largest_play_deg']:.3f} deg")
    return f"overlap {r['max_penetration_mm2']:.3g} mm², " + ", ".join(parts)


def _print_incomplete(rec: dict, folder: Path) -> int:
    """What ``pair`` says of an incomplete pair: locks, entry shocks and the proof per phase."""
    res = rec["results"]
    asm = res["assembly"]
    print(
        f"  centre distance {asm['centre_distance_mm']:.6f} mm; driven axis at {asm['driven_centre_mm']} mm in the "
        f"driver's DXF frame, turned {asm['driven_angle_at_start_deg']:g} deg at the start"
    )
    for lock in res["locks"]:
        print(
            f"  dwell {lock['dwell_deg'][0]:g}..{lock['dwell_deg'][1]:g} deg: locking arcs "
            f"{lock['driver_arc_radius_mm']:.4f} / {lock['driven_arc_radius_mm']:.4f} mm, "
            f"horns at +/-{lock['horns_half_angle_deg']:.1f} deg"
        )
    for t in res["transitions"]:
        print(
            f"  {t['kind']} at driver {t['driver_deg']:g} deg: driven speed jumps by "
            f"{t['speed_jump_w2_per_w1']:.4g} x the driver's, "
            f"acceleration by {t['acceleration_jump_per_w1_squared']:.4g} x w1^2"
        )
    for e in res["entry"]:
        if "first_contact_driver_deg" in e:
            print(
                f"  first tooth contact after the dwell at driver {e['first_contact_driver_deg']:.3f} deg "
                f"({e['after_dwell_end_deg']:+.3f} deg from the law's), "
                f"{e['driver_radius_below_tip_m']:.2f} m below the "
                f"driver's tip, {e['driven_radius_from_tip_m']:.2f} m from the driven's"
            )
    for source, r in sorted((k, v) for k, v in res["meshing"].items() if isinstance(v, dict)):
        print(f"  meshing [{source}]: {_phases_line(r)}")
    shop = [f for f in rec["files"] if f.endswith((".dxf", ".stl", ".step", ".3mf"))]
    print(f"  shop files: {', '.join(shop)}")
    print(f"ok -> {folder} (report.html)")
    return 0


def _made_line(r: dict) -> str:
    """One re-read shop file's figures (``formats``), in words."""
    if "error" in r:
        return "cannot be checked (see below)"
    if "bodies" in r:
        return f"{r['bodies']} bodies, largest overlap {r['max_overlap_mm3']:.3g} mm³"
    return (
        f"{r['solids']} solid, {r['faces']} faces, {'valid' if r['valid'] else 'INVALID'} "
        f"({r.get('checked_by', 'not checked')}), "
        f"volume off by {r['volume_rel_error']:.3g} (relative)"
    )


def _timeout(text: str) -> float:
    """``--timeout`` in seconds, checked by the input layer."""
    try:
        value = float(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from exc
    try:
        return inputs.timeout(value)
    except TransplanterError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from exc


def _per_gear(text: str) -> float | tuple[float, float]:
    """``A`` or ``A,B`` (driver, driven) as numbers; the ranges are the study's to check."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number or two numbers A,B") from exc
    if len(values) not in (1, 2):
        raise argparse.ArgumentTypeError(f"{text!r}: give one number, or two as driver,driven")
    return values[0] if len(values) == 1 else (values[0], values[1])


#: ``pair``'s options that take a value (the next argument is that value, whatever it looks like)
_PAIR_VALUES = {"--teeth", "--module", "--centre-distance", "--ring", "--driven-lobes", "--backlash"}
_PAIR_VALUES |= {"--cutter-teeth", "--width", "--name", "-o", "--output", "--addendum", "--shift"}


def _expression_last(argv: list[str]) -> list[str]:
    """``pair``'s transmission moved behind ``--`` when it starts with ``-`` (``"-0.1*sin(phi) + phi"``):
    argparse would take it for an option. Only what cannot be an option moves (it has a space, a
    bracket, an operator or ``phi`` past its dash)."""
    if not argv or argv[0] != "pair" or "--" in argv:
        return argv
    out, moved, k = [argv[0]], [], 1
    while k < len(argv):
        a = argv[k]
        if a in _PAIR_VALUES:
            out += argv[k : k + 2]
            k += 2
            continue
        body = a.lstrip("-")
        if a.startswith("-") and not a.startswith("--") and (any(c in body for c in " ()*+/^") or "phi" in body):
            moved.append(a)
        else:
            out.append(a)
        k += 1
    return [*out, "--", *moved] if moved else out


def main(argv: list[str] | None = None) -> int:
    """The command line; exit 0 (done), 1 (a part failed or a file could not be written), 2 (bad
    input, named). Anything else — a bug — is "internal error, please report" with a log file of its
    traceback, exit 1: never a bare traceback."""
    try:
        return _main(argv)
    except KeyboardInterrupt:
        print("transplanter: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: said as one, its traceback kept for the report
        import tempfile
        import time
        import traceback

        stamp = time.strftime("%Y%m%d-%H%M%S")
        log = Path(tempfile.gettempdir()) / f"transplanter-internal-error-{stamp}-{os.getpid()}.log"
        try:
            log.write_text("".join(traceback.format_exception(exc)))
            where = f"the traceback is in {log}"
        except OSError:
            where = "(its traceback could not be written)"
        print(f"transplanter: internal error — please report it: {type(exc).__name__}: {exc}; {where}", file=sys.stderr)
        return 1


def _main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="transplanter", description=__doc__.split("\n")[0])
    parser.add_argument("--version", action="version", version=f"transplanter {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="build part families into exports/")
    b.add_argument("scripts", nargs="*", help="part scripts (default: every script in --parts)")
    b.add_argument("-o", "--output", default="exports", help="output folder (default: exports)")
    b.add_argument("--parts", default="parts", help="folder of part scripts (default: parts)")
    b.add_argument(
        "--jobs", type=int, default=None, help="build the parts in N processes (default: one per available core)"
    )
    b.add_argument("--force", action="store_true", help="rebuild every part, changed or not")
    a = sub.add_parser("analyse", aliases=["analyze"], help="print the planting metrics of a part script's arms")
    a.add_argument("script", help="part script")
    a.add_argument("--plots", metavar="DIR", help="also write path and kinematics plots to DIR")
    o = sub.add_parser("optimise", aliases=["optimize"], help="optimise the parameters of a part script's problem()")
    o.add_argument("script", help="part script defining problem()")
    o.add_argument("--seed", type=int, default=0, help="random seed (runs are reproducible)")
    o.add_argument("--maxiter", type=int, default=50, help="generations of differential evolution")
    o.add_argument("--popsize", type=int, default=15, help="population size per variable")
    o.add_argument("--workers", type=int, default=1, help="evaluate candidates on N local processes (dask)")
    o.add_argument("--scheduler", metavar="ADDRESS", help="evaluate candidates on this Dask cluster (tcp://host:port)")
    o.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="a number passed to the script's problem() as a keyword (e.g. --set min_module=3)",
    )
    o.add_argument(
        "--write",
        action="store_true",
        help="record the optimum in the script, where problem() says the part script reads it (Problem(optimum=))",
    )
    c = sub.add_parser("check", help="re-run the meshing and follower checks on built files")
    c.add_argument("folders", nargs="*", help="built family folders, or a folder of them (default: exports)")
    c.add_argument(
        "--run-script",
        action="store_true",
        help="re-run the proofs with the part script: only one inside the project whose SHA-256 is the manifest's",
    )
    c.add_argument("--script", help="with --run-script: the part script (default: the one the manifest records)")
    p = sub.add_parser(
        "pair",
        help="one gear pair from a transmission ratio: shop files, meshing proof and report",
        description="A gear pair from its transmission: an expression in phi (the driven angle, rad, "
        'e.g. "phi - 0.08*sin(2*phi)"), a CSV of ratio samples (driver angle deg, w2/w1), or a named '
        "driver curve (ellipse:E[:LOBES], eccentric:E). Give two of --teeth, --module, --centre-distance. "
        'A law with dwells ("0..60: dwell; 60..360: EXPR", or a CSV whose zero rows are dwells) makes an '
        "incomplete pair: toothed sectors, locking arcs; give --module and --teeth or --centre-distance.",
    )
    p.add_argument("transmission", help="expression in phi, ratio CSV file, or NAME:PARAMS")
    p.add_argument("--teeth", type=int, help="driver tooth count")
    p.add_argument("--module", type=float, help="module, mm")
    p.add_argument("--centre-distance", type=float, help="centre distance, mm")
    p.add_argument("--internal", action="store_true", help="an internal pair (ring gear and planet)")
    p.add_argument("--ring", choices=("driven", "driver"), default="driven", help="internal, from a ratio: the ring")
    p.add_argument("--driven-lobes", type=int, help="named curves: lobes of the mate")
    p.add_argument("--backlash", type=float, help="circumferential backlash, mm (default: ISO/TR 10064-2)")
    p.add_argument("--cutter-teeth", type=int, help="shaper cutter teeth (default: the first of 12..24 that cuts)")
    p.add_argument("--rack", action="store_true", help="cut with a rack cutter (hob): external, convex curves")
    p.add_argument("--width", type=float, default=10.0, help="face width, mm (default 10)")
    p.add_argument("--name", default="pair", help="folder and part name (default: pair)")
    p.add_argument(
        "--addendum",
        type=_per_gear,
        default=1.0,
        metavar="A[,B]",
        help="addendum coefficient, modules: one for both gears or driver,driven (default 1)",
    )
    p.add_argument(
        "--shift", type=_per_gear, default=0.0, metavar="X[,Y]", help="profile-shift coefficient (default 0)"
    )
    p.add_argument(
        "--no-trim-ring-tips",
        dest="trim_ring_tips",
        action="store_false",
        help="internal pairs: refuse ring tips that foul instead of shortening them to the limit",
    )
    p.add_argument("--allow-undercut", action="store_true", help="accept an undercut flank instead of refusing it")
    p.add_argument(
        "--scale-to-close",
        action="store_true",
        help="scale a ratio that does not close by the factor that closes it (default: refuse it, naming the factor)",
    )
    p.add_argument("--lock-clearance", type=float, help="incomplete pairs: the locks' radial clearance, mm")
    p.add_argument(
        "--lock-depth",
        type=float,
        help="incomplete pairs: how deep the driver's locking arc reaches into the driven's tips, modules "
        "(default 0.3 external; internal: 0.3 short of the planet's tips)",
    )
    p.add_argument(
        "--locking-play",
        type=float,
        help="incomplete pairs: the driven's free play allowed in dwells and transitions, deg (default 2)",
    )
    p.add_argument("-o", "--output", default="exports", help="output folder (default: exports)")
    for command in (b, a, o, c):
        command.add_argument(
            "--timeout",
            type=_timeout,
            default=inputs.SCRIPT_TIMEOUT_S,
            metavar="SECONDS",
            help=f"time limit for loading a part script (default {inputs.SCRIPT_TIMEOUT_S:g} s)",
        )
    args = parser.parse_args(_expression_last(list(sys.argv[1:] if argv is None else argv)))
    try:
        if args.command == "build":
            if args.jobs is not None and args.jobs < 1:
                parser.error(f"--jobs = {args.jobs} is out of range: must be >= 1")
            return _cmd_build(args)
        if args.command in ("optimise", "optimize"):
            for option in ("maxiter", "popsize", "workers"):
                if getattr(args, option) < 1:
                    parser.error(f"--{option} = {getattr(args, option)} is out of range: must be >= 1")
            if args.seed < 0:
                parser.error(f"--seed = {args.seed} is out of range: must be >= 0")
            return _cmd_optimise(args)
        if args.command == "check":
            return _cmd_check(args)
        if args.command == "pair":
            return _cmd_pair(args)
        return _cmd_analyse(args)
    except ExportError as exc:  # the input was fine; the files could not be written
        print(f"transplanter: error: {exc}", file=sys.stderr)
        return 1
    except TransplanterError as exc:
        print(f"transplanter: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
