"""The independent generators in ``support/`` stay independent of cadcog.

A truth that imports the estimator's model can only agree with it: the modules that simulate
the physics must not import ``cadcog`` at all, not even inside a function.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SUPPORT = Path(__file__).resolve().parents[1] / "support"
INDEPENDENT = ("swing_truth", "rig_campaigns", "forward_model", "phone_logs", "phone_scenarios")


def _imported_roots(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    roots: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            roots.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            roots.add(node.module.split(".")[0])
    return roots


def _support_imports(path: Path) -> set[str]:
    """The ``support`` modules a file imports (``from support import x``, ``support.x``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module == "support":
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("support."):
            out.add(str(node.module).split(".")[1])
        elif isinstance(node, ast.Import):
            out.update(a.name.split(".")[1] for a in node.names if a.name.startswith("support."))
    return out


@pytest.mark.parametrize("name", INDEPENDENT)
def test_a_physics_generator_imports_no_cadcog(name):
    path = SUPPORT / f"{name}.py"
    assert "cadcog" not in _imported_roots(path), f"support/{name}.py imports cadcog"
    borrowed = _support_imports(path) - set(INDEPENDENT)
    assert not borrowed, f"support/{name}.py imports {sorted(borrowed)}, which use cadcog"


def test_the_check_sees_an_import_inside_a_function(tmp_path):
    f = tmp_path / "m.py"
    f.write_text("def f():\n    from cadcog.method import gls\n    return gls\n")
    assert "cadcog" in _imported_roots(f)


def test_the_benchmarks_import_no_test_module():
    """``benchmarks/`` imports its generators from ``support``, never from ``tests``."""
    bench = SUPPORT.parent / "benchmarks"
    offenders = [p.name for p in sorted(bench.glob("*.py")) if "tests" in _imported_roots(p)]
    assert offenders == []
