"""``cadcog.api.planning``: plan is what the command prints."""

from __future__ import annotations

import json

import cadcog
from tests.api.commandline import cli_json


def test_plan_for_both_is_what_the_command_prints(tmp_path, capsys) -> None:
    """``cadcog.plan(goal="both")`` is ``plan --for both --json``: the CoG's set and the hangs
    grown for the inertia, or why none."""
    setup = "parts/cubesat_3u_setup.toml"
    theirs = cli_json(capsys, "plan", setup, "--for", "both", "--trials", "300")
    mine = cadcog.plan(setup, trials=300, goal="both")
    assert mine.to_json() == theirs
    assert mine.inertia is not None and json.loads(theirs)["goal"] == "both"
