"""The STEP reader: global placements through any nesting, unique names, units, materials.

Every placement check compares the reader (OCCT's XCAF walk) with two computations that share
none of its code: numpy composition of the fixtures' 4 × 4 placements with closed-form boxes,
and OCCT's own explorer over the root compound (``STEPControl_Reader.OneShape``), whose
``TopExp_Explorer`` composes locations itself.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from OCP.BRepGProp import BRepGProp
from OCP.GProp import GProp_GProps
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer

from cadcog.cad.occt import volume_properties
from cadcog.cad.stepread import read_step
from cadcog.core.errors import CadcogError
from cadcog.mass.properties import combine
from support.stepfixtures import (
    Assembly,
    Part,
    Place,
    expected_boxes,
    kicad_like_board,
    nested_three_levels,
    write_step,
)


def root_compound_solids(path):
    """Volume and volume-weighted centroid of every solid of the root compound (OCCT only)."""
    reader = STEPControl_Reader()
    reader.ReadFile(str(path))
    reader.TransferRoots()
    explorer = TopExp_Explorer(reader.OneShape(), TopAbs_SOLID)
    out = []
    while explorer.More():
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(explorer.Current(), props)
        c = props.CentreOfMass()
        out.append((props.Mass(), np.array([c.X(), c.Y(), c.Z()])))
        explorer.Next()
    return out


def reader_solids(model):
    return [volume_properties(b.shape) for b in model.solids]


def assert_same_solids(model, expected):
    """The reader's solids equal the expectation one for one (order-free, by centroid)."""
    got = sorted(reader_solids(model), key=lambda p: tuple(np.round(p.cog_mm, 6)))
    want = sorted(expected, key=lambda p: tuple(np.round(p.cog_mm, 6)))
    assert len(got) == len(want)
    for g, w in zip(got, want, strict=True):
        assert g.volume_mm3 == pytest.approx(w.volume_mm3, rel=1e-9)
        np.testing.assert_allclose(g.cog_mm, w.cog_mm, atol=1e-8)
        np.testing.assert_allclose(
            g.inertia_kg_mm2 / g.volume_mm3, w.inertia_kg_mm2 / w.mass_kg, rtol=1e-7, atol=1e-8
        )


def test_three_levels_with_rotations_match_numpy_composition(tmp_path):
    sat = nested_three_levels()
    model = read_step(write_step(sat, tmp_path / "nested.step"))
    assert_same_solids(model, expected_boxes(sat))


def test_three_levels_match_the_root_compound_explorer(tmp_path):
    path = write_step(nested_three_levels(), tmp_path / "nested.step")
    ours = reader_solids(read_step(path))
    theirs = root_compound_solids(path)
    assert len(ours) == len(theirs) == 5
    v_ours = sum(p.volume_mm3 for p in ours)
    v_theirs = sum(v for v, _ in theirs)
    assert v_ours == pytest.approx(v_theirs, rel=1e-9)
    c_ours = sum(p.volume_mm3 * p.cog_mm for p in ours) / v_ours
    c_theirs = sum(v * c for v, c in theirs) / v_theirs
    np.testing.assert_allclose(c_ours, c_theirs, atol=1e-8)


def test_build123d_leaves_lose_the_parents_placements(tmp_path):
    """The bug this reader fixes: build123d's tree leaves miss their parents' placements."""
    bd = pytest.importorskip("build123d")
    sat = nested_three_levels()
    path = write_step(sat, tmp_path / "nested.step")
    root = bd.import_step(path)

    def leaves(node):
        children = list(node.children)
        return [x for c in children for x in leaves(c)] if children else [node]

    leaf_cog = combine(volume_properties(s.wrapped) for n in leaves(root) for s in n.solids())
    truth = combine(expected_boxes(sat))
    assert np.linalg.norm(leaf_cog.cog_mm - truth.cog_mm) > 1.0  # mm off, not round-off
    ours = combine(reader_solids(read_step(path)))
    np.testing.assert_allclose(ours.cog_mm, truth.cog_mm, atol=1e-8)


def test_instanced_products_get_unique_stable_paths(tmp_path):
    path = write_step(nested_three_levels(), tmp_path / "nested.step")
    first = [b.path for b in read_step(path).bodies]
    assert first == [b.path for b in read_step(path).bodies]  # stable
    assert len(set(first)) == len(first)  # unique
    assert "sat/board/bracket[2]/plate[1]" in first
    assert "sat/base" in first


def test_kicad_like_board_components_named_compound(tmp_path):
    board = kicad_like_board(12)
    model = read_step(write_step(board, tmp_path / "board.step"))
    paths = [b.path for b in model.bodies]
    assert len(paths) == 1 + 12 * 3 and len(set(paths)) == len(paths)
    assert "board_top/COMPOUND[7]/COMPOUND[7]#2" not in paths  # parts are not re-indexed
    assert "board_top/COMPOUND[7]#2" in paths
    assert model.n_instances == 1 + 1 + 12  # the root, the PCB, twelve components
    assert_same_solids(model, expected_boxes(board))


