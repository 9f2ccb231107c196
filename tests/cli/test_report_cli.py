"""``cadcog report``: the whole chain, and a page with every section and its figures."""

from __future__ import annotations

import base64
import re

import pytest

pytest.importorskip("build123d")

from cadcog.cli import main

SECTIONS = (
    "The rig",
    "Ground truth from CAD",
    "Error budget",
    "Monte Carlo",
    "Validation (eqs. 14-15)",
    "Compensated estimate",
)


def test_report_has_every_section_and_figure(tmp_path, capsys):
    out = tmp_path / "report"
    assert main(["report", "--out", str(out)]) == 0
    printed = capsys.readouterr()
    assert f"report: {out / 'index.html'}" in printed.err  # files written: on stderr, always
    assert "compensated CoG" in printed.out
    page = (out / "index.html").read_text(encoding="utf-8")
    for section in SECTIONS:
        assert f">{section}</h2>" in page, section
    images = re.findall(r'<img src="data:image/png;base64,([^"]+)" alt="([^"]+)"', page)
    assert len(images) == 4
    for data, _alt in images:
        assert base64.b64decode(data)[:8] == b"\x89PNG\r\n\x1a\n"
    assert "virtual" in page
    for name in (
        "campaign.csv",
        "budget.json",
        "simulation.json",
        "validation.json",
        "estimate.json",
        "parts/ground_truth.json",
        "parts/assembly.step",
    ):
        assert (out / name).is_file(), name


def test_report_with_a_given_campaign_uses_it(tmp_path, capsys):
    csv = tmp_path / "measured.csv"
    assert main(["campaign", "--seed", "9", "--out", str(csv)]) == 0
    before = csv.read_bytes()
    assert main(["report", "--campaign", str(csv), "--out", str(tmp_path / "r")]) == 0
    page = (tmp_path / "r" / "index.html").read_text(encoding="utf-8")
    assert str(csv) in page and "<b>virtual</b>" not in page
    assert not (tmp_path / "r" / "campaign.csv").exists()
    assert csv.read_bytes() == before
    capsys.readouterr()
    assert (
        main(["report", "--campaign", str(tmp_path / "none.csv"), "--out", str(tmp_path / "x")])
        == 2
    )
    assert "file not found" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()
