"""The independent forward model of the 3U CubeSat test, against closed forms."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import cadcog
from support import forward_model as fm

SETUP = Path(__file__).resolve().parents[2] / "parts" / "cubesat_3u_setup.toml"
IDEAL: frozenset[str] = frozenset()


@pytest.fixture(scope="module")
def setup() -> object:
    return cadcog.load_setup(SETUP)


@pytest.fixture(scope="module")
def cad(setup: object) -> fm.Cad:
    return fm.cad_from_setup(setup)


def test_items_add_up_to_the_cad(setup, cad):
    """Items (bodies grouped, parallel axes) give back the set-up's mass, CoG and inertia."""
    total = setup.mass
    assert cad.mass_kg == pytest.approx(total.mass_kg, rel=1e-12)
    np.testing.assert_allclose(cad.cog_mm, total.cog_mm, atol=1e-9)
    whole = fm.combine_bodies(
        "all",
        [i.mass_kg for i in cad.items],
        np.array([i.cog_mm for i in cad.items]),
        np.array([i.inertia_kg_mm2 for i in cad.items]),
        None,
    )
    np.testing.assert_allclose(whole.inertia_kg_mm2, total.inertia_kg_mm2, rtol=1e-9, atol=1e-6)
    assert len(cad.items) == 7  # the structure (10 bodies) and six components
    assert cad.item("cubesat_3u/structure").sigma_rel == 0.02
    assert cad.me_mass_kg == pytest.approx(0.176)
    np.testing.assert_allclose(cad.me_cog_mm, setup.me_cog_mm, atol=1e-12)


def test_spreads_are_radii_of_gyration(cad):
    """A box's spread is edge/√12; the camera cylinder's R/2 across and L/√12 along."""
    np.testing.assert_allclose(
        cad.item("cubesat_3u/payload_and_bus/adcs_unit").spread_mm,
        np.array([70.0, 70.0, 30.0]) / np.sqrt(12.0),
        rtol=1e-6,
    )
    np.testing.assert_allclose(
        cad.item(fm.CAMERA).spread_mm, [15.0, 15.0, 110.0 / np.sqrt(12.0)], rtol=1e-4
    )


def test_scenario_truths_by_hand(cad):
    rng = np.random.default_rng(0)
    m, g = cad.mass_kg, cad.cog_mm
    cam, bat = cad.item(fm.CAMERA), cad.item(fm.BATTERY)

    t = fm.identical(cad, rng)
    assert t.mass_kg == pytest.approx(m, rel=1e-14) and t.changed == fm.NONE
    np.testing.assert_allclose(t.cog_mm, g, atol=1e-12)

    t = fm.camera_heavy(cad, rng)
    assert t.mass_kg == pytest.approx(m + 0.15 * cam.mass_kg, rel=1e-14)
    np.testing.assert_allclose(t.cog_mm, (m * g + 0.15 * cam.mass_kg * cam.cog_mm) / t.mass_kg)

    t = fm.battery_heavy(cad, rng)
    assert t.mass_kg == pytest.approx(m + 0.15 * bat.mass_kg, rel=1e-14)
    np.testing.assert_allclose(t.cog_mm, (m * g + 0.15 * bat.mass_kg * bat.cog_mm) / t.mass_kg)

    p = np.array(fm.HARNESS_POSITION_MM)
    for fn in (fm.harness, fm.harness_wrong_region):
        t = fn(cad, rng)
        assert t.mass_kg == pytest.approx(m + 0.040, rel=1e-14)
        np.testing.assert_allclose(t.cog_mm, (m * g + 0.040 * p) / (m + 0.040))
        assert t.unmodelled_mass_kg == 0.040 and t.changed == fm.UNMODELLED
    assert fm.harness(cad, rng).region_mm is None
    assert fm.harness_wrong_region(cad, rng).region_mm == fm.WRONG_REGION_MM
    lo = np.array(fm.WRONG_REGION_MM[:3])
    assert not np.all(p >= lo)  # the region given is wrong

    t = fm.camera_offset(cad, rng)
    assert t.mass_kg == pytest.approx(m, rel=1e-14)
    np.testing.assert_allclose(t.cog_mm, g + np.array([3.0 * cam.mass_kg / m, 0, 0]), atol=1e-12)