def test_instance_names_are_used_when_meaningful(tmp_path):
    plate = Part("plate", [((1.0, 1.0, 1.0), (0.0, 0.0, 0.0))])
    top = Assembly("top")
    top.add(plate, Place((0, 0, 0)), "left plate")
    top.add(plate, Place((5, 0, 0)), "right plate")
    top.add(plate, Place((10, 0, 0)))
    model = read_step(write_step(top, tmp_path / "named.step"))
    assert [b.path for b in model.bodies] == ["top/left plate", "top/right plate", "top/plate"]
    assert "plate" in model.bodies[0].match_names()  # the product name still matches


def test_metre_file_is_converted_once_and_its_unit_reported(tmp_path):
    sat = nested_three_levels()
    model = read_step(write_step(sat, tmp_path / "metres.step", metres=True))
    assert model.declared_units == ("metre",)
    assert_same_solids(model, expected_boxes(sat))


def test_xcaf_material_density_is_read(tmp_path):
    part = Part("block", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))], 2700.0, "Al 6061")
    body = read_step(write_step(part, tmp_path / "al.step")).bodies[0]
    assert body.material is not None
    assert body.material.name == "Al 6061" and body.material.density_kg_m3 == pytest.approx(2700)


def test_missing_and_corrupt_files_name_the_file(tmp_path):
    with pytest.raises(CadcogError, match=r"nothere\.step: file not found"):
        read_step(tmp_path / "nothere.step")
    bad = tmp_path / "bad.step"
    bad.write_text("ISO-10303-21;\nthis is not STEP\n", encoding="utf-8")
    with pytest.raises(CadcogError, match=r"bad\.step: cannot read as STEP \(.*Line 3"):
        read_step(bad)  # OCCT's own reason, with the line, instead of a status name
    whole = write_step(nested_three_levels(), tmp_path / "whole.step").read_text()
    cut = tmp_path / "cut.step"
    cut.write_text(whole[: len(whole) // 2], encoding="utf-8")  # a truncated download
    with pytest.raises(CadcogError, match=r"cut\.step: cannot read as STEP \(.*end of file"):
        read_step(cut)
    with pytest.raises(CadcogError, match="is a directory, expected a STEP file"):
        read_step(tmp_path)


def test_names_an_exporter_already_suffixed_stay_unique(tmp_path):
    """Siblings ``COMPOUND`` ×2 beside one literally named ``COMPOUND[1]``, and a two-body part
    ``two`` (bodies ``two#1``, ``two#2``) beside a part literally named ``two#1``."""
    box = ((1.0, 1.0, 1.0), (0.0, 0.0, 0.0))
    top = Assembly("top")
    for k, name in enumerate(["COMPOUND", "COMPOUND", "COMPOUND[1]"]):
        top.add(Part(name, [box]), Place((3.0 * k, 0, 0)))
    top.add(Part("two", [box, ((1.0, 1.0, 1.0), (2.0, 0.0, 0.0))]), Place((0, 5, 0)))
    top.add(Part("two#1", [box]), Place((0, 9, 0)))
    model = read_step(write_step(top, tmp_path / "names.step"))
    paths = [b.path for b in model.bodies]
    assert len(set(paths)) == len(paths) == 6, paths
    assert paths[:3] == ["top/COMPOUND[1][1]", "top/COMPOUND[2]", "top/COMPOUND[1][2]"]
    assert paths[3:] == ["top/two#1~1", "top/two#2", "top/two#1~2"]  # in file order
    assert_same_solids(model, expected_boxes(top))


angles = st.sampled_from([0.0, 15.0, 45.0, 90.0, 137.0, 180.0, 270.0])
axes = st.sampled_from([(0, 0, 1), (1, 0, 0), (0, 1, 0), (1, 1, 0), (1, -2, 3)])
shifts = st.tuples(*[st.floats(-200, 200, allow_nan=False)] * 3)
places = st.builds(Place, shifts, axes, angles)


@settings(max_examples=12, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(places, min_size=3, max_size=3), st.integers(1, 3))
def test_any_placements_at_any_depth_match_numpy(tmp_path, chain, copies):
    """A part placed through three random levels, the middle one instanced ``copies`` times."""
    part = Part("p", [((3.0, 4.0, 5.0), (1.0, -2.0, 0.5))])
    inner = Assembly("inner")
    inner.add(part, chain[2])
    mid = Assembly("mid")
    for k in range(copies):
        mid.add(inner, Place((0.0, 0.0, 20.0 * k)))
    outer = Assembly("outer")
    outer.add(mid, chain[1])
    root = Assembly("root")
    root.add(outer, chain[0])
    model = read_step(write_step(root, tmp_path / "random.step"))
    assert_same_solids(model, expected_boxes(root))
