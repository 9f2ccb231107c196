"""What each entry point imports: ``import cadcog`` and ``cadcog --version`` load no heavy library,
and the commands that need no statistics, CAD or plotting do not load them (each in a fresh
interpreter, where ``sys.modules`` tells). Not timed: speed is in docs/performance.md."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from cadcog.rig.file import default_rig_path

HEAVY = ("scipy", "build123d", "OCP", "matplotlib", "trimesh")


def _loaded(code: str) -> dict[str, list[str]]:
    """Run ``code`` in a fresh interpreter; which of :data:`HEAVY` (and numpy) it loaded."""
    probe = (
        "import sys, json\n"
        f"{code}\n"
        f"print(json.dumps({{'heavy': [m for m in {HEAVY!r} + ('numpy',) if m in sys.modules]}}))"
    )
    out = subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_import_cadcog_loads_nothing_heavy():
    assert _loaded("import cadcog")["heavy"] == []


def test_version_loads_no_command_and_nothing_heavy():
    code = (
        "from cadcog.cli import main\n"
        "try:\n    main(['--version'])\nexcept SystemExit as e:\n    assert e.code == 0\n"
        "assert not [m for m in sys.modules if m.startswith('cadcog.cli.') and m != "
        "'cadcog.cli._main']"
    )
    assert _loaded(code)["heavy"] == []


def _command(argv: list[str]) -> str:
    return (
        "import contextlib, io\nfrom cadcog.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    assert main({argv!r}) == 0\n"
    )


@pytest.mark.parametrize(
    "argv",
    [["budget", "--json"], ["simulate", "--trials", "200", "--json"], ["estimate", "READINGS"]],
)
def test_commands_without_statistics_load_no_scipy(argv, tmp_path):
    if "READINGS" in argv:
        readings = tmp_path / "campaign.csv"
        subprocess.run(
            [sys.executable, "-m", "cadcog", "campaign", "--out", str(readings)],
            check=True,
            capture_output=True,
        )
        argv = [*argv[:-1], str(readings), "--rig", str(default_rig_path())]
    loaded = _loaded(_command(argv))["heavy"]
    assert loaded == ["numpy"], loaded


def test_the_normal_cdf_without_scipy_is_scipys():
    from scipy import stats

    from cadcog.method.mecog import _normal_cdf

    z = np.concatenate([np.linspace(-9.0, 9.0, 721), [0.0, -38.0, 1e-300]])
    ours, theirs = _normal_cdf(z), stats.norm.cdf(z)
    assert np.max(np.abs(ours - theirs)) <= 2.3e-16  # two steps of a double near 1
    tail = theirs > 0
    assert np.max(np.abs(ours[tail] / theirs[tail] - 1)) <= 1e-13  # and relative in the tails


def test_the_suites_blas_is_set_to_one_thread_before_numpy_loads():
    """tests/conftest.py sets the BLAS thread variables before numpy's first import, in this
    worker too: a pool per worker would oversubscribe the CPUs pytest-xdist already fills."""
    import os

    from tests import conftest

    assert not conftest.NUMPY_WAS_IMPORTED_FIRST
    assert all(os.environ.get(name) for name in conftest.BLAS_THREAD_VARIABLES)
