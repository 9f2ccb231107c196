"""Mass properties of STEP models: densities, units, surfaces, overlaps, strictness.

Expected values come from closed forms (boxes, composed with numpy in ``stepfixtures``), from
trimesh over an OCCT-exported mesh of the root compound, or from arithmetic on the fixture.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from cadcog.core.errors import CadcogError, ParameterFileError
from cadcog.mass.materials import LIBRARY, MaterialMap, load_materials
from cadcog.mass.properties import box_properties, combine
from support.stepfixtures import (
    Assembly,
    Part,
    Place,
    box_shape,
    cylinder,
    expected_boxes,
    kicad_like_board,
    nested_three_levels,
    square_face,
    write_step,
)

UNIFORM = MaterialMap.uniform(1000.0)


def _materials(tmp_path, text):
    path = tmp_path / "materials.toml"
    path.write_text(text, encoding="utf-8")
    return load_materials(path)


def _model(tmp_path, root, name="model", **kw):
    return read_step(write_step(root, tmp_path / f"{name}.step", **kw))


def _assert_props(got, want, *, rtol=1e-9):
    assert got.mass_kg == pytest.approx(want.mass_kg, rel=rtol)
    np.testing.assert_allclose(got.cog_mm, want.cog_mm, atol=1e-8 * (1 + np.abs(want.cog_mm).max()))
    scale = np.abs(want.inertia_kg_mm2).max()
    np.testing.assert_allclose(got.inertia_kg_mm2, want.inertia_kg_mm2, atol=rtol * scale)


# --- densities ---------------------------------------------------------------------------------
def test_two_materials_match_the_closed_form(tmp_path):
    top = Assembly("top")
    top.add(Part("alu_block", [((40.0, 20.0, 10.0), (0.0, 0.0, 0.0))]))
    top.add(Part("steel_block", [((10.0, 10.0, 30.0), (50.0, 0.0, 0.0))]))
    mats = _materials(tmp_path, '[materials]\n"alu*" = "aluminium 6061-T6"\n"steel*" = 7850.0\n')
    got = model_mass_properties(_model(tmp_path, top), mats).total
    want = combine(
        [
            box_properties([40, 20, 10], [20, 10, 5], mass_kg=2700e-9 * 8000),
            box_properties([10, 10, 30], [55, 5, 15], mass_kg=7850e-9 * 3000),
        ]
    )
    _assert_props(got, want)


def test_nested_assembly_mass_properties_match_numpy(tmp_path):
    sat = nested_three_levels()
    r = model_mass_properties(_model(tmp_path, sat), UNIFORM)
    _assert_props(r.total, combine(expected_boxes(sat)))
    assert r.audit.n_solids == 5 and not r.notes


def test_total_mass_scales_the_densities(tmp_path):
    top = Assembly("top")
    top.add(Part("a", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    top.add(Part("b", [((10.0, 10.0, 10.0), (20.0, 0.0, 0.0))]))
    model = _model(tmp_path, top)
    mats = _materials(tmp_path, '[materials]\n"a" = 1000.0\n"b" = 3000.0\n')
    r = model_mass_properties(model, mats, total_mass_kg=0.008)
    assert r.total.mass_kg == pytest.approx(0.008)
    assert [b.properties.mass_kg for b in r.bodies] == pytest.approx([0.002, 0.006])
    uniform = model_mass_properties(model, None, total_mass_kg=0.004)
    assert [b.properties.mass_kg for b in uniform.bodies] == pytest.approx([0.002, 0.002])


def test_step_materials_are_used_and_overridden_by_the_file(tmp_path):
    top = Assembly("top")
    top.add(Part("al", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))], 2700.0, "Al"))
    top.add(Part("cu", [((10.0, 10.0, 10.0), (20.0, 0.0, 0.0))], 8900.0, "Cu"))
    model = _model(tmp_path, top)
    r = model_mass_properties(model, None)
    assert [b.properties.mass_kg for b in r.bodies] == pytest.approx([2.7e-3, 8.9e-3])
    assert [b.density_source for b in r.bodies] == [
        "STEP material 'Al' (2700 kg/m³)",
        "STEP material 'Cu' (8900 kg/m³)",
    ]
    override = _materials(tmp_path, '[materials]\n"cu" = "copper C11000"\n')
    r2 = model_mass_properties(model, override)
    assert r2.bodies[0].density_source.startswith("STEP material")
    assert r2.bodies[1].density_kg_m3 == LIBRARY["copper C11000"].density_kg_m3


def test_a_catch_all_rule_fills_only_what_the_step_leaves_open(tmp_path):
    """The CAD's materials first: a drafted default "*" must not turn steel into aluminium."""
    top = Assembly("top")
    top.add(Part("screw", [((2.0, 2.0, 10.0), (0.0, 0.0, 0.0))], 8000.0, "Stainless Steel"))
    top.add(Part("bracket", [((10.0, 10.0, 10.0), (20.0, 0.0, 0.0))]))
    model = _model(tmp_path, top)
    mats = _materials(tmp_path, '[materials]\n"*" = "aluminium 6061-T6"\n')
    r = model_mass_properties(model, mats)
    rho = {b.path.rsplit("/", 1)[-1]: b.density_kg_m3 for b in r.bodies}
    assert rho == {"screw": 8000.0, "bracket": LIBRARY["aluminium 6061-T6"].density_kg_m3}
    # A named rule still overrides the STEP; one density for all (--density-kg-m3) does too.
    named = _materials(tmp_path, '[materials]\n"screw" = 7000.0\n"*" = 2700.0\n')
    assert model_mass_properties(model, named).bodies[0].density_kg_m3 == 7000.0
    uniform = model_mass_properties(model, MaterialMap.uniform(1234.0))
    assert {b.density_kg_m3 for b in uniform.bodies} == {1234.0}


