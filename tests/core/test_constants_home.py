"""Figures with one home: a default that a literal repeats in several signatures drifts (the
weighing's 1 g default was written seven times). Every function default of these arguments
must name its constant, not repeat its value."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "cadcog"

#: Argument name -> the constant its default must be.
HOMES = {"mass_sigma_kg": "DEFAULT_WEIGHING_SIGMA_KG"}


def _defaults(tree: ast.AST):
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            a = node.args
            positional = a.posonlyargs + a.args
            for arg, default in zip(
                positional[len(positional) - len(a.defaults) :], a.defaults, strict=True
            ):
                yield node, arg.arg, default
            for arg, default in zip(a.kwonlyargs, a.kw_defaults, strict=True):
                if default is not None:
                    yield node, arg.arg, default


def test_defaults_name_their_constant():
    stray = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for fn, name, default in _defaults(tree):
            home = HOMES.get(name)
            if home is not None and isinstance(default, ast.Constant) and default.value is not None:
                where = f"{path.relative_to(PACKAGE.parent)}:{fn.lineno}"
                stray.append(f"{where} {fn.name}({name}={default.value!r})")
    assert not stray, "use the named constant:\n" + "\n".join(stray)


def test_the_check_finds_a_literal_default():
    tree = ast.parse("def f(x, *, mass_sigma_kg=0.001):\n    pass\n")
    found = [(n, d.value) for _, n, d in _defaults(tree) if isinstance(d, ast.Constant)]
    assert found == [("mass_sigma_kg", 0.001)]
