"""``cadcog simulate`` in-process (and, with ``budget``, the shared sensor drawn)."""

from __future__ import annotations

import json

from cadcog.cli import main
from support.rigtools import paper_rig_dict, write_rig


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
    for key in ("n_trials", "q50_mm", "q95_mm", "q99_mm", "screened", "per_axis_std_mm"):
        assert key in out
    # Moment fits are there with their quality, but not as the headline.
    for key in ("rayleigh_sigma_mm", "maxwell_a_mm", "ks_rayleigh", "ks_maxwell"):
        assert key in out["fits"] and key not in out
    assert out["error_model"]["inclinometer_model"] == "hang-bias"
    assert out["estimator"]["estimator"] == "generalised least squares"
    assert out["q50_mm"] < out["q95_mm"] < out["q99_mm"]
    assert out["n_trials"] == 28 * 200
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(argv[:-2]) == 0
    assert json.loads(capsys.readouterr().out) == out  # same seed, same numbers


def test_simulate_improvements_reduce_the_95_percent_quantile(capsys):
    base = ["simulate", "--points", "12", "--trials-per-pair", "300", "--seed", "2", "--json"]
    assert main(base) == 0
    paper = json.loads(capsys.readouterr().out)["q95_mm"]  # cadcog's default estimator
    assert main([*base, "--no-wire-correction"]) == 0
    uncorrected = json.loads(capsys.readouterr().out)["q95_mm"]
    assert paper < uncorrected
    assert main([*base, "--min-angle-deg", "20"]) == 0
    screened = json.loads(capsys.readouterr().out)["q95_mm"]
    assert screened < paper


def test_simulate_bad_options(capsys):
    assert main(["simulate", "--trials-per-pair", "1"]) == 2
    assert "--trials-per-pair" in capsys.readouterr().err
    assert main(["simulate", "--points", "5", "--min-angle-deg", "90"]) == 2
    assert "no group" in capsys.readouterr().err


def test_monte_carlo_commands_draw_the_shared_sensor(tmp_path, capsys):
    """A rig declaring a sensor's shared errors: the budget has their row and the simulation
    draws one sensor per campaign (its 95 % error grows); nothing on stderr (the JSON stays
    clean); without them, no row."""
    data = paper_rig_dict()
    data["inclinometer"]["offset_deg"] = 0.3
    rig = str(write_rig(tmp_path / "mems.toml", data))
    assert main(["budget", "--rig", rig, "--json"]) == 0
    captured = capsys.readouterr()
    rows = {r["source"]: r for r in json.loads(captured.out)["sources"]}
    assert rows["sensor_shared"]["share"] > 0.2
    assert captured.err == ""
    assert main(["budget", "--json"]) == 0
    assert "sensor_shared" not in capsys.readouterr().out
    base = ["simulate", "--points", "0", "--trials-per-pair", "2000", "--seed", "1", "--json"]
    assert main([*base, "--rig", rig]) == 0
    shared = json.loads(capsys.readouterr().out)["q95_mm"]
    assert main(base) == 0
    assert shared > 1.2 * json.loads(capsys.readouterr().out)["q95_mm"]