def test_placeholder_materials_are_called_out_with_their_mass(tmp_path):
    """Inventor's "Generic" (1 g/cm³) is no material: said by name, with the mass it carries."""
    top = Assembly("top")
    top.add(Part("plunger", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))], 1000.0, "Generic"))
    top.add(Part("frame", [((10.0, 10.0, 10.0), (20.0, 0.0, 0.0))], 2700.0, "Aluminum 6061"))
    model = _model(tmp_path, top)
    r = model_mass_properties(model, None)
    said = [n for n in r.notes if "placeholder material 'Generic'" in n]
    assert len(said) == 1 and "1 g as counted" in said[0] and "plunger" in said[0], r.notes
    # A catch-all rule replaces a placeholder (not a real material), and says so.
    mats = _materials(tmp_path, '[materials]\n"*" = 2000.0\n')
    r2 = model_mass_properties(model, mats)
    assert [b.density_kg_m3 for b in r2.bodies] == [2000.0, 2700.0]
    assert any("catch-all rule gave them" in n for n in r2.notes), r2.notes


def test_a_rule_that_matches_nothing_is_a_note_naming_it(tmp_path):
    """A misspelt rule is silent in most tools: its bodies fall to the default rule."""
    model = _model(tmp_path, nested_three_levels())
    mats = _materials(
        tmp_path,
        '[materials]\n"plat*" = 1000.0\n"bracket_typo" = 2000.0\n"*" = 1000.0\n'
        '[mass_uncertainty]\n"board/bracket[2]" = 0.05\n"bord" = 0.1\n',
    )
    r = model_mass_properties(model, mats)
    flagged = [n for n in r.notes if "matches no body or assembly name" in n]
    assert len(flagged) == 2, r.notes
    assert "[materials] 'bracket_typo'" in flagged[0]
    assert "[mass_uncertainty] 'bord'" in flagged[1]
    # A path below the top assembly ("board/bracket[2]", without "sat/") names the item.
    assert {b.item for b in r.bodies if b.sigma_rel is not None} == {"sat/board/bracket[2]"}
    with pytest.raises(CadcogError, match="bracket_typo"):
        model_mass_properties(model, mats, strict=True)


def test_one_material_on_every_body_is_flagged_as_a_likely_default(tmp_path):
    top = Assembly("top")
    for k in range(3):
        top.add(Part(f"p{k}", [((5.0, 5.0, 5.0), (10.0 * k, 0.0, 0.0))], 7850.0, "Steel"))
    r = model_mass_properties(_model(tmp_path, top), None)
    assert any("same STEP material 'Steel'" in n for n in r.notes)
    with pytest.raises(CadcogError, match="--strict: 1 note"):
        model_mass_properties(_model(tmp_path, top), None, strict=True)


