"""``cadcog budget`` and ``cadcog simulate`` in-process."""

from __future__ import annotations

import json

import numpy as np
import pytest

from cadcog.cli import main


def test_budget_json(capsys):
    assert main(["budget", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["me_cog_sigma_mm"] == pytest.approx([1.67] * 3, abs=0.01)
    assert out["inclinometer_sigma_deg"] == pytest.approx(
        np.sqrt((0.1**2 / 3 + (5 / 1024 * 30) ** 2 / 12) / 10)
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


def test_simulate_json_and_plot(tmp_path, capsys):
    plot = tmp_path / "hist.png"
    argv = [
        "simulate",
        "--points",
        "8",
        "--trials-per-pair",
        "200",
        "--seed",
        "5",
        "--json",
        "--plot",
        str(plot),
    ]
    assert main(argv) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)  # nothing but JSON on stdout
    for key in (
        "n_trials",
        "rayleigh_sigma_mm",
        "maxwell_a_mm",
        "q50_mm",
        "q95_mm",
        "ks_rayleigh",
        "ks_maxwell",
        "per_axis_std_mm",
    ):
        assert key in out
    assert out["n_trials"] == 28 * 200
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(argv[:-2]) == 0
    assert json.loads(capsys.readouterr().out) == out  # same seed, same numbers


def test_simulate_improvements_reduce_the_95_percent_quantile(capsys):
    base = ["simulate", "--points", "12", "--trials-per-pair", "300", "--seed", "2", "--json"]
    assert main(base) == 0
    paper = json.loads(capsys.readouterr().out)["q95_mm"]
    assert main([*base, "--min-angle-deg", "20", "--wire-correction"]) == 0
    improved = json.loads(capsys.readouterr().out)["q95_mm"]
    assert improved < paper


def test_simulate_bad_options(capsys):
    assert main(["simulate", "--trials-per-pair", "1"]) == 2
    assert "--trials-per-pair" in capsys.readouterr().err
    assert main(["simulate", "--points", "5", "--min-angle-deg", "90"]) == 2
    assert "no group" in capsys.readouterr().err
