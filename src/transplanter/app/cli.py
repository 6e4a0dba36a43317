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
from transplanter.app import one_blas_thread  # noqa: F401 - before numpy loads: one BLAS thread
from transplanter.app.analyse import run as _cmd_analyse
from transplanter.app.build import run as _cmd_build
from transplanter.app.check import run as _cmd_check
from transplanter.app.optimise import run as _cmd_optimise
from transplanter.app.options import expression_last, integer_in, per_gear, timeout_seconds
from transplanter.app.pair import run as _cmd_pair
from transplanter.app.proof_lines import phases_line as _phases_line  # noqa: F401 - tests read it here
from transplanter.core import inputs
from transplanter.core.errors import ExportError, TransplanterError
from transplanter.core.text import shown
from transplanter.design.optimise import MAX_MAXITER, MAX_POPSIZE, MAX_SEED, MAX_WORKERS, SCHEDULER_TIMEOUT_S

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    """The command line; exit 0 (done), 1 (a part failed or a file could not be written), 2 (bad
    input, named). Anything else — a bug — is "internal error, please report" with a log file of its
    traceback (:func:`_internal_error_log`), exit 1: never a bare traceback. Every message is
    printed through :func:`~transplanter.core.text.shown`: a name or an error read from a file
    cannot act on the terminal."""
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        return _main(argv)
    except KeyboardInterrupt:
        print("transplanter: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: said as one, its traceback kept for the report
        import traceback

        try:
            log = _internal_error_log("".join(traceback.format_exception(exc)), _paths_in(argv))
        except Exception:  # the log is a courtesy: its own failure never hides the report
            log = None
        where = f"the traceback is in {log}" if log else "(its traceback could not be written to a private folder)"
        print(
            shown(f"transplanter: internal error — please report it: {type(exc).__name__}: {exc}; {where}"),
            file=sys.stderr,
        )
        return 1


def _paths_in(argv: list[str]) -> list[Path]:
    """The arguments that name something on disk (the folders a command checks or writes), absolute."""
    out = []
    for a in argv:
        try:
            if os.path.lexists(a):
                out.append(Path(os.path.abspath(a)))
        except (ValueError, OSError):  # a NUL in it, a name too long: not a path on disk
            continue
    return out


def _private_dir(folder: Path) -> int | None:
    """A descriptor of ``folder`` if it is a directory of ours that only we can enter (mode 0700 or
    tighter, owned by this user, not a link), else None."""
    import stat

    try:
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError:
        return None
    st = os.fstat(fd)
    if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid() or st.st_mode & 0o077:
        os.close(fd)
        return None
    return fd


def _internal_error_log(text: str, avoid: list[Path]) -> Path | None:
    """Write ``text`` to a new log file where no link can redirect it; its path, or None.

    The folder is ``$XDG_STATE_HOME/transplanter`` (``~/.local/state/transplanter``), created 0700
    and used only if it is a directory of this user's that no one else can enter and not a link;
    else a fresh ``tempfile.mkdtemp()`` folder (0700, a name no one can foresee). A folder inside,
    equal to or beside (same parent) one the command was given is not used. The file is created
    with ``O_CREAT | O_EXCL | O_NOFOLLOW`` relative to the folder's descriptor: an existing file or
    a planted link at its name is never opened."""
    import tempfile
    import time

    def apart(folder: Path) -> bool:
        f = Path(os.path.realpath(folder))
        for p in avoid:
            for q in {p, Path(os.path.realpath(p))}:
                if f == q or q in f.parents or f.parent == q.parent or f == q.parent:
                    return False
        return True

    def state() -> Path | None:
        base = Path(os.environ.get("XDG_STATE_HOME") or Path.home() / ".local" / "state")
        if not base.is_absolute():  # the XDG rule: a relative path is ignored
            return None
        folder = base / "transplanter"
        if not apart(folder):  # judged before anything is made
            return None
        try:
            base.mkdir(mode=0o700, parents=True, exist_ok=True)
            folder.mkdir(mode=0o700, exist_ok=True)
        except OSError:
            return None
        return folder

    def fresh() -> Path | None:
        if not apart(Path(tempfile.gettempdir()) / "transplanter-"):
            return None
        try:
            return Path(tempfile.mkdtemp(prefix="transplanter-"))
        except OSError:
            return None

    name = f"internal-error-{time.strftime('%Y%m%d-%H%M%S')}-{os.getpid()}-{os.urandom(4).hex()}.log"
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC
    for make in (state, fresh):
        folder = make()
        if folder is None or not apart(folder):
            continue
        dfd = _private_dir(folder)
        if dfd is None:
            continue
        try:
            fd = os.open(name, flags, 0o600, dir_fd=dfd)
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(text)
            return folder / name
        except OSError:
            continue
        finally:
            os.close(dfd)
    return None


class _Parser(argparse.ArgumentParser):
    """argparse's parser whose errors (which quote the arguments) are printed as text, one line,
    through :func:`~transplanter.core.text.shown` (its subcommands' parsers too)."""

    def error(self, message: str):
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {shown(message)}\n")


def _main(argv: list[str]) -> int:
    parser = _Parser(prog="transplanter", description=__doc__.split("\n")[0])
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
    o.add_argument(
        "--seed", type=integer_in("--seed", 0, MAX_SEED), default=0, help="random seed, 0..2**32-1 (reproducible runs)"
    )
    o.add_argument(
        "--maxiter",
        type=integer_in("--maxiter", 1, MAX_MAXITER),
        default=50,
        help=f"generations of differential evolution (1..{MAX_MAXITER})",
    )
    o.add_argument(
        "--popsize",
        type=integer_in("--popsize", 1, MAX_POPSIZE),
        default=15,
        help=f"population size per variable (1..{MAX_POPSIZE})",
    )
    o.add_argument(
        "--workers",
        type=integer_in("--workers", 1, MAX_WORKERS),
        default=1,
        help=f"evaluate candidates on N local processes (dask; 1..{MAX_WORKERS})",
    )
    o.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help=f"evaluate candidates on this Dask cluster (tcp://host:port; it must answer within "
        f"{SCHEDULER_TIMEOUT_S:g} s)",
    )
    o.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="a number passed to the script's problem() as a keyword (e.g. --set min_module=3)",
    )
    o.add_argument(
        "--write",
        action="store_true",
        help="record the optimum in the script, where problem() says the part script reads it (Problem(optimum=)): "
        "only the tuple's numbers are rewritten, and only if the optimum is better than what the file holds",
    )
    o.add_argument(
        "--write-infeasible",
        action="store_true",
        help="--write, and record the optimum even if it misses an objective (a margin below 0); "
        "with --write alone such a design is printed, not written",
    )
    d = sub.add_parser(
        "design",
        help="the design studio: a part script's problem() live in the browser (sliders, trajectory, objectives)",
    )
    d.add_argument(
        "script",
        nargs="?",
        help="part script defining problem() (e.g. parts/planetary_seed004.py); without it, a page of those in --parts",
    )
    d.add_argument("--parts", default="parts", help="without a script: the folder of part scripts (default: parts)")
    d.add_argument("--port", type=integer_in("--port", 0, 65535), default=0, help="port (default: a free one)")
    d.add_argument(
        "--host",
        default="127.0.0.1",
        help="interface to listen on (default 127.0.0.1, this machine only; another one is warned about)",
    )
    d.add_argument("--no-browser", action="store_true", help="print the URL, do not open a browser")
    d.add_argument("--start", metavar="NAME", help="open on this named design of the script (e.g. FRONT_280)")
    d.add_argument("--set", action="append", metavar="NAME=VALUE", help="a number passed to problem(), as optimise")
    d.add_argument(
        "--workers",
        type=integer_in("--workers", 1, MAX_WORKERS),
        default=1,
        help="searches from the page evaluate designs on N local processes (dask), as optimise",
    )
    d.add_argument("--scheduler", metavar="ADDRESS", help="searches from the page evaluate on this Dask cluster")
    d.add_argument("-o", "--output", default="exports", help='"make parts" builds into this folder (default: exports)')
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
    p.add_argument(
        "--ring",
        choices=("driven", "driver"),
        help="internal pairs from a ratio: which gear is the ring (default driven; refused for other pairs)",
    )
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
    for command in (b, a, o, c, d):
        command.add_argument(
            "--timeout",
            type=timeout_seconds,
            default=inputs.SCRIPT_TIMEOUT_S,
            metavar="SECONDS",
            help=f"time limit for loading a part script (default {inputs.SCRIPT_TIMEOUT_S:g} s)",
        )
    args = parser.parse_args(expression_last(list(argv)))
    try:
        if args.command == "build":
            if args.jobs is not None and args.jobs < 1:
                parser.error(f"--jobs = {args.jobs} is out of range: must be >= 1")
            return _cmd_build(args)
        if args.command in ("optimise", "optimize"):
            return _cmd_optimise(args)  # its numbers checked as they were parsed (integer_in)
        if args.command == "check":
            return _cmd_check(args)
        if args.command == "design":
            from transplanter.app.studio import run as design

            return design(args)
        if args.command == "pair":
            return _cmd_pair(args)
        return _cmd_analyse(args)
    except TransplanterError as exc:  # bad input (2), or fine input whose files could not be written (1)
        print(shown(f"transplanter: error: {exc}"), file=sys.stderr)
        return 1 if isinstance(exc, ExportError) else 2


if __name__ == "__main__":
    sys.exit(main())
