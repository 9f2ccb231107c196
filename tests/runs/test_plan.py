"""``cadcog/runs/plan.py``: the plan's counts are refused at their bounds, before any CAD."""

from __future__ import annotations

import pytest

from cadcog.core.errors import CadcogError
from cadcog.runs.plan import check_plan_options


@pytest.mark.parametrize(
    ("trials", "max_set", "seed", "max_inertia_set", "refused"),
    [
        (2, 2, 0, 3, None),  # every bound met exactly
        (1, 2, 0, 3, "--trials ≥ 2"),
        (2, 1, 0, 3, "--max-set ≥ 2"),
        (2, 2, -1, 3, "--seed ≥ 0"),
        (2, 2, 0, 2, "--max-inertia-set must be at least 3"),
        (1000, 8, 12345, 8, None),
    ],
)
def test_counts_at_and_beyond_their_bounds(trials, max_set, seed, max_inertia_set, refused):
    if refused is None:
        check_plan_options(trials, max_set, seed, max_inertia_set)
        return
    with pytest.raises(CadcogError, match=refused):
        check_plan_options(trials, max_set, seed, max_inertia_set)
