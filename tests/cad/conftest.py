"""CAD fixtures: the paper rig built once per test session."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def paper_model(paper_rig):
    from cadcog.cad.rigsolids import build_rig

    return build_rig(paper_rig)


@pytest.fixture(scope="session")
def paper_build(paper_rig, tmp_path_factory):
    from cadcog.cad.build import build_parts

    return build_parts(paper_rig, tmp_path_factory.mktemp("paper_build"))
