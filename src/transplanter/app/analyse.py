"""``transplanter analyse``: a part script's metrics tables printed (beside published values where
a study has them) and, with ``--plots DIR``, its studies' analysis files written.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from transplanter.core.text import shown

__all__ = ["run"]


def run(args: argparse.Namespace) -> int:
    """Print the tables of the part script ``args.script`` (and write its plots); the exit status."""
    from transplanter.families import load_family
    from transplanter.shop.export import atomic_write

    fam = load_family(args.script, args.timeout)
    tables = [(study, table) for study in fam.parts for table in study.tables()]
    if not tables:
        print(shown(f"{args.script}: family {fam.name!r} has no study with a table to analyse"), file=sys.stderr)
        return 2
    for _, table in tables:
        published = any(pub is not None for *_, pub in table.rows)
        print()
        print(shown(f"{fam.name} / {table.title}"))
        width = max(34, *(len(label) for label, *_ in table.rows))
        if published:
            print(f"  {'quantity':{width}s} {'value':>12s} {'published':>10s}")
        for label, value, unit, pub in table.rows:
            ref = (" " * 10 if pub is None else f"{pub:10.2f}") + " " if published else ""
            print(shown(f"  {label:{width}s} {value:12.4f} {ref}{unit}"))
    if args.plots:
        for study in fam.parts:
            for fname, data in study.analysis_files().items():
                atomic_write(Path(args.plots) / fname, data)
    return 0