def test_one_solid_of_steel_is_flagged_as_fusions_likely_default(tmp_path):
    """One solid cannot show a stamp (FOSSASAT-1's Fusion 360 frame counted 38.9 g of
    'Steel', 13.4 g as aluminium, without a word): 'Steel' alone gets a note; another
    material alone does not."""
    top = Assembly("top")
    top.add(Part("frame", [((5.0, 5.0, 5.0), (0.0, 0.0, 0.0))], 7850.0, "Steel"))
    r = model_mass_properties(_model(tmp_path, top, "steel"), None)
    assert any("the one solid carries the STEP material 'Steel'" in n for n in r.notes), r.notes
    assert any(n.endswith("or give a materials file") for n in r.notes), r.notes
    # With a materials file whose catch-all rule leaves the STEP's own material in place (a
    # drafted file as a new user keeps it), the remedy is a rule that names the part.
    mats = _materials(tmp_path, '[materials]\n"*" = "aluminium 6061-T6"\n')
    r = model_mass_properties(_model(tmp_path, top, "steel2"), mats)
    assert {b.density_kg_m3 for b in r.bodies} == {7850.0}
    assert any("name the part in the materials file" in n for n in r.notes), r.notes
    other = Assembly("top")
    other.add(Part("frame", [((5.0, 5.0, 5.0), (0.0, 0.0, 0.0))], 2700.0, "Aluminum 6061"))
    assert not model_mass_properties(_model(tmp_path, other, "al"), None).notes


def test_solids_without_a_density_are_listed(tmp_path):
    top = Assembly("top")
    for name, x in (("rail", 0.0), ("board", 10.0), ("battery", 60.0)):
        top.add(Part(name, [((5.0, 5.0, 5.0), (x, 0.0, 0.0))]))
    mats = _materials(tmp_path, '[materials]\n"rail*" = "aluminium 6061-T6"\n')
    with pytest.raises(CadcogError, match=r"no density for 2 solid\(s\): top/board, top/battery"):
        model_mass_properties(_model(tmp_path, top), mats)


def test_materials_file_errors_name_the_key(tmp_path):
    with pytest.raises(ParameterFileError, match="unknown material 'unobtainium'"):
        _materials(tmp_path, '[materials]\n"*" = "unobtainium"\n')
    with pytest.raises(ParameterFileError, match="is it in g/cm³"):
        _materials(tmp_path, '[materials]\n"*" = 2.7\n')
    with pytest.raises(ParameterFileError, match="'2700' is a number written as text") as info:
        _materials(tmp_path, '[materials]\n"*" = "2700"\n')
    assert len(str(info.value)) < 200 + len(str(tmp_path))  # one short line, not the library
    with pytest.raises(ParameterFileError, match=r"key 'growth_allowance\.x'.*unknown maturity"):
        _materials(tmp_path, '[growth_allowance]\n"x" = "new"\n')
    with pytest.raises(ParameterFileError, match=r"key 'mass_uncertainty\.x'.*fraction"):
        _materials(tmp_path, '[mass_uncertainty]\n"x" = 5\n')
    # A misspelt table is named, with the tables a materials file may hold and a suggestion.
    with pytest.raises(
        ParameterFileError, match=r"key 'material'.*did you mean 'materials'.*growth_allowance"
    ):
        _materials(tmp_path, '[material]\n"*" = "FR-4"\n')


# --- units -------------------------------------------------------------------------------------
def test_metre_file_needs_no_option_and_units_never_scale_twice(tmp_path):
    sat = nested_three_levels()
    model = _model(tmp_path, sat, metres=True)
    want = combine(expected_boxes(sat))
    r = model_mass_properties(model, UNIFORM)
    _assert_props(r.total, want)
    assert r.audit.declared_units == ("metre",)
    again = model_mass_properties(model, UNIFORM, units="m")  # the declaration was right
    _assert_props(again.total, want)
    assert any("already declares metre; nothing scaled" in i for i in again.info)


