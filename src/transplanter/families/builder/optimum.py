"""``transplanter optimise --write``: the optimum recorded in the design module's own tuple, and
nothing else in the file touched.

The module is read, never run: its encoding from its PEP 263 cookie or BOM
(``tokenize.detect_encoding``), the tuple ``NAME = (numbers, ...)`` found in its syntax tree
(``ast.parse``), and only the numbers that changed replaced, each in its own source span — the
statements on the tuple's lines, its comments and layout, the BOM, the cookie's encoding and the
file's mode kept. A number is written as the shortest text that reads back as the same float
(``repr``); one that did not change keeps its text (``339.996376`` stays, never
``339.99637599999994``); an int literal stays an int where the value is whole or a choice. A
module reached through a symbolic link is written at the link's target (the link kept); the
write is atomic (a temporary file in the target's folder, then ``os.replace``).

Everything that could refuse the write is checked by :func:`module_file` and :func:`find_optimum`
before the search starts: the file is a regular file, writable (its mode and its folder), decodes
and parses, and holds one module-level assignment of ``NAME`` to a tuple of as many numbers as the
problem has variables. :func:`record_optimum` checks again as it writes (the tuple still holds what
it held when the search started).

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> from transplanter.families.builder.optimum import find_optimum, module_file, record_optimum
>>> with tempfile.TemporaryDirectory() as folder:
...     p = Path(folder) / "design.py"
...     _ = p.write_text("OPTIMUM = (339.996376, 2)  # mm, lobes\\nKEEP = 42\\n")
...     place = find_optimum(module_file(p), "OPTIMUM", 2)
...     written = record_optimum(place, (339.99637599999994, 3.0))  # the first as it was, give or take
...     place.values, written == p, p.read_text()
((339.996376, 2), True, 'OPTIMUM = (339.996376, 3)  # mm, lobes\\nKEEP = 42\\n')
"""

from __future__ import annotations

import ast
import io
import math
import os
import re
import stat
import tempfile
import tokenize
from dataclasses import dataclass
from pathlib import Path

from transplanter.core.errors import ExportError, PartScriptError

__all__ = ["ModuleFile", "OptimumPlace", "find_optimum", "module_file", "number_text", "record_optimum", "rewritten"]

#: a design module larger than this is not one (seed 004's is 30 kB), bytes
MAX_MODULE_BYTES = 4_000_000

_NEWLINE = re.compile(r"\r\n|\r|\n")  # what Python's tokenizer takes for the end of a line


@dataclass(frozen=True)
class ModuleFile:
    """A design module as read for ``--write``: the path given, the file written (``target``: a
    link's target, resolved), its bytes, encoding, text and mode."""

    path: Path
    target: Path
    data: bytes
    encoding: str
    text: str
    mode: int


@dataclass(frozen=True)
class OptimumPlace:
    """The tuple ``name`` in ``module``: its values as the file holds them (ints and floats) and each
    number's source span ``(start, end)`` in ``module.text`` (characters)."""

    module: ModuleFile
    name: str
    values: tuple[int | float, ...]
    spans: tuple[tuple[int, int], ...]


