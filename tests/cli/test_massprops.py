"""``cadcog massprops`` in-process: text, JSON, report, strictness and refusals."""

from __future__ import annotations

import json

import numpy as np
import pytest

from cadcog.cli import main
from cadcog.core.numformat import sig
from cadcog.mass.properties import combine
from support.stepfixtures import (
    Assembly,
    Part,
    Place,
    expected_boxes,
    nested_three_levels,
    square_face,
    write_step,
)

MATERIALS = """
[materials]
"*" = 1000.0
[mass_uncertainty]
"bracket" = 0.1
"*" = 0.05
[maturity_levels]
new = 0.2
[growth_allowance]
"base" = "new"
"""


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    d = tmp_path_factory.mktemp("massprops")
    step = write_step(nested_three_levels(), d / "sat.step")
    mats = d / "materials.toml"
    mats.write_text(MATERIALS, encoding="utf-8")
    return step, mats


def test_json_has_the_budget_inertia_frame_and_audit(model, capsys):
    step, mats = model
    args = ["massprops", str(step), "--materials", str(mats), "--json"]
    assert main([*args, "--about", "centre", "--axes", "+y,-x,+z", "--form-factor", "3U"]) == 0
    out = json.loads(capsys.readouterr().out)
    truth = combine(expected_boxes(nested_three_levels()))
    assert out["mass_kg"] == pytest.approx(truth.mass_kg)
    np.testing.assert_allclose(out["cog_mm"], truth.cog_mm, atol=1e-8)
    paths = [b["path"] for b in out["bodies"]]
    assert len(paths) == len(set(paths)) == 5
    assert out["budget"]["tree"]["name"] == "sat"
    assert out["budget"]["mass_sigma_kg"] > 0 and out["budget"]["growth_kg"] > 0
    products = out["inertia_kg_mm2"]["products"]
    assert products["positive"]["xy"] == pytest.approx(-products["negative"]["xy"])
    assert out["frame"]["axes"] == [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]
    lo, hi = np.array(out["audit"]["bbox_mm"])
    np.testing.assert_allclose(out["frame"]["origin_mm"], (lo + hi) / 2)
    assert out["envelope"]["limits_mm"] == [20.0, 20.0, 70.0]
    assert out["audit"]["declared_units"] == ["millimetre"]


def test_text_shows_the_tree_and_the_uncertainty(model, capsys):
    step, mats = model
    assert main(["massprops", str(step), "--materials", str(mats), "--depth", "1"]) == 0
    out = capsys.readouterr().out
    assert "declared unit millimetre" in out
    assert "\n  board " in out and "bracket[1]" not in out  # depth 1 only
    assert " ± " in out and "with growth allowances" in out
    assert "principal moments" in out


def test_report_is_written_whole(model, tmp_path, capsys):
    step, mats = model
    out = tmp_path / "report"
    args = ["massprops", str(step), "--materials", str(mats), "--report", str(out)]
    assert main([*args, "--form-factor", "3U"]) == 0
    page = (out / "index.html").read_text(encoding="utf-8")
    for section in ("Import audit", "Mass budget", "Inertia", "Views", "CoG envelope", "Bodies"):
        assert section in page
    assert "data:image/png;base64," in page
    assert json.loads((out / "massprops.json").read_text(encoding="utf-8"))["mass_kg"] > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]  # no staging left