def test_units_override_a_wrong_declaration(tmp_path):
    """A file declaring mm whose numbers are metres (a 0.1 m box written as 0.1 'mm')."""
    part = Part("sat", [((0.1, 0.1, 0.34), (0.0, 0.0, 0.0))])
    model = _model(tmp_path, part)
    r = model_mass_properties(model, MaterialMap.uniform(2700.0))
    assert any("spans 0.34 mm" in n and "--units" in n for n in r.notes)  # a note, no refusal
    fixed = model_mass_properties(model, MaterialMap.uniform(2700.0), units="m")
    assert fixed.total.mass_kg == pytest.approx(2700 * 0.1 * 0.1 * 0.34)
    np.testing.assert_allclose(fixed.total.cog_mm, [50, 50, 170])
    assert fixed.audit.scale_to_mm == 1000.0 and not fixed.notes


def test_small_chip_is_a_note_not_a_refusal(tmp_path):
    chip = Part("chip", [((0.84, 0.84, 0.5), (0.0, 0.0, 0.0))])
    r = model_mass_properties(_model(tmp_path, chip), MaterialMap.uniform(2300.0))
    assert r.total.mass_kg == pytest.approx(2300e-9 * 0.84 * 0.84 * 0.5)
    assert any("spans 0.84 mm" in n for n in r.notes)


def test_inch_model_is_flagged_by_the_weighed_mass(tmp_path):
    part = Part("sat", [((3.94, 3.94, 13.4), (0.0, 0.0, 0.0))])
    r = model_mass_properties(_model(tmp_path, part), None, total_mass_kg=4.0)
    assert any("mean density" in n and "--units" in n for n in r.notes)
    fixed = model_mass_properties(_model(tmp_path, part), None, total_mass_kg=4.0, units="in")
    np.testing.assert_allclose(fixed.total.cog_mm, np.array([3.94, 3.94, 13.4]) / 2 * 25.4)


# --- surfaces, exclusion, bad solids ------------------------------------------------------------
def _with_sheet(tmp_path):
    top = Assembly("top")
    top.add(Part("box", [((10.0, 10.0, 10.0), (-5.0, -5.0, 0.0))]))
    top.add(Part("mli_sheet", [], shapes=[square_face(20.0, 30.0)]))
    return _model(tmp_path, top)


def test_surface_bodies_are_left_out_with_their_area(tmp_path):
    r = model_mass_properties(_with_sheet(tmp_path), UNIFORM)
    assert r.audit.n_surfaces == 1
    assert r.audit.left_out_surfaces[0] == ("top/mli_sheet", pytest.approx(400.0))
    assert r.total.mass_kg == pytest.approx(1e-6 * 1000)
    assert any("1 surface body (400 mm²" in n for n in r.notes)


def test_surface_bodies_take_an_areal_density(tmp_path):
    mats = _materials(tmp_path, '[materials]\n"*" = 1000.0\n[surfaces]\n"mli*" = 0.5\n')
    r = model_mass_properties(_with_sheet(tmp_path), mats)
    sheet = next(b for b in r.bodies if b.kind == "surface")
    assert sheet.properties.mass_kg == pytest.approx(0.5 * 400e-6)
    np.testing.assert_allclose(sheet.properties.cog_mm, [0, 0, 30], atol=1e-9)
    # a 20 mm square plate of mass m: Ixx = Iyy = m a²/12, Izz = m a²/6
    m = 0.5 * 400e-6
    np.testing.assert_allclose(
        np.diag(sheet.properties.inertia_kg_mm2), [m * 400 / 12, m * 400 / 12, m * 400 / 6]
    )
    kapton = _materials(
        tmp_path,
        '[materials]\n"*" = 1000.0\n[surfaces]\n'
        '"mli*" = { material = "polyimide (Kapton)", thickness_mm = 0.025 }\n',
    )
    r2 = model_mass_properties(_with_sheet(tmp_path), kapton)
    sheet2 = next(b for b in r2.bodies if b.kind == "surface")
    assert sheet2.properties.mass_kg == pytest.approx(1420 * 0.025e-3 * 400e-6)


