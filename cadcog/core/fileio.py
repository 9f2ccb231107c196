"""Output files that appear whole or not at all, one writer at a time.

Commands write into a temporary directory (or file) beside the destination and move the
finished output into place with :func:`os.replace` (a file) or by swapping the whole folder (a
report folder), both atomic on POSIX file systems. If anything fails on the way, including an
interrupt (Ctrl-C) or a SIGTERM (``cadcog.cli`` turns it into an exception), the temporary files
are removed and the destination is left as it was. Finished files get the permissions the user's
umask gives a new file, not the 0600 of a temporary file; errors name the destination the user
gave, never the temporary name.

Outputs that are not regular files (``-`` for standard output, ``/dev/stdout``, ``/dev/null``,
a FIFO, a terminal, a symbolic link into ``/proc/self/fd``) are never replaced: the finished
output is streamed into them in one piece. Every replaced or appended output is held under an
advisory lock (:func:`cadcog.core.outputlock.output_lock`) while it is written: a second cadcog
run on the same output stops with one line naming the holder's PID.
"""

from __future__ import annotations

import errno
import os
import shutil
import signal
import stat
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager, suppress
from contextvars import ContextVar
from pathlib import Path

from cadcog.core.errors import CadcogError
from cadcog.core.outputlock import _new_file_mode, _stream_kind, is_stream, output_lock

#: The files the running command has read (resolved path → what it was), while a command runs
#: inside :func:`guarding_inputs`; staged outputs refuse to replace any of them.
_INPUTS: ContextVar[dict[Path, str] | None] = ContextVar("cadcog_inputs", default=None)

#: Outputs this process has put in place since :func:`reset_written` (for the message after a
#: signal: "nothing was written" only when true).
_WRITTEN: list[Path] = []

#: Errors of the file system being full or a size limit, whatever file was being written.
_FULL = {errno.EFBIG, errno.ENOSPC, errno.EDQUOT}


@contextmanager
def guarding_inputs() -> Iterator[None]:
    """While inside, every file read through :func:`note_input` is protected from the outputs.

    The command line runs each command inside one: whatever a command reads (a rig file, a
    set-up and the model it names, readings, a STEP file, a materials file), no staged output of
    the same command may replace it, however the output's name was given.
    """
    token = _INPUTS.set({})
    try:
        yield
    finally:
        _INPUTS.reset(token)


def note_input(path: str | Path, what: str) -> None:
    """Record ``path`` as an input of the running command (a no-op outside
    :func:`guarding_inputs`)."""
    inputs = _INPUTS.get()
    if inputs is not None:
        with suppress(OSError, RuntimeError):
            inputs.setdefault(Path(path).resolve(), what)


def noted_inputs() -> list[Path]:
    """The inputs noted so far by the running command, in the order read."""
    return list(_INPUTS.get() or {})


def reset_written() -> None:
    """Forget the outputs written so far (the command line calls it as a command starts)."""
    _WRITTEN.clear()


def written_outputs() -> list[Path]:
    """The outputs put in place since :func:`reset_written`, as the user named them."""
    return list(_WRITTEN)


def _refuse_inputs(destinations: list[Path]) -> None:
    """Raise, before anything is replaced, if a destination is a file the command read."""
    inputs = _INPUTS.get()
    if not inputs:
        return
    for dst in destinations:
        what = inputs.get(dst.resolve())
        if what is not None:
            raise CadcogError(f"{dst}: is the command's input ({what}); write elsewhere")


def _cannot_write(target: Path | str, exc: OSError) -> CadcogError:
    why = exc.strerror or str(exc)
    if exc.errno in _FULL:
        why += ": the disk is full or a file-size limit (ulimit -f) was reached"
    return CadcogError(f"{target}: cannot write here ({why})")


def _renamed(exc: BaseException, temporary: Path, target: Path | str) -> BaseException | None:
    """``exc`` as the user should see it when it escaped the writing of ``target`` into
    ``temporary``: an OSError of a full disk or of the temporary path, or a CadcogError naming the
    temporary path, names ``target`` instead (None: leave ``exc`` as it is)."""
    tmp = str(temporary)
    if isinstance(exc, OSError):
        names = (str(exc.filename or ""), str(exc.filename2 or ""))
        if exc.errno in _FULL or any(n.startswith(tmp) for n in names if n):
            return _cannot_write(target, exc)
        return None
    if isinstance(exc, CadcogError) and tmp in str(exc):
        return CadcogError(str(exc).replace(tmp, str(target)))
    return None


def _missing_dirs(folder: Path) -> list[Path]:
    """``folder`` and its parents that do not exist yet, outermost first."""
    missing = []
    p = folder
    while not p.exists():
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    return missing[::-1]


