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
    # masses to 4 significant figures in one unit for the column, volumes likewise (issue 22)
    rows = dict(re.findall(r'<tr><td class="l">(\w+)</td><td class="">([^<]*)</td>', page))
    assert ">mass (kg)</th>" in page
    assert (rows["transmitter"], rows["assembly"], rows["proof_mass"]) == ("0.02", "9.376", "9.2")
    assert '<td class="">9633</td></tr>' in page  # the transmitter's 9633.1 mm³
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


def _nauo_masked(step: bytes) -> bytes:
    """A STEP file without its line breaks (which move with the ids) and its NAUO ids."""
    flat = re.sub(rb"\s*\n\s*", b"", step)
    return re.sub(rb"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('\d+'", b"NAUO('#'", flat)


def _tree(folder):
    """Every file under ``folder``: relative path → bytes."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()
    }


def test_the_rig_parts_come_back_from_the_cache_to_the_last_byte(paper_rig, tmp_path, monkeypatch):
    from dataclasses import replace

    import cadcog.cad.build
    from cadcog.cad import cachestore
    from cadcog.core.jsontext import dumps_json
    from cadcog.reports.rig_report import parts_cache_key, rig_parts

    built = rig_parts(paper_rig, tmp_path / "a")
    folder = cachestore.cache_dir()
    assert folder is not None and len(list(folder.glob("*.json"))) == 1
    real_build = cadcog.cad.build.build_parts

    def no_build(*_a):
        pytest.fail("built again")

    monkeypatch.setattr(cadcog.cad.build, "build_parts", no_build)
    again = rig_parts(paper_rig, tmp_path / "b")
    assert again == built and dumps_json(again) == dumps_json(built)
    assert (
        again["bodies"]["proof_mass"]["inertia_kg_mm2"]
        == built["bodies"]["proof_mass"]["inertia_kg_mm2"]
    )
    files = _tree(tmp_path / "a")
    assert sorted(files) == sorted(
        ["assembly.step", "ground_truth.json"]
        + [f"stl/{b}.stl" for b in ("proof_mass", *[v.name for v in paper_rig.me_volumes])]
    )
    assert _tree(tmp_path / "b") == files
    assert files["ground_truth.json"] == dumps_json(built).encode()

    # any field of the rig is part of the key: a deeper hole is built afresh, and differs
    deeper = replace(paper_rig, holes=replace(paper_rig.holes, depth_mm=13.0))
    assert parts_cache_key(deeper) != parts_cache_key(paper_rig)
    monkeypatch.setattr(cadcog.cad.build, "build_parts", real_build)
    other = rig_parts(deeper, tmp_path / "c")
    assert other["bodies"]["proof_mass"]["mass_kg"] == pytest.approx(paper_rig.proof_mass.mass_kg)
    assert other["bodies"]["proof_mass"]["volume_mm3"] < built["bodies"]["proof_mass"]["volume_mm3"]

    # a damaged entry is built again (and rewritten); with the cache off nothing is kept
    entry = folder / f"{parts_cache_key(paper_rig)}.json"
    entry.write_text('{"format": 1, "result": {"files": {"../x": "AA=="}}}', encoding="utf-8")
    assert rig_parts(paper_rig, tmp_path / "d") == built
    rebuilt = _tree(tmp_path / "d")
    assert not (tmp_path / "x").exists()
    # OCCT numbers the assembly links by the assemblies a process has written before: a
    # second build in one process differs from the first in those ids, and only in them
    assert {n: rebuilt[n] for n in files if n != "assembly.step"} == {
        n: files[n] for n in files if n != "assembly.step"
    }
    assert _nauo_masked(rebuilt["assembly.step"]) == _nauo_masked(files["assembly.step"])
    assert '"ground_truth"' in entry.read_text(encoding="utf-8")
    monkeypatch.setenv("CADCOG_NO_CACHE", "1")
    for e in folder.glob("*.json"):
        e.unlink()
    rig_parts(paper_rig, tmp_path / "e")
    assert not list(folder.glob("*.json"))


def test_a_report_on_cached_parts_imports_no_cad_kernel(paper_rig, tmp_path):
    """With the rig's parts in the cache the report needs no CAD kernel (a fresh interpreter;
    sys.modules tells)."""
    import json
    import subprocess
    import sys

    from cadcog.reports.rig_report import rig_parts

    rig_parts(paper_rig, tmp_path / "parts")  # fills this test's cache (CADCOG_CACHE_DIR)
    probe = (
        "import contextlib, io, json, sys\nfrom cadcog.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):"
        f"\n    assert main(['report', '--out', {str(tmp_path / 'r')!r}]) == 0\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('build123d', 'OCP', 'sklearn'))))"
    )
    out = subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True, text=True)
    assert json.loads(out.stdout.strip().splitlines()[-1]) == []
    assert (tmp_path / "r" / "parts" / "ground_truth.json").read_bytes() == (
        tmp_path / "parts" / "ground_truth.json"
    ).read_bytes()


def test_an_accelerometers_rig_is_refused_before_any_cad_is_built(tmp_path, capsys):
    """The report's Monte Carlo models an inclinometer: it printed 'building the CAD parts'
    and 'error budget' before refusing (second new-user trial). One line, nothing written."""
    from support.rigtools import paper_rig_dict, write_rig

    data = paper_rig_dict()
    data["inclinometer"] = {"device": "accelerometer", "axes": ["+x", "+y", "+z"], "offset_g": 0.02,
                            "scale_error_rel": 0.01, "mounting_misalignment_deg": 1.0}  # fmt: skip
    rig = write_rig(tmp_path / "phone_rig.toml", data)
    assert main(["report", "--rig", str(rig), "--out", str(tmp_path / "rep")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("cadcog: error: cadcog report models a dual-axis inclinometer")
    assert err.count("\n") == 1 and not (tmp_path / "rep").exists()
