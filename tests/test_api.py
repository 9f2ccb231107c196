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
from cadcog.core.errors import CadcogError
from cadcog.core.tolerances import DEFAULT_WEIGHING_SIGMA_KG
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
    parser = _subparser(COMMAND.get(function, function))
    for keyword, dest in SAME_DEFAULTS[function].items():
        mine = signature.parameters[keyword].default
        theirs = parser.get_default(dest)
        if theirs is None and (function, dest) in RESOLVED_DEFAULTS:
            theirs = RESOLVED_DEFAULTS[function, dest]
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


def test_estimate_refuses_a_hang_naming_the_readings_file_as_the_command(tmp_path) -> None:
    """A point inside the body (no face, no bolt axis): the API's error names the readings
    file and line, as the command's does (it named the line only before runs/estimate.py)."""
    from support.rigtools import ideal_rows, write_csv

    rig = cadcog.load_rig()
    rows = ideal_rows(rig)
    rows.append("S9,100,30,30,10,5,true")
    csv = write_csv(tmp_path / "r.csv", rows)
    with pytest.raises(CadcogError, match=r"r\.csv: line 8: suspension S9 .* inside the bounding"):
        cadcog.estimate(csv, rig)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"weighed_mass_kg": [9.2]}, r"weighed_mass_kg=\[9\.2\]\): expected one number"),
        ({"weighed_mass_kg": (9.2, 1)}, r"expected one number"),
        ({"wire_correction": "no"}, r"wire_correction='no'\): expected True or False, got str"),
        ({"self_calibrate_wire": None}, r"expected True or False, got None\b"),
        ({"mass_sigma_kg": 0.5}, r"mass_sigma_kg=0\.5\): goes with weighed_mass_kg"),
        ({"weighed_mass_kg": 0.1}, r"campaign\.csv: the object CoG .* is outside the object"),
    ],
)
def test_estimate_refuses_what_the_command_refuses(campaign_csv, kwargs, message) -> None:
    """Round 4 of the reliability audit: a list where one number goes, a string or None where
    a yes/no goes ('no' is true to Python), a weighing's σ without a weighing, a weighed mass
    that puts the CoG outside the object: a CadcogError naming the argument (or the file)."""
    with pytest.raises(CadcogError, match=message):
        cadcog.estimate(campaign_csv, cadcog.load_rig(), **kwargs)


def test_update_is_what_the_command_prints(tmp_path, capsys) -> None:
    setup = "parts/cubesat_3u_setup.toml"
    csv = tmp_path / "r.csv"
    points = "--points=+x_-30_-30,-x_30_-30,+y_30_-30,-y_-30_-30"
    assert main(["campaign", "--setup", setup, points, "--out", str(csv)]) == 0
    capsys.readouterr()
    mine = cadcog.update(csv, setup, 2.6, unmodelled_region_mm=(-45, -45, -165, 45, 45, -140),
                         unmodelled_sigma_kg=0.1)  # fmt: skip
    theirs = _cli_json(
        capsys, "update", str(csv), "--setup", setup, "--weighed-mass-kg", "2.6",
        "--unmodelled-region-mm=-45,-45,-165,45,45,-140", "--unmodelled-sigma-kg", "0.1",
    )  # fmt: skip
    assert mine.to_json() == theirs
    assert mine.to_dict()["verdict"]["differs"]  # 17 g over the CAD, weighed to 1 g


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


def test_validate_options_are_the_command_s(campaign_csv, capsys) -> None:
    """Another rig file, windows and level: the same object as the command's JSON, and the
    options reached the result (not only the defaults agree)."""
    rig = cadcog.load_rig()
    mine = cadcog.validate(
        campaign_csv, rig.source, windows_mm=[1.0, 2.5], campaigns=30, seed=1, level=0.1
    )
    assert mine.to_json() == _cli_json(
        capsys, "validate", str(campaign_csv), "--rig", str(rig.source), "--windows", "1,2.5",
        "--campaigns", "30", "--seed", "1", "--level", "0.1",
    )  # fmt: skip
    assert [w.eps_mm for w in mine.validation.windows] == [1.0, 2.5]
    assert mine.verdict.level == 0.1 and mine.null.n_campaigns == 30


