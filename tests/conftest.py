"""Shared fixtures. CAD fixtures build once per session: build123d is slow to import."""

from __future__ import annotations

from pathlib import Path

import pytest

from cadcog.rig import Rig
from cadcog.rigfile import default_rig_path, load_rig

GOLDEN_DIR = Path(__file__).parent / "golden"


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--update-golden",
        action="store_true",
        help="rewrite the golden files from the current code instead of comparing",
    )


@pytest.fixture(scope="session")
def paper_rig() -> Rig:
    return load_rig(default_rig_path())


@pytest.fixture(scope="session")
def paper_rig_text() -> str:
    return default_rig_path().read_text(encoding="utf-8")
