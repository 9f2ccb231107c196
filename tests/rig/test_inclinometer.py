"""Readings → vertical (eq. 2), its normalisation, axis signs and the ADC sensor model."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.rig.inclinometer import (
    InclinometerConfig,
    SensorModel,
    readings_from_verticals,
    verticals_from_readings,
)

angles = st.floats(min_value=-89.0, max_value=89.0)


@given(angles, angles, st.booleans())
def test_verticals_are_unit_vectors_with_the_recorded_orientation(x, y, up):
    v = verticals_from_readings([x], [y], [up])
    u = v.u[0]
    assert np.linalg.norm(u) == pytest.approx(1.0, abs=1e-12)
    if not v.normalized[0] and abs(u[2]) > 1e-9:
        assert (u[2] > 0) == up


def test_eq2_by_hand():
    v = verticals_from_readings([30.0, -30.0], [0.0, 30.0], [True, False])
    np.testing.assert_allclose(v.u[0], [0.5, 0.0, np.sqrt(0.75)])
    np.testing.assert_allclose(v.u[1], [-0.5, 0.5, -np.sqrt(0.5)])
    assert v.n_normalized == 0


def test_normalisation_when_sines_exceed_the_unit_circle():
    # sin²(50°)·2 = 1.17 > 1: impossible without noise.
    v = verticals_from_readings([50.0, 10.0], [50.0, 10.0], [True, True])
    assert v.normalized.tolist() == [True, False]
    assert v.n_normalized == 1
    np.testing.assert_allclose(v.u[0], [np.sqrt(0.5), np.sqrt(0.5), 0.0], atol=1e-15)


def test_axis_sign_flips_are_configuration():
    flipped = InclinometerConfig(sign_x=-1, sign_y=1)
    a = verticals_from_readings([20.0], [10.0], [True], flipped).u[0]
    b = verticals_from_readings([-20.0], [10.0], [True]).u[0]
    np.testing.assert_allclose(a, b)


@given(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1))
def test_readings_round_trip(x, y, z):
    u = np.array([x, y, z])
    if np.linalg.norm(u) < 1e-3 or abs(z) < 0.2 * np.linalg.norm(u):
        return  # eq. 2 recovers z through a square root: only well-conditioned for |u_z| ≥ 0.2
    u = u / np.linalg.norm(u)
    cfg = InclinometerConfig(sign_x=-1, sign_y=-1)
    rx, ry, up = readings_from_verticals(u, cfg)
    back = verticals_from_readings(rx, ry, up, cfg).u[0]
    np.testing.assert_allclose(back, u, atol=1e-14)


def test_sensor_model_counts_and_lsb():
    s = SensorModel(adc_bits=10, adc_reference_v=5.0, sensitivity_v_per_deg=4 / 120, zero_v=2.5)
    assert s.lsb_deg == pytest.approx(5 / 1024 * 30)  # 0.146°
    assert s.max_counts == 1023
    # A count at 60°: V = 4.5 V → 921.6 counts before rounding.
    assert float(s.deg_to_counts(60.0)) == pytest.approx(4.5 * 1024 / 5 - 0.5)
    counts = np.arange(0, 1024)
    np.testing.assert_allclose(s.deg_to_counts(s.counts_to_deg(counts)), counts, atol=1e-9)
    # Quantisation error of a bin-centred reading is within ±LSB/2.
    true_deg = np.linspace(-60, 60, 10001)
    read = s.counts_to_deg(np.floor(s.deg_to_counts(true_deg) + 0.5))
    assert np.max(np.abs(read - true_deg)) <= s.lsb_deg / 2 + 1e-12


@given(st.integers(0, 4095), st.sampled_from([10, 12, 16]))
def test_one_reading_converts_to_the_same_bits_as_an_array(counts, bits):
    from cadcog.rig.inclinometer import SensorModel

    sensor = SensorModel(adc_bits=bits)
    assert sensor.count_to_deg(float(counts)) == float(sensor.counts_to_deg([counts])[0])
