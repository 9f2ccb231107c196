"""Flat assemblies: the private parent records give every body exactly as OCCT's own transfer."""

from __future__ import annotations

import re

import numpy as np
import pytest

from cadcog.cad import flatassembly, stepread
from cadcog.cad.occt import volume_properties
from support.stepfixtures import Assembly, Part, Place, kicad_like_board, write_step


def _read(path, monkeypatch, min_siblings):
    """read_step with the pass's threshold set; returns the model and how many it changed."""
    changed = []
    real = flatassembly.isolate_sibling_placements

    def counted(step_reader, threshold=None):
        changed.append(real(step_reader, threshold))
        return changed[-1]

    with monkeypatch.context() as m:
        m.setattr(flatassembly, "MIN_SIBLINGS", min_siblings)
        m.setattr(stepread, "isolate_sibling_placements", counted)
        model = stepread.read_step(path)
    assert len(changed) == 1
    return model, changed[0]


def _described(model):
    rows = []
    for b in model.bodies:
        t = b.placement.Transformation()
        props = volume_properties(b.shape)
        rows.append(
            (
                b.path,
                b.kind,
                b.product_key,
                b.material,
                b.made_from_shell,
                tuple(t.Value(i, j) for i in (1, 2, 3) for j in (1, 2, 3, 4)),
                props.volume_mm3,
                tuple(props.cog_mm),
            )
        )
    return rows, model.n_products, model.n_instances, model.declared_units


def _flat_model() -> Assembly:
    """12 products under one root (rotated, one placed twice) and a sub-assembly of two."""
    top = Assembly("flat")
    twice = Part("twice", [((3.0, 2.0, 1.0), (0.5, 0.0, 0.0))], density_kg_m3=2700.0)
    for k in range(10):
        top.add(
            Part(f"block_{k}", [((5.0, 4.0 + k, 3.0), (0.0, 0.0, 0.0))]),
            Place((10.0 * k, 3.0, -2.0), (0, 0.6, 0.8), 17.0 * k),
        )
    top.add(twice, Place((0, 50, 0), (1, 0, 0), 90.0), "first")
    top.add(twice, Place((0, 60, 0)), "second")
    sub = Assembly("sub")
    sub.add(Part("inner", [((1.0, 1.0, 1.0), (0.0, 0.0, 0.0))]), Place((1, 2, 3), (0, 0, 1), 45))
    sub.add(Part("inner2", [((2.0, 1.0, 1.0), (0.0, 0.0, 0.0))]), Place((-1, 2, 3)))
    top.add(sub, Place((100, 0, 0), (0, 1, 0), 30.0))
    return top


def _placements_in(path) -> int:
    return path.read_text(encoding="utf-8").count("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(")


@pytest.mark.parametrize(
    ("name", "model", "metres"),
    [
        ("flat", _flat_model(), False),
        ("flat_metres", _flat_model(), True),
        ("board", kicad_like_board(12), False),
    ],
)
def test_every_body_is_as_occt_places_it(tmp_path, monkeypatch, name, model, metres):
    path = write_step(model, tmp_path / f"{name}.step", metres=metres)
    as_is, untouched = _read(path, monkeypatch, min_siblings=10**9)
    isolated, changed = _read(path, monkeypatch, min_siblings=2)
    assert untouched == 0
    assert changed == _placements_in(path) > 0  # every placement went through the pass
    assert _described(isolated) == _described(as_is)  # to the bit


def test_relationships_written_the_other_way_round_are_left_alone(tmp_path, monkeypatch):
    path = write_step(_flat_model(), tmp_path / "flat.step")
    text = path.read_text(encoding="utf-8")
    # Rep1 and Rep2 swapped, and the transformation's two items with them: the same
    # placements, stated from the parent's side
    text, n = re.subn(
        r"REPRESENTATION_RELATIONSHIP\('([^']*)','([^']*)',(#\d+),(#\d+)\)",
        r"REPRESENTATION_RELATIONSHIP('\1','\2',\4,\3)",
        text,
    )
    text, m = re.subn(
        r"ITEM_DEFINED_TRANSFORMATION\('([^']*)','([^']*)',(#\d+),(#\d+)\)",
        r"ITEM_DEFINED_TRANSFORMATION('\1','\2',\4,\3)",
        text,
    )
    assert n == m == _placements_in(path)
    reversed_path = tmp_path / "reversed.step"
    reversed_path.write_text(text, encoding="utf-8")
    as_is, _ = _read(reversed_path, monkeypatch, min_siblings=10**9)
    isolated, changed = _read(reversed_path, monkeypatch, min_siblings=2)
    assert changed == 0
    assert _described(isolated) == _described(as_is)
    forward, _ = _read(path, monkeypatch, min_siblings=10**9)
    rows, *_ = _described(as_is)
    np.testing.assert_allclose(  # OCCT reads the reversed file as the same placements
        [r[7] for r in rows], [r[7] for r in _described(forward)[0]], atol=1e-9
    )


def test_small_assemblies_are_not_touched(tmp_path, monkeypatch):
    path = write_step(_flat_model(), tmp_path / "flat.step")
    _, changed = _read(path, monkeypatch, min_siblings=flatassembly.MIN_SIBLINGS)
    assert flatassembly.MIN_SIBLINGS >= 1000 and changed == 0
