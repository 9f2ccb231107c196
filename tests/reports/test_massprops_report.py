"""``cadcog/reports/massprops_report.py`` and ``budget_csv.py``: names a STEP file gives its
parts are text, whatever characters they hold: escaped in the page, whole in the CSV."""

from __future__ import annotations

import csv
import re

import pytest

pytest.importorskip("build123d")

from cadcog.cli import main

HOSTILE = ['<script>alert("x")</script>', "a & b <b>bold</b>", 'it\'s "quoted", with commas']


@pytest.fixture(scope="module")
def hostile_step(tmp_path_factory):
    from support.stepfixtures import Assembly, Part, write_step

    top = Assembly("sat <i>top</i>")
    for i, name in enumerate(HOSTILE):
        top.add(Part(name, [((10.0, 10.0, 10.0), (20.0 * i, 0.0, 0.0))]))
    path = tmp_path_factory.mktemp("hostile") / "hostile.step"
    write_step(top, path)
    return path


def test_part_names_are_escaped_in_the_page_and_whole_in_the_csv(hostile_step, tmp_path, capsys):
    rep, table = tmp_path / "rep", tmp_path / "budget.csv"
    argv = ["massprops", str(hostile_step), "--density-kg-m3", "2700"]
    assert main([*argv, "--report", str(rep), "--csv", str(table)]) == 0
    page = (rep / "index.html").read_text(encoding="utf-8")
    assert "<script" not in page.lower() and "<i>top" not in page and "<b>bold" not in page
    assert "sat &lt;i&gt;top&lt;_i&gt;" in page
    # (a "/" in a name is "_": the path's separator)
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;_script&gt;" in page
    assert "a &amp; b &lt;b&gt;bold&lt;_b&gt;" in page
    # every tag in the page is one the report writes (no element from a name)
    assert set(re.findall(r"<([a-zA-Z][a-zA-Z0-9]*)", page)) <= {
        "html", "head", "meta", "title", "style", "body", "h1", "h2", "h3", "p", "table", "thead",
        "tbody", "tr", "th", "td", "img", "div", "nav", "a", "span", "ul", "li", "b", "code",
        "small", "details", "summary", "br", "strong", "em", "sup", "sub", "section", "figure",
        "figcaption", "i",
    }  # fmt: skip
    with open(table, encoding="utf-8", newline="") as fh:
        rows = list(csv.DictReader(fh))
    bodies = {r["name"] for r in rows if r["kind"] == "body"}
    assert bodies == {n.replace("/", "_") for n in HOSTILE}
    assert sum(float(r["mass_kg"]) for r in rows if r["kind"] == "body") == pytest.approx(
        3 * 1e-6 * 2700.0, rel=1e-9
    )
