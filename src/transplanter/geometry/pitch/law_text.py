"""The text of an intermittent law (``transplanter pair "0..60: dwell; 60..360: EXPR"``): its
grammar, and each refusal naming the segment and what was expected.

A law is **segments** separated by ``;`` or a line break (blank segments — a trailing ``;``, an
empty line — are skipped; a ``,`` is no separator). A segment is ``A..B: dwell`` or ``A..B: EXPR``:
A and B driver angles in degrees, plain numbers (no ``nan``, ``inf`` or words); the body the word
``dwell`` (any case) or an expression in ``phi`` by the rules of
:mod:`transplanter.geometry.pitch.transmission` (compiled here, so its error names the segment). A
body holding another segment's ``A..B`` (two segments joined by a comma) is refused, as is a lone
word other than ``dwell`` and ``phi`` (``dwel``: an unknown segment kind, never a motion). At most
``MAX_SEGMENTS`` segments. :class:`~transplanter.geometry.pitch.intermittent.IntermittentLaw`
checks what the segments say together (contiguous, one turn, dwells and motions alternating).

Examples
--------
>>> segments("0..60: dwell; 60..360: 1.2*phi;")
[(0.0, 60.0, None), (60.0, 360.0, '1.2*phi')]
"""

from __future__ import annotations

import re

from transplanter.core.errors import SpecError
from transplanter.core.inputs import is_csv_path
from transplanter.geometry.pitch.transmission import MAX_EXPRESSION, _compile

__all__ = ["MAX_SEGMENTS", "is_segmented", "segments"]

#: the most segments a law may have (dwells and motions): every dwell is a lock, swept on its own
#: (seconds each) with 1.5 pitches of transition either side, every motion a sector of two teeth
#: at least — 32 dwells are already a driver of 160 pitches and a build of minutes, and no
#: transplanting law has more than a handful
MAX_SEGMENTS = 64
#: the text between segments: ``;`` or a line break
_SEPARATOR = re.compile(r";|\r\n|\r|\n")
#: a plain number of degrees (no words: nan, inf)
_ANGLE = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
_HEAD = re.compile(r"^\s*(\S*?)\s*\.\.\s*(\S*?)\s*(:|$|\s)")
_WORD = re.compile(r"^[A-Za-z_][A-Za-z_0-9]*$")


def is_segmented(spec: str) -> bool:
    """Whether ``spec`` states a law of segments (it holds ``..`` or the word ``dwell``), not a
    periodic transmission, a named curve or a ratio CSV: none of those can hold them, so a law
    with a bad segment — its first included — is refused as a law, naming the segment."""
    if not isinstance(spec, str) or is_csv_path(spec):
        return False
    return ".." in spec or "dwell" in spec.lower()


def _segment(k: int, text: str) -> tuple[float, float, str | None]:
    """Segment ``k`` (from 1) of a law's text: ``A..B: dwell`` or ``A..B: EXPR``; SpecError naming
    it and what was expected."""
    shown = text.strip() if len(text.strip()) <= 80 else text.strip()[:77] + "..."
    where = f"the law's segment {k} {shown!r}"
    head = _HEAD.match(text)
    if head is None:
        raise SpecError(f"{where}: expected 'A..B: dwell' or 'A..B: EXPR' (A, B driver angles in deg)")
    angles = []
    for side, value in (("start", head.group(1)), ("end", head.group(2))):
        if not re.fullmatch(_ANGLE, value):
            raise SpecError(f"{where}: its {side} angle {value!r} is not a number of degrees (A..B: ..., e.g. 0..60)")
        angles.append(float(value))
    if head.group(3) != ":":
        raise SpecError(
            f"{where}: expected 'A..B: dwell' or 'A..B: EXPR' - no ':' after '{head.group(1)}..{head.group(2)}'"
        )
    body = text[head.end() :].strip()
    if not body:
        raise SpecError(f"{where}: expected 'dwell' or a motion expression in phi after the ':'")
    if ".." in body:
        raise SpecError(
            f"{where}: its body holds another segment's 'A..B' — separate segments with ';' or a new line "
            "(a ',' is no separator)"
        )
    if body.lower() == "dwell":
        return angles[0], angles[1], None
    if _WORD.match(body) and body != "phi":
        raise SpecError(f"{where}: unknown segment kind {body!r}, expected 'dwell' or a motion expression in phi")
    try:
        _compile(body)
    except SpecError as exc:  # said of this segment's expression (the message quotes it once)
        said = str(exc)
        quoted = f"the transmission function {(body if len(body) <= 80 else body[:77] + '...')!r} "
        raise SpecError(
            f"{where}: its body {said.removeprefix(quoted)}" if said.startswith(quoted) else f"{where}: {said}"
        ) from exc
    return angles[0], angles[1], body


def segments(text: str) -> list[tuple[float, float, str | None]]:
    """The segments of a law's ``text`` as (start, end, body) — body None for a dwell, the
    expression for a motion — in order; SpecError naming the first segment that breaks the
    grammar (module docstring) and what was expected."""
    if not isinstance(text, str) or not text.strip():
        raise SpecError(f"the intermittent law must be text 'A..B: dwell; A..B: EXPR', got {text!r}")
    if len(text) > MAX_EXPRESSION:
        raise SpecError.out_of_range("the law's length", len(text), f"<= {MAX_EXPRESSION} characters")
    parts = [p for p in _SEPARATOR.split(text) if p.strip()]
    if len(parts) > MAX_SEGMENTS:
        raise SpecError.out_of_range("the law's number of segments", len(parts), f"<= {MAX_SEGMENTS}")
    return [_segment(k, part) for k, part in enumerate(parts, 1)]
