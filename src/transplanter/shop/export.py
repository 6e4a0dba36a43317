"""Writing files atomically and reproducibly; a family's export as one transaction.

Every export goes through :func:`atomic_write`: the bytes are written to a temporary file
in the target folder, flushed, then renamed over the target, so a reader never sees a
half-written file and a failed build leaves the previous file intact.

A whole family folder is written as a **transaction** (:class:`Transaction`): under an
exclusive lock (``.<name>.lock`` beside it, so two builds cannot write one folder), the new
files go into a staging folder ``.<name>.staging`` beside the target; when it is complete the
target is renamed to ``.<name>.previous``, the staging folder to the target, and the
previous folder is removed. A build killed at any moment leaves either the old folder whole,
or the new one whole, or (between the two renames) the old one whole under
``.<name>.previous``, which :func:`recover` — run by the next build and by ``check`` — puts
back. Leftover staging folders and ``.tmp`` files are removed by :func:`recover` and
reported by :func:`leftovers`. Text and JSON are
serialised deterministically (sorted keys, fixed float formatting, ``\\n`` line ends), so
a rebuild from the same input is byte-identical.

Examples
--------
>>> import tempfile, pathlib
>>> from transplanter.shop.export import atomic_write, json_bytes
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> p = atomic_write(d / "a.json", json_bytes({"b": 1.0, "a": [1, 2]}))
>>> p.read_text()
'{\\n  "a": [\\n    1,\\n    2\\n  ],\\n  "b": 1.0\\n}\\n'
"""

from __future__ import annotations

import csv
import fcntl
import io
import json
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from transplanter.core.errors import ExportError

__all__ = [
    "atomic_write",
    "Transaction",
    "recover",
    "interrupted_swap",
    "leftovers",
    "json_bytes",
    "csv_bytes",
    "csv_array",
]


