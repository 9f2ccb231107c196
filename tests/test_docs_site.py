"""The documentation site builds in strict mode, and what it documents is documented.

``mkdocs build --strict`` fails on a broken link, a missing page or a stale ``:::`` reference
(mkdocstrings cannot find it); the docstring checks below fail on a public function or class of
a documented module without one (mkdocstrings would render it silently empty).
"""

from __future__ import annotations

import importlib
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DIRECTIVE = re.compile(r"^::: ([\w.]+)", re.M)


def _documented() -> list[str]:
    return DIRECTIVE.findall((ROOT / "docs" / "api.md").read_text(encoding="utf-8"))


def _resolve(dotted: str) -> object:
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj: object = importlib.import_module(".".join(parts[:i]))
        except ModuleNotFoundError:
            continue
        for attr in parts[i:]:
            obj = getattr(obj, attr)
        return obj
    raise ImportError(dotted)


def _undocumented(obj: object, name: str) -> list[str]:
    doc = inspect.getdoc(obj) or ""
    generated = inspect.isclass(obj) and doc.startswith(f"{obj.__name__}(")  # a dataclass's
    missing = [] if doc and not generated else [name]
    if inspect.ismodule(obj):
        for member, value in vars(obj).items():
            if member.startswith("_") or getattr(value, "__module__", None) != obj.__name__:
                continue
            if inspect.isfunction(value) or inspect.isclass(value):
                missing += _undocumented(value, f"{name}.{member}")
    elif inspect.isclass(obj):
        for member, value in vars(obj).items():
            if member.startswith("_") or member == "to_dict":
                continue
            func = value.fget if isinstance(value, property) else value
            if inspect.isfunction(func) and not func.__doc__:
                missing.append(f"{name}.{member}")
    return missing


def test_api_page_references_resolve_and_are_documented() -> None:
    names = _documented()
    assert "cadcog.api" in names
    missing = [m for n in names for m in _undocumented(_resolve(n), n)]
    assert not missing, f"public names without a docstring: {missing}"


COMBINED = re.compile(r"^\s*\w+, \w+[\w, ]* : ", re.M)


def test_documented_parameters_are_one_per_entry() -> None:
    """``a, b : float`` renders as two rows with one text and one default (the first's)."""
    found = []
    for name in _documented():
        obj = _resolve(name)
        members = (
            [obj]
            + [
                v
                for k, v in vars(obj).items()
                if not k.startswith("_")
                and (inspect.isfunction(v) or inspect.isclass(v))
                and getattr(v, "__module__", None) == getattr(obj, "__name__", None)
            ]
            if inspect.ismodule(obj)
            else [obj]
        )
        found += [
            f"{name}: {m.group(0).strip()}"
            for o in members
            for m in COMBINED.finditer(inspect.getdoc(o) or "")
        ]
    assert not found, found


def test_the_checker_sees_a_missing_docstring() -> None:
    class Result:
        """Documented."""

        def value(self) -> int:
            return 1

    assert _undocumented(Result, "Result") == ["Result.value"]


@pytest.mark.slow
def test_site_builds_in_strict_mode(tmp_path: Path) -> None:
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "PYTHONPATH": str(ROOT)}
    result = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=env,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    cli = (tmp_path / "site" / "cli.html").read_text(encoding="utf-8")
    assert "cadcog massprops" in cli and "--resolve-overlaps" in cli  # generated from the parser
    api = (tmp_path / "site" / "api.html").read_text(encoding="utf-8")
    assert "mass_properties" in api and "CheckResult" in api
