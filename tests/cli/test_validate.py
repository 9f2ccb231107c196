"""``cadcog validate`` in-process, on a campaign ``cadcog campaign`` writes."""

from __future__ import annotations

import json

from cadcog.cli import main
from support.rigtools import write_csv


def test_campaign_then_validate(tmp_path, capsys):
    csv = tmp_path / "campaign.csv"
    assert main(["campaign", "--seed", "3", "--samples", "5", "--out", str(csv)]) == 0
    assert "30 samples of 6 hangs" in capsys.readouterr().out
    assert main(["validate", str(csv), "--campaigns", "500", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [w["eps_mm"] for w in out["windows"]] == [0.5, 1.0, 1.5, 2.0, 3.0]
    for w in out["windows"]:
        assert set(w) >= {"eps_mm", "F", "k", "n", "p_hat", "ci_low", "ci_high", "consistent"}
        assert w["n"] == 15 and w["ci_low"] <= w["p_hat"] <= w["ci_high"]
        assert 0 <= w["null_k_low"] <= w["null_k_high"] <= 15
    c = out["campaign"]
    assert 1 / 501 <= c["p_value"] <= 1 and c["n_null_campaigns"] == 500
    assert out["consistent"] == (c["p_value"] >= 0.05)
    assert main(["validate", str(csv), "--campaigns", "200", "--windows", "1,2"]) == 0
    printed = capsys.readouterr().out
    assert "campaign test" in printed and "verdict" in printed


def test_validate_needs_three_points(tmp_path, capsys):
    csv = write_csv(tmp_path / "two.csv", ["S1,45,20,82,-50,-14,true", "S2,155,55,82,50,14,true"])
    assert main(["validate", str(csv)]) == 2
    assert "3 or more suspension points" in capsys.readouterr().err


def test_validate_rejects_bad_options(tmp_path, capsys):
    csv = tmp_path / "campaign.csv"
    assert main(["campaign", "--seed", "1", "--out", str(csv)]) == 0
    capsys.readouterr()
    assert main(["validate", str(csv), "--campaigns", "5"]) == 2
    assert "--campaigns" in capsys.readouterr().err
    assert main(["validate", str(csv), "--level", "1.5"]) == 2
    assert "--level" in capsys.readouterr().err