def _make_dirs(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; the ones created, outermost first."""
    missing = _missing_dirs(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return missing


def _remove_empty(created: list[Path]) -> None:
    """Remove the folders a failed command created (innermost first), if still empty."""
    for d in reversed(created):
        try:
            d.rmdir()
        except OSError:
            return


def silent_write_failure() -> str:
    """The likely reason when a library (OCCT, matplotlib) fails to write without saying why:
    the file-size limit if one is set (``ulimit -f``), else a full disk."""
    with suppress(ImportError, OSError, ValueError):
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_FSIZE)
        if soft != resource.RLIM_INFINITY:
            return f"no reason given; a file-size limit of {soft} bytes (ulimit -f) is set"
    return "no reason given; is the disk full?"


def not_a_regular_file(path: str | Path) -> str:
    """Why ``path`` cannot be read as a regular file: not found, or what it is instead (a FIFO
    is not "file not found")."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return "file not found"
    except OSError as exc:
        return f"cannot read ({exc.strerror or exc})"
    kinds = (
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a FIFO (named pipe)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    )
    what = next((name for test, name in kinds if test(mode)), "not a regular file")
    return f"is {what}, expected a regular file"


def _refuse_empty(path: str | Path) -> None:
    if str(path) == "":
        raise CadcogError("an output path is empty: expected a file or folder name")


# --- streams -----------------------------------------------------------------------------------


def _stream_out(path: Path, kind: str, data_file: Path) -> None:
    """Copy the finished ``data_file`` into the stream ``path`` (never replacing it)."""
    if kind == "stdout":
        sys.stdout.flush()
        data = data_file.read_bytes()
        buffer = getattr(sys.stdout, "buffer", None)
        if buffer is not None:
            buffer.write(data)
            buffer.flush()
        else:  # a text stream (tests capture stdout so)
            sys.stdout.write(data.decode("utf-8", "replace"))
            sys.stdout.flush()
        return
    st = os.stat(path)
    if stat.S_ISBLK(st.st_mode):
        raise CadcogError(f"{path}: is a block device; give a file name")
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CLOEXEC)  # no O_TRUNC, no O_CREAT
    try:
        with open(data_file, "rb") as src:
            while chunk := src.read(1 << 20):
                view = memoryview(chunk)
                while view:
                    view = view[os.write(fd, view) :]
    finally:
        os.close(fd)


# --- staged outputs ----------------------------------------------------------------------------


@contextmanager
def staged_output_dir(out_dir: str | Path) -> Iterator[Path]:
    """Yield a scratch directory that becomes ``out_dir`` on success, in one step.

    The new folder holds what the command produced and, beside it, every entry of an existing
    ``out_dir`` that the command does not produce (hard links, so nothing is copied); then the
    two folders are swapped atomically (``renameat2(RENAME_EXCHANGE)``, or two renames with
    signals held off where the system has no exchange) and the old one is removed. A signal at
    any time leaves either the old folder or the new one, never a mixture. The working folder
    itself (``--out .``) is not swapped from under the shell: its files are moved in with
    signals held off. The folder is locked (:func:`cadcog.core.outputlock.output_lock`) while it
    is written.

    Raises
    ------
    CadcogError
        If ``out_dir`` is a file, standard output, or its parent cannot be written (naming
        ``out_dir``), or if another run is writing it.
    """
    _refuse_empty(out_dir)
    out = Path(out_dir)
    if str(out_dir) == "-":
        raise CadcogError("-: this output is a folder; standard output cannot hold it")
    if out.exists() and not out.is_dir():
        raise CadcogError(f"{out}: exists and is not a directory")
    real = out.resolve()
    parent = real.parent
    created: list[Path] = []
    try:
        created = _make_dirs(parent)
    except OSError as exc:
        raise _cannot_write(out, exc) from None
    done = False
    try:
        with output_lock(out):
            stage: Path | None = None
            try:
                # Made and named with SIGINT/SIGTERM held: a signal that arrives as the folder
                # is made is delivered once ``stage`` names it, so the ``finally`` removes it
                # (where a handler raises, as the command's do; the default action ends the
                # process at once, with no clean-up possible).
                with _signals_held():
                    try:
                        stage = Path(
                            tempfile.mkdtemp(prefix=f".{real.name}.", suffix=".partial", dir=parent)
                        )
                    except OSError as exc:
                        raise _cannot_write(out, exc) from None
                try:
                    yield stage
                except BaseException as exc:
                    better = _renamed(exc, stage, out)
                    if better is None:
                        raise
                    raise better from None
                produced = [p.relative_to(stage) for p in sorted(stage.rglob("*")) if p.is_file()]
                _refuse_inputs([out / p for p in produced])
                try:
                    _install_dir(stage, real, out, produced)
                except OSError as exc:
                    raise _cannot_write(out, exc) from None
                _WRITTEN.append(out)
                done = True
            finally:
                if stage is not None:
                    with _signals_held():  # a second signal does not cut the clean-up short
                        shutil.rmtree(stage, ignore_errors=True)
    finally:
        if not done:
            _remove_empty(created)