def module_file(path: str | os.PathLike[str]) -> ModuleFile:
    """The design module at ``path`` read for ``--write``, or PartScriptError saying why it cannot be
    written: not a regular file, a dangling link, read-only (its mode has no write bit for its
    owner, or this user may not write it), its folder not writable (the file is replaced
    atomically), it has other hard links (which a replace would part from it), larger than
    :data:`MAX_MODULE_BYTES`, or its bytes do not decode in its encoding. Nothing in it is run."""
    p = Path(path)
    target = Path(os.path.realpath(p))
    link = f" (a link to {target})" if target != Path(os.path.abspath(p)) else ""
    try:
        st = os.stat(target)
    except OSError as exc:
        raise PartScriptError(f"{p}{link}: --write cannot read it: {exc.strerror or exc}") from exc
    if not stat.S_ISREG(st.st_mode):
        raise PartScriptError(f"{p}{link}: --write records the optimum in a regular file; this is not one")
    if not st.st_mode & stat.S_IWUSR or not os.access(target, os.W_OK):
        raise PartScriptError(
            f"{p}{link}: the design module is read-only (mode {stat.S_IMODE(st.st_mode):04o}): --write will not "
            "replace it; make it writable, or run without --write and copy the printed optimum"
        )
    if st.st_nlink > 1:
        raise PartScriptError(
            f"{p}{link}: the design module has {st.st_nlink} hard links: --write replaces the file atomically, "
            "which would part it from its other names; run without --write and copy the printed optimum"
        )
    if not os.access(target.parent, os.W_OK | os.X_OK):
        raise PartScriptError(
            f"{p}{link}: its folder {target.parent} is not writable: --write replaces the file atomically "
            "(a temporary file beside it)"
        )
    if st.st_size > MAX_MODULE_BYTES:
        raise PartScriptError(f"{p}{link}: {st.st_size} bytes is too large for a design module (<= {MAX_MODULE_BYTES})")
    try:
        fd = os.open(target, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as exc:
        raise PartScriptError(f"{p}{link}: --write cannot read it: {exc.strerror or exc}") from exc
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):  # swapped since the stat
            raise PartScriptError(f"{p}{link}: --write records the optimum in a regular file; this is not one")
        with os.fdopen(fd, "rb", closefd=False) as fh:
            data = fh.read(MAX_MODULE_BYTES + 1)
    finally:
        os.close(fd)
    if len(data) > MAX_MODULE_BYTES:
        raise PartScriptError(f"{p}{link}: larger than a design module can be (<= {MAX_MODULE_BYTES} bytes)")
    try:
        encoding, _ = tokenize.detect_encoding(io.BytesIO(data).readline)
        text = data.decode(encoding)
    except (SyntaxError, LookupError, UnicodeDecodeError) as exc:
        raise PartScriptError(f"{p}{link}: --write cannot read it as Python source: {exc}") from exc
    if text.encode(encoding) != data:  # a text it cannot write back byte for byte is not rewritten
        raise PartScriptError(f"{p}{link}: its bytes do not round-trip through its encoding {encoding}")
    return ModuleFile(p, target, data, encoding, text, stat.S_IMODE(st.st_mode))


def _number(node: ast.expr) -> int | float | None:
    """The value of a number literal (``3``, ``-0.5``, ``+1e-3``), else None (bools are not numbers)."""
    sign = 1
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        sign = -1 if isinstance(node.op, ast.USub) else 1
        node = node.operand
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        return sign * node.value
    return None


def find_optimum(module: ModuleFile, name: str, size: int) -> OptimumPlace:
    """The one module-level assignment ``name = (n1, n2, ...)`` of ``size`` number literals in
    ``module``, or PartScriptError naming what the file holds instead."""
    p = module.path
    try:
        tree = ast.parse(module.text, filename=str(p))
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        raise PartScriptError(f"{p}:{getattr(exc, 'lineno', '?')}: syntax error: {getattr(exc, 'msg', exc)}") from exc

    def targets(node: ast.stmt) -> list[ast.expr]:
        if isinstance(node, ast.Assign):
            return node.targets
        return [node.target] if isinstance(node, ast.AnnAssign | ast.AugAssign) else []

    found = [n for n in tree.body if any(isinstance(t, ast.Name) and t.id == name for t in targets(n))]
    rule = f"the optimum is recorded in one module-level assignment '{name} = (numbers, ...)'"
    if len(found) != 1 or isinstance(found[0], ast.AugAssign) or found[0].value is None:
        raise PartScriptError(f"{p}: {rule}; found {len(found)} assignment{'s' if len(found) != 1 else ''} of {name}")
    node = found[0]
    if isinstance(node, ast.Assign) and len(node.targets) != 1:
        raise PartScriptError(f"{p}:{node.lineno}: {rule}; {name} is assigned with other names at once")
    elts = node.value.elts if isinstance(node.value, ast.Tuple) else None
    values = [_number(e) for e in elts] if elts is not None else [None]
    if elts is None or any(v is None for v in values):
        raise PartScriptError(f"{p}:{node.lineno}: {rule}; {name} is not a tuple of number literals")
    if len(values) != size:
        raise PartScriptError(f"{p}:{node.lineno}: {name} holds {len(values)} values, the problem has {size} variables")
    starts = [0] + [m.end() for m in _NEWLINE.finditer(module.text)]

    def offset(line: int, col: int) -> int:  # ast's columns are UTF-8 bytes into the line
        start = starts[line - 1]
        stop = starts[line] if line < len(starts) else len(module.text)
        return start + len(module.text[start:stop].encode("utf-8")[:col].decode("utf-8"))

    spans = tuple((offset(e.lineno, e.col_offset), offset(e.end_lineno, e.end_col_offset)) for e in elts)
    return OptimumPlace(module, name, tuple(values), spans)


