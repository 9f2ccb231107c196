"""A committed mass-properties baseline, and what changed since.

``cadcog check --update-baseline`` writes the model's bodies (path, mass, CoG) and totals to a
JSON file that the team commits. Later checks compare the model with it: a body added or
removed, or whose mass or CoG moved beyond the tolerances, is a change, described for people
("payload_and_bus/battery_pack +40.0 g, CoG +1.2 mm in z"). The file is data: it is parsed as
JSON and validated, never evaluated.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from cadcog.core.errors import ParameterFileError
from cadcog.core.numformat import signed
from cadcog.core.results import JsonResult

if TYPE_CHECKING:
    from cadcog.cad.stepmass import ModelMassProperties

FORMAT = "cadcog-baseline/1"


@dataclass(frozen=True)
class Tolerances:
    """Changes at or below these are not changes: 1 g and 0.1 mm by default."""

    mass_kg: float = 0.001
    cog_mm: float = 0.1


@dataclass(frozen=True)
class Change:
    """A body (or the total) that differs from the baseline."""

    path: str
    kind: str  # "added", "removed", "changed"
    mass_before_kg: float | None
    mass_after_kg: float | None
    cog_before_mm: tuple[float, float, float] | None
    cog_after_mm: tuple[float, float, float] | None
    cog_tolerance_mm: float

    def describe(self) -> str:
        """e.g. ``sat/battery +40.0 g, CoG +1.2 mm in z``."""
        if self.kind == "added":
            return f"{self.path} added ({(self.mass_after_kg or 0) * 1e3:.1f} g)"
        if self.kind == "removed":
            return f"{self.path} removed (was {(self.mass_before_kg or 0) * 1e3:.1f} g)"
        parts = []
        dm = (self.mass_after_kg or 0.0) - (self.mass_before_kg or 0.0)
        if dm:
            parts.append(f"{signed(dm * 1e3, 1)} g")
        if self.cog_before_mm is not None and self.cog_after_mm is not None:
            d = np.subtract(self.cog_after_mm, self.cog_before_mm)
            moved = [
                f"{signed(d[k], 2)} mm in {'xyz'[k]}"
                for k in range(3)
                if abs(d[k]) > self.cog_tolerance_mm / math.sqrt(3)
            ]
            if moved:
                parts.append("CoG " + ", ".join(moved))
        return f"{self.path} " + ", ".join(parts)


@dataclass(frozen=True)
class BaselineDiff(JsonResult):
    source: Path
    changes: tuple[Change, ...]

    def describe(self, limit: int = 10) -> list[str]:
        lines = [c.describe() for c in self.changes[:limit]]
        if len(self.changes) > limit:
            lines.append(f"... and {len(self.changes) - limit} more")
        return lines

    def to_dict(self) -> dict[str, Any]:
        return {"source": str(self.source), "changes": self.describe(limit=10_000)}


def baseline_dict(result: ModelMassProperties) -> dict[str, Any]:
    """The baseline of a model: totals, and every body's mass and CoG by path."""
    total = result.total
    return {
        "format": FORMAT,
        "mass_kg": total.mass_kg,
        "cog_mm": total.cog_mm.tolist(),
        "bodies": {
            b.path: {"mass_kg": b.properties.mass_kg, "cog_mm": b.properties.cog_mm.tolist()}
            for b in result.bodies
        },
    }


def _entry(path: Path, key: str, value: Any) -> tuple[float, tuple[float, float, float]]:
    if not isinstance(value, dict) or set(value) != {"mass_kg", "cog_mm"}:
        raise ParameterFileError(path, key, "expected an object with mass_kg and cog_mm")
    mass, cog = value["mass_kg"], value["cog_mm"]
    ok_mass = isinstance(mass, (int, float)) and not isinstance(mass, bool) and math.isfinite(mass)
    ok_cog = (
        isinstance(cog, list)
        and len(cog) == 3
        and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in cog)
        and all(math.isfinite(c) for c in cog)
    )
    if not (ok_mass and ok_cog):
        raise ParameterFileError(path, key, "expected a finite mass_kg and three finite cog_mm")
    return float(mass), (float(cog[0]), float(cog[1]), float(cog[2]))


def load_baseline(path: str | Path) -> dict[str, tuple[float, tuple[float, float, float]]]:
    """A baseline file's entries: ``""`` (the total) and every body path → (mass, CoG).

    Raises
    ------
    ParameterFileError
        Naming the file and the key: not found, not JSON, wrong format or values.
    """
    p = Path(path)
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ParameterFileError(
            p, "", "file not found; write it with cadcog check --update-baseline"
        ) from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ParameterFileError(p, "", f"not a baseline JSON file ({exc})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ParameterFileError(p, "format", f"expected {FORMAT!r}")
    bodies = data.get("bodies")
    if not isinstance(bodies, dict):
        raise ParameterFileError(p, "bodies", "expected an object of body paths")
    entries = {
        "": _entry(p, "(total)", {"mass_kg": data.get("mass_kg"), "cog_mm": data.get("cog_mm")})
    }
    for key, value in bodies.items():
        entries[key] = _entry(p, f"bodies.{key}", value)
    return entries


def diff(
    baseline: dict[str, tuple[float, tuple[float, float, float]]],
    result: ModelMassProperties,
    tolerances: Tolerances,
    source: Path,
) -> BaselineDiff:
    """Bodies added, removed or changed beyond ``tolerances`` (the total first), by size."""
    now: dict[str, tuple[float, tuple[float, float, float]]] = {
        b.path: (b.properties.mass_kg, tuple(b.properties.cog_mm.tolist())) for b in result.bodies
    }
    t = result.total
    now[""] = (t.mass_kg, tuple(t.cog_mm.tolist()))
    changes: list[tuple[float, Change]] = []
    for path in sorted(set(baseline) | set(now)):
        label = path or "total"
        before, after = baseline.get(path), now.get(path)
        if before is None and after is not None:
            changes.append((after[0], Change(label, "added", None, after[0], None, after[1], 0)))
        elif after is None and before is not None:
            changes.append(
                (before[0], Change(label, "removed", before[0], None, before[1], None, 0))
            )
        elif before is not None and after is not None:
            dm = abs(after[0] - before[0])
            dc = float(np.linalg.norm(np.subtract(after[1], before[1])))
            if dm > tolerances.mass_kg or dc > tolerances.cog_mm:
                changes.append(
                    (
                        dm + (1.0 if path == "" else 0.0),  # the total first
                        Change(
                            label,
                            "changed",
                            before[0],
                            after[0],
                            before[1],
                            after[1],
                            tolerances.cog_mm,
                        ),
                    )
                )
    ordered: Sequence[Change] = [c for _, c in sorted(changes, key=lambda x: -x[0])]
    return BaselineDiff(source, tuple(ordered))
