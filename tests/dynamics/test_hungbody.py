"""The hung body's linear modes against closed forms and the pivot model written before it."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadcog.bench.pendulum import swing_modes
from cadcog.core.units import STANDARD_GRAVITY_M_S2 as G
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.mass.properties import box_properties

SIZES = st.tuples(*(st.floats(20.0, 300.0) for _ in range(3)))
POINTS = st.tuples(*(st.floats(-1.0, 1.0) for _ in range(3))).filter(
    lambda v: np.linalg.norm(v) > 0.2
)


@settings(max_examples=40, deadline=None)
@given(SIZES, POINTS, st.floats(0.5, 20.0))
def test_pivot_modes_equal_the_compound_pendulum_model(size, direction, mass):
    # L = 0: the wire is a pivot at the exit; bench/pendulum.py derived the same two modes by a
    # Schur complement of the pivot inertia, in periods.
    box = box_properties(size, [0.0, 0.0, 0.0], mass_kg=mass)
    pivot = 0.6 * np.asarray(direction) * np.asarray(size)
    modes = hang_modes(box.inertia_kg_mm2, mass, [0, 0, 0], HangGeometry(pivot, np.zeros(3), 0.0))
    ref = swing_modes(box.inertia_kg_mm2, mass, [0, 0, 0], pivot, 0.0)
    np.testing.assert_allclose(modes.frequencies_hz, np.sort(1.0 / ref.periods_s), rtol=1e-10)


@settings(max_examples=40, deadline=None)
@given(st.floats(10.0, 2000.0), st.floats(10.0, 300.0), st.floats(1e3, 1e6), st.floats(0.1, 10))
def test_planar_double_pendulum_closed_form(wire_mm, d_mm, i_kg_mm2, mass):
    # A body symmetric about the vertical: each horizontal direction is a planar double pendulum
    # with det(K − ω² M) = 0, M = [[m L², m L d], [m L d, I + m d²]], K = diag(m g L, m g d).
    inertia = np.diag([i_kg_mm2, i_kg_mm2, 0.5 * i_kg_mm2])
    geo = HangGeometry(np.array([0.0, 0.0, d_mm]), np.zeros(3), wire_mm)
    modes = hang_modes(inertia, mass, [0, 0, 0], geo)
    L, d, i = wire_mm / 1e3, d_mm / 1e3, i_kg_mm2 / 1e6
    a = mass * L * L * (i + mass * d * d) - (mass * L * d) ** 2
    b = -(mass * G * L * (i + mass * d * d) + mass * G * d * mass * L * L)
    c = mass * G * L * mass * G * d
    w2 = np.sort(np.roots([a, b, c]).real)
    expected = np.sqrt(np.repeat(w2, 2)) / (2 * np.pi)
    np.testing.assert_allclose(modes.frequencies_hz, expected, rtol=1e-9)


@settings(max_examples=30, deadline=None)
@given(SIZES, POINTS, st.floats(0.5, 20.0), st.floats(5.0, 500.0), st.floats(1.1, 4.0))
def test_a_shorter_wire_raises_the_body_modes_and_the_wire_modes_rise_to_the_pivots(
    size, direction, mass, wire_mm, factor
):
    """The physics docs/inertia.md states: shortening the wire raises both the body's rocking
    modes (the fast pair, which carry the inertia) and the wire's own pair, the latter towards
    the pivot's compound-pendulum modes and never beyond them (for a double pendulum the slow
    frequency is bounded by the pivot's, the fast one grows without bound as L → 0)."""
    box = box_properties(size, [0.0, 0.0, 0.0], mass_kg=mass)
    pivot = 0.6 * np.asarray(direction) * np.asarray(size)
    long, short = (
        hang_modes(box.inertia_kg_mm2, mass, [0, 0, 0], HangGeometry(pivot, pivot, wl),
                   with_shapes=False).frequencies_hz
        for wl in (wire_mm * factor, wire_mm)
    )  # fmt: skip
    on_pivot = hang_modes(
        box.inertia_kg_mm2, mass, [0, 0, 0], HangGeometry(pivot, pivot, 0.0), with_shapes=False
    ).frequencies_hz
    assert np.all(short[2:] > long[2:])
    assert np.all(short[:2] >= long[:2] * (1 - 1e-12))
    assert np.all(short[:2] <= on_pivot * (1 + 1e-9))
    assert np.all(short[2:] > on_pivot * (1 - 1e-9))


def test_the_top_hinge_shortens_the_wire():
    inertia = np.diag([3e4, 3e4, 1e4])
    g1 = HangGeometry(np.array([0, 0, 60.0]), np.zeros(3), 300.0, top_hinge_mm=2.0)
    g2 = HangGeometry(np.array([0, 0, 60.0]), np.zeros(3), 298.0)
    a = hang_modes(inertia, 5.0, [0, 0, 0], g1)
    b = hang_modes(inertia, 5.0, [0, 0, 0], g2)
    np.testing.assert_allclose(a.frequencies_hz, b.frequencies_hz, rtol=1e-12)
    assert a.pivot_distance_mm == pytest.approx(60.0)


def test_an_accelerometer_on_a_simple_pendulums_bob_sees_nothing():
    # A point mass on a pivot: the specific force at the bob points along the wire, so a sensor
    # there reads no swing; one at the pivot reads the full tilt (one radian per radian).
    geo_bob = HangGeometry(np.array([0, 0, 500.0]), np.zeros(3), 0.0)
    geo_top = HangGeometry(np.array([0, 0, 500.0]), np.array([0, 0, 500.0]), 0.0)
    inertia = np.diag([1e-6, 1e-6, 1e-6])  # nearly a point
    bob = hang_modes(inertia, 1.0, [0, 0, 0], geo_bob)
    top = hang_modes(inertia, 1.0, [0, 0, 0], geo_top)
    assert np.max(np.abs(bob.reading_shapes_deg)) < 1e-6
    np.testing.assert_allclose(np.max(np.abs(top.reading_shapes_deg), axis=1), np.rad2deg(1.0))


def test_degenerate_hangs_are_refused():
    with pytest.raises(ValueError, match="wire exit is at the CoG"):
        hang_modes(np.eye(3), 1.0, [0, 0, 0], HangGeometry(np.zeros(3), np.zeros(3), 10.0))
    with pytest.raises(ValueError, match="mass_kg must be positive"):
        hang_modes(np.eye(3), 0.0, [0, 0, 0], HangGeometry(np.ones(3), np.zeros(3), 10.0))
    with pytest.raises(ValueError, match="wire_length_mm must be finite"):
        HangGeometry(np.ones(3), np.zeros(3), -1.0)