def test_inverted_solid_is_refused_unless_excluded_first(tmp_path):
    from dataclasses import replace

    model = _model(tmp_path, nested_three_levels())
    bad = model.bodies[0]
    inverted = replace(
        bad,
        shape=bad.shape.Reversed(),
        local_shape=bad.local_shape.Reversed(),
        product_key="inverted",
    )
    broken = replace(model, bodies=(inverted, *model.bodies[1:]))
    with pytest.raises(CadcogError, match=f"zero or negative volume: {re.escape(bad.path)}"):
        model_mass_properties(broken, UNIFORM)
    r = model_mass_properties(broken, UNIFORM, exclude=[bad.path])
    assert r.audit.excluded == (bad.path,) and r.audit.n_solids == 4


def test_exclude_matches_assemblies_and_reports_unmatched_patterns(tmp_path):
    model = _model(tmp_path, nested_three_levels())
    r = model_mass_properties(model, UNIFORM, exclude=["*/bracket[2]", "nothing*"])
    assert r.audit.n_solids == 3
    assert all("bracket[2]" not in b.path for b in r.bodies)
    assert any("--exclude 'nothing*' matched no body" in n for n in r.notes)


# --- overlaps ----------------------------------------------------------------------------------
def _nested_blocks(tmp_path, inner_density):
    """A 20 mm aluminium cube with a 5 mm dense cube modelled inside it (a vendor model)."""
    top = Assembly("top")
    top.add(Part("outer", [((20.0, 20.0, 20.0), (0.0, 0.0, 0.0))], 2700.0, "Al"))
    top.add(Part("inner", [((5.0, 5.0, 5.0), (2.0, 2.0, 2.0))], inner_density, "W"))
    return _model(tmp_path, top)


def test_large_overlap_is_refused_with_a_short_summary(tmp_path):
    model = _nested_blocks(tmp_path, 19300.0)
    with pytest.raises(CadcogError, match=r"1 overlapping pair\(s\): 125 mm³ and") as err:
        model_mass_properties(model, None)
    assert len(str(err.value)) < 600 and "--resolve-overlaps" in str(err.value)


def test_allow_overlap_counts_each_solid_as_it_is(tmp_path):
    r = model_mass_properties(_nested_blocks(tmp_path, 19300.0), None, overlaps="allow")
    assert r.total.mass_kg == pytest.approx(2700e-9 * 8000 + 19300e-9 * 125)
    s = r.overlaps
    assert s.mass_kg == pytest.approx(2700e-9 * 125)  # the lighter density counted twice
    assert s.pairs[0].kept_by == "top/inner"


def test_resolve_overlaps_lets_the_denser_keep_the_common_volume(tmp_path):
    r = model_mass_properties(_nested_blocks(tmp_path, 19300.0), None, overlaps="resolve")
    want = combine(
        [
            box_properties([20, 20, 20], [10, 10, 10], mass_kg=2700e-9 * 8000),
            box_properties([5, 5, 5], [4.5, 4.5, 4.5], mass_kg=(19300 - 2700) * 1e-9 * 125),
        ]
    )
    _assert_props(r.total, want, rtol=1e-8)
    outer = next(b for b in r.bodies if b.path == "top/outer")
    assert outer.removed_mm3 == pytest.approx(125.0)
    # The CoG shift the summary predicted is the one resolution made.
    as_is = model_mass_properties(_nested_blocks(tmp_path, 19300.0), None, overlaps="allow")
    np.testing.assert_allclose(
        as_is.total.cog_mm - r.total.cog_mm, r.overlaps.cog_shift_mm, atol=1e-9
    )


