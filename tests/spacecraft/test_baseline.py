"""The baseline file: validated on load, described for people when things move."""

from __future__ import annotations

import pytest

from cadcog.core.errors import ParameterFileError
from cadcog.spacecraft.baseline import FORMAT, Change, load_baseline


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("not json", "not a baseline JSON file"),
        ('{"format": "other"}', "key 'format'"),
        (f'{{"format": "{FORMAT}", "mass_kg": 1, "cog_mm": [0, 0, 0]}}', "key 'bodies'"),
        (
            f'{{"format": "{FORMAT}", "mass_kg": 1, "cog_mm": [0, 0], "bodies": {{}}}}',
            "three finite cog_mm",
        ),
        (
            f'{{"format": "{FORMAT}", "mass_kg": 1, "cog_mm": [0, 0, 0], '
            '"bodies": {"a": {"mass_kg": NaN, "cog_mm": [0, 0, 0]}}}',
            "key 'bodies.a'",
        ),
    ],
)
def test_bad_baselines_name_the_file_and_key(tmp_path, text, message):
    path = tmp_path / "b.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ParameterFileError, match=message):
        load_baseline(path)


def test_a_change_is_described_with_its_mass_and_the_axes_that_moved():
    c = Change("sat/battery", "changed", 0.4, 0.44, (0.0, 0.0, -100.0), (0.05, 0.0, -98.8), 0.1)
    assert c.describe() == "sat/battery +40.0 g, CoG +1.20 mm in z"
    assert Change("sat/x", "added", None, 0.012, None, (0, 0, 0), 0).describe() == (
        "sat/x added (12.0 g)"
    )
