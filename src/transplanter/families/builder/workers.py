"""Building parts in worker processes: each worker loads a family once and builds the parts it is
given; a part's failure is its outcome, never the worker's."""

from __future__ import annotations

from pathlib import Path

from transplanter.core.errors import TransplanterError
from transplanter.families.builder.scripts import Family, load_family
from transplanter.families.builder.study import Built, Study

__all__ = ["FAMILIES", "executor", "outcome", "part_outcome", "uses"]


def part_outcome(part: Study, root: Path, used: dict[str, bytes] | None = None) -> Built | str:
    """Build one part: its :class:`~transplanter.families.builder.study.Built` (record, files), or the
    error the manifest records for it — any exception a part raises is its failure (a project
    error by its message; anything else with its type, as a bug to report). A part that uses
    others' files (``uses``) is given them, ``used`` (file name -> bytes)."""
    try:
        if uses(part):
            return Built(*part.build_using(root, used or {}))
        return Built(*part.build(root))
    except TransplanterError as exc:
        return f"{type(exc).__name__}: {exc}"
    except Exception as exc:  # a bug, or a library error that escaped: the part fails, the build goes on
        return f"{type(exc).__name__} (unexpected, please report): {exc}"


#: the families being built, by name: set by the builder before it forks its workers
FAMILIES: dict[str, Family] = {}


def executor(jobs: int):
    """A pool of ``jobs`` worker processes, forked where the platform can (the workers then
    start with everything this process has imported and loaded)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else None)
    return ProcessPoolExecutor(max_workers=jobs, mp_context=ctx)


def uses(part: Study) -> tuple[str, ...]:
    """The names of the parts whose files ``part`` is built from (its ``uses``; none for most)."""
    return tuple(getattr(part, "uses", ()) or ())


def outcome(family: str, script: str | None, part: str, used: dict[str, bytes] | None = None):
    fam = FAMILIES.get(family)
    if fam is None:  # a worker that was not forked from the builder: load the script itself
        fam = FAMILIES[family] = load_family(script)
    return part_outcome(next(p for p in fam.parts if p.name == part), Path("."), used)
