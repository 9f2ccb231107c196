"""``cadcog.api._checks``: bad arguments, one clear error; one BLAS thread per call."""

from __future__ import annotations

import inspect

import pytest

import cadcog
from cadcog import api
from cadcog.core.errors import CadcogError


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
        r"simulate\(inclinometer_model='perfect'\): expected one of hang-bias, paper-averaged",
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
        lambda: cadcog.mass_properties("m.step", density_kg_m3=2700, form_factor="7U"),
        r"mass_properties\(form_factor='7U'\): expected one of 1U, 1\.5U",
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
        r"update\(weighed_mass_kg=0\.0\): expected at least 1e-06 \(a weighed mass",
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


def test_every_entry_point_limits_blas_to_one_thread_unless_the_user_set_it(monkeypatch):
    """From Python as from the command: cadcog's small matrices on a many-thread BLAS pool
    made ``cadcog.update`` 9× slower than ``cadcog update``."""
    from threadpoolctl import threadpool_info, threadpool_limits

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


def test_overlapping_calls_keep_one_blas_thread_until_the_last_returns(monkeypatch):
    """threadpoolctl's limits are process-wide: a call from another thread that ends while
    this one runs must not lift the limit; the first call in sets it, the last one out restores
    it (the limiter is recorded here: OpenBLAS ignores limits set from some threads, so the
    pools themselves cannot show it)."""
    import threading

    import threadpoolctl

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


def _none_cases() -> list[tuple[str, str]]:
    """Every (entry point, argument) whose signature takes no None."""

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

    f = getattr(cadcog, function)
    params = inspect.signature(f).parameters
    kwargs = {a: str(tmp_path / "absent") for a, p in params.items() if p.default is p.empty}
    kwargs[argument] = None
    with pytest.raises(CadcogError, match=rf"^{function}\({argument}=None\): expected .*None$"):
        f(**kwargs)
    assert list(tmp_path.iterdir()) == []
