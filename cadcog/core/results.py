"""What every result object shares: ``to_json()`` from its ``to_dict()``.

The command line prints ``to_dict()`` through the same function with ``--json``, so a result
obtained in Python serialises to exactly what the command prints.
"""

from __future__ import annotations

from typing import Any

from cadcog.core.fileio import dumps_json


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

    def to_dict(self) -> dict[str, Any]:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def to_json(self) -> str:
        """The JSON text ``--json`` prints for this result (two-space indent, no final newline)."""
        return dumps_json(self.to_dict()).rstrip("\n")
