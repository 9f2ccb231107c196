"""One writer at a time for each output: an advisory lock file beside it
(:func:`output_lock`), and which outputs are streams written into rather than replaced
(:func:`is_stream`). :mod:`cadcog.core.fileio` stages every output under these."""

from __future__ import annotations

import errno
import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

from cadcog.core.errors import CadcogError

#: Lock files this process holds (path → open descriptor): a lock is taken once per output.
_HELD: dict[str, int] = {}


def _new_file_mode() -> int:
    """The mode a new file gets under the current umask (0666 & ~umask)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def _stream_kind(path: Path) -> str | None:
    """``'stdout'`` for ``-``, ``'device'`` for an existing node that is not a regular file or a
    folder (a FIFO, a terminal, /dev/null) or a path through /dev or /proc (``/dev/stdout``, a
    link to ``/proc/self/fd/1``); None for an ordinary file name."""
    if str(path) == "-":
        return "stdout"
    try:
        st = os.stat(path)
    except OSError:
        return None
    if stat.S_ISDIR(st.st_mode):
        return None
    if not stat.S_ISREG(st.st_mode):
        return "device"
    p = Path(os.path.abspath(path))
    for _ in range(40):  # every link of the chain, in case one goes through /dev or /proc
        if p.parts[1:2] in (("dev",), ("proc",)):
            return "device"
        if not p.is_symlink():
            break
        p = Path(os.path.abspath(p.parent / os.readlink(p)))
    return None


def is_stream(path: str | Path) -> bool:
    """Whether an output ``path`` is streamed into rather than replaced (``-``, a device, a
    FIFO, a link into /proc): a command then says what it wrote on stderr, not beside it."""
    return str(path) == "-" or _stream_kind(Path(path)) is not None


def _lock_file(target: Path) -> Path:
    real = target.resolve()
    return real.parent / f".{real.name}.cadcog-lock"


def _holder(fd: int) -> str:
    with suppress(OSError):
        os.lseek(fd, 0, os.SEEK_SET)
        pid = os.read(fd, 32).decode("ascii", "replace").strip()
        if pid.isdigit():
            return f"PID {pid}"
    return "PID unknown"


def _acquire(lock: Path, target: Path) -> int | None:
    """Lock ``lock`` (created as needed) for this process; None where no lock can be made (the
    folder is missing or read-only: the write itself will say so). Anything else at the lock's
    path (a link, a hard link to another file, a folder, a FIFO) is refused: a lock never
    writes through it, and a run never goes on unlocked because of it."""
    import fcntl

    flags = os.O_RDWR | os.O_CREAT | os.O_CLOEXEC | os.O_NOFOLLOW | os.O_NONBLOCK
    for _ in range(20):
        try:
            fd = os.open(lock, flags, _new_file_mode())
        except OSError as exc:
            if exc.errno == errno.ELOOP:  # never write through a link planted as the lock
                raise CadcogError(
                    f"{target}: its lock file {lock} is a link; remove it (cadcog only ever "
                    "makes a plain file there)"
                ) from None
            if exc.errno in (errno.ENOENT, errno.ENOTDIR, errno.EACCES, errno.EPERM, errno.EROFS):
                return None  # no folder (or a file), or one not writable: the write says so
            raise CadcogError(  # a folder, a FIFO, ... planted there: no lock would be taken
                f"{target}: its lock file {lock} cannot be made ({exc.strerror}); remove "
                "what is there (cadcog only ever makes a plain file)"
            ) from None
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_nlink > 1:  # a hard link: another file
            os.close(fd)
            raise CadcogError(
                f"{target}: its lock file {lock} is not a plain file of its own (a link or "
                "another kind of file); remove it"
            )
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _holder(fd)
            os.close(fd)
            raise CadcogError(
                f"{target}: another cadcog run ({holder}) is writing it; wait for it to end "
                "or give another path"
            ) from None
        except OSError:  # a file system without locks
            os.close(fd)
            return None
        try:
            current = os.lstat(lock).st_ino
        except OSError:
            current = -1
        if current != os.fstat(fd).st_ino:  # the holder removed it as we opened it: again
            os.close(fd)
            continue
        with suppress(OSError):
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()}\n".encode("ascii"))
        return fd
    return None  # pragma: no cover - twenty lost races in a row


@contextmanager
def output_lock(target: str | Path) -> Iterator[None]:
    """Hold an advisory lock on the output ``target`` while inside.

    The lock is a small file beside it (``.NAME.cadcog-lock``, holding this process's id),
    removed on the way out. A second cadcog run taking the same output's lock stops at once;
    a run killed outright leaves the file, but not the lock, so the next run goes ahead. Streams
    (standard output, devices, FIFOs) are not locked. Taking a lock this process holds is a
    no-op.

    Raises
    ------
    CadcogError
        If another process holds it, naming ``target`` and that process's id.
    """
    path = Path(target)
    if str(target) in ("", "-") or _stream_kind(path) is not None:
        yield
        return
    try:
        lock = _lock_file(path)
    except (OSError, RuntimeError):
        yield
        return
    key = str(lock)
    if key in _HELD:
        yield
        return
    fd = _acquire(lock, path)
    if fd is None:
        yield
        return
    _HELD[key] = fd
    try:
        yield
    finally:
        del _HELD[key]
        with suppress(OSError):
            os.unlink(lock)  # while still holding it: a waiter that opened it retries
        os.close(fd)
