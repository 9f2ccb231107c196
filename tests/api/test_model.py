"""``cadcog.api.model``: mass_properties as the command reads a model."""

from __future__ import annotations

import pytest

import cadcog


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
