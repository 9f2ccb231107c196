"""``cadcog.api``: what ``import cadcog`` gives, its defaults and compositions are the commands'."""

from __future__ import annotations

import inspect
import subprocess
import sys

import pytest

import cadcog
from cadcog import api
from cadcog.core.tolerances import DEFAULT_WEIGHING_SIGMA_KG
from tests.api.commandline import subparser


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
        "self_calibrate_wire": "self_calibrate_wire",
        "samples": "samples",
        "inclinometer_model": "inclinometer_model",
        "wire_model": "wire_model",
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
    "plan": {
        "trials": "trials",
        "max_set": "max_set",
        "seed": "seed",
        "goal": "goal",
        "max_inertia_set": "max_inertia_set",
    },
    "mass_properties": {
        "axes": "axes",
        "about": "about",
        "strict": "strict",
        "exclude": "exclude",
        "surface_area": "surface_area",
    },
    "estimate": {"self_calibrate_wire": "self_calibrate_wire", "mass_sigma_kg": "mass_sigma_kg"},
    "update": {"mass_sigma_kg": "mass_sigma_kg", "unmodelled_mass_kg": "unmodelled_mass_kg"},
    "campaign": {"seed": "seed", "samples": "samples", "noise_deg": "noise_deg"},
    "acquire": {
        "seed": "seed",
        "device": "device",
        "time_scale": "time_scale",
        "duration_s": "duration_s",
    },
    "acquire_log": {"log_format": "log_format", "average_s": "average_s", "swings": "swings"},
}


COMMAND = {"mass_properties": "massprops", "acquire_log": "acquire"}


#: Options whose command default is None only so that giving them alone can be refused
#: (``estimate --mass-sigma-kg`` without a weighing, ``update --unmodelled-mass-kg`` without a
#: region): the command then uses these, the API's defaults.
RESOLVED_DEFAULTS = {
    ("estimate", "mass_sigma_kg"): DEFAULT_WEIGHING_SIGMA_KG,
    ("update", "unmodelled_mass_kg"): 0.0,
}


@pytest.mark.parametrize("function", sorted(SAME_DEFAULTS))
def test_defaults_are_the_commands(function: str) -> None:
    signature = inspect.signature(getattr(api, function))
    parser = subparser(COMMAND.get(function, function))
    for keyword, dest in SAME_DEFAULTS[function].items():
        mine = signature.parameters[keyword].default
        theirs = parser.get_default(dest)
        if theirs is None and (function, dest) in RESOLVED_DEFAULTS:
            theirs = RESOLVED_DEFAULTS[function, dest]
        assert mine == theirs or (mine == () and theirs == []), (function, keyword, mine, theirs)


def test_validate_default_windows_are_the_commands() -> None:
    from cadcog.validation.verification import DEFAULT_WINDOWS_MM

    assert tuple(subparser("validate").get_default("windows")) == DEFAULT_WINDOWS_MM


@pytest.mark.parametrize(
    ("command", "composition", "steps"),
    [
        ("simulate", "simulate_rig", ("run_simulation", "SimulationSettings", "ErrorModel")),
        ("validate", "validate_readings", ("validate_campaign", "read_readings")),
        ("update", "update_from_files", ("update_for_setup", "inertia_observation")),
        ("campaign", "run_campaign", ("simulated_campaign", "campaign_text", "virtual_swings")),
        ("setup", "run_setup_init", ("read_step", "draft_materials", "project_grid")),
        ("acquire", "run_acquire", ("run_session", "compare_with_cad", "write_run_report")),
        ("plan", "run_plan", ("plan_test", "plan_inertia_for_setup")),
    ],
)
def test_the_command_and_the_api_call_one_composition(command, composition, steps) -> None:
    """Each command and its API function call the one function below them, and neither
    composes its steps itself (the API and the CLI cannot drift apart again)."""
    import ast
    from pathlib import Path

    package = Path(cadcog.__file__).parent
    cli = ast.parse((package / "cli" / f"{command}.py").read_text(encoding="utf-8"))
    name = {"setup": "setup_init"}.get(command, command)
    api_function = next(
        n
        for path in sorted((package / "api").glob("*.py"))
        for n in ast.parse(path.read_text(encoding="utf-8")).body
        if isinstance(n, ast.FunctionDef) and n.name == name
    )
    for node in (cli, api_function):
        names = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}
        assert composition in names
        assert not names & set(steps), names & set(steps)


def test_large_results_print_in_one_short_line(campaign_csv) -> None:
    """A notebook shows a result's repr: one line, shapes and lengths instead of contents."""
    est = cadcog.estimate(campaign_csv, cadcog.load_rig())
    text = repr(est)
    assert "\n" not in text and len(text) < 400, text
    assert text.startswith("CogEstimate(suspensions=<tuple of 6>, verticals=<array 6×3>")
    assert "n_normalized=0" in text


def test_short_field_texts() -> None:
    import numpy as np

    from cadcog.core.results import _short

    assert _short(np.zeros((4, 2))) == "<array 4×2>"
    assert _short(np.array([1.0, 2.0])) == "[1.0, 2.0]"
    assert _short(list(range(10))) == "<list of 10>"
    assert _short("x" * 100).endswith("...") and len(_short("x" * 100)) == 60


def test_a_setup_prints_in_one_short_line() -> None:
    """``load_setup``'s repr ran to 21 847 characters in a notebook (every body and candidate)."""
    text = repr(cadcog.load_setup("parts/cubesat_3u_setup.toml"))
    assert "\n" not in text and len(text) < 400, text
    assert text.startswith("Setup(name='cubesat_3u'") and "candidates=<tuple of 49>" in text
