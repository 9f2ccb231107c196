"""A cache of models' mass properties, by the content of everything that determines them.

``cadcog plan``, ``estimate --setup``, ``update`` and ``check`` read a model named by a set-up or
requirements file (:func:`cadcog.cad.modelfile.load_model`): building a CubeSat spec with OCCT,
writing and reading its STEP, integrating every body. The result depends only on the files
read, the model keys and cadcog's own code, so it is kept, as plain JSON (never pickle), under a
key that hashes all of them: any change to any input, or to cadcog, is a new key, and an entry
is never updated in place.

Where: ``$CADCOG_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/cadcog``, else
``~/.cache/cadcog`` (the XDG base directory convention). ``CADCOG_NO_CACHE=1`` turns it off.
An entry that cannot be read (damaged, from another version) is ignored and recomputed; a
cache that cannot be written is skipped without a word: the cache only saves time, it never
changes a result. Entries are a few kilobytes to a few megabytes; delete the folder to
reclaim the space.

Besides models, ``cadcog report`` keeps the CAD parts of a rig (its ground truth and the STEP
and STL files of ``parts build``, which are byte-for-byte reproducible) as a plain JSON entry
(:func:`load_data`, :func:`store_data`), so that a second report on an unchanged rig does not
import build123d (~4 s).
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from collections.abc import Iterable
from contextlib import suppress
from pathlib import Path
from typing import Any

from cadcog.cad.massresults import ModelMassProperties, from_data, to_data
from cadcog.core.version import __version__

#: Bumped when the stored form changes.
FORMAT = 1

#: The sub-packages whose code computes a model's mass properties (their sources are hashed
#: into every key, so a changed cadcog never reuses an old entry).
_CODE = ("cad", "mass", "core")


def cache_dir() -> Path | None:
    """The cache folder, or None when caching is turned off (``CADCOG_NO_CACHE``)."""
    if os.environ.get("CADCOG_NO_CACHE", "").strip() not in ("", "0"):
        return None
    explicit = os.environ.get("CADCOG_CACHE_DIR", "").strip()
    if explicit:
        return Path(explicit).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME", "").strip()
    base = Path(xdg) if xdg and Path(xdg).is_absolute() else Path.home() / ".cache"
    return base / "cadcog"


_code_digest: dict[tuple[str, ...], str] = {}


def _code(subs: tuple[str, ...] = _CODE) -> str:
    """Digest of cadcog's version and the sources of the sub-packages ``subs`` (computed once
    a run for each)."""
    if subs not in _code_digest:
        h = hashlib.sha256(f"cadcog {__version__} format {FORMAT}".encode())
        root = Path(__file__).resolve().parents[1]
        for sub in subs:
            for path in sorted((root / sub).glob("*.py")):
                h.update(f"{sub}/{path.name}".encode())
                h.update(path.read_bytes())
        _code_digest[subs] = h.hexdigest()
    return _code_digest[subs]


def kernel_versions() -> dict[str, str]:
    """Versions of the geometry kernel's distributions (build123d, OCP), read from their
    installed metadata without importing them; ``"absent"`` for one not installed."""
    from importlib import metadata

    versions = {}
    for dist in ("build123d", "cadquery-ocp", "cadquery-ocp-novtk"):
        try:
            versions[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            versions[dist] = "absent"
    return versions


def key(settings: dict[str, Any], files: Iterable[Path], *, code: tuple[str, ...] = _CODE) -> str:
    """The entry's key: a SHA-256 of cadcog's code (the sources of the sub-packages ``code``),
    ``settings`` (JSON-ready values) and the path and content of every file in ``files``.

    Raises
    ------
    OSError
        If a file cannot be read (the caller then reads it as usual, and reports that).
    """
    h = hashlib.sha256(_code(code).encode())
    h.update(json.dumps(settings, sort_keys=True, default=str).encode())
    for path in files:
        h.update(str(path).encode() + b"\0")
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        h.update(b"\0")
    return h.hexdigest()


def load(entry: str) -> ModelMassProperties | None:
    """The cached result under ``entry``, or None (no cache, no entry, or a damaged one)."""
    data = load_data(entry)
    if data is None:
        return None
    try:
        return from_data(data)
    except (ValueError, KeyError, TypeError, IndexError, AttributeError):
        return None


def store(entry: str, result: ModelMassProperties) -> None:
    """Keep ``result`` under ``entry`` (written whole or not at all; errors ignored)."""
    store_data(entry, to_data(result))


def load_data(entry: str) -> Any:
    """The JSON data kept under ``entry`` by :func:`store_data`, or None (no cache, no entry,
    or a damaged one)."""
    folder = cache_dir()
    if folder is None:
        return None
    try:
        data = json.loads((folder / f"{entry}.json").read_text(encoding="utf-8"))
        if data.get("format") != FORMAT:
            return None
        return data["result"]
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None


def store_data(entry: str, data: Any) -> None:
    """Keep ``data`` (JSON data; numpy values as exact Python numbers) under ``entry``,
    written whole or not at all; errors ignored."""
    folder = cache_dir()
    if folder is None:
        return
    text = json.dumps({"format": FORMAT, "result": data}, default=_plain)
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


def _plain(value: Any) -> Any:
    """numpy scalars and arrays as Python numbers and lists (exact)."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"not JSON data: {type(value).__name__}")
