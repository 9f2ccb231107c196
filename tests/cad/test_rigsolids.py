"""The CAD model against closed forms, and its geometric invariants."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("build123d")

from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
from OCP.BRepClass3d import BRepClass3d_SolidClassifier
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.BRepGProp import BRepGProp
from OCP.gp import gp_Pnt
from OCP.GProp import GProp_GProps
from OCP.TopAbs import TopAbs_IN, TopAbs_OUT

from cadcog.cad.occt import solid_properties
from cadcog.core import tolerances
from cadcog.mass.properties import combine

RTOL = tolerances.CLOSED_FORM_RTOL


def assert_props_close(got, want, length_scale_mm, rtol=RTOL):
    assert got.volume_mm3 == pytest.approx(want.volume_mm3, rel=rtol)
    assert got.mass_kg == pytest.approx(want.mass_kg, rel=rtol)
    np.testing.assert_allclose(got.cog_mm, want.cog_mm, rtol=0, atol=rtol * length_scale_mm)
    scale = np.abs(want.inertia_kg_mm2).max()
    np.testing.assert_allclose(got.inertia_kg_mm2, want.inertia_kg_mm2, rtol=0, atol=rtol * scale)


def test_proof_mass_matches_box_minus_holes(paper_rig, paper_model):
    got = solid_properties(
        paper_model.proof_mass.wrapped, paper_model.densities_kg_mm3["proof_mass"]
    ).properties
    want = paper_rig.analytic_proof_mass
    assert_props_close(got, want, max(paper_rig.proof_mass.size_mm))
    assert got.mass_kg == pytest.approx(9.2, rel=1e-12)  # the density is derived from 9.2 kg


def test_holes_shift_the_cog_by_the_papers_order_of_magnitude(paper_rig, paper_model):
    got = solid_properties(paper_model.proof_mass.wrapped, 1.0).properties
    shift = np.linalg.norm(got.cog_mm - 0.5 * np.array(paper_rig.proof_mass.size_mm))
    assert 1e-3 < shift < 0.05  # paper: ~0.01 mm at worst


def test_me_volumes_match_closed_forms(paper_rig, paper_model):
    for volume, solid in zip(paper_rig.me_volumes, paper_model.me_volumes, strict=True):
        got = solid_properties(solid.wrapped, paper_model.densities_kg_mm3[volume.name]).properties
        assert_props_close(got, paper_rig.analytic_me_volume(volume), max(volume.size_mm))
        assert solid.label == volume.name


def test_mass_weighted_combination_agrees_with_occt_gprops_add(paper_model):
    """cadcog.mass.properties.combine against OCCT's own density-weighted accumulation."""
    total = GProp_GProps()
    parts = []
    for solid in paper_model.bodies:
        rho = paper_model.densities_kg_mm3[solid.label]
        p = GProp_GProps()
        BRepGProp.VolumeProperties_s(solid.wrapped, p, tolerances.OCCT_INTEGRATION_EPS, True)
        total.Add(p, rho)
        parts.append(solid_properties(solid.wrapped, rho).properties)
    ours = combine(parts)
    c = total.CentreOfMass()
    m = total.MatrixOfInertia()
    assert ours.mass_kg == pytest.approx(total.Mass(), rel=1e-12)
    np.testing.assert_allclose(ours.cog_mm, [c.X(), c.Y(), c.Z()], atol=1e-9)
    occt_inertia = np.array([[m.Value(i, j) for j in (1, 2, 3)] for i in (1, 2, 3)])
    np.testing.assert_allclose(ours.inertia_kg_mm2, occt_inertia, rtol=1e-9, atol=1e-9)
    # A volume-weighted centre (what Shape.center(CenterOf.MASS) of a compound gives) differs.
    vol_weighted = sum(p.volume_mm3 * p.cog_mm for p in parts) / sum(p.volume_mm3 for p in parts)
    assert np.linalg.norm(vol_weighted - ours.cog_mm) > 1.0


def _common_volume(a, b) -> float:
    common = BRepAlgoAPI_Common(a, b)
    common.Build()
    p = GProp_GProps()
    BRepGProp.VolumeProperties_s(common.Shape(), p)
    return p.Mass()


def _distance(a, b) -> float:
    d = BRepExtrema_DistShapeShape(a, b)
    d.Perform()
    assert d.IsDone()
    return d.Value()


def test_me_touches_the_top_face_without_entering_the_proof_mass(paper_rig, paper_model):
    pm = paper_model.proof_mass.wrapped
    for solid in paper_model.me_volumes:
        assert _common_volume(pm, solid.wrapped) == pytest.approx(0.0, abs=1e-9)
        for other in paper_model.me_volumes:
            if other is not solid:
                assert _common_volume(solid.wrapped, other.wrapped) == pytest.approx(0.0, abs=1e-9)
    base = paper_model.me_volumes[0]
    assert _distance(pm, base.wrapped) == pytest.approx(0.0, abs=tolerances.ON_SURFACE_MM)
    top = paper_rig.proof_mass.size_mm[2]
    assert min(s.bounding_box().min.Z for s in paper_model.me_volumes) == pytest.approx(top)


def _state(solid, point) -> int:
    classifier = BRepClass3d_SolidClassifier(solid, gp_Pnt(*point), 1e-7)
    return classifier.State()


def test_every_suspension_point_sits_on_the_surface_over_its_hole(paper_rig, paper_model):
    pm = paper_model.proof_mass.wrapped
    size = np.array(paper_rig.proof_mass.size_mm)
    r, depth = paper_rig.hole_radius_mm, paper_rig.holes.depth_mm
    for p in paper_rig.suspension_points:
        pos, n = np.array(p.position_mm), p.normal
        axis = int(np.argmax(np.abs(n)))
        assert pos[axis] == (size[axis] if n[axis] > 0 else 0.0)  # on the face plane
        vertex = BRepBuilderAPI_MakeVertex(gp_Pnt(*pos)).Vertex()
        assert _distance(pm, vertex) == pytest.approx(r, rel=1e-9)  # nearest material: the rim
        tangent = np.roll(n, 1)
        assert _state(pm, pos - 0.5 * n) == TopAbs_OUT  # inside the hole
        assert _state(pm, pos - (depth + 0.5) * n) == TopAbs_IN  # below its bottom
        assert _state(pm, pos - 0.5 * n + (r + 0.5) * tangent) == TopAbs_IN  # beside it
        assert _state(pm, pos + 0.5 * n) == TopAbs_OUT  # outside the part
