"""A cache of models' mass properties, by the content of everything that determines them.

``cadcog plan``, ``estimate --setup``, ``update`` and ``check`` read a model named by a set-up or
requirements file (:func:`cadcog.cad.modelfile.load_model`): building a CubeSat spec with OCCT,
writing and reading its STEP, integrating every body. The result depends only on the files
read, the model keys and cadcog's own code, so it is kept, as plain JSON (never pickle), under a
key that hashes all of them: any change to any input, or to cadcog, is a new key, and an entry
is never updated in place.

The folder and its entries (where it is, the checked read and the whole write, trimming,
clearing) are :mod:`cadcog.cad.cachestore`'s. An entry that cannot be read (damaged, from
another version, another key's) is ignored and recomputed; a cache that cannot be written is
skipped without a word: the cache only saves time, it never changes a result. Entries are a
few kilobytes to a few megabytes (a 5000-solid model's ~5 MB); beyond
:data:`~cadcog.cad.cachestore.MAX_BYTES` (1 GB) in all, the entries used least recently are
deleted as a new one is written. ``cadcog cache`` shows the folder and its size; ``--clear``
empties it.

``cadcog massprops`` and :func:`cadcog.mass_properties` keep their result the same way, under
the STEP file, the materials file and every option that changes a number
(:func:`step_mass_properties`): a second run on an unchanged model reads no CAD at all. A refusal
(overlaps under ``check``, a note under ``--strict``) is kept too, with the model as counted
that it carries, and raised again; other errors are not kept.

Besides models, ``cadcog report`` keeps the CAD parts of a rig (its ground truth and the STEP
and STL files of ``parts build``, which are byte-for-byte reproducible) as a plain JSON entry
under :func:`key` (:func:`~cadcog.cad.cachestore.load_data`,
:func:`~cadcog.cad.cachestore.store_data`), so that a second report on an unchanged rig does
not import build123d (~4 s).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections.abc import Callable, Iterable, Sequence
from contextlib import suppress
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cadcog.cad.cachestore import FORMAT, load_data, store_data
from cadcog.cad.massresults import ModelMassProperties, Refusal, from_data, to_data
from cadcog.core.version import __version__

if TYPE_CHECKING:
    from cadcog.cad.bodies import ProgressFactory
    from cadcog.cad.resolve import OverlapPolicy
    from cadcog.cad.stepmodel import StepModel

#: The sub-packages whose code computes a model's mass properties (their sources are hashed
#: into every key, so a changed cadcog never reuses an old entry).
_CODE = ("cad", "mass", "core")


_code_digest: dict[tuple[str, ...], str] = {}


def _code(subs: tuple[str, ...] = _CODE) -> str:
    """Digest of cadcog's version, the geometry kernel's versions (:func:`kernel_versions`: a
    new OCCT may integrate to other digits) and the sources of the sub-packages ``subs``
    (computed once a run for each)."""
    if subs not in _code_digest:
        h = hashlib.sha256(f"cadcog {__version__} format {FORMAT}".encode())
        h.update(json.dumps(kernel_versions(), sort_keys=True).encode())
        root = Path(__file__).resolve().parents[1]
        for sub in subs:
            for path in sorted((root / sub).glob("*.py")):
                h.update(f"{sub}/{path.name}".encode())
                h.update(path.read_bytes())
        _code_digest[subs] = h.hexdigest()
    return _code_digest[subs]


#: The geometry kernel's packages, and the distributions that install each.
KERNEL_PACKAGES = (
    ("build123d", ("build123d",)),
    ("OCP", ("cadquery-ocp", "cadquery-ocp-novtk")),
)


def kernel_versions() -> dict[str, str]:
    """Versions of the geometry kernel's distributions (build123d, OCP), without importing
    them; ``"absent"`` for one not installed.

    Read from the names of the ``<name>-<version>.dist-info`` folders beside each package (a
    directory listing, ~1 ms). A package installed otherwise (no such folder beside it: an
    editable or conda install) is identified by ``importlib.metadata`` (~40 ms to import, on
    a cached ``plan`` of ~0.8 s) and by the names, sizes and modification times of its own
    top-level files (``"<package> files"``), so that a new build changes the key too.
    """
    import importlib.util

    versions: dict[str, str] = {}
    for package, dists in KERNEL_PACKAGES:
        versions.update(dict.fromkeys(dists, "absent"))
        spec = importlib.util.find_spec(package)
        if spec is None or not spec.submodule_search_locations:
            continue
        folder = Path(next(iter(spec.submodule_search_locations)))
        try:
            beside = os.listdir(folder.parent)
        except OSError:
            beside = []
        found = False
        for dist in dists:
            prefix = dist.replace("-", "_") + "-"
            names = [n for n in beside if n.startswith(prefix) and n.endswith(".dist-info")]
            if len(names) == 1:
                versions[dist] = names[0][len(prefix) : -len(".dist-info")]
            found = found or bool(names)
            if len(names) > 1:
                versions[dist] = _metadata_version(dist)
        if not found:
            versions.update({dist: _metadata_version(dist) for dist in dists})
            versions[f"{package} files"] = _fingerprint(folder)
    return versions


def _metadata_version(dist: str) -> str:
    from importlib import metadata

    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "absent"


def _fingerprint(folder: Path) -> str:
    """The names, sizes and modification times of a folder's files (not its sub-folders')."""
    h = hashlib.sha256()
    with suppress(OSError), os.scandir(folder) as it:
        for e in sorted(it, key=lambda e: e.name):
            with suppress(OSError):
                if e.is_file():
                    st = e.stat()
                    h.update(f"{e.name} {st.st_size} {st.st_mtime_ns}\n".encode())
    return h.hexdigest()[:16]


#: A STEP entity naming another file: OCCT's reader follows it (multi-file assemblies), so a
#: key on the main file alone would miss a change in the files it names.
_EXTERNAL_REFERENCES = (b"DOCUMENT_FILE", b"document_file")


def key(settings: dict[str, Any], files: Iterable[Path], *, code: tuple[str, ...] = _CODE) -> str:
    """The entry's key: a SHA-256 of cadcog's code (the sources of the sub-packages ``code``),
    ``settings`` (JSON-ready values) and the content of every file in ``files``, in order (not
    their paths: the same bytes reached from another folder, or by an absolute path from the
    API, are the same entry; :func:`mass_properties` puts the caller's paths in the result).

    Raises
    ------
    OSError
        If a file is not a regular file, cannot be read, or names other files its reader
        follows (a STEP ``DOCUMENT_FILE``: the key cannot see them). The caller then computes
        without the cache, and reading says what is wrong if anything is.
    """
    h = hashlib.sha256(_code(code).encode())
    h.update(json.dumps(settings, sort_keys=True, default=str).encode())
    width = max(len(r) for r in _EXTERNAL_REFERENCES) - 1
    for i, path in enumerate(files):
        if not os.path.isfile(path):  # never open a pipe or a device (it could block)
            raise OSError(f"{path}: not a regular file")
        h.update(f"file {i}".encode() + b"\0")  # the content, not how the path is spelled
        tail = b""
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
                window = tail + block  # a name across two blocks is found too
                if any(r in window for r in _EXTERNAL_REFERENCES):
                    raise OSError(f"{path}: refers to other files (DOCUMENT_FILE)")
                tail = block[-width:]
        h.update(b"\0")
    return h.hexdigest()


def _stamps(files: Iterable[Path]) -> list[tuple[int, int, int, int]] | None:
    """Device, inode, size and modification time of each file (None if one cannot be
    stat'ed): equal before and after a computation, the files it read are the ones hashed."""
    try:
        return [(st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns) for st in map(os.stat, files)]
    except OSError:
        return None


@dataclass(frozen=True)
class _Slot:
    """Where a computation's result is kept: its entry (None when the key cannot see every
    input) and its files' stamps before it ran, so that a result is only kept under the
    content it was computed from."""

    entry: str | None
    files: tuple[Path, ...]
    before: list[tuple[int, int, int, int]] | None

    @classmethod
    def of(cls, settings: dict[str, Any], files: Sequence[Path], code: tuple[str, ...]) -> _Slot:
        before = _stamps(files)
        try:
            entry: str | None = key(settings, files, code=code)
        except OSError:
            entry = None
        return cls(entry, tuple(files), before)

    def load(self) -> Any:
        """The kept data, or None."""
        return None if self.entry is None else load_data(self.entry)

    def keep(self, data: Any) -> None:
        """Store ``data``, unless a file changed since the slot was made (or no key)."""
        if self.entry is not None and self.before is not None:
            if _stamps(self.files) == self.before:
                store_data(self.entry, data)


def cached_data(
    settings: dict[str, Any],
    files: Sequence[Path],
    compute: Callable[[], Any],
    *,
    code: tuple[str, ...] = _CODE,
) -> tuple[Any, bool]:
    """``compute()``'s JSON data, kept under :func:`key` ``(settings, files, code)``: read back
    if an entry exists, else computed and stored, unless a file changed while it ran (as
    :func:`mass_properties`). Returns the data and whether the cache gave it. ``code`` names
    every sub-package whose sources the computation depends on."""
    slot = _Slot.of(settings, files, code)
    data = slot.load()
    if data is not None:
        return data, True
    data = compute()
    slot.keep(data)
    return data, False


def model_settings(
    kind: str,
    *,
    total_mass_kg: float | None,
    units: str | None,
    exclude: Sequence[str],
    overlaps: str,
    strict: bool,
) -> dict[str, Any]:
    """The settings of a model's entry (with its files' content, the key): one function, so
    that ``massprops MODEL --materials M`` and a set-up naming the same two files share it."""
    return {
        "kind": kind,
        "total_mass_kg": total_mass_kg,
        "units": units,
        "exclude": list(exclude),
        "overlaps": overlaps,
        "strict": bool(strict),
    }


def step_mass_properties(
    step: Path,
    materials: Path | None,
    *,
    density_kg_m3: float | None,
    total_mass_kg: float | None,
    units: str | None,
    exclude: Sequence[str],
    overlaps: OverlapPolicy,
    strict: bool,
    surface_areas: bool,
    workers: int,
    progress: ProgressFactory | None = None,
    read: Callable[[], StepModel] | None = None,
) -> tuple[ModelMassProperties, bool]:
    """What ``cadcog massprops`` and :func:`cadcog.mass_properties` compute for a STEP file
    (:func:`~cadcog.cad.stepmass.model_mass_properties` with the materials file, or one
    density), through :func:`mass_properties`: the command and the API share entries.

    The key holds both files and every option that changes the result; ``workers`` and
    ``progress`` change no bit and are not in it. ``read`` reads the model (default:
    :func:`~cadcog.cad.stepread.read_step` of ``step``); the command passes its own, which
    keeps the model for the report's views. Returns the result and whether the cache gave it.

    Raises
    ------
    Refusal
        Computed, or kept in the cache (then ``read`` was not called).
    CadcogError
        Any other bad input, computed.
    """
    settings = model_settings(
        "model_step",
        total_mass_kg=total_mass_kg,
        units=units,
        exclude=exclude,
        overlaps=overlaps,
        strict=strict,
    )  # a set-up's model_step with these materials: the same entry
    if density_kg_m3 is not None or surface_areas:
        settings |= {"density_kg_m3": density_kg_m3, "surface_areas": bool(surface_areas)}

    def afresh() -> ModelMassProperties:
        from cadcog.cad.stepmass import model_mass_properties
        from cadcog.cad.stepread import read_step
        from cadcog.mass.materials import MaterialMap, load_materials

        material_map = (  # read here: a result is kept under the content it read
            load_materials(materials)
            if materials is not None
            else MaterialMap.uniform(density_kg_m3)
            if density_kg_m3 is not None
            else None
        )
        return model_mass_properties(
            read() if read is not None else read_step(step),
            material_map,
            total_mass_kg=total_mass_kg,
            units=units,
            exclude=exclude,
            overlaps=overlaps,
            strict=strict,
            progress=progress,
            workers=workers,
            surface_areas=surface_areas,
        )

    files = [step] if materials is None else [step, materials]
    return mass_properties(settings, files, afresh)


def mass_properties(
    settings: dict[str, Any], files: Iterable[Path], compute: Callable[[], ModelMassProperties]
) -> tuple[ModelMassProperties, bool]:
    """``compute()``'s result, kept under :func:`key` ``(settings, files)``: read back if an
    entry exists, else computed and stored.

    A refusal (:class:`~cadcog.cad.massresults.Refusal`: overlaps, ``strict``) depends only on
    the inputs: it is kept with the model as counted that it carries, and raised again on a
    hit. Any other error is not kept (some depend on the machine: memory, a full temporary
    folder). An input that cannot be read, or that names other files, makes no key:
    ``compute()`` then runs and nothing is kept; nor is anything when a file changed while it
    ran (its device, inode, size or modification time), so a result is only ever kept under
    the content it was computed from. ``compute()`` should read every file itself (for the
    same reason).

    Parameters
    ----------
    settings : dict
        Every option that changes the result (JSON-ready values).
    files : iterable of Path
        Every file read (their contents are hashed, in order; the paths name them in the
        result).
    compute : callable
        Computes the result (reading the files).

    Returns
    -------
    result : ModelMassProperties
    from_cache : bool
        True if ``result`` (or the refusal raised) was read from the cache.

    Raises
    ------
    CadcogError
        What ``compute()`` raises, or the refusal kept under the key.
    """
    files = list(files)
    slot = _Slot.of(settings, files, _CODE)
    paths = [str(f) for f in files]
    data = slot.load()
    if isinstance(data, dict) and isinstance(data.get("refused"), str):
        _raise_kept(data, paths)
    if data is not None:
        with suppress(ValueError, KeyError, TypeError, IndexError, AttributeError):
            return _relabelled(from_data(data), data["paths"], paths), True
    try:
        result = compute()
    except Refusal as exc:
        slot.keep({"refused": str(exc), "as_is": to_data(exc.as_is), "paths": paths})
        raise
    slot.keep({**to_data(result), "paths": paths})
    return result, False


def _swap(text: str, old: Sequence[str], new: Sequence[str]) -> str:
    """``text`` with each whole path of ``old`` replaced by the one of ``new`` at its place: a
    path inside a longer path or name (a product named like the file) is left alone.

    Examples
    --------
    >>> _swap("m.step: note on m.step/part", ["m.step"], ["/b/m.step"])
    '/b/m.step: note on m.step/part'
    """
    for a, b in zip(old, new, strict=True):
        if a != b:
            whole = re.compile(r"(?<![\w./\\-])" + re.escape(a) + r"(?![\w/\\-]|\.\w)")
            text = whole.sub(b.replace("\\", "\\\\"), text)
    return text


def _relabelled(
    result: ModelMassProperties, old: Sequence[str], new: Sequence[str]
) -> ModelMassProperties:
    """A kept result as the caller's paths name its files (its source, notes and info)."""
    if len(old) != len(new) or not all(isinstance(p, str) for p in old):
        raise ValueError("damaged entry: its paths")
    if list(old) == list(new):
        return result
    return replace(
        result,
        bodies=tuple(
            replace(b, density_source=_swap(b.density_source, old, new)) for b in result.bodies
        ),
        audit=replace(result.audit, source=_swap(result.audit.source, old, new)),
        notes=tuple(_swap(n, old, new) for n in result.notes),
        info=tuple(_swap(n, old, new) for n in result.info),
    )


def _raise_kept(data: dict[str, Any], paths: Sequence[str]) -> None:
    """Raise the refusal kept as ``data`` (a damaged entry: return)."""
    if set(data) == {"refused", "as_is", "paths"}:
        try:
            as_is = _relabelled(from_data(data["as_is"]), data["paths"], paths)
            message = _swap(data["refused"], data["paths"], paths)
        except (ValueError, KeyError, TypeError, IndexError, AttributeError):
            return
        raise Refusal(message, as_is)
