"""``cadcog/cad/massrules.py``: which density a solid takes, and what the run says about it."""

from __future__ import annotations

import pytest

pytest.importorskip("build123d")

from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from cadcog.mass.materials import MaterialMap
from support.stepfixtures import Assembly, Part, write_step


@pytest.fixture(scope="module")
def two_materials(tmp_path_factory):
    """Two aluminium plates and a steel pin, each with its own STEP material, in a 'JST'
    connector assembly (a rule matching the assembly matches all three)."""
    top = Assembly("board")
    jst = Assembly("JST_header")
    jst.add(Part("plate_a", [((10.0, 10.0, 2.0), (0.0, 0.0, 0.0))], 2700.0, "Aluminium"))
    jst.add(Part("plate_b", [((10.0, 10.0, 2.0), (0.0, 0.0, 5.0))], 2700.0, "Aluminium"))
    jst.add(Part("pin", [((1.0, 1.0, 8.0), (20.0, 0.0, 0.0))], 7850.0, "Steel"))
    top.add(jst)
    path = tmp_path_factory.mktemp("rules") / "board.step"
    write_step(top, path)
    return read_step(path)


def test_a_named_rule_over_the_steps_own_material_is_said(two_materials):
    """A rule matching an assembly's name gives every solid in it its density, over their own
    STEP materials (the documented order): an info line says which and what they had (a
    new-user trial saw the pins' steel replaced without a word)."""
    rules = MaterialMap((("*JST*", 1400.0),), source="m.toml")
    result = model_mass_properties(two_materials, rules)
    assert {b.density_kg_m3 for b in result.bodies} == {1400.0}
    lines = [i for i in result.info if "took materials rule '*JST*'" in i]
    assert len(lines) == 2  # one per STEP material replaced
    steel = next(i for i in lines if "'Steel'" in i)
    assert steel.startswith("1 solid(s) with their own STEP material 'Steel' (7850 kg/m³)")
    assert "pin" in steel and 'a catch-all "*" does not' in steel
    assert any(i.startswith("2 solid(s) with their own STEP material 'Aluminium'") for i in lines)
    assert not result.notes  # what the file asked for: information, not a note (--strict)


def test_a_catch_all_rule_leaves_the_steps_materials_and_says_nothing(two_materials):
    result = model_mass_properties(two_materials, MaterialMap((("*", 1400.0),), source="m.toml"))
    assert sorted(b.density_kg_m3 for b in result.bodies) == [2700.0, 2700.0, 7850.0]
    assert not any("took materials rule" in i for i in result.info)


def test_a_rule_of_the_same_density_as_the_step_is_not_an_override(two_materials):
    result = model_mass_properties(two_materials, MaterialMap((("*pin*", 7850.0),), source="m"))
    assert not any("took materials rule" in i for i in result.info)


def test_one_density_for_every_solid_is_asked_for_and_not_reported(two_materials):
    """``--density-kg-m3`` (a catch-all that overrides the STEP's materials) is what the user
    asked for: no info line per solid."""
    result = model_mass_properties(two_materials, MaterialMap.uniform(1000.0))
    assert {b.density_kg_m3 for b in result.bodies} == {1000.0}
    assert not any("took materials rule" in i for i in result.info)
