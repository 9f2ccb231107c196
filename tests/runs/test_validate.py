"""``cadcog/runs/validate.py``: a campaign against simulated ones, reproducible by its seed;
too few hangs refused naming the file."""

from __future__ import annotations

from pathlib import Path

import pytest

from cadcog.core.errors import CadcogError
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.runs.validate import MIN_POINTS, validate_readings

READINGS = Path(__file__).resolve().parents[2] / "docs" / "examples" / "paper_rig_readings.csv"


@pytest.fixture(scope="module")
def rig():
    return load_rig(default_rig_path())


def test_same_seed_same_verdict_to_the_bit(rig):
    kwargs = {"campaigns": 40, "level": 0.05}
    a = validate_readings(rig, READINGS, (0.5, 1.0), seed=3, **kwargs)
    b = validate_readings(rig, READINGS, (0.5, 1.0), seed=3, **kwargs)
    c = validate_readings(rig, READINGS, (0.5, 1.0), seed=4, **kwargs)
    assert a.to_json() == b.to_json() != c.to_json()


def test_fewer_hangs_than_three_pairs_need_are_refused_naming_the_file(rig, tmp_path):
    lines = READINGS.read_text(encoding="utf-8").splitlines(keepends=True)
    kept = [f"S{i}" for i in range(1, MIN_POINTS)]
    short = tmp_path / "short.csv"
    short.write_text("".join(x for x in lines if not x.startswith("S") or x[:2] in kept))
    with pytest.raises(CadcogError, match=rf"short\.csv: validation needs {MIN_POINTS} or more"):
        validate_readings(rig, short, (1.0,), campaigns=40, seed=0, level=0.05)
