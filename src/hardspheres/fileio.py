"""Writing files safely: the one home of atomic outputs and write locks.

Every file hardspheres writes (checkpoints, viewer pages, CSV tables,
pictures, movies) is written through :func:`atomic_write` (or
:func:`atomic_path` for writers that want a file name): to a temporary
file with a unique name in the target's folder, flushed and ``fsync``-ed,
then renamed over the target.  On any failure the temporary is removed and
the target keeps its old contents, so a reader sees the old file or the new
one, never a part.  Trajectories, which grow as a run goes, are written in
place but under the same lock (:class:`PathLock`).

Two writers of one file: each takes an advisory lock (``fcntl.flock``) on a
lock file beside the target (``.NAME.lock``, removed when released); the
second gets :class:`FileInUseError` at once, naming the file and the
process holding it.  The lock is advisory: programs other than hardspheres
do not see it.  Where ``fcntl`` does not exist (Windows) the library still
imports and writes atomically, but takes no lock: a second writer of one
file is not refused there.

Errors: an :class:`OSError` raised while writing carries the target's name
(``err.filename``), so :func:`hardspheres.messages.oserror_line` prints one
line naming the file.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterator
from typing import IO, Any, Literal

try:  # POSIX; Windows has no flock: writes stay atomic, but unlocked
    import fcntl
except ImportError:  # pragma: no cover - exercised by tests/test_packaging.py
    fcntl = None  # type: ignore[assignment]

from .errors import FileInUseError  # noqa: F401 (re-exported)
from .messages import oserror_line


def _special(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` exists and is not a regular file or folder (``/dev/null``, a FIFO)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def _lock_name(path: str | os.PathLike[str]) -> str:
    head, tail = os.path.split(os.path.abspath(path))
    return os.path.join(head, f".{tail}.lock")


class PathLock:
    """An exclusive advisory lock on writing ``path``, held until :meth:`release`.

    Taking it also proves that the target's folder exists and is writable,
    and that ``path`` is not a folder, so a run can check its outputs
    before it starts.

    Args:
        path: the file to be written.

    Raises:
        FileInUseError: another writer holds the lock.
        OSError: the folder is missing or not writable, or ``path`` is a
            folder (``filename`` is ``path``).
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = os.fspath(path)
        self.lock_path = _lock_name(self.path)
        self._fd = None
        if os.path.isdir(self.path):
            raise IsADirectoryError(errno.EISDIR, "is a folder, not a file", self.path)
        if _special(self.path):
            return  # /dev/null, a FIFO: nothing to lock, and no lock file in /dev
        if fcntl is None:
            return  # no advisory locks on this platform (module docstring)
        while True:
            try:
                fd = os.open(self.lock_path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as e:
                raise type(e)(e.errno, f"cannot write here ({e.strerror})", self.path) from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as e:
                holder = _read_pid(fd)
                os.close(fd)
                if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                    who = f" (process {holder})" if holder else ""
                    raise FileInUseError(
                        f"{self.path} is being written by another writer{who}; "
                        "wait for it to finish or choose another file"
                    ) from None
                raise type(e)(e.errno, e.strerror, self.path) from None
            # the holder before us may have removed the lock file as we opened
            # it: then we hold a lock on a file nobody else will open; retry
            try:
                same = os.stat(self.lock_path).st_ino == os.fstat(fd).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
        self._fd = fd
        with contextlib.suppress(OSError):
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()}\n".encode())

    @property
    def held(self) -> bool:
        """Whether the lock is still held."""
        return self._fd is not None

    def release(self) -> None:
        """Release the lock and remove the lock file (idempotent)."""
        if self._fd is not None:
            with contextlib.suppress(OSError):
                os.unlink(self.lock_path)
            os.close(self._fd)
            self._fd = None

    def __enter__(self) -> PathLock:
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        self.release()
        return False

    def __del__(self) -> None:
        self.release()


def _read_pid(fd: int) -> str:
    try:
        data = os.pread(fd, 32, 0).decode("ascii", "replace").strip()
    except OSError:
        return ""
    return data if data.isdigit() else ""


def _mode_for(path: str | os.PathLike[str]) -> int:
    """Permissions the new file gets: the old file's, else 0666 less the umask."""
    try:
        return os.stat(path).st_mode & 0o7777
    except OSError:
        mask = os.umask(0)
        os.umask(mask)
        return 0o666 & ~mask


def _named(err: BaseException, path: str | os.PathLike[str]) -> OSError:
    """``err`` as the same kind of OSError, naming ``path``."""
    if isinstance(err, OSError) and err.errno is not None:
        return type(err)(err.errno, err.strerror, path)
    return OSError(errno.EIO, str(err), path)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], lock: bool = True) -> Iterator[str]:
    """A temporary file name to write ``path`` through; renamed on success.

    The temporary is in the target's folder (so the rename is atomic), has
    a unique name ending like the target (``.NAME.XXXX.tmp.png``: tools that
    choose a format by extension still work), and is removed if the block
    raises.  On success its contents are ``fsync``-ed and it replaces
    ``path``.

    Args:
        path: the target file.
        lock: take a :class:`PathLock` on ``path`` while writing (``True``),
            or not (``False``: the caller holds one).

    Yields:
        The temporary's path (the file exists, empty); or ``path`` itself
        if it is a device or FIFO (``/dev/null``), which is written as is.

    Raises:
        FileInUseError: another writer holds ``path``.
        OSError: naming ``path`` (``filename``).
    """
    path = os.fspath(path)
    if _special(path):
        try:
            yield path
        except OSError as e:
            raise _named(e, path) from None
        return
    held = PathLock(path) if lock else None
    try:
        head, tail = os.path.split(path)
        ext = os.path.splitext(tail)[1]
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{tail}.", suffix=f".tmp{ext}", dir=head or ".")
            os.close(fd)
            os.chmod(tmp, _mode_for(path))
        except OSError as e:
            raise _named(e, path) from None
        try:
            yield tmp
            _fsync(tmp)
            os.replace(tmp, path)
        except BaseException as e:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            if isinstance(e, OSError):
                raise _named(e, path) from None
            raise
        _sync_folder(head or ".")
    finally:
        if held is not None:
            held.release()


@contextlib.contextmanager
def atomic_write(
    path: str | os.PathLike[str], mode: str = "wb", lock: bool = True, **open_args: Any
) -> Iterator[IO[Any]]:
    """Open a temporary for writing ``path``; it replaces ``path`` on success.

    As :func:`atomic_path`, with the file opened (``mode`` ``"wb"`` or
    ``"w"``, ``open_args`` as for :func:`open`) and flushed before the
    rename.

    Example:
        >>> import os, tempfile
        >>> target = os.path.join(tempfile.mkdtemp(), "out.txt")
        >>> with atomic_write(target, "w") as fh:
        ...     _ = fh.write("all or nothing\\n")
        >>> open(target).read(), sorted(os.listdir(os.path.dirname(target)))
        ('all or nothing\\n', ['out.txt'])
    """
    with atomic_path(path, lock=lock) as tmp:
        with open(tmp, mode, **open_args) as fh:
            yield fh
            fh.flush()


def _fsync(path: str | os.PathLike[str]) -> None:
    """Flush ``path`` (a file or a folder) to the disk; raises :class:`OSError`."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _sync_folder(folder: str | os.PathLike[str]) -> None:
    """Make a rename in ``folder`` durable (best effort)."""
    with contextlib.suppress(OSError):
        _fsync(folder)


__all__ = ["FileInUseError", "PathLock", "atomic_path", "atomic_write", "oserror_line"]
