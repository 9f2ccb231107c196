"""The cache's folder and its entries: where it lives, an entry read and written whole and
checked, the folder trimmed and cleared.

Where: ``$CADCOG_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/cadcog``, else
``~/.cache/cadcog`` (the XDG base directory convention). ``CADCOG_NO_CACHE=1`` turns it off.
An entry is plain JSON (never pickle) carrying its format, its own key and a digest of its
content (:func:`load_data` checks all three: a damaged entry, or another key's copied over it,
is a miss); it is opened only as a regular file, without following a link, within
:data:`MAX_ENTRY_BYTES`. What is kept under which key, and why a key sees every input, is
:mod:`cadcog.cad.cache`'s.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import stat
import tempfile
from contextlib import suppress
from pathlib import Path
from typing import Any

from cadcog.core.errors import CadcogError

#: Bumped when the stored form changes.
FORMAT = 2

#: The largest entry read or written (bytes): a 5000-solid model's is ~5 MB.
MAX_ENTRY_BYTES = 256 * 1024 * 1024

#: The most the cache folder holds; beyond it the entries used least recently are deleted
#: (a 5000-solid model's entry is ~5 MB, a 3U CubeSat's ~13 kB).
MAX_BYTES = 1_000_000_000

#: Age after which a temporary file left by a killed writer is deleted (s).
STALE_TMP_S = 3600.0


#: The name of an entry (a SHA-256 key): the only files :func:`trim` deletes, with its own
#: temporary files, whatever else the folder holds.
_ENTRY_NAME = re.compile(r"[0-9a-f]{64}\.json")


def cache_dir() -> Path | None:
    """The cache folder, or None when caching is turned off (``CADCOG_NO_CACHE``)."""
    return None if turned_off() else where()[0]


def turned_off() -> bool:
    """Whether ``CADCOG_NO_CACHE`` turns the cache off (any value but empty or ``0``)."""
    return os.environ.get("CADCOG_NO_CACHE", "").strip() not in ("", "0")


def where() -> tuple[Path, str]:
    """The cache folder (whether or not the cache is turned off) and what chose it:
    ``"CADCOG_CACHE_DIR"``, ``"XDG_CACHE_HOME"`` or ``"default"`` (``~/.cache/cadcog``)."""
    explicit = os.environ.get("CADCOG_CACHE_DIR", "").strip()
    if explicit:
        return Path(explicit).expanduser(), "CADCOG_CACHE_DIR"
    xdg = os.environ.get("XDG_CACHE_HOME", "").strip()
    if xdg and Path(xdg).is_absolute():  # the XDG spec: relative values are ignored
        return Path(xdg) / "cadcog", "XDG_CACHE_HOME"
    return Path.home() / ".cache" / "cadcog", "default"


def _digest(entry: str, result: Any) -> str:
    """What an entry's ``digest`` must be: a SHA-256 of its key and its result's JSON text."""
    text = json.dumps(result, sort_keys=True, default=_plain)
    return hashlib.sha256(f"{entry}\0{text}".encode()).hexdigest()


def _own_file(st: os.stat_result) -> bool:
    """A regular file with no other name (a hard link's other name may be anywhere)."""
    return stat.S_ISREG(st.st_mode) and st.st_nlink == 1


def _read_entry(path: Path) -> tuple[str, tuple[int, int]]:
    """An entry's text and its (device, inode): a regular file of its own (no link followed,
    no hard link, never a pipe or a device) of at most :data:`MAX_ENTRY_BYTES`; else OSError."""
    flags = os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOFOLLOW", 0)
    fd = os.open(path, flags)
    with os.fdopen(fd, "rb") as f:
        st = os.fstat(f.fileno())
        if not _own_file(st) or st.st_size > MAX_ENTRY_BYTES:
            raise OSError(f"{path}: not a cache entry")
        data = f.read(MAX_ENTRY_BYTES + 1)
    if len(data) > MAX_ENTRY_BYTES:
        raise OSError(f"{path}: not a cache entry")
    return data.decode("utf-8"), (st.st_dev, st.st_ino)


def load_data(entry: str) -> Any:
    """The JSON data kept under ``entry`` by :func:`store_data`, or None (no cache, no entry,
    or one that is damaged, of another format, or not this key's: its digest must match)."""
    folder = cache_dir()
    if folder is None:
        return None
    path = folder / f"{entry}.json"
    try:
        text, identity = _read_entry(path)
        data = json.loads(text)
        if data.get("format") != FORMAT or data.get("key") != entry:
            return None
        result = data["result"]
        if data.get("digest") != _digest(entry, result):
            return None
    except (OSError, ValueError, KeyError, TypeError, AttributeError, RecursionError):
        return None
    with suppress(OSError, NotImplementedError):  # used now: the last to go when trimmed
        st = os.lstat(path)
        if _own_file(st) and (st.st_dev, st.st_ino) == identity:  # the file just read
            os.utime(path, follow_symlinks=False)
    return result


def store_data(entry: str, data: Any) -> None:
    """Keep ``data`` (JSON data; numpy values as exact Python numbers) under ``entry`` with its
    key and digest (:func:`load_data` checks both: a damaged entry, or another's copied over it,
    is ignored), written whole or not at all; errors ignored."""
    folder = cache_dir()
    if folder is None:
        return
    plain = json.loads(json.dumps(data, default=_plain))
    text = json.dumps(
        {"format": FORMAT, "key": entry, "digest": _digest(entry, plain), "result": plain}
    )
    if len(text.encode("utf-8")) > MAX_ENTRY_BYTES:
        return
    with suppress(OSError):
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".entry-", suffix=".tmp")
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
            os.replace(tmp, folder / f"{entry}.json")
        finally:
            with suppress(OSError):
                os.unlink(tmp)
        trim(folder, keep=f"{entry}.json")


