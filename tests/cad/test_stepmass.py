"""Mass properties of STEP models: multi-material closed forms, round trips, messy CAD."""

from __future__ import annotations

import numpy as np
import pytest

bd = pytest.importorskip("build123d")

from cadcog.cad.cubesat import build_cubesat, load_cubesat  # noqa: E402
from cadcog.cad.stepmass import model_mass_properties, read_step_solids  # noqa: E402
from cadcog.errors import CadcogError, ParameterFileError  # noqa: E402
from cadcog.massprops import box_properties, combine, cylinder_properties  # noqa: E402
from cadcog.materials import LIBRARY, MaterialMap, load_materials  # noqa: E402
from cadcog.rigfile import default_rig_path  # noqa: E402

OVERLAP = "solids overlap"
OPEN = "open shells|surfaces without a closed solid"
EMPTY = "zero or negative volume"
NO_MATERIAL = "no material for"
UNITS = "--units"


def _box(name, size, corner):
    s = bd.Solid.make_box(*size, bd.Plane(origin=corner))
    s.label = name
    return s


def _step(tmp_path, solids, name="model"):
    path = tmp_path / f"{name}.step"
    bd.export_step(bd.Compound(children=list(solids), label=name), path)
    return path


def _materials(tmp_path, text):
    path = tmp_path / "materials.toml"
    path.write_text("[materials]\n" + text, encoding="utf-8")
    return load_materials(path)


def test_two_materials_match_the_closed_form(tmp_path):
    step = _step(
        tmp_path,
        [_box("alu_block", (40, 20, 10), (0, 0, 0)), _box("steel_block", (10, 10, 30), (50, 0, 0))],
    )
    mats = _materials(tmp_path, '"alu*" = "aluminium 6061-T6"\n"steel*" = 7850.0\n')
    got = model_mass_properties(read_step_solids(step), mats).total
    want = combine(
        [
            box_properties([40, 20, 10], [20, 10, 5], mass_kg=2700e-9 * 8000),
            box_properties([10, 10, 30], [55, 5, 15], mass_kg=7850e-9 * 3000),
        ]
    )
    assert got.mass_kg == pytest.approx(want.mass_kg, rel=1e-9)
    np.testing.assert_allclose(got.cog_mm, want.cog_mm, atol=1e-9)
    np.testing.assert_allclose(got.inertia_kg_mm2, want.inertia_kg_mm2, rtol=1e-9, atol=1e-12)


def test_total_mass_scales_the_densities(tmp_path):
    step = _step(
        tmp_path, [_box("a", (10, 10, 10), (0, 0, 0)), _box("b", (10, 10, 10), (20, 0, 0))]
    )
    mats = _materials(tmp_path, '"a" = 1000.0\n"b" = 3000.0\n')
    r = model_mass_properties(read_step_solids(step), mats, total_mass_kg=0.008)
    assert r.total.mass_kg == pytest.approx(0.008)
    masses = [s.properties.mass_kg for s in r.solids]
    assert masses == pytest.approx([0.002, 0.006])  # the ratio of the densities is kept
    uniform = model_mass_properties(read_step_solids(step), None, total_mass_kg=0.004)
    assert [s.properties.mass_kg for s in uniform.solids] == pytest.approx([0.002, 0.002])


def test_cubesat_step_round_trip_keeps_names_and_closed_form(tmp_path):
    spec = load_cubesat(default_rig_path().parent / "cubesat_3u.toml")
    asm, mats = build_cubesat(spec)
    entries = read_step_solids(_step(tmp_path, [asm], spec.name))
    assert sorted(e.name for e in entries) == sorted(mats)
    assert {e.path[-2] if len(e.path) > 1 else "" for e in entries} >= {"structure"}
    r = model_mass_properties(entries, MaterialMap(tuple(mats.items())))
    # Closed form from the solids built (boxes and one cylinder), with their materials.
    parts = []
    for solid in [leaf for group in asm.children for leaf in group.children]:
        rho = LIBRARY[mats[solid.label]].density_kg_m3 * 1e-9
        bb = solid.bounding_box()
        lo = np.array([bb.min.X, bb.min.Y, bb.min.Z])
        hi = np.array([bb.max.X, bb.max.Y, bb.max.Z])
        if solid.label == "payload_camera":
            d, length = hi[0] - lo[0], hi[2] - lo[2]
            base = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2]]
            parts.append(cylinder_properties(base, [0, 0, 1], d / 2, length, density_kg_mm3=rho))
        else:
            parts.append(box_properties(hi - lo, (lo + hi) / 2, mass_kg=rho * np.prod(hi - lo)))
    want = combine(parts)
    assert r.total.mass_kg == pytest.approx(want.mass_kg, rel=1e-9)
    np.testing.assert_allclose(r.total.cog_mm, want.cog_mm, atol=1e-8)


