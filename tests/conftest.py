"""Shared fixtures. CAD fixtures build once per session: build123d is slow to import."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

from cadcog.rig.file import default_rig_path, load_rig
from cadcog.rig.parameters import Rig

# CI runs the same examples every time (a red CI is then a real regression, not a lucky draw);
# local runs explore new examples. No deadline: this 2-core machine is shared and its timing
# noisy.
settings.register_profile("ci", derandomize=True, deadline=None)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

GOLDEN_DIR = Path(__file__).parent / "golden"


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--update-golden",
        action="store_true",
        help="rewrite the golden files from the current code instead of comparing",
    )


@pytest.fixture(autouse=True)
def _own_cache_dir(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    """Each test's mass-properties cache (cadcog.cad.cache) is a fresh temporary folder: never
    the user's ~/.cache, and no test sees another's entries."""
    monkeypatch.setenv("CADCOG_CACHE_DIR", str(tmp_path_factory.mktemp("cadcog-cache")))
    monkeypatch.delenv("CADCOG_NO_CACHE", raising=False)


@pytest.fixture(scope="session")
def paper_rig() -> Rig:
    return load_rig(default_rig_path())


@pytest.fixture(scope="session")
def paper_rig_text() -> str:
    return default_rig_path().read_text(encoding="utf-8")


@pytest.fixture(scope="session")
def cubesat_setup():
    """The example 3U CubeSat set-up (builds its CAD with build123d: once per session)."""
    pytest.importorskip("build123d")
    from cadcog.spacecraft.setup import load_setup

    return load_setup(default_rig_path().parent / "cubesat_3u_setup.toml")
