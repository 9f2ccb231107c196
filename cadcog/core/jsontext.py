"""JSON text as cadcog writes it: floats rounded, two-space indent, the same bytes every time.

Every JSON output (``--json`` on standard output, the files of a report folder) is
``json.dumps(round_floats(data), indent=2, ensure_ascii=False, allow_nan=False)`` plus a
newline. :mod:`json` writes indented text with its pure-Python encoder; this module writes the
same text in one pass, in chunks (:func:`json_chunks`), so a 12 MB document is neither rounded
into a second copy first nor held as hundreds of thousands of pieces.

Examples
--------
>>> print(dumps_json({"a": [0.1 + 0.2, 1, None], "b": {}}), end="")
{
  "a": [
    0.3,
    1,
    null
  ],
  "b": {}
}
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterable
from typing import Any, TextIO

from cadcog.core import tolerances

#: Pieces of text joined into one chunk by :func:`json_chunks` (a few hundred kB).
_PIECES_PER_CHUNK = 1 << 14


def round_floats(value: Any, digits: int = tolerances.JSON_SIGNIFICANT_DIGITS) -> Any:
    """Round every float in a JSON-like structure to ``digits`` significant digits.

    Examples
    --------
    >>> round_floats({"a": [0.1 + 0.2, 1]}, 15)
    {'a': [0.3, 1]}
    """
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"refusing to write non-finite value {value!r} to JSON")
        return float(f"{value:.{digits}g}")
    if isinstance(value, dict):
        return {k: round_floats(v, digits) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [round_floats(v, digits) for v in value]
    return value


class _NotPlain(Exception):
    """A value :func:`json_chunks` leaves to :mod:`json` (a key that is not a string, a type
    :mod:`json` may reject)."""


def _rounded_repr(value: float, digits: int) -> str:
    """``repr(float(f"{value:.{digits}g}"))`` (``digits`` ≤ 15), mostly without the round trip.

    A decimal of at most 15 significant digits is the shortest that gives its float back (IEEE
    doubles hold 15.95), so ``repr`` of the rounded float has the digits of the ``g`` format;
    only the layout differs: ``repr`` adds ``.0`` to whole numbers and writes exponents from
    10¹⁶ where ``g`` does from 10^digits, and subnormal floats hold fewer digits (those few go
    the long way).

    Raises
    ------
    ValueError
        If the value, rounded, is not finite.
    """
    return _float_writer(digits)(value)


def _float_writer(digits: int) -> Any:
    """:func:`_rounded_repr` for one ``digits``, its format spec built once."""
    spec = f".{digits}g"
    tiny = sys.float_info.min

    def text_of(value: float) -> str:
        text = format(value, spec)
        if "e" in text:
            if -4 <= int(text[text.index("e") + 1 :]) < 16 or abs(value) < tiny:
                text = float.__repr__(float(text))
        elif "." not in text:
            if text[-1] in "fn":  # inf, nan
                raise ValueError(f"refusing to write non-finite value {value!r} to JSON")
            text += ".0"
        if abs(value) > 1.7976931348623e308 and not math.isfinite(float(text)):
            raise ValueError(f"refusing to write non-finite value {value!r} to JSON")
        return text

    return text_of


def json_chunks(data: Any, digits: int = tolerances.JSON_SIGNIFICANT_DIGITS) -> list[str]:
    """The text of :func:`dumps_json` (trailing newline included), as consecutive chunks.

    Written in one pass when ``data`` is plain (string keys; strings, numbers, booleans, None,
    lists, tuples and dicts: every JSON cadcog writes): floats rounded as :func:`round_floats`
    does, then written as ``float.__repr__`` (as :mod:`json` does), strings escaped by
    :mod:`json`'s own C escaper; anything else goes through :mod:`json` itself.

    Raises
    ------
    ValueError
        On a NaN or infinity (JSON has none); nothing is returned, so nothing is written.
    """
    try:
        return _plain_chunks(data, digits)
    except _NotPlain:
        text = json.dumps(round_floats(data, digits), indent=2, ensure_ascii=False, allow_nan=False)
        return [text, "\n"]


def _plain_chunks(value: Any, digits: int) -> list[str]:
    escape = json.encoder.encode_basestring  # ensure_ascii=False
    number = _float_writer(digits)
    chunks: list[str] = []
    out: list[str] = []
    add = out.append

    def emit(v: Any, pad: str) -> None:
        if isinstance(v, str):
            add(escape(v))
        elif isinstance(v, float):
            add(number(v))
        elif v is None:
            add("null")
        elif v is True:
            add("true")
        elif v is False:
            add("false")
        elif isinstance(v, int):
            add(int.__repr__(v))
        elif isinstance(v, (dict, list, tuple)):
            mapping = isinstance(v, dict)
            if not v:
                add("{}" if mapping else "[]")
                return
            inner = pad + "  "
            between = ",\n" + inner
            add(("{\n" if mapping else "[\n") + inner)
            first = True
            entries: Iterable[Any] = v.items() if isinstance(v, dict) else v
            for entry in entries:
                if first:
                    first = False
                else:
                    add(between)
                if mapping:
                    key, item = entry
                    if type(key) is not str and not isinstance(key, str):
                        raise _NotPlain
                    add(escape(key) + ": ")
                else:
                    item = entry
                kind = type(item)  # the commonest leaves here, the rest by emit
                if kind is float:
                    add(number(item))
                elif kind is str:
                    add(escape(item))
                else:
                    emit(item, inner)
            add("\n" + pad + ("}" if mapping else "]"))
            if len(out) > _PIECES_PER_CHUNK:
                chunks.append("".join(out))
                out.clear()
        else:
            raise _NotPlain

    emit(value, "")
    add("\n")
    chunks.append("".join(out))
    return chunks


def dumps_json(data: Any) -> str:
    """Deterministic JSON text: floats rounded, two-space indent, trailing newline.

    The text is ``json.dumps(round_floats(data), indent=2, ensure_ascii=False,
    allow_nan=False) + "\\n"`` (see :func:`json_chunks`).

    Raises
    ------
    ValueError
        On a NaN or infinity (JSON has none).
    """
    return "".join(json_chunks(data))


def write_json(data: Any, stream: TextIO) -> None:
    """Write :func:`dumps_json`'s text to ``stream`` chunk by chunk (the whole text is made
    first: a value JSON cannot hold raises before anything is written)."""
    for chunk in json_chunks(data):
        stream.write(chunk)