def test_strict_turns_a_note_into_exit_2(tmp_path, capsys):
    top = Assembly("top")
    top.add(Part("box", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    top.add(Part("sheet", [], shapes=[square_face(20.0, 30.0)]))
    step = write_step(top, tmp_path / "sheet.step")
    assert main(["massprops", str(step), "--density-kg-m3", "1000"]) == 0
    assert "note: 1 surface body" in capsys.readouterr().out
    assert main(["massprops", str(step), "--density-kg-m3", "1000", "--strict"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("cadcog: error: ") and "--strict" in err and err.count("\n") == 1


def test_refusals_are_one_line_with_exit_2(model, tmp_path, capsys):
    step, _ = model
    top = Assembly("top")
    top.add(Part("outer", [((20.0, 20.0, 20.0), (0.0, 0.0, 0.0))], 2700.0))
    top.add(Part("inner", [((5.0, 5.0, 5.0), (2.0, 2.0, 2.0))], 19300.0))
    nested = write_step(top, tmp_path / "nested.step")
    for argv, text in [
        (["massprops", str(nested)], "--resolve-overlaps"),
        (["massprops", str(step)], "no density for 5 solid(s)"),
        (["massprops", str(step), "--density-kg-m3", "1e3", "--axes", "+x,+x,+z"], "orthonormal"),
        (["massprops", str(step), "--density-kg-m3", "2.7"], "is it in g/cm³?"),
        (["massprops", str(step), "--density-kg-m3", "-3"], "--density-kg-m3 -3.0: expected at"),
        (["massprops", str(tmp_path / "none.step"), "--density-kg-m3", "1e3"], "file not found"),
    ]:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert text in err and err.count("\n") == 1, (argv, err)
    assert main(["massprops", str(nested), "--resolve-overlaps", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["overlaps"]["n_pairs"] == 1 and out["overlaps"]["policy"] == "resolve"


def test_units_option_on_a_metre_file_never_scales_twice(tmp_path, capsys):
    step = write_step(nested_three_levels(), tmp_path / "m.step", metres=True)
    assert main(["massprops", str(step), "--density-kg-m3", "1000", "--units", "m", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    truth = combine(expected_boxes(nested_three_levels()))
    np.testing.assert_allclose(out["cog_mm"], truth.cog_mm, atol=1e-7)
    assert any("nothing scaled" in i for i in out["info"])


def test_a_refusal_still_writes_the_json_and_the_csv_and_exits_2(tmp_path, capsys):
    top = Assembly("top")
    top.add(Part("outer", [((20.0, 20.0, 20.0), (0.0, 0.0, 0.0))], 2700.0))
    top.add(Part("inner", [((5.0, 5.0, 5.0), (2.0, 2.0, 2.0))], 19300.0))
    nested = write_step(top, tmp_path / "nested.step")
    table = tmp_path / "budget.csv"
    assert main(["massprops", str(nested), "--json", "--csv", str(table)]) == 2
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    assert out["refused"]["exit_status"] == 2 and "--resolve-overlaps" in out["refused"]["error"]
    assert out["overlaps"]["n_pairs"] == 1 and out["overlaps"]["policy"] == "allow"
    # counted as it is: both boxes whole (20³ and 5³ mm³), each at its own density
    volumes = {b["path"].split("/")[-1]: b["volume_mm3"] for b in out["bodies"]}
    assert volumes == pytest.approx({"outer": 8000.0, "inner": 125.0})
    mass = sum(b["density_kg_m3"] * b["volume_mm3"] * 1e-9 for b in out["bodies"])
    assert out["mass_kg"] == pytest.approx(mass, rel=1e-12)
    assert captured.err.count("cadcog: error: ") == 1 and "report: " in captured.err
    rows = table.read_text(encoding="utf-8").splitlines()
    assert rows[0].startswith("kind,level,path,name,count") and len(rows) == 1 + 3 + 2


def test_csv_rows_add_up_and_name_the_product_convention(model, tmp_path, capsys):
    import csv

    step, mats = model
    table = tmp_path / "budget.csv"
    args = ["massprops", str(step), "--materials", str(mats), "--csv", str(table), "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    with table.open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    bodies = [r for r in rows if r["kind"] == "body"]
    assert len(bodies) == len(out["bodies"]) == 5
    assert sum(float(r["mass_kg"]) for r in bodies) == pytest.approx(out["mass_kg"], rel=1e-12)
    root = rows[0]
    assert root["kind"] == "node" and float(root["mass_kg"]) == pytest.approx(out["mass_kg"])
    products = out["inertia_kg_mm2"]["products"]["positive"]
    assert float(root["Pyz_kg_mm2 (+∫yz dm)"]) == pytest.approx(products["yz"], rel=1e-9)
    # a node's moments about the total's CoG add up to the total's moments
    level1 = [r for r in rows if r["kind"] == "node" and r["level"] == "1"]
    total_ixx = out["inertia_kg_mm2"]["tensor"][0][0]
    each = sum(float(r["Ixx_total_cog_kg_mm2"]) for r in level1 for _ in range(int(r["count"])))
    assert each == pytest.approx(total_ixx, rel=1e-9)
    # radius of gyration k = √(I/m) about the row's own CoG
    for r in bodies:
        assert float(r["kx_mm"]) ** 2 * float(r["mass_kg"]) == pytest.approx(
            float(r["Ixx_kg_mm2"]), rel=1e-9
        )


def test_text_groups_copies_names_the_convention_and_fits_small_masses(model, capsys):
    step, _ = model
    assert main(["massprops", str(step), "--density-kg-m3", "1000", "--depth", "3"]) == 0
    out = capsys.readouterr().out
    assert "bracket ×2" in out and "2 × 0.2" in out  # two brackets of 0.2 g each
    assert "total 7.6 g" in out  # 7600 mm³ at 1000 kg/m³, not "0.00760 kg"
    assert "Pxy = +∫xy dm" in out and "densities from --density-kg-m3 1000 ×5" in out
    assert main(["massprops", str(step), "--density-kg-m3", "1000", "--products", "negative"]) == 0
    assert "Ixy = −∫xy dm" in capsys.readouterr().out


def test_the_views_name_the_heaviest_parts_two_levels_down(model):
    from cadcog.cad.stepmass import model_mass_properties
    from cadcog.cad.stepread import read_step
    from cadcog.mass.materials import MaterialMap
    from cadcog.reports.massprops_report import view_labels
    from cadcog.spacecraft.mass_summary import build_mass_report

    step, _ = model
    result = model_mass_properties(read_step(step), MaterialMap.uniform(1000.0))
    labels = view_labels(build_mass_report(result))
    names = [name for name, _ in labels]
    assert names[0] == "base" and "bracket ×2" in names  # base 7.2 g; the brackets grouped
    masses = {r.path.rsplit("/", 1)[-1]: r.properties.mass_kg for r in result.bodies}
    assert masses["base"] == max(masses.values())


def test_surface_area_adds_a_column_and_keys_that_add_up_to_the_closed_form(
    model, tmp_path, capsys
):
    import csv

    step, mats = model
    table = tmp_path / "budget.csv"
    base = ["massprops", str(step), "--materials", str(mats)]
    assert main([*base, "--surface-area", "--csv", str(table), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # the boxes of the fixture: 2 (ab + bc + ca) each (faces shared by touching boxes twice)
    sizes = [size for _, size in _box_sizes(nested_three_levels())]
    want = sum(2 * (a * b + b * c + c * a) for a, b, c in sizes)
    assert sum(b["surface_area_mm2"] for b in out["bodies"]) == pytest.approx(want, rel=1e-9)
    assert out["budget"]["tree"]["surface_area_mm2"] == pytest.approx(want, rel=1e-9)
    with table.open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert float(rows[0]["surface_area_mm2"]) == pytest.approx(want, rel=1e-9)
    assert main([*base, "--surface-area"]) == 0
    text = capsys.readouterr().out
    assert "area (mm²)" in text and sig(want) in text
    assert main([*base, "--json"]) == 0  # not asked for: not computed, not in the JSON
    plain = json.loads(capsys.readouterr().out)
    assert "surface_area_mm2" not in plain["budget"]["tree"]
    assert all("surface_area_mm2" not in b for b in plain["bodies"])


def _box_sizes(root):
    """(path, size) of every box of a fixture assembly, whatever its placement."""
    out = []
    for child, _, _ in root.components:
        if hasattr(child, "components"):
            out.extend(_box_sizes(child))
        else:
            out.extend((child.name, size) for size, _ in child.boxes)
    return out


@pytest.mark.parametrize(
    ("instances", "exporter"),
    [
        (["48-0381:1", "48-0381:2", "48-0381:3"], "Inventor"),
        (["R1", "R7", "R12"], "KiCad reference designators"),
        (["screw-1", "screw-2", "screw-3"], "SolidWorks"),
        (["screw <1>", "screw <2>", "screw <3>"], "Onshape"),
    ],
)
def test_copies_are_grouped_by_their_product_whatever_their_instance_names(
    tmp_path, capsys, instances, exporter
):
    """Three placements of one product: one row "name ×3" with its mass each, in the text and
    the JSON's products, whatever names the exporter gave the instances."""
    screw = Part("48-0381", [((2.0, 2.0, 10.0), (0.0, 0.0, 0.0))])
    top = Assembly("sat")
    top.add(Part("plate", [((50.0, 50.0, 2.0), (0.0, 0.0, 0.0))]))
    for k, name in enumerate(instances):
        top.add(screw, Place((10.0 * (k + 1), 5.0, 2.0)), name)
    step = write_step(top, tmp_path / "copies.step")
    assert main(["massprops", str(step), "--density-kg-m3", "1000"]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if "×3" in line]
    assert len(rows) == 1, (exporter, out)
    assert "3 × 0.04" in rows[0]  # 40 mm³ at 1000 kg/m³: 0.04 g each
    assert not any(name in out for name in instances[1:]), out


def test_a_form_factor_the_box_does_not_match_is_a_note(tmp_path, capsys):
    """``--form-factor 3U`` on a 30 mm block: the envelope check runs as asked, and a note says
    the box is not a 3U's (it passed silently before)."""
    top = Assembly("block")
    top.add(Part("block", [((30.0, 30.0, 30.0), (0.0, 0.0, 0.0))], 1000.0, "ABS"))
    step = write_step(top, tmp_path / "block.step")
    assert main(["massprops", str(step), "--form-factor", "3U", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    (note,) = [n for n in data["notes"] if "form factor 3U" in n]
    assert "30 × 30 × 30 mm" in note and "is not a 3U's" in note
    assert "--axes" in note  # the way out, named
    # A 3U whose rails run along the model's x, checked in its CDS axes: no note. A PocketQube
    # form factor (no CubeSat box to compare): the check runs, no note, no crash.
    top = Assembly("sat")
    top.add(Part("sat", [((340.5, 100.0, 100.0), (0.0, 0.0, 0.0))], 1000.0, "Al"))
    sat = write_step(top, tmp_path / "sat.step")
    assert main(["massprops", str(sat), "--form-factor", "3U", "--axes", "+y,+z,+x", "--json"]) == 0
    assert not [n for n in json.loads(capsys.readouterr().out)["notes"] if "form factor" in n]
    assert main(["massprops", str(step), "--form-factor", "1p", "--json"]) == 0
    assert not [n for n in json.loads(capsys.readouterr().out)["notes"] if "form factor" in n]


def test_the_axes_of_equal_moments_are_said_to_be_not_unique(tmp_path, capsys):
    """A cube's three moments are equal, a 10 × 10 × 30 box's two: their axes got an angle
    from a model axis as if determined (new-user trial)."""
    for size, unique in (((10.0, 10.0, 10.0), 0), ((10.0, 10.0, 30.0), 1)):
        top = Assembly("sat")
        top.add(Part("box", [(size, (0.0, 0.0, 0.0))]))
        path = write_step(top, tmp_path / f"b{unique}.step")
        assert main(["massprops", str(path), "--density-kg-m3", "2700"]) == 0
        out = capsys.readouterr().out
        assert out.count("(not unique: see below)") == 3 - unique
        assert out.count("° from a model axis)") == unique
        assert "Pxy 0  Pxz 0  Pyz 0  (" in out  # products below round-off are 0, not 7.9e-17
