"""``cadcog budget`` in-process."""

from __future__ import annotations

import json

import numpy as np
import pytest

from cadcog.cli import main


def test_budget_json(capsys):
    assert main(["budget", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["me_cog_sigma_mm"] == pytest.approx([1.67] * 3, abs=0.01)
    # The hang-bias model: the ±0.1° accuracy is a bias of each hang; noise (0.05°) and the
    # ADC step average over the 10 samples (the part the samples share is 0.13 % of this σ).
    lsb = 5 / 1024 * 30
    assert out["inclinometer_sigma_deg"] == pytest.approx(
        np.sqrt(0.1**2 / 3 + (0.05**2 + lsb**2 / 12) / 10), rel=2e-3
    )
    assert sum(s["share"] for s in out["sources"]) == pytest.approx(1.0)
    assert {s["source"] for s in out["sources"]} == {
        "me_cog",
        "inclinometer",
        "point_play",
        "wire_offset",
    }


def test_budget_table(capsys):
    assert main(["budget"]) == 0
    out = capsys.readouterr().out
    assert "point_play" in out and "share" in out
