"""The command a test compares an API function with: its parser, its ``--json`` output."""

from __future__ import annotations

import argparse

from cadcog.cli import main
from cadcog.cli._main import build_parser


def subparser(name: str) -> argparse.ArgumentParser:
    """The parser of command ``name``."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[name]


def cli_json(capsys, *argv: str) -> str:
    """What ``cadcog ARGV --json`` prints (it must exit 0)."""
    assert main([*argv, "--json"]) == 0
    return capsys.readouterr().out.rstrip("\n")
