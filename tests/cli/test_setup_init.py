"""``cadcog setup init``: a set-up file and a materials file drafted from one's own STEP."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.cli import main
from cadcog.mass.materials import load_materials
from cadcog.spacecraft.setup_draft import guess_form_factor
from tests.cad.stepfixtures import Assembly, Part, Place, write_step


@pytest.fixture(scope="module")
def sat_step(tmp_path_factory):
    """A 3U-sized frame (100 × 100 × 340.5 mm) holding two copies of a board and a battery."""
    top = Assembly("sat")
    top.add(Part("frame", [((100.0, 100.0, 5.0), (0.0, 0.0, 0.0))]))
    top.add(Part("lid", [((100.0, 100.0, 5.0), (0.0, 0.0, 335.5))]))
    board = Part("board", [((90.0, 90.0, 1.6), (5.0, 5.0, 0.0))])
    top.add(board, Place((0.0, 0.0, 100.0)))
    top.add(board, Place((0.0, 0.0, 200.0)))
    top.add(Part("battery", [((60.0, 60.0, 40.0), (20.0, 20.0, 20.0))]))
    return write_step(top, tmp_path_factory.mktemp("init") / "sat.step")


def test_the_draft_loads_as_a_set_up_and_lists_every_part(sat_step, tmp_path, capsys):
    from cadcog.spacecraft.setup import load_setup

    out = tmp_path / "mine_setup.toml"
    assert main(["setup", "init", str(sat_step), "--out", str(out)]) == 0
    assert "cadcog plan" in capsys.readouterr().out
    text = out.read_text(encoding="utf-8")
    assert 'form_factor = "3U"' in text
    materials = (tmp_path / "mine_materials.toml").read_text(encoding="utf-8")
    rules = [line for line in materials.splitlines() if line.startswith('# "') and "= ?" in line]
    # one commented rule per part name, the largest volume first (the frame and the lid tie)
    assert rules[0].split('"')[1] == "battery"
    assert sorted(r.split('"')[1] for r in rules) == ["battery", "board", "frame", "lid"]
    assert "2 bodies" in next(r for r in rules if '"board"' in r)
    load_materials(tmp_path / "mine_materials.toml")  # valid TOML with one default rule
    setup = load_setup(out)
    lo, hi = setup.bbox_mm
    np.testing.assert_allclose(hi - lo, [100.0, 100.0, 340.5], atol=1e-6)
    # the ME base at the centre of the +z face; candidates on the four side faces only
    np.testing.assert_allclose(setup.me_volumes[0].center_mm[2] >= hi[2] - 1e-6, True)
    normals = {tuple(np.round(c.normal).astype(int)) for c in setup.candidates}
    assert normals == {(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0)}
    # a draft never replaces a file, unless --force
    assert main(["setup", "init", str(sat_step), "--out", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert main(["setup", "init", str(sat_step), "--out", str(out), "--force"]) == 0


@pytest.mark.parametrize(
    ("extent", "expected"),
    [
        ((100, 100, 113.5), "1U"),
        ((104, 98, 230), "2U"),  # a little larger: rails, deployables
        ((226.3, 100, 366), "6U"),
        ((100, 100, 290), None),  # between 2U and 3U
        ((340.5, 100, 100), None),  # the long axis along x: not guessed
    ],
)
def test_form_factor_guess(extent, expected):
    assert guess_form_factor([0, 0, 0], extent) == expected