def test_overlapping_solids_are_named(tmp_path):
    step = _step(
        tmp_path, [_box("left", (20, 10, 10), (0, 0, 0)), _box("right", (20, 10, 10), (15, 0, 0))]
    )
    entries = read_step_solids(step)
    mats = MaterialMap.uniform(1000.0)
    with pytest.raises(CadcogError, match=f"{OVERLAP}.*: left & right \\(500 mm³\\)"):
        model_mass_properties(entries, mats)
    both = model_mass_properties(entries, mats, allow_overlap=True)
    assert both.total.volume_mm3 == pytest.approx(4000.0)
    one = model_mass_properties(entries, mats, exclude=["right"])
    assert one.excluded == ("right",) and one.total.volume_mm3 == pytest.approx(2000.0)


def test_open_shell_is_refused(tmp_path):
    box = bd.Solid.make_box(10, 10, 10)
    shell = bd.Shell(box.faces()[:-1])  # one face missing
    shell.label = "lid_missing"
    path = tmp_path / "open.step"
    bd.export_step(
        bd.Compound(children=[_box("ok", (5, 5, 5), (20, 0, 0)), shell], label="open"), path
    )
    with pytest.raises(CadcogError, match=OPEN):
        model_mass_properties(read_step_solids(path), MaterialMap.uniform(1000.0))


def test_inverted_solid_is_refused(tmp_path):
    from cadcog.cad.stepmass import SolidEntry

    good = _box("good", (10, 10, 10), (0, 0, 0))
    inverted = SolidEntry("inside_out", ("model",), good.wrapped.Reversed())
    with pytest.raises(CadcogError, match=f"{EMPTY}: inside_out"):
        model_mass_properties([inverted], MaterialMap.uniform(1000.0))


def test_model_in_metres_is_detected_and_converted(tmp_path):
    step = _step(tmp_path, [_box("sat", (0.1, 0.1, 0.34), (0, 0, 0))])
    entries = read_step_solids(step)
    with pytest.raises(CadcogError, match=f"metres.*{UNITS}"):
        model_mass_properties(entries, MaterialMap.uniform(2700.0))
    r = model_mass_properties(entries, MaterialMap.uniform(2700.0), units="m")
    assert r.total.mass_kg == pytest.approx(2700 * 0.1 * 0.1 * 0.34)
    np.testing.assert_allclose(r.total.cog_mm, [50, 50, 170])


def test_model_in_inches_is_caught_by_the_weighed_mass(tmp_path):
    step = _step(tmp_path, [_box("sat", (3.94, 3.94, 13.4), (0, 0, 0))])
    entries = read_step_solids(step)
    with pytest.raises(CadcogError, match=f"mean density.*{UNITS} in"):
        model_mass_properties(entries, None, total_mass_kg=4.0)
    r = model_mass_properties(entries, None, total_mass_kg=4.0, units="in")
    np.testing.assert_allclose(r.total.cog_mm, np.array([3.94, 3.94, 13.4]) / 2 * 25.4)


def test_unassigned_solids_are_listed(tmp_path):
    step = _step(
        tmp_path,
        [
            _box("rail", (5, 5, 50), (0, 0, 0)),
            _box("board", (40, 40, 2), (10, 0, 0)),
            _box("battery", (20, 20, 20), (10, 0, 10)),
        ],
    )
    mats = _materials(tmp_path, '"rail*" = "aluminium 6061-T6"\n')
    with pytest.raises(CadcogError, match=f"{NO_MATERIAL} 2 solid\\(s\\): board, battery"):
        model_mass_properties(read_step_solids(step), mats)


def test_materials_file_errors(tmp_path):
    with pytest.raises(ParameterFileError, match="unknown material 'unobtainium'"):
        _materials(tmp_path, '"*" = "unobtainium"\n')
    with pytest.raises(ParameterFileError, match="is it in g/cm³"):
        _materials(tmp_path, '"*" = 2.7\n')
