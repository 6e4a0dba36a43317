"""Part scripts: a family of parts from a short Python file, loaded with its folder importable.

A part script defines ``family()`` returning a :class:`Family`; the modules beside it (``_*.py``)
hold its design models and are imported afresh for every load (:func:`run_script`). Loading a
script runs it: only scripts a user chose to build or check are loaded.
"""

from __future__ import annotations

import dataclasses
import os
import re
import runpy
import signal
import sys
import threading
import time
import traceback
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from transplanter.core.errors import PartScriptError, SpecError, TransplanterError
from transplanter.core.inputs import SCRIPT_TIMEOUT_S
from transplanter.families.builder.study import Study

__all__ = ["Family", "discover", "load_family", "run_script"]


_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")


def _check_name(kind: str, name: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise SpecError.out_of_range(
            f"{kind} name", name, "a file name: a letter or digit first, then letters, digits, '_', '-', '.'"
        )
    return name


@dataclass(frozen=True)
class Family:
    """A named set of parts defined by one part script."""

    name: str
    description: str
    parts: tuple[Study, ...] = field(default_factory=tuple)
    #: the part script it came from (set by :func:`load_family`)
    script: str | None = None
    #: the modules beside the script that it imported (``_*.py`` in its folder; set by
    #: :func:`load_family`), recorded with the script in the manifest
    modules: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        _check_name("family", self.name)
        if not isinstance(self.description, str):  # Family(name, (parts...)) would build nothing, silently
            raise PartScriptError(
                f"family {self.name!r}: description must be text, got {type(self.description).__name__} "
                "(Family(name, description, parts))"
            )
        object.__setattr__(self, "parts", tuple(self.parts))
        seen: set[str] = set()
        for p in self.parts:
            if not isinstance(p, Study):
                raise PartScriptError(
                    f"family {self.name!r}: parts must be studies (transplanter.families.Study: a name, cost, "
                    f"build, check, tables and analysis_files — e.g. ArmStudy, ToothedPairStudy, CamStudy), "
                    f"got {type(p).__name__}"
                )
            _check_name("part", p.name)
            if p.name in seen:
                raise PartScriptError(f"family {self.name!r}: part name {p.name!r} is used twice")
            for used in getattr(p, "uses", ()) or ():
                if used not in seen:
                    raise PartScriptError(
                        f"family {self.name!r}: part {p.name!r} uses {used!r}, which is not a part listed before it"
                    )
            seen.add(p.name)


def _namesakes(files: set[str]) -> dict:
    """The imported top-level modules named as a file in ``files`` but read from elsewhere — a
    design module of another copy of ``parts/`` (``_seed002`` imported from the project while a
    copy's script asks for its own) — outside the interpreter's own library and site-packages
    (a ``numpy.py`` beside a script is not taken for numpy's namesake here)."""
    installed = tuple(os.path.realpath(p) + os.sep for p in {sys.prefix, sys.base_prefix, sys.exec_prefix})
    out = {}
    for name, module in list(sys.modules.items()):
        path = getattr(module, "__file__", None)
        if "." in name or not path or os.path.basename(path) != f"{name}.py" or f"{name}.py" not in files:
            continue
        if not os.path.realpath(path).startswith(installed):
            out[name] = module
    return out


@contextmanager
def _beside(folder: Path, imported: list[str]) -> Iterator[None]:
    """Run with ``folder`` first on ``sys.path``, as ``python script.py`` would: a part script
    imports the modules beside it (``_seed004.py`` → ``from _seed004 import ...``). Those modules
    are read afresh — any copy already imported (by a notebook, by pytest's doctest collection)
    is set aside for the run and put back after, as is a namesake read from another folder
    (:func:`_namesakes`) — listed in ``imported``, and forgotten again,
    so the next load reads them afresh too (an edited design module is never served from a cache)."""
    where = str(folder.resolve())
    files = {f.name for f in folder.glob("*.py")}

    def beside() -> dict:  # the imported modules whose file is in the folder (by name first: cheap)
        return {
            name: module
            for name, module in list(sys.modules.items())
            if os.path.basename(getattr(module, "__file__", None) or "") in files
            and os.path.dirname(os.path.realpath(module.__file__)) == where
        }

    held = beside() | _namesakes(files)
    for name in held:
        del sys.modules[name]
    sys.path.insert(0, where)
    try:
        yield
    finally:
        sys.path.remove(where)
        for name, module in sorted(beside().items()):
            imported.append(str(folder / os.path.basename(module.__file__)))
            del sys.modules[name]
        sys.modules.update(held)


class _TimedOut(BaseException):
    """Raised into a part script that outlives its time limit (a BaseException: the script's own
    ``except Exception`` cannot swallow it)."""


@contextmanager
def _guarded(p: Path, what: str, limit: float | None) -> Iterator[None]:
    """Run a part script's code (``what``: "the script", "family()") as one: any error it raises
    becomes a PartScriptError naming the script and the line, its working folder is put back
    however it leaves it, and with ``limit`` (seconds; main thread only, where a signal can reach
    it) it is stopped when it runs longer."""
    cwd = os.getcwd()
    timed = limit is not None and threading.current_thread() is threading.main_thread() and hasattr(signal, "SIGALRM")
    if timed:

        def stop(signum, frame):
            raise _TimedOut

        previous = signal.signal(signal.SIGALRM, stop)
        signal.setitimer(signal.ITIMER_REAL, limit)
    try:
        yield
    except _TimedOut as exc:
        raise PartScriptError(
            f"{p}: {what} ran longer than its time limit of {limit:g} s (raise it with --timeout)"
        ) from exc
    except SyntaxError as exc:
        raise PartScriptError(f"{exc.filename or p}:{exc.lineno}: syntax error: {exc.msg}") from exc
    except TransplanterError as exc:
        raise PartScriptError(f"{p}: {exc}") from exc
    except SystemExit as exc:
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: {what} called sys.exit({exc.code!r})") from exc
    except RecursionError as exc:
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: {what} recursed too deep") from exc
    except Exception as exc:  # a user script can raise anything; report where
        raised = "" if what == "the script" else f"{what} raised "
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: {raised}{type(exc).__name__}: {exc}") from exc
    finally:
        if timed:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
        if os.getcwd() != cwd:
            os.chdir(cwd)


def run_script(path: str | Path, imported: list[str] | None = None, timeout: float | None = SCRIPT_TIMEOUT_S) -> dict:
    """The namespace of a part script (or of a design module beside one), run with its folder
    importable (:func:`_beside`); ``imported`` collects the modules beside it that it imported.
    It must finish within ``timeout`` seconds (None: no limit).

    Raises
    ------
    PartScriptError
        If the file is missing or a folder, does not parse, raises or runs too long; the message
        names the script and the line.
    """
    p = Path(path)
    if p.is_dir():
        raise PartScriptError(f"{p} is a folder, not a part script (give a .py file, or --parts {p})")
    if not p.is_file():
        raise PartScriptError(f"part script {p} does not exist")
    with _guarded(p, "the script", timeout), _beside(p.parent, imported if imported is not None else []):
        return runpy.run_path(str(p), run_name="transplanter_part_script")


def load_family(path: str | Path, timeout: float | None = SCRIPT_TIMEOUT_S) -> Family:
    """Run a part script and return the :class:`Family` its ``family()`` builds.

    The script runs with its folder importable, so its design models and optimisation problems
    can live beside it in modules named ``_*.py`` (which :func:`discover` skips). The script and
    ``family()`` together must finish within ``timeout`` seconds (None: no limit); the script
    must still be there when they have (one that deletes itself is refused).

    Raises
    ------
    PartScriptError
        If the file is missing, does not parse, lacks ``family()``, raises, runs too long, or
        returns something that is not a Family. The message names the script (and line).
    """
    p = Path(path)
    imported: list[str] = []
    start = time.monotonic()
    ns = run_script(p, imported, timeout)
    fn = ns.get("family")
    if not callable(fn):
        raise PartScriptError(f"{p}: a part script must define family() returning transplanter.families.Family")
    left = None if timeout is None else max(timeout - (time.monotonic() - start), 1e-3)
    with _guarded(p, "family()", left):
        fam = fn()
    if not isinstance(fam, Family):
        raise PartScriptError(f"{p}: family() returned {type(fam).__name__}, expected transplanter.families.Family")
    if not p.is_file():
        raise PartScriptError(f"{p}: the part script is gone after it ran (it deleted or moved itself)")
    return dataclasses.replace(fam, script=str(p), modules=tuple(imported))


def _script_line(exc: BaseException, path: Path) -> str:
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if Path(f.filename).resolve() == path.resolve()]
    return str(frames[-1].lineno) if frames else "?"


def discover(parts_dir: str | Path) -> list[Path]:
    """Part scripts in ``parts_dir`` (``*.py`` not starting with ``_``: those are the modules the
    scripts import), sorted by name."""
    d = Path(parts_dir)
    if not d.is_dir():
        raise PartScriptError(f"parts folder {d} does not exist (run from the project root or pass scripts)")
    return sorted(p for p in d.glob("*.py") if not p.name.startswith("_"))