def _install_dir(stage: Path, real: Path, out: Path, produced: list[Path]) -> None:
    """Put the finished ``stage`` in place of ``real`` (see :func:`staged_output_dir`)."""
    cwd = Path.cwd().resolve()
    if not real.exists():
        os.chmod(stage, 0o777 & ~_umask())
        os.rename(stage, real)
        return
    _carry_over(real, stage, set(produced), out)
    if real == cwd or real in cwd.parents:
        _move_in(stage, real, produced)
        return
    os.chmod(stage, stat.S_IMODE(os.stat(real).st_mode))
    if not _exchange(stage, real):
        with _signals_held():
            old = stage.with_name(stage.name + ".old")
            os.rename(real, old)
            os.rename(stage, real)
            os.rename(old, stage)  # removed with the stage
    # stage now holds the old folder; the caller removes it


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _carry_over(old: Path, new: Path, produced: set[Path], out: Path) -> None:
    """Hard-link into ``new`` every entry of ``old`` that the command did not produce."""
    produced_dirs = {d for p in produced for d in p.parents if d != Path(".")}
    for root, dirs, files in os.walk(old):
        rel_root = Path(root).relative_to(old)
        for name in list(dirs):
            rel = rel_root / name
            src = old / rel
            if rel in produced:
                raise CadcogError(f"{out}: cannot write here ({rel} is a folder)")
            if src.is_symlink():
                dirs.remove(name)
                files.append(name)
                continue
            (new / rel).mkdir(exist_ok=True)
            os.chmod(new / rel, stat.S_IMODE(src.stat().st_mode))
        for name in files:
            rel = rel_root / name
            if rel in produced:
                continue
            if rel in produced_dirs:
                raise CadcogError(f"{out}: cannot write here ({rel} is a file)")
            src, dst = old / rel, new / rel
            if src.is_symlink():
                os.symlink(os.readlink(src), dst)
                continue
            try:
                os.link(src, dst, follow_symlinks=False)
            except OSError:
                shutil.copy2(src, dst, follow_symlinks=False)


def _exchange(a: Path, b: Path) -> bool:
    """Swap two folders atomically (Linux ``renameat2``); False where the system cannot."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    at_fdcwd, rename_exchange = -100, 2
    if renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EPERM, errno.ENOTSUP):
        return False
    raise OSError(err, os.strerror(err))


@contextmanager
def _signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM wait (not lost) until the block is done.

    In the main thread the Python handlers are swapped for one that notes the signal, and a
    noted signal is raised again, once, when the block ends (so the command's own handler, or
    the default action, then runs). A mask alone would not do: a signal sent to the process
    reaches any thread that does not block it (BLAS's worker threads), and its Python handler
    then runs in the main thread all the same. Elsewhere (no handlers can be set there), or
    where a handler was not set from Python (it could not be put back), the calling thread's
    mask holds them.
    """
    held = (signal.SIGINT, signal.SIGTERM)
    main = threading.current_thread() is threading.main_thread()
    if not main or any(signal.getsignal(signum) is None for signum in held):
        try:
            previous_mask = signal.pthread_sigmask(signal.SIG_BLOCK, set(held))
        except (AttributeError, OSError, ValueError):  # pragma: no cover - no POSIX signals
            yield
            return
        try:
            yield
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, previous_mask)
        return
    noted: list[int] = []

    def note(signum: int, frame: object) -> None:
        if signum not in noted:
            noted.append(signum)

    previous = {signum: signal.signal(signum, note) for signum in held}
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        _deliver(noted)


def _deliver(pending: list[int]) -> None:
    """Raise each of ``pending`` in turn, each even if the handler of the one before raised (the
    last one's exception is the one that propagates, the others chained to it)."""
    if not pending:
        return
    try:
        signal.raise_signal(pending[0])
    finally:
        _deliver(pending[1:])


def _move_in(stage: Path, real: Path, produced: list[Path]) -> None:
    """Move the produced files into ``real`` one by one, with signals held off."""
    with _signals_held():
        for rel in produced:
            dst = real / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            os.chmod(stage / rel, _new_file_mode())
            os.replace(stage / rel, dst)


