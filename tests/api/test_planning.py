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


def test_balance_takes_a_setup_as_plan_estimate_and_update_do(tmp_path) -> None:
    """A loaded ``Setup`` in ``setup=`` (a new user passed one, as to ``plan``) balances as its
    file does; it was refused as 'expected a file path'."""
    setup = "parts/cubesat_3u_setup.toml"
    ballast = tmp_path / "b.toml"
    ballast.write_text('[[points]]\nid = "B1"\nposition_mm = [0.0, 0.0, -170.25]\n')
    by_file = cadcog.balance(ballast, setup=setup, cog_limits_mm=[20.0, 20.0, 10.0])
    by_object = cadcog.balance(
        ballast, setup=cadcog.load_setup(setup), cog_limits_mm=[20.0, 20.0, 10.0]
    )
    assert by_object.to_json() == by_file.to_json()
    assert by_file.feasible and by_file.total_ballast_kg > 0  # the CoG 12 mm up: ballast below


def test_balance_given_the_commands_order_names_the_step_as_the_ballast(tmp_path) -> None:
    """``balance(model, materials, ballast)``, the command line's order: the STEP was read as
    the ballast file ('invalid TOML'; new-user trial). Refused first, naming the argument."""
    import pytest

    from cadcog.core.errors import CadcogError

    step = tmp_path / "sat.STEP"
    step.write_text("ISO-10303-21;\n", encoding="utf-8")
    with pytest.raises(CadcogError, match=r"^balance\(ballast=.*\): a STEP model; the ballast"):
        cadcog.balance(step, tmp_path / "m.toml", tmp_path / "b.toml")