SIMULATE_CASES = [
    ({"points": 0, "paper": True}, "--points 0 --paper"),
    (
        {"points": 6, "group_size": 3, "min_angle_deg": 20.0, "wire_correction": False},
        "--points 6 --group-size 3 --min-angle-deg 20 --no-wire-correction",
    ),
]


@pytest.mark.parametrize(("keywords", "options"), SIMULATE_CASES)
def test_simulate_options_are_the_command_s(keywords, options, capsys) -> None:
    mine = cadcog.simulate(trials=60, seed=2, **keywords)
    argv = ["simulate", "--trials-per-pair", "60", "--seed", "2", *options.split()]
    assert mine.to_json() == _cli_json(capsys, *argv)
    paper = keywords.get("paper", False)
    assert mine.settings.weighted is not paper  # the options reached the settings
    assert mine.settings.wire_correction is (not paper and keywords.get("wire_correction", True))


def test_the_error_model_overrides_are_the_command_s(capsys) -> None:
    """The error model's overrides and the self-calibrated wire: the API gives the command's
    JSON, and the options change the model it reports."""
    mine = cadcog.simulate(
        points=5, trials=30, seed=4, group_size=3, self_calibrate_wire=True, samples=3,
        inclinometer_model="paper-averaged", wire_model="elastica",
    )  # fmt: skip
    assert mine.to_json() == _cli_json(
        capsys, "simulate", "--points", "5", "--trials-per-pair", "30", "--seed", "4",
        "--group-size", "3", "--self-calibrate-wire", "--samples", "3",
        "--inclinometer-model", "paper-averaged", "--wire-model", "elastica",
    )  # fmt: skip
    assert (mine.model.samples, mine.model.inclinometer_model, mine.model.wire_model) == (
        3, "paper-averaged", "elastica",
    )  # fmt: skip
    assert mine.settings.self_calibrate


def test_update_with_swings_is_what_the_command_prints(tmp_path, capsys) -> None:
    setup = "parts/cubesat_3u_setup.toml"
    csv, swings = tmp_path / "r.csv", tmp_path / "swings.csv"
    points = "--points=+x_-30_-30,-x_30_-30,+y_30_-30,-y_-30_-30"
    argv = ["campaign", "--setup", setup, points, "--out", str(csv), "--swings", str(swings)]
    assert main(argv) == 0
    capsys.readouterr()
    mine = cadcog.update(csv, setup, 2.6, mass_sigma_kg=0.002, swings=swings)
    theirs = _cli_json(
        capsys, "update", str(csv), "--setup", setup, "--weighed-mass-kg", "2.6",
        "--mass-sigma-kg", "0.002", "--swings", str(swings),
    )  # fmt: skip
    assert mine.to_json() == theirs
    assert mine.dof == 10  # the tensor's six entries observed with the mass and the CoG


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


def test_a_bad_file_raises_the_error_the_command_prints(tmp_path) -> None:
    from cadcog.core.errors import CadcogError

    bad = tmp_path / "r.csv"
    bad.write_text("point_id,x_mm\n1,2\n")
    with pytest.raises(CadcogError, match=r"r\.csv"):
        cadcog.estimate(bad)


