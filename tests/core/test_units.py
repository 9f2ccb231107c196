"""``cadcog.core.units``: the conversions against their definitions, and the reading of a STEP
file's density whichever way the exporter declared it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadcog.core import units

# The definitions (SI brochure; the international yard and pound of 1959).
INCH_M = 0.0254
POUND_KG = 0.45359237


def test_length_units_are_their_definitions():
    mm = units.LENGTH_UNIT_MM
    assert mm["inch"] == mm["in"] == INCH_M * 1e3
    assert mm["foot"] == mm["ft"] == pytest.approx(12 * INCH_M * 1e3, rel=1e-15)
    assert mm["mil"] == pytest.approx(INCH_M, rel=1e-15)  # a thousandth of an inch, in mm
    assert mm["metre"] == mm["meter"] == mm["m"] == units.MM_PER_M
    assert set(units.UNIT_CHOICES) <= set(mm)


def test_density_units_are_their_definitions():
    assert units.density_kg_m3_from_named_unit(1.0, "lb/in^3") == pytest.approx(
        POUND_KG / INCH_M**3, rel=1e-9
    )
    assert units.density_kg_m3_from_named_unit(1.0, "g/mm3") == pytest.approx(1e-3 / 1e-9)
    assert units.density_kg_m3_from_named_unit(1.0, " G / CM^3 ") == pytest.approx(1000.0)


@given(st.floats(1e-3, 1e5))
def test_density_round_trips(d_kg_m3):
    there = units.density_kg_m3_to_kg_mm3(d_kg_m3)
    assert there == pytest.approx(d_kg_m3 * 1e-9, rel=1e-15)
    assert units.density_kg_mm3_to_kg_m3(there) == pytest.approx(d_kg_m3, rel=1e-15)


@given(st.floats(-720.0, 720.0, allow_nan=False))
def test_angles_round_trip(angle_deg):
    rad = units.deg_to_rad(angle_deg)
    assert float(rad) == pytest.approx(math.radians(angle_deg), rel=1e-15, abs=1e-300)
    assert float(units.rad_to_deg(rad)) == pytest.approx(angle_deg, rel=1e-14, abs=1e-12)


@given(st.floats(25.0, 10_000.0, exclude_min=True, exclude_max=True))
@settings(max_examples=200)
def test_a_step_density_is_read_whichever_way_it_was_declared(d_kg_m3):
    """OCCT hands on 7850 kg/m³ as 0.00785 (a kg·m⁻³ declaration) or 7.85 (a g·cm⁻³ one): both
    read back as the density, to the 12 figures kept."""
    for as_passed in (d_kg_m3 * 1e-6, d_kg_m3 * 1e-3):
        got = units.density_kg_m3_from_step(as_passed, "density measure")
        assert got == pytest.approx(d_kg_m3, rel=1e-11)


@given(st.floats(10.0, 25.0))
def test_an_ambiguous_step_density_is_left_unknown(d_kg_m3):
    """From 10 to 25 kg/m³ (ends included) a value fits both readings (×1000: 10 000-25 000)."""
    assert units.density_kg_m3_from_step(d_kg_m3 * 1e-3, "") is None


def test_a_named_density_is_taken_as_named_and_nonsense_is_unknown():
    assert units.density_kg_m3_from_step(2.7, "g/cm^3") == pytest.approx(2700.0)
    assert units.density_kg_m3_from_step(0.0, "") is None
    assert units.density_kg_m3_from_step(-1.0, "") is None
    assert units.density_kg_m3_from_step(1e9, "") is None


def test_areal_density():
    assert units.areal_density_kg_m2_to_kg_mm2(1.0) == pytest.approx(1e-6, rel=1e-15)
    assert np.isclose(units.MM2_PER_M2, units.MM_PER_M**2)
