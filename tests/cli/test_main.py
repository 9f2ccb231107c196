"""The CLI, called in-process through ``main(argv)``."""

from __future__ import annotations

import pytest

from cadcog import __version__
from cadcog.cli import main


def test_version(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert capsys.readouterr().out.strip() == f"cadcog {__version__}"


def test_help_lists_the_subcommands(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    for command in (
        "parts",
        "estimate",
        "budget",
        "simulate",
        "campaign",
        "validate",
        "report",
        "massprops",
        "plan",
        "acquire",
    ):
        assert f"    {command}" in out, command


def test_no_command_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as info:
        main([])
    assert info.value.code == 2


def test_unwritable_output_is_an_error_not_a_traceback(tmp_path, capsys):
    target = tmp_path / "a_directory"
    target.mkdir()
    assert main(["campaign", "--out", str(target)]) == 2
    assert "cadcog: error:" in capsys.readouterr().err
    assert list(target.iterdir()) == []
