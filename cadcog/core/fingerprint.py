"""A content fingerprint of a computation's inputs, for keys of the results cache.

A cached result may only be read back under the inputs it was computed from. For a result
whose inputs are objects already read (a set-up with its CAD bodies, its rig, the hangs'
readings), :func:`fingerprint` hashes those objects themselves, not the files they came from:
nothing a set-up reads can be missed (a rig file it names, a materials file its model names),
and a change in any number changes the key. Every value is encoded exactly (floats by their
hexadecimal form, arrays by their bytes, dtype and shape; dataclasses by their type and every
field); any other type is refused (``TypeError``), so an input the encoding does not know
never silently drops out of a key.
"""

from __future__ import annotations

import dataclasses
import enum
import hashlib
from collections.abc import Mapping
from pathlib import PurePath
from typing import Any

import numpy as np


def fingerprint(value: Any) -> str:
    """SHA-256 (hex) of ``value``'s exact content.

    Parameters
    ----------
    value : any
        None, bool, int, float, str, bytes, a path, an enum, a numpy array or scalar, a
        dataclass instance, or a tuple, list, dict, set or frozenset of these, nested.

    Returns
    -------
    str
        64 hexadecimal digits.

    Raises
    ------
    TypeError
        A value of any other type (named), wherever it is nested.

    Examples
    --------
    >>> fingerprint((1.0, "a")) == fingerprint((1.0, "a"))
    True
    >>> fingerprint(0.1) == fingerprint(float(np.nextafter(0.1, 1.0)))  # the last bit counts
    False
    >>> fingerprint([1]) == fingerprint((1,)), fingerprint(1) == fingerprint(1.0)
    (False, False)
    """
    h = hashlib.sha256()
    _feed(h, value)
    return h.hexdigest()


def _feed(h: Any, v: Any) -> None:
    """Feed ``v``'s tagged encoding into ``h`` (each tag names the type, each length is given,
    so two different values never encode alike)."""
    if v is None or isinstance(v, bool):
        h.update(f"<{v!r}>".encode())
    elif isinstance(v, enum.Enum):
        h.update(f"<enum {type(v).__qualname__}>".encode())
        _feed(h, v.value)
    elif isinstance(v, int):
        h.update(f"<int {v}>".encode())
    elif isinstance(v, float):
        h.update(f"<float {v.hex()}>".encode())
    elif isinstance(v, str):
        _bytes(h, "str", v.encode("utf-8", "surrogatepass"))
    elif isinstance(v, bytes):
        _bytes(h, "bytes", v)
    elif isinstance(v, PurePath):
        _bytes(h, "path", str(v).encode("utf-8", "surrogatepass"))
    elif isinstance(v, np.ndarray | np.generic):
        a = np.ascontiguousarray(v)
        if a.dtype == object:
            raise TypeError("fingerprint: a numpy array of Python objects")
        h.update(f"<array {a.dtype.str} {a.shape}>".encode())
        _bytes(h, "data", a.tobytes())
    elif dataclasses.is_dataclass(v) and not isinstance(v, type):
        fields = dataclasses.fields(v)
        h.update(f"<dataclass {type(v).__module__}.{type(v).__qualname__} {len(fields)}>".encode())
        for f in fields:
            _feed(h, f.name)
            _feed(h, getattr(v, f.name))
    elif isinstance(v, tuple | list):
        h.update(f"<{type(v).__name__} {len(v)}>".encode())
        for x in v:
            _feed(h, x)
    elif isinstance(v, Mapping):
        items = sorted(((fingerprint(k), v[k]) for k in v), key=lambda kx: kx[0])
        h.update(f"<mapping {len(items)}>".encode())
        for fk, x in items:
            h.update(fk.encode())
            _feed(h, x)
    elif isinstance(v, set | frozenset):
        h.update(f"<set {len(v)}>".encode())
        for fx in sorted(fingerprint(x) for x in v):
            h.update(fx.encode())
    else:
        raise TypeError(f"fingerprint: cannot encode a {type(v).__module__}.{type(v).__qualname__}")


def _bytes(h: Any, tag: str, data: bytes) -> None:
    h.update(f"<{tag} {len(data)}>".encode())
    h.update(data)