def _entries(
    folder: Path, *, stale_s: float | None = None, listed: bool = False, links: bool = False
) -> list[tuple[int, str, int]]:
    """The entries of ``folder`` as (modification time in ns, name, size in bytes), oldest
    first; with ``stale_s``, our temporary files older than that (s) are deleted on the way;
    with ``links``, links named as entries too (never read: :func:`load_data` follows no
    link; size 0). Errors ignored (another process may be writing or trimming), but with
    ``listed`` a folder that exists and cannot be listed raises :class:`CadcogError` (a missing
    one is empty)."""
    import time

    entries = []
    try:
        it = os.scandir(folder)
    except FileNotFoundError:
        return []
    except OSError as exc:
        if not listed:
            return []
        what = "not a folder" if isinstance(exc, NotADirectoryError) else exc.strerror
        raise CadcogError(f"{folder}: cannot list the cache folder ({what})") from None
    with it:
        for e in it:
            with suppress(OSError):
                st = e.stat(follow_symlinks=False)
                if e.name.startswith(".entry-") and e.name.endswith(".tmp"):
                    if stale_s is not None and time.time() - st.st_mtime > stale_s:
                        os.unlink(e.path)
                elif _ENTRY_NAME.fullmatch(e.name) and e.is_file(follow_symlinks=False):
                    entries.append((st.st_mtime_ns, e.name, st.st_size))
                elif links and _ENTRY_NAME.fullmatch(e.name) and e.is_symlink():
                    entries.append((st.st_mtime_ns, e.name, 0))
    return sorted(entries)


def trim(folder: Path, *, keep: str = "", max_bytes: int = MAX_BYTES) -> None:
    """Delete the entries of ``folder`` used least recently (modification time: a hit
    touches its entry) until they hold at most ``max_bytes``, never the entry named ``keep``,
    and temporary files of ours older than :data:`STALE_TMP_S`; no other file. Errors
    ignored (another process may be trimming too)."""
    entries = _entries(folder, stale_s=STALE_TMP_S)
    total = sum(size for _, _, size in entries)
    for _, name, size in entries:
        if total <= max_bytes:
            break
        if name != keep:
            with suppress(OSError):
                os.unlink(folder / name)
                total -= size


def usage(folder: Path) -> tuple[int, int]:
    """The number of entries in ``folder`` and their size in bytes.

    Raises
    ------
    CadcogError
        If the folder exists and cannot be listed (or is not a folder).
    """
    entries = _entries(folder, listed=True)
    return len(entries), sum(size for _, _, size in entries)


def clear(folder: Path) -> tuple[int, int]:
    """Delete every entry of ``folder`` (a link named as one: the link, never what it names)
    and our temporary files older than a minute (a writer's current one is left to finish); no
    other file. Returns the number of entries and
    the bytes deleted.

    Raises
    ------
    CadcogError
        If the folder cannot be listed or an entry cannot be deleted (naming it and why).
    """
    n, freed = 0, 0
    for _, name, size in _entries(folder, stale_s=60.0, listed=True, links=True):
        try:
            (folder / name).unlink()
        except FileNotFoundError:  # another process trimmed it
            continue
        except OSError as exc:
            raise CadcogError(f"{folder / name}: cannot delete ({exc.strerror})") from None
        n, freed = n + 1, freed + size
    return n, freed


def _plain(value: Any) -> Any:
    """numpy scalars and arrays as Python numbers and lists (exact)."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"not JSON data: {type(value).__name__}")
