"""``docs/tutorial.md`` runs as written: each Python block, in order, in one namespace, from the
repository's root, must print exactly the text block that follows it."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "tutorial.md"
BLOCK = re.compile(r"```(python|text)\n(.*?)```", re.S)


def cells(text: str) -> list[tuple[str, str | None]]:
    """(code, expected output or None) for every Python block of the page."""
    blocks = BLOCK.findall(text)
    out: list[tuple[str, str | None]] = []
    for i, (kind, body) in enumerate(blocks):
        if kind != "python":
            continue
        follows = blocks[i + 1] if i + 1 < len(blocks) else None
        out.append((body, follows[1] if follows and follows[0] == "text" else None))
    return out


def test_the_page_has_cells_with_outputs() -> None:
    found = cells(PAGE.read_text(encoding="utf-8"))
    assert len(found) >= 6 and all(expected is not None for _, expected in found)


@pytest.mark.slow
def test_tutorial_runs_and_prints_what_it_shows(monkeypatch) -> None:
    monkeypatch.chdir(ROOT)
    namespace: dict[str, object] = {"__name__": "tutorial"}
    for n, (code, expected) in enumerate(cells(PAGE.read_text(encoding="utf-8")), start=1):
        buffer = io.StringIO()
        with contextlib.redirect_stdout(buffer):
            exec(compile(code, f"{PAGE.name} cell {n}", "exec"), namespace)
        assert buffer.getvalue() == expected, f"cell {n}:\n{code}"