BAD_CALLS = [
    (
        lambda: cadcog.simulate(trials="100"),
        r"simulate\(trials='100'\): expected a number, got str",
    ),
    (lambda: cadcog.simulate(trials=2.5), r"simulate\(trials=2\.5\): expected an integer"),
    (lambda: cadcog.simulate(trials=-5), r"simulate\(trials=-5\): expected at least 2"),
    (lambda: cadcog.simulate(points=-1), r"simulate\(points=-1\): expected at least 0"),
    (lambda: cadcog.simulate(points=1), r"simulate\(points=1\): give 0"),
    (lambda: cadcog.simulate(seed=-1), r"simulate\(seed=-1\): expected at least 0"),
    (
        lambda: cadcog.simulate(min_angle_deg=-5),
        r"simulate\(min_angle_deg=-5\): expected at least 0",
    ),
    (lambda: cadcog.simulate(workers=0), r"simulate\(workers=0\): expected at least 1"),
    (
        lambda: cadcog.simulate(samples=0),
        r"simulate\(samples=0\): expected at least 1 \(samples per hang\)",
    ),
    (
        lambda: cadcog.simulate(inclinometer_model="perfect"),
        r"simulate: inclinometer_model='perfect': expected one of hang-bias, paper-averaged",
    ),
    (
        lambda: cadcog.simulate(self_calibrate_wire=True),
        r"simulate\(self_calibrate_wire=True\): needs group_size 3 or more",
    ),
    (
        lambda: cadcog.simulate(rig=["a.toml"]),
        r"simulate\(rig=\['a\.toml'\]\): expected a file path",
    ),
    (lambda: cadcog.plan("s.toml", max_set=1), r"plan\(max_set=1\): expected at least 2"),
    (
        lambda: cadcog.validate("r.csv", campaigns=5),
        r"validate\(campaigns=5\): expected at least 20",
    ),
    (
        lambda: cadcog.validate("r.csv", windows_mm=1.0),
        r"validate\(windows_mm=1\.0\): expected a sequence",
    ),
    (lambda: cadcog.validate("r.csv", level=2.0), r"validate\(level=2\.0\): expected at most 0\.5"),
    (
        lambda: cadcog.mass_properties("m.step", density_kg_m3=2.7),
        r"mass_properties\(density_kg_m3=2\.7\): expected at least 10 .*g/cm³",
    ),
    (
        lambda: cadcog.mass_properties("m.step", density_kg_m3="2700"),
        r"mass_properties\(density_kg_m3='2700'\): expected a number",
    ),
    (
        lambda: cadcog.mass_properties("m.step", density_kg_m3=2700, total_mass_kg=-1.0),
        r"mass_properties\(total_mass_kg=-1\.0\): expected at least 1e-06",
    ),
    (
        lambda: cadcog.mass_properties("m.step", density_kg_m3=2700, cog_limits_mm=[1, 2]),
        r"mass_properties\(cog_limits_mm=\[1, 2\]\): expected three positive half-widths",
    ),
    (
        lambda: cadcog.mass_properties("m.step", "mat.toml", density_kg_m3=2700),
        r"give either materials or density_kg_m3",
    ),
    (
        lambda: cadcog.estimate("r.csv", cadcog.load_rig(), setup="s.toml"),
        r"estimate: give rig or setup, not both",
    ),
    (
        lambda: cadcog.estimate("r.csv", weighed_mass_kg=2.5),
        r"estimate: weighed_mass_kg needs a rig or a set-up",
    ),
    (
        lambda: cadcog.update("r.csv", "s.toml", 0.0),
        r"update\(weighed_mass_kg=0\.0\): expected a positive number",
    ),
    (
        lambda: cadcog.update("r.csv", "s.toml", 2.5, unmodelled_region_mm=[0, 0, 0, 1]),
        r"update\(unmodelled_region_mm=\[0, 0, 0, 1\]\): expected six numbers",
    ),
    (
        lambda: cadcog.update("r.csv", "s.toml", 2.5, unmodelled_sigma_kg=0.1),
        r"update\(unmodelled_region_mm=None\): an unmodelled mass σ needs a region",
    ),
    (
        lambda: cadcog.update("r.csv", "s.toml", None),
        r"update\(weighed_mass_kg=None\): expected a number, got None",
    ),
    (
        lambda: cadcog.update("r.csv", "s.toml", 2.5, mass_sigma_kg=None),
        r"update\(mass_sigma_kg=None\): expected a number, got None",
    ),
    (
        lambda: cadcog.update("r.csv", "s.toml", 2.5, unmodelled_mass_kg=None),
        r"update\(unmodelled_mass_kg=None\): expected a number, got None",
    ),
    (
        lambda: cadcog.inertia("s.csv", "r.csv", mass_sigma_kg=None),
        r"inertia\(mass_sigma_kg=None\): expected a number, got None",
    ),
    (
        lambda: cadcog.campaign("c.csv", samples="10"),
        r"campaign\(samples='10'\): expected a number, got str",
    ),
]


