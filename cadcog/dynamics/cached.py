"""Inertia results kept in the results cache (:mod:`cadcog.cad.cache`), keyed by content.

The swing fit is the slow part of ``cadcog inertia`` and ``cadcog update --swings`` (seconds
of least squares per file); on unchanged inputs both read the result back. The key holds the
files' bytes (the swing file, the readings when read from a file), an exact fingerprint of the
objects already read (the set-up with its CAD bodies or the rig, the hangs, the weighing:
:func:`cadcog.core.fingerprint.fingerprint`) and the sources of every sub-package the chain
runs through, so a change in any of them is a new entry. The swings' own refusal (a
:class:`~cadcog.core.errors.DegenerateGeometryError`: no tensor in these records) is kept and
raised again with its message; any other error is not kept.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from cadcog.cad import cache
from cadcog.core.errors import DegenerateGeometryError
from cadcog.core.fingerprint import fingerprint
from cadcog.dynamics.result import InertiaResult

#: The sub-packages whose code computes an inertia result (hashed into its key).
INERTIA_CODE = ("core", "mass", "rig", "cad", "method", "uncertainty", "spacecraft", "dynamics")


def cached_inertia(
    compute: Callable[[], InertiaResult], inputs: dict[str, Any], files: Sequence[Path]
) -> tuple[InertiaResult, bool]:
    """``compute()``'s result, or the one kept under ``inputs`` and ``files``'s content.

    Parameters
    ----------
    compute : callable
        Computes the result from the inputs (called only when no entry exists).
    inputs : dict
        Every object the computation reads other than ``files``' bytes (fingerprinted:
        :func:`~cadcog.core.fingerprint.fingerprint`).
    files : sequence of Path
        The files it reads.

    Returns
    -------
    result : InertiaResult
        Always read back from its JSON data, hit or miss, so that both give the same object.
    hit : bool
        Whether the cache gave it.

    Raises
    ------
    DegenerateGeometryError
        The swings give no tensor (computed, or kept with its message).
    """

    def data() -> dict[str, Any]:
        try:
            return {"result": compute().to_dict()}
        except DegenerateGeometryError as exc:
            return {"refused": str(exc)}

    settings = {"kind": "inertia", "inputs": fingerprint(inputs)}
    kept, hit = cache.cached_data(settings, list(files), data, code=INERTIA_CODE)
    if "refused" in kept:
        raise DegenerateGeometryError(kept["refused"])
    return InertiaResult.from_dict(kept["result"]), hit
