"""Text from data printed as text: a name, a path or an error read from a file may hold characters
a terminal obeys instead of showing — ``ESC [2J`` clears the screen, ``\\r`` rewrites the line
already shown ("ok"), a bidi override reorders what follows. :func:`shown` escapes them, so a
message quoting untrusted text cannot act on the terminal. Every line the command line prints
that quotes a name, a path or an error goes through it (``transplanter check``'s lines, the error
and internal-error printers).

Examples
--------
>>> from transplanter.core.text import shown
>>> shown("part\\x1b[2J\\rok")
'part\\\\x1b[2J\\\\rok'
>>> shown("ring \\u202eplanet")
'ring \\\\u202eplanet'
>>> shown("µm, ², –: printable, kept")
'µm, ², –: printable, kept'
"""

from __future__ import annotations

__all__ = ["CONTROLS", "shown"]

_NAMED = {"\t": "\\t", "\n": "\\n", "\r": "\\r"}

#: the characters escaped: C0 (every one, newline and tab too: a message is one line), DEL, C1,
#: and the bidirectional controls (marks U+200E/200F/061C, embeddings and overrides U+202A–202E,
#: isolates U+2066–2069) that reorder the text shown after them
CONTROLS = frozenset(
    [chr(c) for c in range(0x20)]
    + [chr(0x7F)]
    + [chr(c) for c in range(0x80, 0xA0)]
    + ["\u061c", "\u200e", "\u200f"]
    + [chr(c) for c in range(0x202A, 0x202F)]
    + [chr(c) for c in range(0x2066, 0x206A)]
)

_TABLE = {ord(c): _NAMED.get(c) or (f"\\x{ord(c):02x}" if ord(c) < 0x100 else f"\\u{ord(c):04x}") for c in CONTROLS}


def shown(text: object) -> str:
    """``str(text)`` with every character of :data:`CONTROLS` written as its escape (``\\x1b``,
    ``\\r``, ``\\u202e``); everything else — letters of any script, µ, ², dashes — as it is.

    Idempotent (an escape is printable text), so a message escaped where it is made and again
    where it is printed reads the same.
    """
    return str(text).translate(_TABLE)
