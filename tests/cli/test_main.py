"""The CLI, called in-process through ``main(argv)``."""

from __future__ import annotations

import os

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
        "cache",
    ):
        assert f"    {command}" in out, command


def test_no_command_is_a_usage_error(capsys):
    assert main([]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "required: COMMAND" in err and "cadcog --help" in err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["massprops"], "massprops: the following arguments are required: model"),
        (["estimate", "r.csv", "--no-such-option"], "unrecognized arguments: --no-such-option"),
        (["simulate", "--trials-per-pair"], "argument --trials-per-pair: expected one argument"),
        (["simulate", "--trials-per-pair", "many"], "invalid int value: 'many'"),
        (["massprops", "m.step", "--units", "furlong"], "invalid choice: 'furlong'"),
    ],
)
def test_usage_errors_are_one_line_naming_the_command(capsys, argv, message):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.startswith(f"cadcog: error: {argv[0]}: ") and message in err
    assert f"`cadcog {argv[0]} --help`" in err


def test_values_that_start_with_a_dash_are_values(tmp_path, capsys):
    """``--about -10,0,0`` and ``--points -x_…`` mean what they say, without ``=``."""
    from cadcog.cli._main import attach_dash_values, build_parser

    parser = build_parser()
    argv = ["massprops", "m.step", "--about", "-10,0,0", "--json", "--units", "mm"]
    assert attach_dash_values(parser, argv) == [
        "massprops",
        "m.step",
        "--about=-10,0,0",
        "--json",
        "--units",
        "mm",
    ]
    # An option after an option stays an option (a missing value is still an error).
    assert attach_dash_values(parser, ["massprops", "m.step", "--about", "--json"]) == [
        "massprops",
        "m.step",
        "--about",
        "--json",
    ]
    assert main(["massprops", "m.step", "--about", "--json"]) == 2
    assert "argument --about: expected one argument" in capsys.readouterr().err
    # After "--" nothing is touched.
    assert attach_dash_values(parser, ["massprops", "--", "-m.step"]) == [
        "massprops",
        "--",
        "-m.step",
    ]


def test_unwritable_output_is_an_error_not_a_traceback(tmp_path, capsys):
    target = tmp_path / "a_directory"
    target.mkdir()
    assert main(["campaign", "--out", str(target)]) == 2
    assert "cadcog: error:" in capsys.readouterr().err
    assert list(target.iterdir()) == []


@pytest.mark.parametrize(
    ("signum", "status", "word"), [(15, 143, "terminated"), (2, 130, "interrupted")]
)
def test_a_signal_that_surfaces_as_another_error_still_stops_cleanly(
    monkeypatch, capsys, signum, status, word
):
    """A signal while an extension module initialises comes out as ImportError
    ("initialization failed"), its cause the handler's exception: still one line, 143 or 130."""
    import os
    import time

    from cadcog.cli import budget

    def importing(args):
        try:
            os.kill(os.getpid(), signum)
            time.sleep(5)
        except BaseException as exc:
            raise ImportError("initialization failed") from exc
        return 0

    monkeypatch.setattr(budget, "run", importing)
    assert main(["budget"]) == status
    err = capsys.readouterr().err
    assert err == f"cadcog: {word}; nothing was written\n"


def test_an_ordinary_bug_is_not_mistaken_for_a_signal(monkeypatch):
    from cadcog.cli import budget

    def broken(args):
        raise ImportError("a real bug")

    monkeypatch.setattr(budget, "run", broken)
    with pytest.raises(ImportError, match="a real bug"):
        main(["budget"])


def test_the_commands_load_without_scipy_or_cad() -> None:
    """`cadcog --version` and `--help` stay fast: scipy.stats (a second) and build123d (three)
    are imported only by the functions that need them."""
    import subprocess
    import sys

    code = (
        "import sys, cadcog.cli._main\n"
        "heavy = [m for m in ('scipy', 'build123d', 'OCP', 'matplotlib') if m in sys.modules]\n"
        "assert not heavy, heavy\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_console_command_runs_blas_single_threaded_unless_the_user_says(monkeypatch):
    import cadcog.cli as cli

    monkeypatch.setattr(cli, "main", lambda argv=None: 0)
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "4")
    for name in ("MKL_NUM_THREADS", "OMP_NUM_THREADS"):
        monkeypatch.delenv(name, raising=False)
    assert cli.console_main() == 0
    assert os.environ["OPENBLAS_NUM_THREADS"] == "4"  # the user's value wins
    assert os.environ["MKL_NUM_THREADS"] == os.environ["OMP_NUM_THREADS"] == "1"