@contextmanager
def staged_file(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path`` (same suffix) that replaces ``path`` on success.

    A symbolic link is written through (the file it points to is replaced, the link kept).
    ``-`` (standard output) and nodes that are not regular files (``/dev/stdout``, a FIFO, a
    terminal, ``/dev/null``) are never replaced: the finished output is written into them in
    one piece. The file is locked (:func:`cadcog.core.outputlock.output_lock`) while it is written.

    Raises
    ------
    CadcogError
        If ``path`` is a directory or its folder cannot be written (naming ``path``), or if
        another run is writing it.
    """
    _refuse_empty(path)
    target = Path(path)
    kind = _stream_kind(target)
    if kind is not None:
        with _streamed(target, kind) as scratch:
            yield scratch
        return
    if target.is_dir():
        raise CadcogError(f"{target}: is a directory, expected a file name")
    real = target.resolve()  # through a symbolic link: the link stays
    created: list[Path] = []
    try:
        created = _make_dirs(real.parent)
    except OSError as exc:
        raise _cannot_write(target, exc) from None
    done = False
    try:
        with output_lock(target):
            tmp: str | None = None
            try:
                with _signals_held():  # as for a folder: a signal finds ``tmp`` named
                    try:
                        fd, tmp = tempfile.mkstemp(
                            prefix=f".{real.stem}.", suffix=real.suffix, dir=real.parent
                        )
                    except OSError as exc:
                        raise _cannot_write(target, exc) from None
                    os.close(fd)
                try:
                    yield Path(tmp)
                except BaseException as exc:
                    better = _renamed(exc, Path(tmp), target)
                    if better is None:
                        raise
                    raise better from None
                _refuse_inputs([target])
                try:
                    os.chmod(tmp, _new_file_mode())
                    os.replace(tmp, real)
                except OSError as exc:
                    raise _cannot_write(target, exc) from None
                _WRITTEN.append(target)
                done = True
            finally:
                if tmp is not None and os.path.exists(tmp):
                    os.unlink(tmp)
    finally:
        if not done:
            _remove_empty(created)


@contextmanager
def staged_files(*paths: str | Path) -> Iterator[list[Path]]:
    """:func:`staged_file` for several outputs of one command: all are written, or none.

    Each is staged as :func:`staged_file` stages it; when the block succeeds they are put in
    place one after the other with SIGINT and SIGTERM held off (a signal is delivered once all
    are in place). If putting one in place fails, those already put in place that did not
    exist before are removed again.
    """
    existed = [Path(p).exists() or Path(p).is_symlink() for p in paths]
    missing = [_missing_dirs(Path(p).absolute().parent) for p in paths]
    stack = ExitStack()
    try:
        staged = [stack.enter_context(staged_file(p)) for p in paths]
        yield staged
    except BaseException:
        if not stack.__exit__(*sys.exc_info()):
            raise
        return  # pragma: no cover - staged_file never swallows an exception
    before = len(_WRITTEN)
    with _signals_held():
        try:
            stack.close()
        except BaseException:
            done = _WRITTEN[before:]
            for p, was in zip(paths, existed, strict=True):
                if not was and Path(p) in done and not is_stream(p):
                    with suppress(OSError):
                        os.unlink(p)
                    _WRITTEN.remove(Path(p))
            for created in missing:
                _remove_empty(created)
            raise


@contextmanager
def _streamed(target: Path, kind: str) -> Iterator[Path]:
    """Stage in a private temporary folder, then stream into ``target`` (see
    :func:`staged_file`)."""
    shown = "standard output" if kind == "stdout" else str(target)
    scratch: Path | None = None
    try:
        with _signals_held():  # as for a folder: a signal finds ``scratch`` named
            scratch = Path(tempfile.mkdtemp(prefix=".cadcog-stream."))
        tmp = scratch / f"out{target.suffix}"
        try:
            yield tmp
        except BaseException as exc:
            better = _renamed(exc, tmp, shown)
            if better is None:
                raise
            raise better from None
        if not tmp.exists():
            return
        _refuse_inputs([] if kind == "stdout" else [target])
        try:
            _stream_out(target, kind, tmp)
        except OSError as exc:
            raise _cannot_write(shown, exc) from None
        _WRITTEN.append(target)
    finally:
        if scratch is not None:
            with _signals_held():
                shutil.rmtree(scratch, ignore_errors=True)


def refuse_overwriting_inputs(output: str | Path, inputs: dict[str, str | Path | None]) -> None:
    """Refuse an output that is one of the command's own inputs.

    Parameters
    ----------
    output : path-like
    inputs : mapping of option or argument name → path (or None when not given)

    Raises
    ------
    CadcogError
        Naming both, if ``output`` resolves to the same file as an input.
    """
    if str(output) in ("", "-"):
        return
    out = Path(output).resolve()
    for name, value in inputs.items():
        if value is not None and Path(value).resolve() == out:
            raise CadcogError(f"{output}: is the command's input ({name}); write elsewhere")