def atomic_write(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temp file + rename); returns the path."""
    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except OSError as exc:
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; exports are meant to be shared
        os.replace(tmp, target)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


def _beside(target: Path, what: str) -> Path:
    return target.parent / f".{target.name}.{what}"


def _fsync_dir(folder: Path) -> None:
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def refuse_links(target: str | os.PathLike[str]) -> None:
    """ExportError if the family folder ``target`` or anything the build keeps beside it (its
    ``.previous``, ``.staging`` and ``.lock``) is a symbolic link: an export is written, swapped,
    recovered and removed only where it is, never through a link into another folder."""
    target = Path(target)
    for path in (target, _beside(target, "previous"), _beside(target, "staging"), _beside(target, "lock")):
        if path.is_symlink():
            raise ExportError(
                f"{path} is a symbolic link (to {os.readlink(path)}): transplanter never writes, recovers or "
                "removes through a link — remove the link or choose another output folder"
            )


def interrupted_swap(target: str | os.PathLike[str]) -> Path | None:
    """The whole previous export when a build stopped between its two renames (the target is
    gone, ``.<name>.previous`` is there), else None; :func:`recover` puts it back."""
    target = Path(target)
    previous = _beside(target, "previous")
    return previous if previous.is_dir() and not target.exists() else None


def recover(target: str | os.PathLike[str]) -> list[str]:
    """Put a family folder back in a whole state after an interrupted build; returns what it did.

    The previous folder comes back if the build stopped between its two renames; a leftover
    staging folder, a leftover previous folder (when the target is whole) and ``.tmp`` files
    in the target are removed.
    """
    target = Path(target)
    refuse_links(target)
    done = []
    previous, staging = _beside(target, "previous"), _beside(target, "staging")
    try:
        if interrupted_swap(target) is not None:
            os.rename(previous, target)
            done.append(f"restored the previous export of {target.name} (a build stopped while swapping it)")
        if previous.is_dir():
            shutil.rmtree(previous)
            done.append(f"removed {previous.name}")
        if staging.exists():
            shutil.rmtree(staging)
            done.append(f"removed the unfinished build {staging.name}")
        if target.is_dir():
            for tmp in sorted(target.glob(".*.tmp")):
                if tmp.is_symlink() or not tmp.is_file():
                    continue  # not a file a build half-wrote: left alone
                tmp.unlink()
                done.append(f"removed the half-written {tmp.name}")
    except OSError as exc:
        raise ExportError(f"cannot recover {target}: {exc.strerror or exc}") from exc
    return done


def leftovers(target: str | os.PathLike[str]) -> list[str]:
    """What an interrupted build left beside or in ``target`` (nothing is changed)."""
    target = Path(target)
    out = [p.name for p in (_beside(target, "previous"), _beside(target, "staging")) if p.exists()]
    if target.is_dir():
        out += [p.name for p in sorted(target.glob(".*.tmp"))]
    return out


class Transaction:
    """Write a family folder all at once (see the module docstring).

    >>> import tempfile, pathlib
    >>> root = pathlib.Path(tempfile.mkdtemp()) / "fam"
    >>> with Transaction(root) as t:
    ...     _ = t.write("a.txt", b"new")
    >>> (root / "a.txt").read_bytes(), sorted(p.name for p in root.parent.iterdir())
    (b'new', ['.fam.lock', 'fam'])
    """

    def __init__(self, target: str | os.PathLike[str], beside: dict[str, bytes] | None = None):
        self.target = Path(target)
        self.staging = _beside(self.target, "staging")
        self._lock = None
        #: files written beside the folder (``transplanter pair``'s part script) with the swap, under
        #: the same lock: never one without the other
        self.beside = dict(beside or {})

    def __enter__(self) -> Transaction:
        refuse_links(self.target)
        for name in self.beside:
            if (self.target.parent / name).is_symlink():
                raise ExportError(f"{self.target.parent / name} is a symbolic link: never written through")
        try:
            self.target.parent.mkdir(parents=True, exist_ok=True)
            self._lock = open(_beside(self.target, "lock"), "a+b")  # noqa: SIM115 - held until __exit__
        except OSError as exc:
            raise ExportError(f"cannot write {self.target}: {exc.strerror or exc}") from exc
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            self._lock.close()
            raise ExportError(
                f"another build is writing {self.target} (lock {_beside(self.target, 'lock').name}); "
                "wait for it to finish"
            ) from exc
        recover(self.target)
        try:
            self.staging.mkdir()
        except OSError as exc:
            self._release()
            raise ExportError(f"cannot write {self.target}: {exc.strerror or exc}") from exc
        return self

    def write(self, name: str, data: bytes) -> Path:
        """Write one file of the new export (into the staging folder)."""
        return atomic_write(self.staging / name, data)

    def keep(self, name: str) -> bool:
        """Carry ``name`` over from the current export unchanged (a hard link, or a copy)."""
        src = self.target / name
        if src.is_symlink() or not src.is_file():  # a link is never carried over (nor followed)
            return False
        try:
            os.link(src, self.staging / name, follow_symlinks=False)
        except OSError:
            shutil.copy2(src, self.staging / name)
        return True

    def _swap(self) -> None:
        previous = _beside(self.target, "previous")
        _fsync_dir(self.staging)
        if self.target.exists():
            os.rename(self.target, previous)
        os.rename(self.staging, self.target)
        for name, data in sorted(self.beside.items()):
            atomic_write(self.target.parent / name, data)
        _fsync_dir(self.target.parent)
        if previous.exists():
            shutil.rmtree(previous)

    def _release(self) -> None:
        if self._lock is not None:
            fcntl.flock(self._lock, fcntl.LOCK_UN)
            self._lock.close()
            self._lock = None

    def __exit__(self, kind, exc, tb) -> None:
        try:
            if kind is None:
                try:
                    self._swap()
                except OSError as err:
                    raise ExportError(f"cannot write {self.target}: {err.strerror or err}") from err
            else:
                shutil.rmtree(self.staging, ignore_errors=True)
        finally:
            self._release()


def json_bytes(obj: object) -> bytes:
    """Deterministic JSON (sorted keys, 2-space indent, trailing newline), UTF-8."""
    return (json.dumps(obj, indent=2, sort_keys=True, allow_nan=False) + "\n").encode()


def csv_bytes(header: list[str], rows: list[list[object]]) -> bytes:
    """CSV with ``\\n`` line ends; floats written with ``repr`` (round-trip exact)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for row in rows:
        w.writerow([repr(x) if isinstance(x, float) else x for x in row])
    return buf.getvalue().encode()


def csv_array(data: bytes) -> np.ndarray:
    """The numbers of a CSV written by :func:`csv_bytes` (header skipped), as an (n, k) array."""
    return np.loadtxt(io.BytesIO(data), delimiter=",", skiprows=1, ndmin=2)
