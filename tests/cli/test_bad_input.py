"""The catalogue of bad inputs: every subcommand, as a careless or hostile user would call it.

Each case runs ``main(argv)`` in-process in a fresh working folder holding the case's input
files, and asserts: exit status 2; one line on stderr, ``cadcog: error: ...``, that matches the
case's pattern (naming the file and line, the key or the option); no traceback; no file created,
changed or removed anywhere in the folder (inputs unchanged, nothing partial left behind); and
the shipped example files unchanged.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

from cadcog.cli import main
from tests.cli.catalogue import audit_cases, cad_cases, rig_cases
from tests.cli.catalogue.files import PARTS

CASES = rig_cases.CASES + cad_cases.CASES + audit_cases.CASES


def _snapshot(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        if p.is_file()
        else "dir"
        for p in sorted(root.rglob("*"))
    }


SHIPPED = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in PARTS.glob("*.*")}


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(case, tmp_path, monkeypatch, capsys):
    import re

    for name, content in case.files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if callable(content):
            content(path)
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8", newline="")
    before = _snapshot(tmp_path)
    monkeypatch.chdir(tmp_path)
    status = main(case.argv)
    err = capsys.readouterr().err
    assert status == 2, (status, err)
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if not line.startswith("cadcog: warning")]
    assert len(lines) == 1 and lines[0].startswith("cadcog: error: "), err
    assert re.search(case.message, lines[0]), lines[0]
    assert _snapshot(tmp_path) == before  # nothing new, nothing changed, nothing left behind
    assert {
        p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in PARTS.glob("*.*")
    } == SHIPPED


def test_the_catalogue_covers_every_subcommand():
    from cadcog.cli._main import _subparsers, build_parser

    covered = {c.argv[0] for c in CASES if c.argv}
    assert set(_subparsers(build_parser())) <= covered
    assert len(CASES) >= 60
