"""``cadcog campaign`` in-process: its refusals and warnings (what it writes is checked by
tests/cli/test_validate.py, tests/cli/test_inertia.py and tests/api/test_simulation.py)."""

from __future__ import annotations

from cadcog.cli import main


def test_campaign_rejects_bad_samples(tmp_path, capsys):
    assert main(["campaign", "--samples", "0", "--out", str(tmp_path / "c.csv")]) == 2
    assert "samples" in capsys.readouterr().err
    assert not (tmp_path / "c.csv").exists()


def test_a_point_the_plan_says_cannot_work_is_simulated_with_a_warning(tmp_path, capsys):
    """The 3U example's +x_-30_30 leaves the vertical 5.4° from the inclinometer's plane
    (docs/spacecraft.md): the campaign still simulates it (a rehearsal of that mistake) and
    says so on stderr and in its JSON; a usable point gets no warning."""
    import json

    setup = "parts/cubesat_3u_setup.toml"
    out = tmp_path / "c.csv"
    argv = ["campaign", "--setup", setup, "--points=+x_-30_30,-x_-30_90", "--out", str(out)]
    assert main([*argv, "--json"]) == 0
    captured = capsys.readouterr()
    warnings = json.loads(captured.out)["warnings"]
    assert len(warnings) == 1 and warnings[0].startswith("+x_-30_30: cannot work")
    assert (
        "inclinometer's plane" in warnings[0]
        and f"cadcog: warning: {warnings[0]}\n" in captured.err
    )
    assert main(["campaign", "--setup", setup, "--points=+x_30_90,-x_-30_90", "--out",
                 str(out), "--json"]) == 0  # fmt: skip
    assert "warnings" not in json.loads(capsys.readouterr().out)