def test_prior_draws_have_the_stated_spread(cad):
    """Scenario 2's relative mass changes and scenario 8's CoG shifts have the priors' σ."""
    rng = np.random.default_rng(1)
    n = 4000
    m0 = np.array([i.mass_kg for i in cad.items])
    c0 = np.array([i.cog_mm for i in cad.items])
    sig = np.array([i.sigma_rel for i in cad.items])
    rel = np.array([fm.priors(cad, rng).item_masses_kg / m0 - 1 for _ in range(n)])
    np.testing.assert_allclose(rel.std(axis=0), sig, rtol=0.06)
    np.testing.assert_allclose(rel.mean(axis=0), 0.0, atol=4 * sig.max() / np.sqrt(n))
    draws = [fm.cog_priors(cad, rng) for _ in range(n)]
    shift = np.array([d.item_cogs_mm - c0 for d in draws])
    expect = sig[:, None] * np.array([i.spread_mm for i in cad.items])
    np.testing.assert_allclose(shift.std(axis=0), expect, rtol=0.06)
    t = draws[0]
    np.testing.assert_allclose(t.mass_kg, t.item_masses_kg.sum())
    np.testing.assert_allclose(t.cog_mm, t.item_masses_kg @ t.item_cogs_mm / t.mass_kg)


def test_ideal_hangs_point_through_the_assembly_cog(cad):
    """Without errors: the wire leaves the nominal point, the vertical passes through the true
    assembly CoG (spacecraft + ME at its CAD CoG) and points up from it."""
    truth = fm.camera_heavy(cad, np.random.default_rng(0))
    c = fm.simulate(cad, truth, np.random.default_rng(0), sources=IDEAL)
    m = truth.mass_kg + cad.me_mass_kg
    g = (truth.mass_kg * truth.cog_mm + cad.me_mass_kg * cad.me_cog_mm) / m
    np.testing.assert_allclose(c.assembly_cog_mm, g, atol=1e-12)
    np.testing.assert_allclose(c.wire_points_mm, cad.hangs.points_mm)
    d = cad.hangs.points_mm - g
    np.testing.assert_allclose(np.cross(d, c.verticals), 0.0, atol=1e-12)
    assert np.all(np.sum(d * c.verticals, axis=1) > 0)
    # readings: sin X = u·x_b, sin Y = u·y_b (rig signs +1), as the device reports them
    np.testing.assert_allclose(np.sin(np.radians(c.readings_deg[:, 0, 0])), c.verticals[:, 0])
    np.testing.assert_allclose(np.sin(np.radians(c.readings_deg[:, 0, 1])), c.verticals[:, 1])
    assert c.weighed_mass_kg == truth.mass_kg


def test_every_hang_is_in_equilibrium(cad):
    """With every error on, each true vertical still passes through the true virtual point and
    the true assembly CoG; the virtual point is the nominal one moved within the play square
    and along the bolt axis by one wire's offset, λ ≤ 1 mm times the elastica's 1/cos(θ/2)."""
    c = fm.campaign(cad, "priors", 3)
    d = c.wire_points_mm - c.assembly_cog_mm
    np.testing.assert_allclose(np.cross(d, c.verticals), 0.0, atol=1e-10)
    off = c.wire_points_mm - cad.hangs.points_mm
    along = np.sum(off * cad.hangs.normals, axis=1)
    across = off - along[:, None] * cad.hangs.normals
    cos_theta = np.sum(c.verticals * cad.hangs.normals, axis=1)
    shape = np.sqrt(2.0 / (1.0 + cos_theta))
    assert np.all((along >= 0) & (along <= 1.0 * shape + 1e-12))
    lam = along / shape  # one wire: the same λ on every hang
    np.testing.assert_allclose(lam, lam[0], atol=1e-9)
    assert np.all(np.abs(across) <= 0.5)