@pytest.mark.parametrize(("call", "message"), BAD_CALLS, ids=[m for _, m in BAD_CALLS])
def test_bad_arguments_raise_one_clear_error_naming_them(call, message, tmp_path, monkeypatch):
    """Before any file is read (none of these exist): the argument, its value and what was
    expected, as the command line says it of its options."""
    from cadcog.core.errors import CadcogError

    monkeypatch.chdir(tmp_path)
    with pytest.raises(CadcogError, match=message):
        call()
    assert list(tmp_path.iterdir()) == []


def test_numpy_numbers_are_numbers() -> None:
    import numpy as np

    report = cadcog.simulate(points=np.int64(0), trials=np.int64(50), seed=np.int64(1))
    assert report.fits.n == 50 * len(report.groups)


def test_a_setup_passed_as_the_rig_gets_a_hint(campaign_csv) -> None:
    from cadcog.core.errors import CadcogError

    fake = type("Setup", (), {})()  # the message goes by the type's name
    with pytest.raises(CadcogError, match=r"estimate\(rig=.*\): expected a file path .*setup="):
        cadcog.estimate(campaign_csv, fake)


@pytest.mark.slow
def test_one_exclusion_pattern_is_one_pattern(tmp_path) -> None:
    """exclude='plate' leaves out the plate, not bodies matching the letters p, l, a, t, e."""
    from support.stepfixtures import Assembly, Part, write_step

    top = Assembly("sat")
    top.add(Part("box", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    top.add(Part("plate", [((10.0, 10.0, 1.0), (0.0, 0.0, 20.0))]))
    step = tmp_path / "m.step"
    write_step(top, step)
    whole = cadcog.mass_properties(step, density_kg_m3=1000.0, workers=1)
    kept = cadcog.mass_properties(step, density_kg_m3=1000.0, exclude="plate", workers=1)
    assert whole.result.total.mass_kg == pytest.approx(1.1e-3, rel=1e-9)  # 1000 + 100 mm³
    assert kept.result.total.mass_kg == pytest.approx(1.0e-3, rel=1e-9)
    assert kept.result.total.cog_mm == pytest.approx([5.0, 5.0, 5.0], abs=1e-9)  # corner at 0
    areas = cadcog.mass_properties(step, density_kg_m3=1000.0, surface_area=True, workers=1)
    assert areas.budget.root.surface_area_mm2 == pytest.approx(600.0 + 240.0, rel=1e-9)


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


def test_every_entry_point_limits_blas_to_one_thread_unless_the_user_set_it(monkeypatch):
    """From Python as from the command: cadcog's small matrices on a many-thread BLAS pool
    made ``cadcog.update`` 9× slower than ``cadcog update``."""
    from threadpoolctl import threadpool_info, threadpool_limits

    from cadcog import api
    from cadcog.cli import BLAS_THREAD_VARIABLES

    assert all(hasattr(getattr(api, name), "__wrapped__") for name in api.__all__)
    probe = api._one_blas_thread(
        lambda: [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
    )
    for name in BLAS_THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    with threadpool_limits(limits=2, user_api="blas"):
        inside = probe()
        assert inside and set(inside) == {1}
        monkeypatch.setenv("OPENBLAS_NUM_THREADS", "2")  # the user's choice wins
        assert probe() == [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]


def test_campaign_is_what_the_command_writes(tmp_path, capsys) -> None:
    """The same readings and swings, byte for byte, and the command's --json."""
    setup = "parts/cubesat_3u_setup.toml"
    points = "+x_30_90,-x_-30_90,+y_-30_-30"
    theirs = _cli_json(
        capsys, "campaign", "--setup", setup, f"--points={points}", "--seed", "3",
        "--out", str(tmp_path / "a.csv"), "--swings", str(tmp_path / "a_swings.csv"),
    )  # fmt: skip
    mine = cadcog.campaign(
        tmp_path / "b.csv",
        setup=setup,
        points=points.split(","),
        seed=3,
        swings=tmp_path / "b_swings.csv",
    )
    assert mine.to_dict() | {"out": "", "swings": ""} == json.loads(theirs) | {
        "out": "",
        "swings": "",
    }
    for a, b in (("a.csv", "b.csv"), ("a_swings.csv", "b_swings.csv")):
        assert (tmp_path / a).read_bytes() == (tmp_path / b).read_bytes()


def test_a_campaign_that_cannot_write_its_swings_writes_nothing(tmp_path) -> None:
    """All outputs or none: the swings' folder is a file, so the readings are not left."""
    from cadcog.core.errors import CadcogError

    (tmp_path / "blocker").write_text("a file", encoding="utf-8")
    with pytest.raises(CadcogError):
        cadcog.campaign(tmp_path / "r.csv", swings=tmp_path / "blocker" / "s.csv")
    assert not (tmp_path / "r.csv").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocker"]


def test_setup_init_is_what_the_command_drafts(tmp_path, capsys) -> None:
    from support.stepfixtures import Assembly, Part, write_step

    top = Assembly("sat")
    top.add(Part("frame", [((100.0, 100.0, 5.0), (0.0, 0.0, 0.0))], 2700.0, "Aluminum 6061"))
    top.add(Part("battery", [((60.0, 60.0, 40.0), (20.0, 20.0, 20.0))]))
    step = write_step(top, tmp_path / "sat.step")
    theirs = json.loads(
        _cli_json(capsys, "setup", "init", str(step), "--out", str(tmp_path / "a_setup.toml"))
    )
    draft = cadcog.setup_init(step, out=tmp_path / "b_setup.toml")
    paths = {"setup": "", "materials": ""}
    assert draft.to_dict() | paths == theirs | paths
    init = next(
        a for a in _subparser("setup")._actions if isinstance(a, argparse._SubParsersAction)
    ).choices["init"]
    signature = inspect.signature(api.setup_init)
    for keyword in ("units", "force"):
        assert signature.parameters[keyword].default == init.get_default(keyword)
    assert draft.n_solids == 2 and draft.n_lacking_material == 1  # the battery's
    assert (tmp_path / "a_materials.toml").read_bytes() == (
        tmp_path / "b_materials.toml"
    ).read_bytes()
    a = (tmp_path / "a_setup.toml").read_text(encoding="utf-8").replace('"a"', '"b"')
    b = (tmp_path / "b_setup.toml").read_text(encoding="utf-8")
    assert a.replace("a_materials", "b_materials") == b


def test_overlapping_calls_keep_one_blas_thread_until_the_last_returns(monkeypatch):
    """threadpoolctl's limits are process-wide: a call from another thread that ends while
    this one runs must not lift the limit; the first call in sets it, the last one out restores
    it (the limiter is recorded here: OpenBLAS ignores limits set from some threads, so the
    pools themselves cannot show it)."""
    import threading

    import threadpoolctl

    from cadcog import api
    from cadcog.cli import BLAS_THREAD_VARIABLES

    for name in BLAS_THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    events: list[str] = []

    class Limiter:
        def __init__(self, limits, user_api):
            assert (limits, user_api) == (1, "blas")
            events.append("limit")

        def restore_original_limits(self):
            events.append("restore")

    monkeypatch.setattr(threadpoolctl, "threadpool_limits", Limiter)

    @api._one_blas_thread
    def other() -> None:
        events.append("other")

    @api._one_blas_thread
    def this() -> None:
        t = threading.Thread(target=other)
        t.start()
        t.join(5)  # the other call has come and gone
        events.append("this")

    this()
    assert events == ["limit", "other", "this", "restore"]
    this()  # and again, once the first pair is done
    assert events[4:] == ["limit", "other", "this", "restore"]


def test_swings_that_give_no_inertia_are_a_note_not_a_failure(tmp_path, monkeypatch) -> None:
    """``update --swings`` on swings the modal fit cannot read (a light object, a release with
    no twist): the CoG and mass update still runs, and says which file was not used and why;
    a swing file that cannot be read at all stays an error."""
    from cadcog.core.errors import CadcogError, DegenerateGeometryError
    from cadcog.dynamics import measure

    setup = "parts/cubesat_3u_setup.toml"
    points = ["+x_30_90", "-x_-30_90", "+y_-30_-30", "-y_30_-30"]
    cadcog.campaign(tmp_path / "r.csv", setup=setup, points=points, swings=tmp_path / "s.csv")

    def no_modes(*args, **kwargs):
        raise DegenerateGeometryError("hang +x_30_90: no swing mode stands out of the noise")

    monkeypatch.setattr(measure, "inertia_observation", no_modes)
    r = cadcog.update(tmp_path / "r.csv", setup, 2.583, swings=tmp_path / "s.csv")
    (note,) = [n for n in r.notes if "swings" in n]
    assert "s.csv" in note and "no swing mode stands out" in note
    assert r.dof == 4  # mass and CoG only
    monkeypatch.undo()
    (tmp_path / "bad.csv").write_text("point_id,t_s,inc_x_deg,inc_y_deg\nS1,x,1,2\n", "utf-8")
    with pytest.raises(CadcogError, match=r"bad\.csv"):
        cadcog.update(tmp_path / "r.csv", setup, 2.583, swings=tmp_path / "bad.csv")


@pytest.mark.slow
def test_acquire_is_the_command_s_simulated_run(tmp_path, capsys) -> None:
    """The same summary as ``acquire --simulate --non-interactive --json`` (the simulated
    device runs in real time, its lost samples vary: the same hangs, keys and verdicts, and
    estimates that agree within their σ)."""
    import numpy as np

    setup = "parts/cubesat_3u_setup.toml"
    points = ["+x_30_90", "-x_-30_90", "+y_-30_-30", "-y_30_-30"]
    theirs = json.loads(
        _cli_json(
            capsys,
            "acquire",
            "--simulate",
            "--non-interactive",
            "--setup",
            setup,
            f"--points={','.join(points)}",
            "--seed",
            "2",
            "--out",
            str(tmp_path / "a.csv"),
        )
    )
    run = cadcog.acquire(tmp_path / "b.csv", setup=setup, points=points, seed=2)
    mine = run.to_dict()
    assert sorted(mine) == sorted(theirs)
    assert [h["id"] for h in mine["hangs"]] == [h["id"] for h in theirs["hangs"]] == points
    a, b = (np.array(d["estimate"]["cog_mm"]) for d in (mine, theirs))
    sa, sb = (np.sqrt(np.diag(np.array(d["estimate"]["cov_mm2"]))) for d in (mine, theirs))
    assert np.all(np.abs(a - b) <= 5 * np.hypot(sa, sb))
    assert run.cad is not None and run.truth is not None and run.result.estimate is not None


def test_plan_for_both_is_what_the_command_prints(tmp_path, capsys) -> None:
    """``cadcog.plan(goal="both")`` is ``plan --for both --json``: the CoG's set and the hangs
    grown for the inertia, or why none."""
    setup = "parts/cubesat_3u_setup.toml"
    theirs = _cli_json(capsys, "plan", setup, "--for", "both", "--trials", "300")
    mine = cadcog.plan(setup, trials=300, goal="both")
    assert mine.to_json() == theirs
    assert mine.inertia is not None and json.loads(theirs)["goal"] == "both"


def _none_cases() -> list[tuple[str, str]]:
    """Every (entry point, argument) whose signature takes no None."""
    import inspect

    cases = []
    for name in cadcog.__all__:
        f = getattr(cadcog, name)
        if not inspect.isfunction(f):
            continue
        for arg, p in inspect.signature(f).parameters.items():
            if p.default is not None and "None" not in str(p.annotation):
                cases.append((name, arg))
    return cases


@pytest.mark.parametrize(("function", "argument"), _none_cases())
def test_none_where_the_signature_takes_none_is_refused_by_name(function, argument, tmp_path):
    """``None`` for an argument whose signature does not take it is a CadcogError naming the
    function and the argument, raised before any work (no TypeError deep inside, no
    ``seed=None`` run as a fresh random seed where the signature says ``int = 0``)."""
    import inspect

    f = getattr(cadcog, function)
    params = inspect.signature(f).parameters
    kwargs = {a: str(tmp_path / "absent") for a, p in params.items() if p.default is p.empty}
    kwargs[argument] = None
    with pytest.raises(CadcogError, match=rf"^{function}\({argument}=None\): expected .*None$"):
        f(**kwargs)
    assert list(tmp_path.iterdir()) == []