def test_three_solids_sharing_a_region_are_counted_exactly(tmp_path):
    """Nested cubes (densities 1000 < 2000 < 3000): the innermost region lies in all three.
    Counting each as it is adds the inner 8 mm³ twice and the middle shell once; the summary
    must say so (pairwise sums would add the inner cube three times), and resolving must
    remove exactly that."""
    top = Assembly("top")
    top.add(Part("a", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))], 1000.0, "A"))
    top.add(Part("b", [((4.0, 4.0, 4.0), (1.0, 1.0, 1.0))], 2000.0, "B"))
    top.add(Part("c", [((2.0, 2.0, 2.0), (2.0, 2.0, 2.0))], 3000.0, "C"))
    model = _model(tmp_path, top)
    r = model_mass_properties(model, None, overlaps="allow")
    # a loses b's 64 mm³ (1000 kg/m³); b loses c's 8 mm³ (2000 kg/m³).
    assert r.overlaps.volume_mm3 == pytest.approx(64 + 8)
    assert r.overlaps.mass_kg == pytest.approx((64 * 1000 + 8 * 2000) * 1e-9)
    # The pairs each list their own common volume (a&b 64 mm³, a&c 8, b&c 8 at the lighter
    # density: 0.088 g); the headline's total (0.08 g) says why the two differ.
    pairs = sum(p.mass_kg for p in r.overlaps.pairs)
    assert pairs == pytest.approx((64 * 1000 + 8 * 1000 + 8 * 2000) * 1e-9)
    assert "0.08 g counted more than once" in r.overlaps.headline()
    assert "the pairs' own shares sum to 0.088 g" in r.overlaps.headline()
    resolved = model_mass_properties(model, None, overlaps="resolve")
    assert r.total.mass_kg - resolved.total.mass_kg == pytest.approx(r.overlaps.mass_kg)
    np.testing.assert_allclose(
        r.total.cog_mm - resolved.total.cog_mm, r.overlaps.cog_shift_mm, atol=1e-12
    )
    want = combine(
        [
            box_properties([10, 10, 10], [5, 5, 5], mass_kg=1000e-9 * 1000),
            box_properties([4, 4, 4], [3, 3, 3], mass_kg=1000e-9 * 64),
            box_properties([2, 2, 2], [3, 3, 3], mass_kg=1000e-9 * 8),
        ]
    )
    _assert_props(resolved.total, want, rtol=1e-9)


def test_total_mass_scaling_scales_the_overlap_masses(tmp_path):
    model = _nested_blocks(tmp_path, 19300.0)
    r = model_mass_properties(model, None, overlaps="allow")
    assert "pairs' own shares" not in r.overlaps.headline()  # one pair: nothing to explain
    scaled = model_mass_properties(model, None, overlaps="allow", total_mass_kg=2 * r.total.mass_kg)
    assert scaled.overlaps.mass_kg == pytest.approx(2 * r.overlaps.mass_kg)
    assert scaled.overlaps.pairs[0].mass_kg == pytest.approx(2 * r.overlaps.pairs[0].mass_kg)
    assert scaled.overlaps.mass_fraction == pytest.approx(r.overlaps.mass_fraction)


