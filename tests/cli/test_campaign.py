"""``cadcog campaign`` in-process: its refusals (what it writes is checked by
tests/cli/test_validate.py, tests/cli/test_inertia.py and tests/api/test_simulation.py)."""

from __future__ import annotations

from cadcog.cli import main


def test_campaign_rejects_bad_samples(tmp_path, capsys):
    assert main(["campaign", "--samples", "0", "--out", str(tmp_path / "c.csv")]) == 2
    assert "samples" in capsys.readouterr().err
    assert not (tmp_path / "c.csv").exists()
