"""Helpers for tests that need modified rig files: the paper rig as a dict, and a TOML writer.

The writer covers exactly what rig files use (scalars, arrays of scalars, tables and arrays of
tables nested under tables) so tests can change one key and write the file back.
"""

from __future__ import annotations

import copy
import json
import tomllib
from pathlib import Path
from typing import Any

from cadcog.rigfile import default_rig_path


def paper_rig_dict() -> dict[str, Any]:
    with default_rig_path().open("rb") as fh:
        return copy.deepcopy(tomllib.load(fh))


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(type(v))


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _emit(lines: list[str], table: dict[str, Any], prefix: str) -> None:
    for k, v in table.items():
        if not isinstance(v, dict) and not _is_table_array(v):
            lines.append(f"{k} = {_value(v)}")
    for k, v in table.items():
        name = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            lines.append(f"\n[{name}]")
            _emit(lines, v, name)
        elif _is_table_array(v):
            for item in v:
                lines.append(f"\n[[{name}]]")
                _emit(lines, item, name)


def to_toml(data: dict[str, Any]) -> str:
    lines: list[str] = []
    _emit(lines, data, "")
    return "\n".join(lines) + "\n"


def write_rig(path: Path, data: dict[str, Any]) -> Path:
    path.write_text(to_toml(data), encoding="utf-8")
    return path