def test_touching_solids_are_contact_not_overlap(tmp_path):
    """Boxes sharing a face are pruned by their boxes; a pin line-on-line in its hole passes
    the box test and is found to be contact by the boolean."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut

    top = Assembly("top")
    top.add(Part("a", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    top.add(Part("b", [((10.0, 10.0, 10.0), (10.0, 0.0, 0.0))]))  # shares a face
    plate = BRepAlgoAPI_Cut(
        box_shape((20.0, 20.0, 5.0), (-10.0, -10.0, 0.0)), cylinder(2.0, 5.0)
    ).Shape()
    top.add(Part("plate", [], shapes=[plate]), Place((50.0, 0.0, 0.0)))
    top.add(Part("pin", [], shapes=[cylinder(2.0, 5.0)]), Place((50.0, 0.0, 0.0)))
    r = model_mass_properties(_model(tmp_path, top), UNIFORM)
    assert not r.overlaps.pairs
    assert r.overlaps.n_candidates == 1 and r.overlaps.n_contact == 1


def test_small_overlap_below_the_threshold_is_a_note(tmp_path):
    board = kicad_like_board(8, pin_depth_mm=0.05)
    r = model_mass_properties(_model(tmp_path, board), None)
    assert len(r.overlaps.pairs) == 16  # two pins per component sink into the PCB
    assert r.overlaps.volume_mm3 == pytest.approx(16 * 0.6 * 0.6 * 0.05, rel=1e-6)
    assert r.overlaps.mass_fraction < 1e-3
    assert any("under the refusal threshold" in n for n in r.notes)


def test_instanced_overlaps_match_a_direct_boolean(tmp_path):
    """Pairs sharing a cached boolean give what a fresh boolean of the placed solids gives."""
    from cadcog.cad.overlaps import common_volume

    model = _model(tmp_path, kicad_like_board(10))
    r = model_mass_properties(model, None, overlaps="allow")
    by_path = {b.path: b for b in model.bodies}
    for pair in r.overlaps.pairs:
        direct = common_volume(by_path[pair.a].shape, by_path[pair.b].shape)
        assert direct is not None and direct.volume_mm3 == pytest.approx(pair.volume_mm3)


def test_parallel_and_serial_give_the_same_result(tmp_path):
    model = _model(tmp_path, kicad_like_board(16))
    one = model_mass_properties(model, None, overlaps="allow", workers=1)
    two = model_mass_properties(model, None, overlaps="allow", workers=2)
    assert one.to_dict() == two.to_dict()


# --- independent mesh check ---------------------------------------------------------------------
def test_trimesh_of_an_occt_mesh_agrees(tmp_path):
    """Volume and centroid from trimesh over an STL of the root compound (uniform density)."""
    trimesh = pytest.importorskip("trimesh")
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.STEPControl import STEPControl_Reader
    from OCP.StlAPI import StlAPI_Writer

    path = write_step(nested_three_levels(), tmp_path / "nested.step")
    reader = STEPControl_Reader()
    reader.ReadFile(str(path))
    reader.TransferRoots()
    shape = reader.OneShape()
    BRepMesh_IncrementalMesh(shape, 1e-3, False, 0.1, True).Perform()
    writer = StlAPI_Writer()
    writer.Write(shape, str(tmp_path / "nested.stl"))
    mesh = trimesh.load(tmp_path / "nested.stl")
    r = model_mass_properties(read_step(path), UNIFORM)
    assert mesh.volume == pytest.approx(r.total.volume_mm3, rel=1e-6)
    np.testing.assert_allclose(mesh.center_mass, r.total.cog_mm, atol=1e-4)
    # every face of every solid is in the mesh (planar: triangulated exactly)
    areas = model_mass_properties(read_step(path), UNIFORM, surface_areas=True)
    assert mesh.area == pytest.approx(sum(b.surface_area_mm2 for b in areas.bodies), rel=1e-9)


# --- surface areas ------------------------------------------------------------------------------
def test_surface_areas_match_closed_forms_and_follow_instances_and_units(tmp_path):
    top = Assembly("top")
    block = Part("block", [((10.0, 20.0, 30.0), (0.0, 0.0, 0.0))])
    top.add(block, instance="a")
    top.add(block, Place((50.0, 0.0, 0.0), (1.0, 1.0, 0.0), 33.0), instance="b")  # rotated copy
    top.add(Part("rod", [], shapes=[cylinder(3.0, 10.0)]), Place((0.0, 60.0, 0.0)))
    top.add(Part("mli_sheet", [], shapes=[square_face(20.0, 40.0)]))
    mats = _materials(tmp_path, '[materials]\n"*" = 1000.0\n[surfaces]\n"mli*" = 0.5\n')
    want = {"block": 2 * (200 + 300 + 600), "rod": 2 * np.pi * 9 + 2 * np.pi * 3 * 10}
    want["mli_sheet"] = 400.0
    for metres in (False, True):  # a file in metres: areas scale by 1000² to mm²
        model = _model(tmp_path, top, name=f"areas{metres}", metres=metres)
        r = model_mass_properties(model, mats, surface_areas=True)
        got = {b.path: b.surface_area_mm2 for b in r.bodies}
        assert len(got) == 4
        for path, area in got.items():
            name = {"a": "block", "b": "block"}.get(path.split("/")[1], path.split("/")[1])
            assert area == pytest.approx(want[name], rel=1e-9), path
        sheet = next(b for b in r.bodies if b.kind == "surface")
        assert sheet.surface_area_mm2 == pytest.approx(sheet.to_dict()["area_mm2"], rel=1e-12)
    plain = model_mass_properties(model, mats)  # not asked for: absent, the JSON unchanged
    assert all(b.surface_area_mm2 is None for b in plain.bodies)
    assert all("surface_area_mm2" not in b.to_dict() for b in plain.bodies)
    assert plain.total.to_dict() == r.total.to_dict()


# --- uncertainty and growth items ---------------------------------------------------------------
def test_uncertainty_rules_pick_items_and_growth(tmp_path):
    mats = _materials(
        tmp_path,
        '[materials]\n"*" = 1000.0\n'
        '[mass_uncertainty]\n"bracket" = 0.1\n"*" = 0.02\n'
        "[maturity_levels]\nnew = 0.2\n"
        '[growth_allowance]\n"base" = "new"\n',
    )
    r = model_mass_properties(_model(tmp_path, nested_three_levels()), mats)
    items = {b.path: (b.item, b.sigma_rel, b.growth, b.growth_label) for b in r.bodies}
    assert items["sat/board/bracket[1]/plate[2]"] == ("sat/board/bracket[1]", 0.1, 0.0, "")
    assert items["sat/base"] == ("sat/base", 0.02, 0.2, "new")


# --- the example CubeSat ------------------------------------------------------------------------
def test_cubesat_round_trip_matches_the_spec_closed_form(tmp_path):
    """Built as an instanced, nested assembly; compared with boxes and a cylinder computed
    from the spec's numbers alone."""
    from cadcog.cad.assembly import write_assembly
    from cadcog.cad.cubesat import build_cubesat, load_cubesat
    from cadcog.mass.properties import cylinder_properties
    from cadcog.rig.file import default_rig_path

    spec = load_cubesat(default_rig_path().parent / "cubesat_3u.toml")
    asm, mats = build_cubesat(spec)
    path = tmp_path / "cubesat.step"
    write_assembly(asm, path)
    model = read_step(path)
    assert model.n_products < model.n_instances  # rails, panels and plates are instanced
    r = model_mass_properties(model, MaterialMap(tuple(mats.items())))
    w, rail, t, h = spec.width_mm / 2, spec.rail_mm, spec.panel_mm, spec.length_mm / 2
    inner = w - rail
    rho = LIBRARY[spec.structure_material].density_kg_m3 * 1e-9

    def box(lo, hi, density):
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        return box_properties(hi - lo, (lo + hi) / 2, mass_kg=density * np.prod(hi - lo))

    parts = [box([w - rail, w - rail, -h], [w, w, h], rho)]
    parts += [box([-w, w - rail, -h], [rail - w, w, h], rho)]
    parts += [box([-w, -w, -h], [rail - w, rail - w, h], rho)]
    parts += [box([w - rail, -w, -h], [w, rail - w, h], rho)]
    parts += [
        box([w - t, -inner, -h], [w, inner, h], rho),
        box([-w, -inner, -h], [t - w, inner, h], rho),
    ]
    parts += [
        box([-inner, w - t, -h], [inner, w, h], rho),
        box([-inner, -w, -h], [inner, t - w, h], rho),
    ]
    parts += [box([-inner, -inner, h - t], [inner, inner, h], rho)]
    parts += [box([-inner, -inner, -h], [inner, inner, t - h], rho)]
    for c in spec.components:
        density = LIBRARY[c.material].density_kg_m3 * 1e-9
        if c.size_mm is not None:
            lo, hi = c.bounds()
            parts.append(box(lo, hi, density))
        else:
            d, length = c.cylinder
            base = np.asarray(c.center_mm) - [0, 0, length / 2]
            parts.append(
                cylinder_properties(base, [0, 0, 1], d / 2, length, density_kg_mm3=density)
            )
    _assert_props(r.total, combine(parts), rtol=1e-9)
    assert {b.path.rsplit("/", 1)[-1] for b in r.bodies} == set(mats)


def test_a_catch_all_rule_over_one_stamped_material_is_said(tmp_path):
    """Every solid carries 'Steel' (Fusion 360's default): the catch-all rule replaces it, as
    asked, and the info says so, naming the STEP's material (not a note: nothing to fix)."""
    top = Assembly("top")
    for k in range(3):
        top.add(Part(f"p{k}", [((5.0, 5.0, 5.0), (10.0 * k, 0.0, 0.0))], 7850.0, "Steel"))
    mats = _materials(tmp_path, '[materials]\n"*" = 1850.0\n')
    r = model_mass_properties(_model(tmp_path, top), mats)
    assert {b.density_kg_m3 for b in r.bodies} == {1850.0}
    assert any("same STEP material on every solid" in i and "'Steel'" in i for i in r.info)
    assert not any("Steel" in n for n in r.notes)
