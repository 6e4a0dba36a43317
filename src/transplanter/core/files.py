"""One reader for every file the tool opens from a folder it does not own outright: an export's
manifest and files, the build record and the lock beside it, the part scripts a check hashes.

A file is opened only if it is a **regular file**: a FIFO (which would block the open, or the
read, forever), a device (which may never end), a socket, a folder or — unless the caller asks
for links to be followed — a symbolic link is refused *before it is opened*, from ``lstat``; the
open itself does not follow a link and does not block (``O_NOFOLLOW | O_NONBLOCK``), and what was
opened is checked again (``fstat``: still a regular file, the same one ``lstat`` saw). Every kind
of file is read only up to a stated limit (the callers' constants: a manifest's is
:data:`transplanter.families.builder.manifest.MAX_MANIFEST_BYTES`).

Every refusal is a :class:`FileRefused` (a :class:`~transplanter.core.errors.SpecError`) of one
line saying what the file is for, its path and what is wrong (``reason``: that last part alone).

Examples
--------
>>> import os, tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> _ = (d / "a.txt").write_bytes(b"abc")
>>> read_regular(d / "a.txt", "the data file", 10)
b'abc'
>>> os.mkfifo(d / "pipe")
>>> read_regular(d / "pipe", "the data file", 10)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
transplanter.core.files.FileRefused: the data file .../pipe: a FIFO (a named pipe), not a regular file: not opened
"""

from __future__ import annotations

import errno
import os
import stat

from transplanter.core.errors import SpecError

__all__ = ["FileRefused", "kind_of", "open_regular", "read_regular"]

#: what a file that is not a regular one is, by its ``stat`` type
_KINDS = (
    (stat.S_ISFIFO, "a FIFO (a named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISLNK, "a symbolic link"),
    (stat.S_ISDIR, "a folder"),
)
_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_NONBLOCK = getattr(os, "O_NONBLOCK", 0)
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


def kind_of(mode: int) -> str:
    """What a file of ``st_mode`` ``mode`` is, in words ("a regular file", "a FIFO (a named pipe)", ...)."""
    if stat.S_ISREG(mode):
        return "a regular file"
    return next((said for test, said in _KINDS if test(mode)), "not a regular file")


class FileRefused(SpecError):
    """A file that is not read: ``"<what> <path>: <reason>"``; ``reason`` alone says what is wrong
    ("a symbolic link: not followed", "a FIFO (a named pipe), not a regular file: not opened",
    "larger than 10 bytes (12): not read", "cannot be read: Permission denied")."""

    def __init__(self, what: str, path, reason: str):
        super().__init__(f"{what} {os.fspath(path)}: {reason}")
        self.reason = reason


def _refused(what: str, path, kind: str) -> FileRefused:
    if kind == "a symbolic link":
        return FileRefused(what, path, "a symbolic link: not followed")
    return FileRefused(what, path, f"{kind}, not a regular file: not opened")


def _unreadable(what: str, path, exc: OSError) -> FileRefused:
    return FileRefused(what, path, f"cannot be read: {exc.strerror or exc}")


def _too_large(what: str, path, size: int, limit: int) -> FileRefused:
    return FileRefused(what, path, f"larger than {limit} bytes ({size}): not read")


def _regular_info(path, what: str, follow_links: bool, missing_ok: bool) -> os.stat_result | None:
    """``lstat`` (``stat`` when following links) of ``path`` if it is a regular file; None when
    it is missing and ``missing_ok``; SpecError otherwise — before anything opens it."""
    try:
        info = os.stat(path) if follow_links else os.lstat(path)
    except FileNotFoundError as exc:
        if missing_ok:
            return None
        raise _unreadable(what, path, exc) from exc
    except OSError as exc:  # a name too long, a folder on the way that is a file, no permission
        raise _unreadable(what, path, exc) from exc
    if not stat.S_ISREG(info.st_mode):
        raise _refused(what, path, kind_of(info.st_mode))
    return info


def _same_regular(fd: int, seen: os.stat_result, path, what: str) -> os.stat_result:
    """``fstat`` of the opened ``fd``: the regular file ``lstat`` saw, or SpecError (it was swapped)."""
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode):
        raise _refused(what, path, kind_of(info.st_mode))
    if (info.st_dev, info.st_ino) != (seen.st_dev, seen.st_ino):
        raise FileRefused(what, path, "replaced while it was opened: not read")
    return info


def read_regular(path, what: str, limit: int, *, follow_links: bool = False, missing_ok: bool = False) -> bytes | None:
    """The bytes of the regular file ``path``, at most ``limit`` of them.

    ``what`` names the file in the messages ("the manifest", "the build record"). A file that is
    not a regular file (a FIFO, a device, a socket, a folder; a symbolic link unless
    ``follow_links``) is refused before it is opened, one larger than ``limit`` before it is read
    (and if it grows while read); the open neither follows a link nor blocks. Returns None for a
    missing file when ``missing_ok``.

    Raises
    ------
    FileRefused
        Saying what the file is for, its path and what is wrong with it.
    """
    seen = _regular_info(path, what, follow_links, missing_ok)
    if seen is None:
        return None
    if seen.st_size > limit:
        raise _too_large(what, path, seen.st_size, limit)
    flags = os.O_RDONLY | _NONBLOCK | _CLOEXEC | (0 if follow_links else _NOFOLLOW)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        if exc.errno == errno.ELOOP:  # made a link between lstat and open
            raise _refused(what, path, "a symbolic link") from exc
        raise _unreadable(what, path, exc) from exc
    try:
        _same_regular(fd, seen, path, what)
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise _unreadable(what, path, exc) from exc
    finally:
        os.close(fd)
    if size > limit:  # it grew while it was read
        raise _too_large(what, path, size, limit)
    return b"".join(chunks)


def open_regular(path, what: str, flags: int, mode: int = 0o644) -> int:
    """A file descriptor of the regular file ``path`` opened with ``flags`` (``os.O_*``; created
    when ``flags`` has ``O_CREAT`` and it is missing), never through a link and never blocking —
    for a file that is held rather than read (a lock). FileRefused if ``path`` is anything but a
    regular file (refused before it is opened) or cannot be opened."""
    seen = _regular_info(path, what, False, bool(flags & os.O_CREAT))
    try:
        fd = os.open(path, flags | _NONBLOCK | _CLOEXEC | _NOFOLLOW, mode)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise _refused(what, path, "a symbolic link") from exc
        raise FileRefused(what, path, f"cannot be opened: {exc.strerror or exc}") from exc
    try:
        if seen is None:  # created here (or by someone else meanwhile): a regular file all the same
            seen = os.fstat(fd)
        _same_regular(fd, seen, path, what)
    except BaseException:
        os.close(fd)
        raise
    return fd
