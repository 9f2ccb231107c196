"""Arguments of the wrong kind reach the library from the API (issue 21): each is a
CadcogError (or the ValueError the API turns into one) naming the argument, never an
AttributeError from deep inside."""

from __future__ import annotations

import pytest

from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from cadcog.core.arguments import check_choice, check_text
from cadcog.core.errors import CadcogError
from cadcog.mass.inertia import Frame
from cadcog.mass.materials import MaterialMap
from support.stepfixtures import Assembly, Part, write_step


def test_an_unknown_overlap_policy_is_a_user_error(tmp_path):
    top = Assembly("sat")
    top.add(Part("box", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    model = read_step(write_step(top, tmp_path / "m.step"))
    with pytest.raises(
        CadcogError, match=r"overlaps: expected check, allow, resolve or skip, got 'maybe'"
    ):
        model_mass_properties(model, MaterialMap.uniform(2700.0), overlaps="maybe")  # type: ignore[arg-type]


@pytest.mark.parametrize("axes", [["+x", "+y", "+z"], None, 3])
def test_axes_that_are_not_text_are_a_value_error_naming_the_kind(axes):
    with pytest.raises(ValueError, match=rf"\(a str\), got {type(axes).__name__} "):
        Frame.parse(axes, (0.0, 0.0, 0.0))


def test_the_api_helpers_name_function_argument_and_expectation():
    with pytest.raises(CadcogError, match=r"^mass_properties\(overlaps='maybe'\): expected one of"):
        check_choice("mass_properties", "overlaps", "maybe", ("check", "allow", "resolve"))
    with pytest.raises(CadcogError, match=r"^mass_properties\(axes=\['\+x'\]\): expected a str"):
        check_text("mass_properties", "axes", ["+x"], "'+y,-x,+z'")
    check_text("mass_properties", "axes", "+y,-x,+z", "'+y,-x,+z'")
