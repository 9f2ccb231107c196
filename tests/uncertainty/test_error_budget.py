"""``cadcog/uncertainty/error_budget.py`` (``cadcog budget``): the representative pair is the
one at the median angle, and the rows account for the whole linearised CoG variance."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cadcog.method.errormodel import ErrorModel
from cadcog.uncertainty.error_budget import error_budget, representative_pair
from cadcog.uncertainty.montecarlo import Scenario

MEMS = {"offset_deg": 0.3, "scale_error_rel": 0.01, "mounting_misalignment_deg": 0.5}


@pytest.fixture(scope="module")
def scenario(paper_rig):
    return Scenario.from_rig(paper_rig)


def _angle_deg(a, b) -> float:
    c = abs(float(a @ b)) / (np.linalg.norm(a) * np.linalg.norm(b))
    return float(np.degrees(np.arccos(min(c, 1.0))))


def test_the_representative_pair_meets_at_the_median_angle(scenario):
    g, p = scenario.assembly_cog_mm, scenario.points_mm
    n = len(scenario.ids)
    angles = sorted(_angle_deg(p[a] - g, p[b] - g) for a in range(n) for b in range(a + 1, n))
    a, b = representative_pair(scenario)
    assert _angle_deg(p[a] - g, p[b] - g) == pytest.approx(angles[len(angles) // 2], abs=1e-9)


@pytest.mark.parametrize("variant", ["rig", "paper", "shared sensor"])
def test_the_rows_share_the_whole_variance(paper_rig, scenario, variant):
    model = ErrorModel.from_rig(paper_rig)
    if variant == "paper":
        model = model.paper()
    elif variant == "shared sensor":
        rig = replace(paper_rig, inclinometer=replace(paper_rig.inclinometer, **MEMS))
        model = ErrorModel.from_rig(rig)
    budget = error_budget(scenario, model)
    total = float(np.trace(budget.cov_mm2))
    assert total > 0
    assert sum(s.share for s in budget.sources) == pytest.approx(1.0, abs=1e-12)
    assert sum(s.cog_sigma_mm**2 for s in budget.sources) == pytest.approx(total, rel=1e-12)
    assert all(0.0 <= s.share <= 1.0 and s.sigma >= 0.0 for s in budget.sources)
    data = budget.to_dict()
    assert data["cog_sigma_mm"] == pytest.approx(np.sqrt(total), rel=1e-9)
    assert data["representative_pair"] == list(budget.pair)
    assert (variant == "shared sensor") == any(
        "one sensor" in s.distribution for s in budget.sources
    )


def test_a_source_switched_off_has_no_share(paper_rig, scenario):
    model = ErrorModel.from_rig(paper_rig)
    alone = error_budget(scenario, model.only("inclinometer"))
    rows = {s.source: s for s in alone.sources}
    assert rows["inclinometer"].share == pytest.approx(1.0)
    assert all(
        s.share == 0.0 and s.cog_sigma_mm == 0.0 for k, s in rows.items() if k != "inclinometer"
    )
