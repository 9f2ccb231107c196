"""``cadcog/cad/resolve.py`` (the overlap policy): a model drawn in inches and read with
``units='in'`` has the mass properties of the same model drawn in millimetres, under every
policy (every volume and contact floor judged in mm³ whatever the file's unit)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("build123d")

from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from support.stepfixtures import Assembly, Part, write_step

MM_PER_IN = 25.4


def _blocks(path, scale: float):
    """An aluminium cube with a small tungsten block half inside it (drawn in mm / scale)."""
    top = Assembly("top")
    s = 1.0 / scale
    top.add(Part("outer", [((20.0 * s, 20.0 * s, 20.0 * s), (0.0, 0.0, 0.0))], 2700.0, "Al"))
    top.add(Part("inner", [((4.0 * s, 4.0 * s, 4.0 * s), (18.0 * s, 2.0 * s, 2.0 * s))], 19300.0,
                 "W"))  # fmt: skip
    write_step(top, path)
    return read_step(path)


@pytest.mark.parametrize("policy", ["allow", "resolve", "skip"])
def test_inches_read_as_inches_are_the_millimetre_model(tmp_path, policy):
    mm = model_mass_properties(_blocks(tmp_path / "mm.step", 1.0), None, overlaps=policy)
    inch = model_mass_properties(
        _blocks(tmp_path / "in.step", MM_PER_IN), None, overlaps=policy, units="in"
    )
    assert inch.total.mass_kg == pytest.approx(mm.total.mass_kg, rel=1e-9)
    np.testing.assert_allclose(inch.total.cog_mm, mm.total.cog_mm, rtol=0, atol=1e-9)
    np.testing.assert_allclose(
        inch.total.inertia_kg_mm2, mm.total.inertia_kg_mm2, rtol=1e-9, atol=1e-12
    )
    if policy != "skip":
        assert len(inch.overlaps.pairs) == len(mm.overlaps.pairs) == 1
        assert inch.overlaps.volume_mm3 == pytest.approx(mm.overlaps.volume_mm3, rel=1e-9)
        assert mm.overlaps.volume_mm3 == pytest.approx(2.0 * 4.0 * 4.0, rel=1e-9)


def test_the_closed_form_of_resolving_the_half_inside_block(tmp_path):
    """The denser block keeps the 32 mm³ it shares: the aluminium loses it."""
    r = model_mass_properties(_blocks(tmp_path / "mm.step", 1.0), None, overlaps="resolve")
    expected = 2700e-9 * (8000.0 - 32.0) + 19300e-9 * 64.0
    assert r.total.mass_kg == pytest.approx(expected, rel=1e-9)
