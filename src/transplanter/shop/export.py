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
``.<name>.previous``, which :func:`recover` — run by the next build — puts back. The files a
build keeps *beside* the folder (its build record, ``transplanter pair``'s part script) are part
of the same transaction: staged in ``.<name>.beside`` before the swap and renamed into place
after it; if one cannot be, the folder is swapped back and those already replaced are restored,
so the old export and its files beside it stay together. Leftover staging folders and ``.tmp``
files are removed by :func:`recover` and reported by :func:`leftovers`. The lock is opened only
if it is a regular file (:func:`transplanter.core.files.open_regular`) and never waited for. Text and JSON are
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

from transplanter.core.errors import ExportError, SpecError
from transplanter.core.files import open_regular, read_regular

__all__ = [
    "MAX_BESIDE_BYTES",
    "atomic_write",
    "Transaction",
    "recover",
    "interrupted_swap",
    "leftovers",
    "json_bytes",
    "csv_bytes",
    "csv_array",
]


def _staged(folder: Path, name: str, data: bytes) -> str:
    """``data`` written and flushed to a new temporary file in ``folder`` for the file ``name``
    (mode 644); its path."""
    folder.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; exports are meant to be shared
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return tmp


def atomic_write(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temp file + rename); returns the path."""
    target = Path(path)
    try:
        tmp = _staged(target.parent, target.name, data)
    except OSError as exc:
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    try:
        os.replace(tmp, target)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from exc
    return target


#: the largest file a build replaces beside a family folder (its build record, ``pair``'s part
#: script), bytes: read first so that a failed swap can put it back (the seed-004 record is 0.2 MB)
MAX_BESIDE_BYTES = 50_000_000


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
    ``.previous``, ``.staging``, ``.beside`` and ``.lock``) is a symbolic link: an export is written, swapped,
    recovered and removed only where it is, never through a link into another folder."""
    target = Path(target)
    for path in (target, *(_beside(target, w) for w in ("previous", "staging", "beside", "lock"))):
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
    previous, staging, outbox = (_beside(target, w) for w in ("previous", "staging", "beside"))
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
        if outbox.exists():
            shutil.rmtree(outbox)
            done.append(f"removed the unfinished files beside it, {outbox.name}")
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
    out = [p.name for p in (_beside(target, w) for w in ("previous", "staging", "beside")) if p.exists()]
    if target.is_dir():
        out += [p.name for p in sorted(target.glob(".*.tmp"))]
    return out


class Transaction:
    """Write a family folder all at once (see the module docstring).

    Entered, it holds the family's lock (refused at once, never waited for, if another build
    holds it), has put back what an interrupted build left, and stages the new files;
    :meth:`commit` swaps them in with the files beside the folder, :meth:`cancel` drops them —
    either releases the lock (leaving the ``with`` block does whichever was not done: commit
    when the block ran through, cancel when it raised).

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
        self._lock: int | None = None
        #: files written beside the folder (``transplanter pair``'s part script, the build record)
        #: with the swap, under the same lock: never one without the other
        self.beside: dict[str, bytes] = {}
        #: what each of them held before (None: nothing), put back if the swap is undone
        self._before: dict[str, bytes | None] = {}
        self._pending = dict(beside or {})

    def __enter__(self) -> Transaction:
        refuse_links(self.target)
        lock = _beside(self.target, "lock")
        try:
            self.target.parent.mkdir(parents=True, exist_ok=True)
            self._lock = open_regular(lock, "the lock", os.O_RDWR | os.O_CREAT)
        except OSError as exc:
            raise ExportError(f"cannot write {self.target}: {exc.strerror or exc}") from exc
        except SpecError as exc:  # a FIFO, a device or a folder where the lock file goes
            raise ExportError(f"cannot lock {self.target}: {exc} - remove it") from exc
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(self._lock)
            self._lock = None
            raise ExportError(
                f"another build is writing {self.target} (lock {lock.name}); wait for it to finish"
            ) from exc
        try:
            recover(self.target)
            for name, data in sorted(self._pending.items()):
                self.put_beside(name, data)
            self.staging.mkdir()
        except ExportError:
            self._release()
            raise
        except OSError as exc:
            self._release()
            raise ExportError(f"cannot write {self.target}: {exc.strerror or exc}") from exc
        except BaseException:
            self._release()
            raise
        return self

    def put_beside(self, name: str, data: bytes) -> None:
        """Write ``name`` beside the folder with the swap (a plain name; replaced only if it is a
        regular file — a link, a FIFO or a folder there is refused now, before anything is built)."""
        if not name or "/" in name or name in (".", ".."):
            raise ExportError(f"{name!r} is not a file name beside {self.target}")
        path = self.target.parent / name
        if name not in self._before:
            try:
                self._before[name] = read_regular(path, "the file beside the export", MAX_BESIDE_BYTES, missing_ok=True)
            except SpecError as exc:
                raise ExportError(f"{exc} - transplanter replaces only its own regular files beside an export") from exc
        self.beside[name] = data

    def write(self, name: str, data: bytes) -> Path:
        """Write one file of the new export (into the staging folder)."""
        return atomic_write(self.staging / name, data)

    def _swap(self) -> None:
        """The new folder and the files beside it in place, or (on an error) neither: the files
        beside it are staged first, then the folder swapped, then they are renamed into place —
        a failure there renames the folder back and restores the ones already replaced."""
        parent, previous, outbox = self.target.parent, _beside(self.target, "previous"), _beside(self.target, "beside")
        _fsync_dir(self.staging)
        staged: dict[str, str] = {}
        try:
            for name, data in sorted(self.beside.items()):
                staged[name] = _staged(outbox, name, data)
            had = self.target.exists()
            if had:
                os.rename(self.target, previous)
            try:
                os.rename(self.staging, self.target)
            except OSError:
                if had:
                    os.rename(previous, self.target)
                raise
            replaced: list[str] = []
            try:
                for name, tmp in staged.items():
                    os.replace(tmp, parent / name)
                    replaced.append(name)
            except OSError:
                self._undo(replaced, had)
                raise
        finally:
            shutil.rmtree(outbox, ignore_errors=True)
        _fsync_dir(parent)
        if previous.exists():
            shutil.rmtree(previous)

    def _undo(self, replaced: list[str], had: bool) -> None:
        """Put back the folder and the files beside it that a failed swap had replaced."""
        os.rename(self.target, self.staging)
        if had:
            os.rename(_beside(self.target, "previous"), self.target)
        for name in replaced:
            before = self._before.get(name)
            if before is None:
                (self.target.parent / name).unlink(missing_ok=True)
            else:
                atomic_write(self.target.parent / name, before)

    def commit(self) -> None:
        """Swap the new folder (and the files beside it) in; ExportError, with the old export and
        the files beside it as they were, if that cannot be done. Releases the lock."""
        if self._lock is None:
            raise ExportError(f"the transaction on {self.target} is over")
        try:
            self._swap()
        except ExportError:
            shutil.rmtree(self.staging, ignore_errors=True)
            raise
        except OSError as err:
            shutil.rmtree(self.staging, ignore_errors=True)
            raise ExportError(f"cannot write {self.target}: {err.strerror or err}") from err
        finally:
            self._release()

    def cancel(self) -> None:
        """Drop what was staged; the export stays as it is. Releases the lock."""
        if self._lock is not None:
            shutil.rmtree(self.staging, ignore_errors=True)
            self._release()

    def _release(self) -> None:
        if self._lock is not None:
            fcntl.flock(self._lock, fcntl.LOCK_UN)
            os.close(self._lock)
            self._lock = None

    def __exit__(self, kind, exc, tb) -> None:
        if self._lock is None:  # committed or cancelled already
            return
        if kind is None:
            self.commit()
        else:
            self.cancel()


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
