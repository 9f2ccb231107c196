"""Fixtures of the bench tests: the paper rig as a bench target, and simulated devices."""

from __future__ import annotations

import pytest

from cadcog.bench.target import BenchTarget, target_from_rig


@pytest.fixture(scope="session")
def paper_target(paper_rig) -> BenchTarget:
    return target_from_rig(paper_rig)
