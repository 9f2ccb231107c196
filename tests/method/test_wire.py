"""``cadcog.method.wire``: the wire's offset against the elastica solved numerically, and the
moments of its length's factor against quadrature."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_bvp

from cadcog.method.wire import (
    elastica_length_mm,
    sqrt_uniform_moments,
    wire_offset_mm,
    wire_shape_factor,
)


@pytest.mark.parametrize("theta_deg", [10.0, 45.0, 90.0, 135.0])
def test_elastica_offset_against_a_numerical_solution(theta_deg):
    """Solve EI φ'' = W sin φ as a boundary-value problem and find where the far-field
    vertical line meets the bolt axis; compare with Δ = λ/cos(θ/2)."""
    lam = 0.6
    theta = np.deg2rad(theta_deg)
    length = 30 * lam

    def rhs(s, y):  # y = (φ, φ', x): φ from the vertical, x the sideways drift
        return np.vstack([y[1], np.sin(y[0]) / lam**2, np.sin(y[0])])

    def bc(ya, yb):
        return np.array([ya[0] - theta, yb[0], ya[2]])

    s = np.linspace(0, length, 2000)
    guess = np.vstack([theta * np.exp(-s / lam), -theta / lam * np.exp(-s / lam), np.zeros_like(s)])
    sol = solve_bvp(rhs, bc, s, guess, tol=1e-10, max_nodes=200_000)
    assert sol.success
    drift = sol.sol(length)[2]  # sideways offset of the far-field vertical line
    delta_numeric = drift / np.sin(theta)
    assert delta_numeric == pytest.approx(float(wire_offset_mm(theta_deg, lam)), rel=1e-6)


@given(st.floats(1e-4, 0.99))
@settings(max_examples=40, deadline=None)
def test_the_moments_of_the_length_factor_are_the_integrals(rel):
    """Mean and variance of √(1 + U), U uniform on ±rel, by quadrature (the closed form's
    variance, 1 − mean², cancels to ~1e-12 absolute as rel → 0: far below any λ it scales)."""
    mean, var = sqrt_uniform_moments(rel)
    density = 1.0 / (2.0 * rel)
    m1 = quad(lambda u: np.sqrt(1.0 + u) * density, -rel, rel, epsabs=1e-14)[0]
    m2 = quad(lambda u: (1.0 + u) * density, -rel, rel, epsabs=1e-14)[0]
    assert mean == pytest.approx(m1, rel=1e-10)
    assert var == pytest.approx(m2 - m1 * m1, rel=1e-6, abs=1e-11)


@given(st.floats(0.0, 179.0), st.floats(0.01, 5.0))
@settings(max_examples=60, deadline=None)
def test_the_elastica_shape_is_the_offset_per_length(theta_deg, lam):
    """f(θ) = √(2/(1 + cos θ)) is Δ(θ)/λ = 1/cos(θ/2); the paper's model is flat."""
    c = np.cos(np.deg2rad(theta_deg))
    assert float(wire_shape_factor(c, "elastica")) == pytest.approx(
        float(wire_offset_mm(theta_deg, lam)) / lam, rel=1e-9
    )
    assert float(wire_shape_factor(c, "paper")) == 1.0


def test_the_elastica_length_is_the_root_of_stiffness_over_tension():
    # A 0.5 mm steel wire (E = 200 GPa, I = π d⁴/64 = 3.068e-3 mm⁴: EI = 613.6 N·mm²) under a
    # 9.2 kg object (90.22 N): λ = √6.801 = 2.608 mm.
    ei = 200e3 * np.pi * 0.5**4 / 64
    w = 9.2 * 9.80665
    assert elastica_length_mm(ei, w) == pytest.approx(np.sqrt(ei / w), rel=1e-15)
    assert elastica_length_mm(ei, w) == pytest.approx(2.608, abs=1e-3)
