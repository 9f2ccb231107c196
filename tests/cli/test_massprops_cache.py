"""``cadcog massprops`` on unchanged inputs: the result (or the refusal) read back from the cache
is what the computation writes, byte for byte; any input that changes a number is computed
afresh; the command and the API share entries; a cached run reads no CAD."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import cadcog
from cadcog.cad import stepmass, stepread
from cadcog.cli import main
from support.stepfixtures import Assembly, Part, nested_three_levels, write_step

MATERIALS = '[materials]\n"*" = 1000.0\n[mass_uncertainty]\n"*" = 0.05\n'


@pytest.fixture
def model(tmp_path):
    step = write_step(nested_three_levels(), tmp_path / "sat.step")
    mats = tmp_path / "materials.toml"
    mats.write_text(MATERIALS, encoding="utf-8")
    return step, mats


@pytest.fixture
def computed(monkeypatch):
    """Counts the computations (each reads the STEP file once)."""
    calls: list[Path] = []
    real = stepread.read_step

    def counted(path):
        calls.append(Path(path))
        return real(path)

    monkeypatch.setattr(stepread, "read_step", counted)
    return calls


def _run(capsys, argv: list[str]) -> tuple[int, str, str]:
    status = main(argv)
    out = capsys.readouterr()
    return status, out.out, out.err


def test_a_second_run_reads_the_cache_and_writes_the_same_bytes(model, tmp_path, capsys, computed):
    step, mats = model
    argv = ["massprops", str(step), "--materials", str(mats), "--json", "--surface-area"]
    first = _run(capsys, [*argv, "--csv", str(tmp_path / "a.csv")])
    assert first[0] == 0 and len(computed) == 1 and "from the cache" not in first[2]
    second = _run(capsys, [*argv, "--csv", str(tmp_path / "b.csv"), "--workers", "1"])
    assert len(computed) == 1, "the second run read the STEP file"
    assert second[0] == 0 and second[1] == first[1]
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    assert second[2].count(f"cadcog: {step}: mass properties from the cache") == 1
    text = _run(capsys, ["massprops", str(step), "--materials", str(mats), "--surface-area"])
    assert text[0] == 0 and "bracket" in text[1] and len(computed) == 1


def test_the_api_and_the_command_share_entries(model, capsys, computed):
    step, mats = model
    report = cadcog.mass_properties(step, mats, surface_area=True)
    assert len(computed) == 1
    status, out, _ = _run(
        capsys, ["massprops", str(step), "--materials", str(mats), "--json", "--surface-area"]
    )
    assert status == 0 and len(computed) == 1
    assert json.loads(out)["mass_kg"] == report.result.total.mass_kg
    again = cadcog.mass_properties(step, mats, surface_area=True, workers=1)
    assert len(computed) == 1 and again.to_dict() == report.to_dict()


CHANGES = {
    "materials file": ["--materials", "{mats2}"],
    "density": ["--density-kg-m3", "1001"],
    "total mass": ["--total-mass-kg", "1.0"],
    "units": ["--units", "in"],
    "exclude": ["--exclude", "bracket"],
    "allow": ["--allow-overlap"],
    "resolve": ["--resolve-overlaps"],
    "skip": ["--skip-overlaps"],
    "strict": ["--strict"],
    "surface area": ["--surface-area"],
}


@pytest.mark.parametrize("change", list(CHANGES))
def test_any_option_that_changes_a_number_is_computed_afresh(
    change, model, tmp_path, capsys, computed, monkeypatch
):
    step, mats = model
    mats2 = tmp_path / "materials2.toml"
    mats2.write_text(MATERIALS.replace("1000.0", "1000.5"), encoding="utf-8")
    base = ["massprops", str(step), "--json"]
    extra = [a.format(mats2=mats2) for a in CHANGES[change]]
    density = [] if extra[0] in ("--materials", "--density-kg-m3") else ["--materials", str(mats)]
    assert _run(capsys, [*base, "--materials", str(mats)])[0] == 0 and len(computed) == 1
    changed = _run(capsys, [*base, *density, *extra])
    assert len(computed) == 2, f"{change}: answered from the entry of another input"
    monkeypatch.setenv("CADCOG_NO_CACHE", "1")
    assert _run(capsys, [*base, *density, *extra])[:2] == changed[:2] and len(computed) == 3


def test_a_changed_step_file_is_computed_afresh(model, capsys, computed):
    step, mats = model
    argv = ["massprops", str(step), "--materials", str(mats), "--json"]
    before = json.loads(_run(capsys, argv)[1])
    top = nested_three_levels()
    top.add(Part("extra", [((1.0, 2.0, 3.0), (50.0, 0.0, 0.0))], 1000.0))
    write_step(top, step)
    after = json.loads(_run(capsys, argv)[1])
    assert len(computed) == 2 and after["mass_kg"] > before["mass_kg"]


def test_a_refusal_is_kept_and_said_again_with_the_same_outputs(tmp_path, capsys, computed):
    top = Assembly("top")
    top.add(Part("outer", [((20.0, 20.0, 20.0), (0.0, 0.0, 0.0))], 2700.0))
    top.add(Part("inner", [((5.0, 5.0, 5.0), (2.0, 2.0, 2.0))], 19300.0))
    nested = write_step(top, tmp_path / "nested.step")
    plain = _run(capsys, ["massprops", str(nested)])
    assert plain[0] == 2 and "--resolve-overlaps" in plain[2] and len(computed) == 1
    again = _run(capsys, ["massprops", str(nested)])
    assert len(computed) == 1 and again[0] == 2
    assert again[2].endswith(plain[2]) and "from the cache" in again[2]
    # with --json, what was refused is counted as it is (a second entry), then both are kept
    first = _run(capsys, ["massprops", str(nested), "--json"])
    assert first[0] == 2 and json.loads(first[1])["refused"]["exit_status"] == 2
    n = len(computed)
    second = _run(capsys, ["massprops", str(nested), "--json"])
    assert len(computed) == n and second[:2] == first[:2]


def test_a_report_from_a_cached_result_is_the_computed_report(model, tmp_path, capsys, computed):
    """The second page reads no CAD (its views come from the cache: the same bytes); a view
    that shows something else (the envelope's box) is drawn afresh."""
    step, mats = model
    base = ["massprops", str(step), "--materials", str(mats)]
    assert main([*base, "--report", str(tmp_path / "one")]) == 0
    assert main([*base, "--report", str(tmp_path / "two")]) == 0  # no CAD read
    capsys.readouterr()
    one, two = (sorted((tmp_path / d).iterdir()) for d in ("one", "two"))
    assert [p.name for p in one] == [p.name for p in two] and len(computed) == 1
    for name in ("massprops.json", "views.png"):
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes()
    assert main([*base, "--form-factor", "1U", "--report", str(tmp_path / "three")]) == 0
    capsys.readouterr()
    assert len(computed) == 2  # the envelope's box is in the picture: drawn again
    assert (tmp_path / "three" / "views.png").read_bytes() != (
        tmp_path / "one" / "views.png"
    ).read_bytes()


def test_a_damaged_entry_is_computed_again(model, capsys, computed):
    step, mats = model
    argv = ["massprops", str(step), "--materials", str(mats), "--json"]
    first = _run(capsys, argv)
    folder = Path(os.environ["CADCOG_CACHE_DIR"])
    (entry,) = folder.glob("*.json")
    entry.write_text('{"format": 1, "result": {"refused": 3}}', encoding="utf-8")
    assert _run(capsys, argv)[1] == first[1] and len(computed) == 2


def test_a_pipe_is_never_opened_for_the_key(tmp_path, capsys):
    fifo = tmp_path / "model.step"
    os.mkfifo(fifo)
    status, _, err = _run(capsys, ["massprops", str(fifo), "--density-kg-m3", "1000"])
    assert status == 2 and f"{fifo}: " in err and "expected a regular file" in err


def test_a_cached_run_imports_no_cad_kernel(model):
    step, mats = model
    argv = ["massprops", str(step), "--materials", str(mats), "--json"]
    assert main(argv) == 0
    code = (
        "import sys\nfrom cadcog.cli import main\n"
        f"status = main({argv!r})\n"
        "loaded = sorted({m.split('.')[0] for m in sys.modules} & {'OCP', 'build123d'})\n"
        "print(status, loaded, file=sys.stderr)\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=os.environ.copy()
    )
    assert run.stderr.strip().endswith("0 []"), run.stderr
    assert len(json.loads(run.stdout)["bodies"]) > 0


def _multi_file_assembly(folder: Path, length_mm: float) -> Path:
    """``main.step`` naming two component files (``DOCUMENT_FILE``), as OCCT's multi-file
    export writes them; the second box ``length_mm`` long."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Trsf, gp_Vec
    from OCP.STEPCAFControl import STEPCAFControl_Writer
    from OCP.STEPControl import STEPControl_AsIs
    from OCP.TCollection import TCollection_ExtendedString
    from OCP.TDocStd import TDocStd_Document
    from OCP.TopLoc import TopLoc_Location
    from OCP.XCAFApp import XCAFApp_Application
    from OCP.XCAFDoc import XCAFDoc_DocumentTool

    from support.stepfixtures import _name

    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    XCAFApp_Application.GetApplication_s().InitDocument(doc)
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    a = tool.AddShape(BRepPrimAPI_MakeBox(10, 10, 10).Shape(), False)
    b = tool.AddShape(BRepPrimAPI_MakeBox(length_mm, 10, 10).Shape(), False)
    asm = tool.NewShape()
    for label, name in ((a, "partA"), (b, "partB"), (asm, "asm")):
        _name(label, name)
    move = gp_Trsf()
    move.SetTranslation(gp_Vec(50, 0, 0))
    tool.AddComponent(asm, a, TopLoc_Location())
    tool.AddComponent(asm, b, TopLoc_Location(move))
    tool.UpdateAssemblies()
    writer = STEPCAFControl_Writer()
    cwd = Path.cwd()
    os.chdir(folder)  # the component files are written beside the main one
    try:
        assert writer.Transfer(doc, STEPControl_AsIs, "comp")
        writer.Write("main.step")
    finally:
        os.chdir(cwd)
    return folder / "main.step"


def test_a_model_that_names_other_files_is_never_kept(tmp_path, capsys):
    main_step = _multi_file_assembly(tmp_path, 10.0)
    text = main_step.read_bytes()
    assert b"DOCUMENT_FILE" in text and len(list(tmp_path.glob("*.stp"))) == 2
    argv = ["massprops", str(main_step), "--density-kg-m3", "1000", "--json"]
    first = json.loads(_run(capsys, argv)[1])
    _multi_file_assembly(tmp_path, 30.0)  # a component changes...
    main_step.write_bytes(text)  # ...and the main file's bytes do not
    status, out, err = _run(capsys, argv)
    assert status == 0 and "from the cache" not in err
    assert json.loads(out)["mass_kg"] == pytest.approx(first["mass_kg"] * 4 / 2, rel=1e-9)
    assert not list(Path(os.environ["CADCOG_CACHE_DIR"]).glob("*.json"))


def test_a_file_changed_while_it_was_read_is_not_kept(model, monkeypatch, capsys):
    """Hashed as A, changed to B before it was read (an export still being written): B's result
    must not be kept under A's key, where A's bytes coming back (a checkout) would find it."""
    step, mats = model
    a_bytes = step.read_bytes()
    real = stepread.read_step

    def change_then_read(path):
        top = nested_three_levels()
        top.add(Part("late", [((1.0, 1.0, 1.0), (90.0, 0.0, 0.0))], 1000.0))
        write_step(top, step)
        return real(path)

    monkeypatch.setattr(stepread, "read_step", change_then_read)
    argv = ["massprops", str(step), "--materials", str(mats), "--json"]
    b_result = json.loads(_run(capsys, argv)[1])
    monkeypatch.setattr(stepread, "read_step", real)
    step.write_bytes(a_bytes)
    status, out, err = _run(capsys, argv)
    assert status == 0 and "from the cache" not in err
    assert json.loads(out)["mass_kg"] < b_result["mass_kg"]  # A's own result, computed


def test_an_error_that_may_pass_is_not_kept(model, monkeypatch, capsys):
    from cadcog.core.errors import CadcogError

    step, mats = model
    real = stepmass.model_mass_properties

    def once(*a, **k):
        monkeypatch.setattr(stepmass, "model_mass_properties", real)
        raise CadcogError(f"{step}: cannot read as STEP (std::bad_alloc)")

    monkeypatch.setattr(stepmass, "model_mass_properties", once)
    argv = ["massprops", str(step), "--materials", str(mats), "--json"]
    assert _run(capsys, argv)[0] == 2
    status, out, err = _run(capsys, argv)
    assert status == 0 and "from the cache" not in err and json.loads(out)["mass_kg"] > 0


def test_a_computation_that_fails_unexpectedly_keeps_nothing(model, monkeypatch, capsys):
    step, mats = model

    def broken(*a, **k):
        raise RuntimeError("a bug")

    monkeypatch.setattr(stepmass, "model_mass_properties", broken)
    with pytest.raises(RuntimeError, match="a bug"):
        main(["massprops", str(step), "--materials", str(mats), "--json"])
    assert not list(Path(os.environ["CADCOG_CACHE_DIR"]).glob("*.json"))


def test_a_cached_run_still_never_writes_over_its_inputs(model, capsys):
    step, mats = model
    before = step.read_bytes(), mats.read_bytes()
    assert main(["massprops", str(step), "--materials", str(mats), "--json"]) == 0
    for target in (step, mats):
        argv = ["massprops", str(step), "--materials", str(mats), "--csv", str(target)]
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert "from the cache" in err and str(target.name) in err.splitlines()[-1]
    assert (step.read_bytes(), mats.read_bytes()) == before
