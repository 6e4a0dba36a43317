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
shop files, meshing proof on them, report (:mod:`transplanter.families.pairs.gear_pair`).
``transplanter --version`` prints the version; ``python -m transplanter`` is the same command.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from transplanter import __version__
from transplanter.app.analyse import run as _cmd_analyse
from transplanter.app.build import run as _cmd_build
from transplanter.app.check import run as _cmd_check
from transplanter.app.optimise import run as _cmd_optimise
from transplanter.app.options import expression_last, per_gear, timeout_seconds
from transplanter.app.pair import run as _cmd_pair
from transplanter.app.proof_lines import phases_line as _phases_line  # noqa: F401 - tests read it here
from transplanter.core import inputs
from transplanter.core.errors import ExportError, TransplanterError

__all__ = ["main"]


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
        type=per_gear,
        default=1.0,
        metavar="A[,B]",
        help="addendum coefficient, modules: one for both gears or driver,driven (default 1)",
    )
    p.add_argument("--shift", type=per_gear, default=0.0, metavar="X[,Y]", help="profile-shift coefficient (default 0)")
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
            type=timeout_seconds,
            default=inputs.SCRIPT_TIMEOUT_S,
            metavar="SECONDS",
            help=f"time limit for loading a part script (default {inputs.SCRIPT_TIMEOUT_S:g} s)",
        )
    args = parser.parse_args(expression_last(list(sys.argv[1:] if argv is None else argv)))
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
