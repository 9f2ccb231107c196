"""What every result object shares: ``to_json()`` from its ``to_dict()``.

The command line prints ``to_dict()`` through the same function with ``--json``, so a result
obtained in Python serialises to exactly what the command prints.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from cadcog.core.jsontext import dumps_json

#: Longest text of one field in a result's repr.
_REPR_FIELD_CHARS = 60

#: How deep :meth:`JsonResult.__post_init__` follows nested dataclasses and tuples.
_MAX_FREEZE_DEPTH = 4


class JsonResult:
    """Mixin for frozen result dataclasses: JSON text of :meth:`to_dict`.

    Floats are rounded to :data:`cadcog.core.tolerances.JSON_SIGNIFICANT_DIGITS` significant
    digits, non-finite values are refused, keys keep their order.

    Examples
    --------
    >>> from cadcog.mass.properties import box_properties
    >>> print(box_properties((10, 10, 10), (0, 0, 0), mass_kg=1.0).to_json().splitlines()[1])
      "mass_kg": 1.0,
    """

    def __post_init__(self) -> None:
        """Every array of a result is read-only, down through the plain dataclasses and tuples
        it holds (a result's own arrays are read-only views: the caller's arrays it was built
        from stay writable). A subclass with its own ``__post_init__`` freezes its fields."""
        _freeze_fields(self, _MAX_FREEZE_DEPTH)

    def to_dict(self) -> dict[str, Any]:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def to_json(self) -> str:
        """The JSON text ``--json`` prints for this result (two-space indent, no final newline)."""
        return dumps_json(self.to_dict()).rstrip("\n")

    def __repr__(self) -> str:
        """One line for a notebook: numbers and short texts as they are, arrays by their shape,
        collections by their length, nested results by their type (``to_dict()`` has it all).

        Large results use it (their dataclass is declared with ``repr=False``); a plan's full
        dataclass repr runs to a hundred kilobytes.
        """
        return one_line_repr(self)


def one_line_repr(obj: Any) -> str:
    """A dataclass in one line: numbers and short texts as they are, arrays by their shape,
    collections by their length, nested dataclasses by their type (what a notebook shows of a
    result, or of a set-up)."""
    if not dataclasses.is_dataclass(obj):
        return object.__repr__(obj)
    parts = [f"{f.name}={_short(getattr(obj, f.name))}" for f in dataclasses.fields(obj)]
    return f"{type(obj).__name__}({', '.join(parts)})"


def _short(value: Any) -> str:
    """A field of a result, in a few characters."""
    shape = getattr(value, "shape", None)
    if shape is not None and getattr(value, "size", 0) > 3:
        return f"<array {'×'.join(str(n) for n in shape)}>"
    if isinstance(value, (list, tuple, dict, set)) and len(value) > 3:
        return f"<{type(value).__name__} of {len(value)}>"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return f"<{type(value).__name__}>"
    text = repr(value.tolist() if shape is not None else value)
    return text if len(text) <= _REPR_FIELD_CHARS else text[: _REPR_FIELD_CHARS - 3] + "..."


def _frozen(value: Any, depth: int) -> Any:
    """``value`` with its arrays read-only: an array as a read-only view, a plain tuple
    rebuilt, a frozen dataclass that is not a result itself frozen in place."""
    if hasattr(value, "setflags") and hasattr(value, "view"):  # a numpy array (no import)
        view = value.view()
        view.setflags(write=False)
        return view
    if depth <= 0:
        return value
    if type(value) is tuple:
        return tuple(_frozen(v, depth - 1) for v in value)
    if (
        dataclasses.is_dataclass(value)
        and not isinstance(value, (type, JsonResult))
        and type(value).__dataclass_params__.frozen  # type: ignore[attr-defined]
    ):
        _freeze_fields(value, depth - 1)
    return value


def _freeze_fields(obj: Any, depth: int) -> None:
    """Each field of the frozen dataclass ``obj`` with its arrays read-only."""
    if not dataclasses.is_dataclass(obj):
        return
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        frozen = _frozen(value, depth)
        if frozen is not value:
            object.__setattr__(obj, f.name, frozen)
