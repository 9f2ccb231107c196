"""``cadcog/runs/setup_init.py``: where ``setup init`` writes its two files, for any name."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from cadcog.core.errors import CadcogError
from cadcog.runs.setup_init import draft_paths

STEMS = st.from_regex(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,20}", fullmatch=True)


@given(STEMS)
def test_without_out_both_files_go_beside_the_model_named_after_it(stem):
    model = Path("cad") / f"{stem}.step"
    setup, materials, name = draft_paths(model, None)
    assert setup.parent == materials.parent == model.parent
    assert setup.name == f"{model.stem}_setup.toml"
    assert materials.name == f"{model.stem}_materials.toml" and name == model.stem


@example("sat_setup")  # "o/sat_setup.toml" names the set-up "sat"
@given(STEMS)
def test_the_materials_file_goes_beside_the_set_up_given(stem):
    plain = stem.removesuffix("_setup")
    for out, expected in (
        (Path("o") / f"{stem}_setup.toml", stem),
        (Path("o") / f"{stem}.toml", plain),
    ):
        setup, materials, name = draft_paths(Path("m.step"), out)
        assert setup == out and materials == Path("o") / f"{name}_materials.toml"
        assert name == expected  # "_setup" is not repeated in the materials' name


@pytest.mark.parametrize("out", ["sat.json", "sat", "sat.toml.bak"])
def test_a_set_up_not_named_toml_is_refused_naming_the_option(out):
    with pytest.raises(CadcogError, match=rf"--out {out}: expected a file name ending in \.toml"):
        draft_paths(Path("m.step"), Path(out))
