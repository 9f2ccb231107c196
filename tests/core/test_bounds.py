"""The bounds on every number (cadcog/core/bounds.py), and the page that lists them."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core import bounds
from cadcog.core.errors import ParameterFileError
from cadcog.core.paramfile import TableReader

DOCS = Path(__file__).resolve().parents[2] / "docs" / "inputs.md"


def test_the_docs_table_is_generated_from_the_module():
    assert bounds.markdown_table() in DOCS.read_text(encoding="utf-8")


@pytest.mark.parametrize(
    ("name", "value", "expected"),
    [
        ("size_mm", 20_000.0, None),
        ("size_mm", 20_000.1, "expected at most 20000 (lengths"),
        ("center_mm", -20_000.1, "expected at least -20000"),
        ("cog_cov_mm2", -1.0, "expected at least 0"),  # _mm2 before _mm
        ("density_kg_m3", 2.7, "is it in g/cm³?"),  # _kg_m3 before _kg
        ("inertia_kg_mm2", -5.0, None),  # products of inertia are negative
        ("sensitivity_v_per_deg", 500.0, "V per degree"),  # not an angle
        ("--noise-deg", -0.1, "expected a number >= 0"),  # a spread, whatever its unit
        ("cog_sigma_mm", -1e-9, "expected a number >= 0"),
        ("mass_sigma_kg", 0.0, "expected more than 0 (a weighing's 1 σ)"),  # its own bound
        ("mass_sigma_kg", -1.0, "expected more than 0 (a weighing's 1 σ)"),  # ... over the rule
        ("mass_sigma_kg", 1e-12, None),
        ("adc_bits", 33, "at most 32"),
        ("seed", -1, "at least 0"),
        ("mass_kg", float("nan"), "expected a finite number"),
        ("anything", float("inf"), "expected a finite number"),
        ("anything", 1e300, None),  # no unit, no bound
    ],
)
def test_bounds_follow_the_name(name, value, expected):
    got = bounds.check(name, value)
    if expected is None:
        assert got is None
    else:
        assert got is not None and expected in got


@given(st.sampled_from(sorted(bounds.UNIT_BOUNDS)), st.floats(allow_nan=True))
def test_a_file_key_is_refused_exactly_when_its_bound_says_so(suffix, value):
    """Through TableReader: a key refused iff bounds.check says so, naming the key."""
    key = f"some{suffix}"
    reader = TableReader({key: value}, Path("f.toml"))
    problem = bounds.check(key, value)
    if problem is None:
        assert reader.number(key) == value
    else:
        with pytest.raises(ParameterFileError, match=rf"f\.toml: key '{key}'"):
            reader.number(key)


def test_integers_get_their_named_bound_in_files():
    reader = TableReader({"adc_bits": 10**18}, Path("rig.toml"))
    with pytest.raises(ParameterFileError, match=r"adc_bits.*at most 32"):
        reader.integer("adc_bits", minimum=1)
