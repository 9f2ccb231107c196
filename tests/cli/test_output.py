"""What a command says besides its result: one form for a warning, a file written and a JSON
result (``cadcog/cli/_output.py``), and no command that words them itself."""

from __future__ import annotations

import ast
import json
from pathlib import Path

import numpy as np

from cadcog.cli._output import print_json, warn, wrote

CLI = Path(__file__).resolve().parents[2] / "cadcog" / "cli"


def test_a_warning_and_a_file_written_are_one_line_each_on_stderr(capsys):
    warn("S3: the line passes 4.1 σ from the others")
    wrote(Path("out") / "index.html")
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.splitlines() == [
        "cadcog: warning: S3: the line passes 4.1 σ from the others",
        f"report: {Path('out') / 'index.html'}",
    ]


def test_a_json_result_is_one_object_newline_ended_as_to_json_says(capsys):
    from cadcog.mass.properties import box_properties

    result = box_properties((10.0, 20.0, 30.0), (1.0, 2.0, 3.0), mass_kg=np.float64(0.7))
    print_json(result.to_dict())
    out = capsys.readouterr().out
    assert out == result.to_json() + "\n" and out.count("\n{") == 0
    assert json.loads(out)["mass_kg"] == 0.7 and json.loads(out)["cog_mm"] == [1.0, 2.0, 3.0]


def _string_constants(tree: ast.AST) -> list[str]:
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            out.append(node.value)
        elif isinstance(node, ast.JoinedStr):  # an f-string's literal head
            first = node.values[0] if node.values else None
            if isinstance(first, ast.Constant) and isinstance(first.value, str):
                out.append(first.value)
    return out


def test_no_command_words_a_warning_or_a_written_file_itself():
    """Two commands once said ``warning: ...`` where the others said ``cadcog: warning: ...``
    (a script filtering the one missed the other): every command goes through ``_output``."""
    own = {}
    for path in sorted(CLI.glob("*.py")):
        if path.name == "_output.py":
            continue
        texts = _string_constants(ast.parse(path.read_text(encoding="utf-8")))
        bad = [t for t in texts if t.startswith(("cadcog: warning", "warning: ", "report: "))]
        if bad:
            own[path.name] = bad
    assert not own, own
