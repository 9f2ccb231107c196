"""The Python API: what ``import cadcog`` gives, and that it is what the commands compute."""

from __future__ import annotations

import argparse
import inspect
import json
import subprocess
import sys

import pytest

import cadcog
from cadcog import api
from cadcog.cli import main
from cadcog.cli._main import build_parser
from cadcog.validation.campaign import virtual_campaign, write_campaign


def _subparser(name: str) -> argparse.ArgumentParser:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[name]


def _cli_json(capsys, *argv: str) -> str:
    assert main([*argv, "--json"]) == 0
    return capsys.readouterr().out.rstrip("\n")


def test_import_is_light_and_lazy() -> None:
    """``import cadcog`` loads neither numpy nor build123d; the names load on first use."""
    code = (
        "import sys, cadcog\n"
        "heavy = [m for m in ('numpy', 'scipy', 'build123d', 'OCP') if m in sys.modules]\n"
        "assert not heavy, heavy\n"
        "assert callable(cadcog.simulate) and 'cadcog.api' in sys.modules\n"
        "assert 'build123d' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_api_names_are_listed_and_unknown_names_fail() -> None:
    assert set(cadcog.__all__) - {"__version__"} == set(api.__all__)
    assert set(api.__all__) <= set(dir(cadcog))
    for name in api.__all__:
        assert getattr(cadcog, name) is getattr(api, name)
        assert getattr(api, name).__doc__, name
    with pytest.raises(AttributeError, match="no attribute 'simulation'"):
        cadcog.simulation  # noqa: B018


# API keyword → the command's option dest, where the two differ.
SAME_DEFAULTS = {
    "simulate": {
        "points": "points",
        "trials": "trials",
        "seed": "seed",
        "group_size": "group_size",
        "min_angle_deg": "min_angle_deg",
        "wire_correction": "wire_correction",
        "paper": "paper",
        "workers": "workers",
    },
    "validate": {"campaigns": "campaigns", "seed": "seed", "level": "level"},
    "plan": {"trials": "trials", "max_set": "max_set", "seed": "seed"},
    "mass_properties": {"axes": "axes", "about": "about", "strict": "strict", "exclude": "exclude"},
    "estimate": {"self_calibrate_wire": "self_calibrate_wire"},
}
COMMAND = {"mass_properties": "massprops"}


@pytest.mark.parametrize("function", sorted(SAME_DEFAULTS))
def test_defaults_are_the_commands(function: str) -> None:
    signature = inspect.signature(getattr(api, function))
    parser = _subparser(COMMAND.get(function, function))
    for keyword, dest in SAME_DEFAULTS[function].items():
        mine = signature.parameters[keyword].default
        theirs = parser.get_default(dest)
        assert mine == theirs or (mine == () and theirs == []), (function, keyword, mine, theirs)


def test_validate_default_windows_are_the_commands() -> None:
    from cadcog.validation.verification import DEFAULT_WINDOWS_MM

    assert tuple(_subparser("validate").get_default("windows")) == DEFAULT_WINDOWS_MM


@pytest.fixture(scope="module")
def campaign_csv(tmp_path_factory):
    rig = cadcog.load_rig()
    path = tmp_path_factory.mktemp("api") / "campaign.csv"
    write_campaign(path, virtual_campaign(rig, seed=7))
    return path


def test_estimate_is_what_the_command_prints(campaign_csv, capsys) -> None:
    rig = cadcog.load_rig()
    mine = cadcog.estimate(campaign_csv, rig)
    assert mine.to_json() == _cli_json(
        capsys, "estimate", str(campaign_csv), "--rig", str(rig.source)
    )
    assert json.loads(mine.to_json())["cog_mm"] == pytest.approx(mine.cog_mm.tolist(), rel=1e-9)


def test_estimate_without_a_rig_is_the_command_without_one(campaign_csv, capsys) -> None:
    mine = cadcog.estimate(campaign_csv)
    assert mine.compensation is None
    assert mine.to_json() == _cli_json(capsys, "estimate", str(campaign_csv))


def test_validate_is_what_the_command_prints(campaign_csv, capsys) -> None:
    mine = cadcog.validate(campaign_csv, campaigns=40, seed=3)
    assert mine.to_json() == _cli_json(
        capsys, "validate", str(campaign_csv), "--campaigns", "40", "--seed", "3"
    )


def test_simulate_is_what_the_command_prints(capsys) -> None:
    mine = cadcog.simulate(points=0, trials=300, seed=5)
    assert mine.to_json() == _cli_json(
        capsys, "simulate", "--points", "0", "--trials-per-pair", "300", "--seed", "5"
    )
    assert mine.fits.n == 300 * len(mine.groups)


def test_a_bad_file_raises_the_error_the_command_prints(tmp_path) -> None:
    from cadcog.core.errors import CadcogError

    bad = tmp_path / "r.csv"
    bad.write_text("point_id,x_mm\n1,2\n")
    with pytest.raises(CadcogError, match=r"r\.csv"):
        cadcog.estimate(bad)
