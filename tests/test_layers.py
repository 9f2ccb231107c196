"""The package's layers: lower sub-packages never import higher ones, and no import circles.

Each module's imports are read with :mod:`ast` (function-level imports included), so a lazy
import that climbs a layer fails here just as a top-level one does.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "cadcog"

#: Bottom to top; a module may import its own sub-package and any lower one. Sub-packages of
#: the same rank are siblings that must not import each other. Keep in step with the drawing
#: in docs/development.md (``test_development_doc_draws_these_layers`` checks it).
LAYERS: dict[str, int] = {
    "core": 0,
    "mass": 1,
    "rig": 2,
    "cad": 3,
    "method": 3,
    "uncertainty": 4,
    "validation": 5,
    "spacecraft": 6,
    "reports": 7,
    "dynamics": 7,
    "bench": 8,
    "runs": 9,
    "cli": 10,
    "api": 11,
}


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path) -> set[str]:
    """Every ``cadcog`` module the file imports (``from cadcog.x import y``: y, if a module)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("cadcog"))
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("cadcog"):
            for a in node.names:
                sub = f"{node.module}.{a.name}"
                found.add(sub if sub in MODULES else node.module)
    return found


FILES = sorted(PACKAGE.rglob("*.py"))
MODULES = {_module_name(p): p for p in FILES}


def _layer(module: str) -> str | None:
    parts = module.split(".")
    if len(parts) == 1:
        return "api" if module == "cadcog" else None
    top = parts[1]
    if top in ("__main__", "api"):
        return "api"
    return top


def test_every_module_sits_in_a_named_layer() -> None:
    loose = [m for m in MODULES if _layer(m) is not None and _layer(m) not in LAYERS]
    flat = [
        m
        for m in MODULES
        if m.count(".") == 1
        and m.split(".")[1] not in LAYERS
        and m.split(".")[1] not in ("__main__", "api")
        and MODULES[m].name != "__init__.py"
    ]
    assert not loose and not flat, f"modules outside the layers: {loose + flat}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_module_imports_a_higher_layer(module: str) -> None:
    here = _layer(module)
    if here is None:
        return
    upward = []
    for target in sorted(_imports(MODULES[module])):
        there = _layer(target)
        if there is None or there == here:
            continue
        if LAYERS[there] >= LAYERS[here]:
            upward.append(f"{target} ({there}, rank {LAYERS[there]})")
    assert not upward, f"{module} ({here}, rank {LAYERS[here]}) imports {upward}"


def test_no_import_circles() -> None:
    graph = {m: {t for t in _imports(p) if t in MODULES and t != m} for m, p in MODULES.items()}
    # a package's __init__ is imported by its modules implicitly; only explicit edges count
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m: str) -> list[str] | None:
        state[m] = 1
        stack.append(m)
        for t in sorted(graph[m]):
            if state.get(t) == 1:
                return [*stack[stack.index(t) :], t]
            if t not in state and (cycle := visit(t)):
                return cycle
        stack.pop()
        state[m] = 2
        return None

    for m in sorted(graph):
        if m not in state and (cycle := visit(m)):
            pytest.fail("import circle: " + " -> ".join(cycle))


def test_the_layer_test_sees_an_upward_import(tmp_path: Path) -> None:
    """The checker itself: a lower module importing a higher one is caught."""
    f = tmp_path / "x.py"
    f.write_text("def f():\n    from cadcog.reports import html\n")
    assert "cadcog.reports.html" in _imports(f)


def test_development_doc_draws_these_layers() -> None:
    text = (PACKAGE.parent / "docs" / "development.md").read_text(encoding="utf-8")
    missing = [name for name in LAYERS if name != "api" and f"cadcog/{name}/" not in text]
    assert not missing, f"docs/development.md does not show {missing}"
