"""The command line's option types and defaults: the processes a command spreads over, ``--timeout``
in seconds, a per-gear ``A[,B]`` value, and ``pair``'s transmission moved out of argparse's way when
it starts with a dash (:mod:`transplanter.app.cli` builds the parser with them).
"""

from __future__ import annotations

import argparse
import os

from transplanter.core import inputs
from transplanter.core.errors import TransplanterError

__all__ = ["PAIR_FLAGS", "PAIR_VALUES", "default_jobs", "expression_last", "integer_in", "per_gear", "timeout_seconds"]


def default_jobs() -> int:
    """The processes a command spreads over unless told: one per core this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def timeout_seconds(text: str) -> float:
    """``--timeout`` in seconds, checked by the input layer."""
    try:
        value = float(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from exc
    try:
        return inputs.timeout(value)
    except TransplanterError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from exc


def integer_in(option: str, low: int, high: int):
    """An option's type: an integer in ``[low, high]``, checked when the command line is parsed (the
    error names the option, the value and the limits), e.g. ``integer_in("--seed", 0, 2**32 - 1)``."""

    def parse(text: str) -> int:
        try:
            value = int(text.strip())
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not an integer") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"{option} = {value} is out of range: must be an integer from {low} to {high}"
            )
        return value

    parse.__name__ = option.lstrip("-")  # argparse names the type in "invalid <name> value"
    return parse


def per_gear(text: str) -> float | tuple[float, float]:
    """``A`` or ``A,B`` (driver, driven) as numbers; the ranges are the study's to check."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number or two numbers A,B") from exc
    if len(values) not in (1, 2):
        raise argparse.ArgumentTypeError(f"{text!r}: give one number, or two as driver,driven")
    return values[0] if len(values) == 1 else (values[0], values[1])


#: how ``pair``'s errors name its options: as typed on the command line
#: (:func:`transplanter.families.pairs.pair_options.check_options` names them so)
PAIR_FLAGS = {
    "spec": "the transmission",
    "internal": "--internal",
    "teeth": "--teeth",
    "module": "--module",
    "centre_distance": "--centre-distance",
    "driven_lobes": "--driven-lobes",
    "ring": "--ring",
    "backlash": "--backlash",
    "cutter_teeth": "--cutter-teeth",
    "rack": "--rack",
    "width": "--width",
    "name": "--name",
    "scale_to_close": "--scale-to-close",
    "addendum": "--addendum",
    "shift": "--shift",
    "trim_ring_tips": "--no-trim-ring-tips",
    "allow_undercut": "--allow-undercut",
    "lock_clearance": "--lock-clearance",
    "lock_depth": "--lock-depth",
    "locking_play": "--locking-play",
    "out": "-o/--output",
}

#: ``pair``'s options that take a value (the next argument is that value, whatever it looks like)
PAIR_VALUES = {"--teeth", "--module", "--centre-distance", "--ring", "--driven-lobes", "--backlash"}
PAIR_VALUES |= {"--cutter-teeth", "--width", "--name", "-o", "--output", "--addendum", "--shift"}


def expression_last(argv: list[str]) -> list[str]:
    """``pair``'s transmission moved behind ``--`` when it starts with ``-`` (``"-0.1*sin(phi) + phi"``):
    argparse would take it for an option. Only what cannot be an option moves (it has a space, a
    bracket, an operator or ``phi`` past its dash)."""
    if not argv or argv[0] != "pair" or "--" in argv:
        return argv
    out, moved, k = [argv[0]], [], 1
    while k < len(argv):
        a = argv[k]
        if a in PAIR_VALUES:
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