def test_me_cog_stays_in_the_convolution_of_the_cubes(cad):
    rng = np.random.default_rng(2)
    truth = fm.identical(cad, rng)
    me = np.array(
        [fm.simulate(cad, truth, rng, sources=frozenset({"me_cog"})).me_cog_mm for _ in range(3000)]
    )
    w = cad.me_masses_kg / cad.me_mass_kg
    half = float(w @ (cad.me_cube_mm / 2))
    assert np.all(np.abs(me - cad.me_cog_mm) <= half)
    sigma = 10.0 / np.sqrt(12.0) * np.sqrt(np.sum(w**2))  # 1.670 mm (docs/rig.md)
    assert sigma == pytest.approx(1.670, abs=5e-4)
    np.testing.assert_allclose(me.std(axis=0), sigma, rtol=0.06)


def test_elastica_offset(cad):
    """The elastica: the offset along the bolt axis is λ/cos(θ/2) at the hang's own θ,
    λ = √(EI/W) with EI within ±50 % of the nominal."""
    elastic = replace(cad, rig=replace(cad.rig, wire_model="elastica"))
    truth = fm.identical(cad, np.random.default_rng(0))
    c = fm.simulate(elastic, truth, np.random.default_rng(4), sources=frozenset({"wire"}))
    n = cad.hangs.normals
    along = np.sum((c.wire_points_mm - cad.hangs.points_mm) * n, axis=1)
    theta = np.arccos(np.sum(c.verticals * n, axis=1))
    lam = along * np.cos(theta / 2)
    np.testing.assert_allclose(lam, lam[0], rtol=1e-9)  # one wire
    w = (truth.mass_kg + cad.me_mass_kg) * fm.STANDARD_GRAVITY
    ei = lam[0] ** 2 * w
    assert 15.0 <= ei <= 45.0


def test_adc_counts_round_trip(cad):
    """Counts are the bin of the sensor voltage: the bin centre is within LSB/2 of the angle,
    and cadcog's reader of the transfer function gives the same angle."""
    from cadcog.rig.inclinometer import SensorModel

    rig = cad.rig
    angles = np.linspace(-59.9, 59.9, 2001)
    counts = rig.deg_to_counts(angles)
    back = rig.counts_to_deg(counts)
    assert np.all(np.abs(back - angles) <= rig.lsb_deg / 2 + 1e-12)
    sensor = SensorModel(rig.adc_bits, rig.adc_reference_v, rig.sensitivity_v_per_deg, rig.zero_v)
    np.testing.assert_allclose(sensor.counts_to_deg(counts), back, atol=1e-12)
    assert rig.lsb_deg == pytest.approx(0.1465, abs=1e-4)
    assert rig.deg_to_counts(np.array([-200.0, 200.0])).tolist() == [0, 1023]


def test_csv_reads_back_as_the_readings(cad, tmp_path):
    """cadcog's reader of the documented CSV format gets each hang's mean reading, samples and
    orientation back."""
    from cadcog.method.readings import read_readings

    c = fm.campaign(cad, "identical", 0)
    path = c.write_csv(tmp_path / "r.csv")
    lines = path.read_text().splitlines()
    assert lines[0] == "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up"
    assert len(lines) == 1 + 4 * cad.rig.samples == 41
    sus = read_readings(path, cadcog.load_rig().inclinometer)
    assert [s.id for s in sus] == list(fm.RECOMMENDED_POINTS)
    for j, s in enumerate(sus):
        np.testing.assert_allclose(s.position_mm, cad.hangs.points_mm[j])
        assert s.top_face_up == bool(c.verticals[j, 2] > 0)
        mean = cad.rig.counts_to_deg(c.counts[j]).mean(axis=0)
        np.testing.assert_allclose([s.inc_x_deg, s.inc_y_deg], mean, atol=1e-9)
        # the hang's mean reading errs by the bias (≤ 0.1°) plus averaged noise and ADC
        true = np.degrees(np.arcsin(c.verticals[j, :2]))
        assert np.all(np.abs(mean - true) < 0.1 + 0.15)


def test_reproducible_per_scenario_and_seed(cad):
    a = fm.campaign(cad, "priors", 7).csv_text()
    assert a == fm.campaign(cad, "priors", 7).csv_text()
    assert a != fm.campaign(cad, "priors", 8).csv_text()
    w = [fm.campaign(cad, "identical", s).weighed_mass_kg - cad.mass_kg for s in range(400)]
    assert np.std(w) == pytest.approx(fm.WEIGHING_SIGMA_KG, rel=0.12)
