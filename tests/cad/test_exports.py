"""STL and STEP exports against the exact B-rep properties, and the golden ground truth."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("build123d")
import build123d as bd
import trimesh

from cadcog.cad.build import GROUND_TRUTH_FILE, STEP_FILE, STL_DIR
from cadcog.cad.occt import solid_properties
from cadcog.core import tolerances
from tests.conftest import GOLDEN_DIR

GOLDEN = GOLDEN_DIR / "paper_rig_ground_truth.json"


def _float32_mm(max_coordinate_mm: float) -> float:
    """Largest rounding of a coordinate stored as float32 in an STL file (mm)."""
    return float(max_coordinate_mm) * 2.0**-24


def _curved_area_mm2(rig) -> float:
    """Area of the proof mass's curved faces: the holes' cylindrical walls."""
    return len(rig.suspension_points) * 2 * np.pi * rig.hole_radius_mm * rig.holes.depth_mm


def test_stl_mass_properties_agree_with_brep_within_the_deflection_bound(paper_rig, paper_build):
    truth = paper_build.ground_truth
    body = truth["bodies"]["proof_mass"]
    mesh = trimesh.load_mesh(paper_build.out_dir / STL_DIR / "proof_mass.stl")
    assert mesh.is_watertight and mesh.is_volume
    # The mesh inscribes each curved face: the volume between them is at most deflection × area;
    # float32 vertices add at most their rounding times the whole surface area.
    size = np.array(paper_rig.proof_mass.size_mm)
    total_area = 2 * (size[0] * size[1] + size[1] * size[2] + size[0] * size[2])
    f32_dv = _float32_mm(size.max()) * (total_area + _curved_area_mm2(paper_rig))
    dv_bound = tolerances.STL_DEFLECTION_MM * _curved_area_mm2(paper_rig) + f32_dv
    assert abs(mesh.volume - body["volume_mm3"]) <= dv_bound
    # Inscribed polygons cut away less than the round holes: the mesh holds more steel.
    assert mesh.volume >= body["volume_mm3"] - f32_dv
    # That volume lies within D of the CoG, which bounds the CoG's shift.
    d_max = float(np.linalg.norm(paper_rig.proof_mass.size_mm))
    cog_bound = 2 * d_max * dv_bound / body["volume_mm3"]
    np.testing.assert_allclose(mesh.center_mass, body["cog_mm"], rtol=0, atol=cog_bound)
    rho = body["mass_kg"] / body["volume_mm3"]
    mesh.density = rho
    inertia_bound = 3 * rho * d_max**2 * dv_bound
    np.testing.assert_allclose(
        mesh.moment_inertia, body["inertia_kg_mm2"], rtol=0, atol=inertia_bound
    )


def test_stl_of_each_me_volume_is_its_box(paper_rig, paper_build):
    for v in paper_rig.me_volumes:
        mesh = trimesh.load_mesh(paper_build.out_dir / STL_DIR / f"{v.name}.stl")
        # A box tessellates exactly; only STL's float32 vertices perturb it.
        eps = _float32_mm(np.abs(v.max_mm).max())
        sx, sy, sz = v.size_mm
        area = 2 * (sx * sy + sy * sz + sx * sz)
        assert mesh.volume == pytest.approx(sx * sy * sz, abs=eps * area)
        np.testing.assert_allclose(mesh.center_mass, v.center_mm, atol=2 * eps)


def test_step_round_trip_keeps_names_and_properties(paper_build):
    truth = paper_build.ground_truth
    imported = bd.import_step(paper_build.out_dir / STEP_FILE)
    assert imported.label == "paper_rig"
    tree = {c.label: c for c in imported.children}
    assert sorted(tree) == ["measurement_equipment", "proof_mass"]
    solids = {"proof_mass": tree["proof_mass"]}
    solids.update({c.label: c for c in tree["measurement_equipment"].children})
    expected = [n for n in truth["bodies"] if n != "measurement_equipment"]
    assert sorted(solids) == sorted(expected)
    for name in expected:
        body = truth["bodies"][name]
        rho = body["mass_kg"] / body["volume_mm3"]
        got = solid_properties(solids[name].wrapped, rho).properties
        assert got.volume_mm3 == pytest.approx(body["volume_mm3"], rel=1e-9)
        np.testing.assert_allclose(got.cog_mm, body["cog_mm"], atol=1e-7)
        scale = np.abs(body["inertia_kg_mm2"]).max()
        np.testing.assert_allclose(got.inertia_kg_mm2, body["inertia_kg_mm2"], atol=1e-9 * scale)


def _diff(got, want, path="", rtol=1e-9, atol=1e-12) -> list[str]:
    """Readable differences between two JSON values, with numeric tolerance."""
    if isinstance(want, dict) and isinstance(got, dict):
        out = [f"{path}.{k}: missing" for k in want if k not in got]
        out += [f"{path}.{k}: unexpected" for k in got if k not in want]
        for k in want:
            if k in got:
                out += _diff(got[k], want[k], f"{path}.{k}", rtol, atol)
        return out
    if isinstance(want, list) and isinstance(got, list):
        if len(want) != len(got):
            return [f"{path}: length {len(got)} != golden {len(want)}"]
        return [
            d
            for i, (g, w) in enumerate(zip(got, want, strict=True))
            for d in _diff(g, w, f"{path}[{i}]", rtol, atol)
        ]
    if isinstance(want, float) and isinstance(got, (int, float)) and not isinstance(got, bool):
        if abs(got - want) <= atol + rtol * abs(want):
            return []
    elif got == want:
        return []
    return [f"{path}: {got!r} != golden {want!r}"]


def test_ground_truth_matches_the_golden_file(paper_build, request):
    text = (paper_build.out_dir / GROUND_TRUTH_FILE).read_text(encoding="utf-8")
    if request.config.getoption("--update-golden"):
        GOLDEN.write_text(text, encoding="utf-8")
        pytest.skip("golden file rewritten")
    got = json.loads(text)
    want = json.loads(GOLDEN.read_text(encoding="utf-8"))
    # The integration error estimate is noise at the 1e-16 level; check it is still tiny.
    assert got["integration"].pop("estimated_relative_error") <= tolerances.OCCT_INTEGRATION_EPS
    want["integration"].pop("estimated_relative_error")
    got.pop("cadcog_version")
    want.pop("cadcog_version")
    differences = _diff(got, want)
    assert not differences, (
        "ground truth differs from tests/golden/paper_rig_ground_truth.json; if the change is "
        "intended, run pytest --update-golden and commit the new file:\n" + "\n".join(differences)
    )


def test_ground_truth_agrees_with_the_rig_closed_forms(paper_rig, paper_build):
    truth = paper_build.ground_truth
    assembly = paper_rig.analytic_assembly
    assert truth["assembly"]["mass_kg"] == pytest.approx(assembly.mass_kg, rel=1e-12)
    np.testing.assert_allclose(truth["assembly"]["cog_mm"], assembly.cog_mm, atol=1e-9)
    assert [p["id"] for p in truth["suspension_points"]] == [
        p.id for p in paper_rig.suspension_points
    ]
    for p in truth["suspension_points"]:
        assert p["in_range"]
        assert np.linalg.norm(p["normal"]) == pytest.approx(1.0)
    assert Path(paper_build.out_dir / STEP_FILE).stat().st_size > 0