def number_text(value: float, held: int | float, choice: bool = False) -> str:
    """``value`` as the file should hold it: an int where the file held an int and the value is whole
    (or a choice: its integer part is what the model uses), else the shortest text that reads back
    as the same float."""
    v = float(value)
    if not math.isfinite(v):
        raise PartScriptError(f"the optimum holds {v!r}: not a number a design module can record")
    if isinstance(held, int) and (choice or v == int(v)):
        return str(int(v))
    return repr(v)


def _same(new: float, held: int | float) -> bool:
    """The value the file holds, give or take the rounding of the search's scaling (a few ulps)."""
    return float(new) == float(held) or math.isclose(float(new), float(held), rel_tol=1e-12, abs_tol=0.0)


def record_optimum(place: OptimumPlace, values, choices: tuple[bool, ...] = ()) -> Path | None:
    """Write ``values`` into ``place``'s tuple (only the numbers that changed); the file written
    (a link's target), or None when every number is the one the file holds (nothing is written).

    The file is read again first: if its tuple no longer holds what it held when ``place`` was
    found (edited during the search), nothing is written (PartScriptError). ExportError if the file
    cannot be replaced."""
    new = rewritten(place, values, choices)
    if new is None:
        return None
    module, new_text = new
    _replace(module, new_text.encode(module.encoding))
    return module.target


def rewritten(place: OptimumPlace, values, choices: tuple[bool, ...] = ()) -> tuple[ModuleFile, str] | None:
    """(the file as read now, its text with ``values`` in ``place``'s tuple), checked by reading it
    back, nothing written (what :func:`record_optimum` writes; a diff shows it first); None when
    every number is the one the file holds. PartScriptError as :func:`record_optimum`."""
    module = module_file(place.module.path)
    now = find_optimum(module, place.name, len(place.values))
    if now.module.target != place.module.target or now.values != place.values:
        raise PartScriptError(
            f"{module.path}: {place.name} changed during the search (it held {list(place.values)}, now "
            f"{list(now.values)}): nothing written; the optimum is printed"
        )
    values = [float(v) for v in values]
    if len(values) != len(now.values):
        raise PartScriptError(f"{module.path}: {place.name} holds {len(now.values)} values, the optimum {len(values)}")
    flags = tuple(choices) + (False,) * (len(values) - len(choices))
    text, end, changed = [], 0, False
    for (start, stop), new, held, choice in zip(now.spans, values, now.values, flags, strict=True):
        if _same(new, held) or (choice and isinstance(held, int) and int(new) == held):
            continue
        text += [module.text[end:start], number_text(new, held, choice)]
        end, changed = stop, True
    if not changed:
        return None
    new_text = "".join([*text, module.text[end:]])
    check = find_optimum(
        ModuleFile(module.path, module.target, b"", module.encoding, new_text, module.mode), place.name, len(values)
    )
    for got, new, held, choice in zip(check.values, values, now.values, flags, strict=True):
        want = float(number_text(new, held, choice)) if not _same(new, held) else float(held)
        if float(got) != want:  # the splice is checked by reading it back
            raise PartScriptError(f"{module.path}: the rewritten {place.name} reads back as {list(check.values)}")
    return module, new_text


def _replace(module: ModuleFile, data: bytes) -> None:
    """``data`` in place of ``module.target``, atomically, with its mode (and owner, where this user may)."""
    target = module.target
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except OSError as exc:
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, module.mode)
        st = os.stat(target)
        if (st.st_uid, st.st_gid) != (os.getuid(), os.getgid()):
            try:
                os.chown(tmp, st.st_uid, st.st_gid)
            except OSError:  # not ours to give away: the file is this user's from now on
                pass
        os.replace(tmp, target)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
