"""Swing modes against the textbook compound pendulum and a rigid-body simulation."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from cadcog.bench.pendulum import swing_modes, swing_verticals
from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.mass.properties import box_properties


def test_symmetric_body_is_the_textbook_compound_pendulum():
    # A box hung from the centre of its top face: T = 2π √(I_pivot / (m g d)) about x and y.
    box = box_properties([200.0, 75.0, 78.0], [0.0, 0.0, 0.0], mass_kg=9.2)
    d = 39.0
    modes = swing_modes(box.inertia_kg_mm2, 9.2, [0, 0, 0], [0, 0, d], 0.0)
    i_pivot = np.diag(box.inertia_about([0, 0, d]))[:2] * 1e-6  # kg·m²
    expected = 2 * np.pi * np.sqrt(i_pivot / (9.2 * STANDARD_GRAVITY_M_S2 * d * 1e-3))
    np.testing.assert_allclose(modes.periods_s, np.sort(expected)[::-1], rtol=1e-12)


def _rigid_body_vertical(inertia_cog, mass, cog, pivot, r0, t_eval):
    """Integrate the full (nonlinear) rigid body about a fixed pivot; body-frame up vectors."""
    c = (np.asarray(cog) - np.asarray(pivot)) * 1e-3  # CoG from pivot (m), body frame
    i_p = (np.asarray(inertia_cog) + mass * (c @ c * 1e6 * np.eye(3) - np.outer(c, c) * 1e6)) * 1e-6
    i_inv = np.linalg.inv(i_p)

    def rhs(_t, y):
        r = y[:9].reshape(3, 3)
        w = y[9:]
        wx = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        f_body = r.T @ np.array([0.0, 0.0, -mass * STANDARD_GRAVITY_M_S2])
        torque = np.cross(c, f_body)
        return np.concatenate([(r @ wx).ravel(), i_inv @ (torque - np.cross(w, i_p @ w))])

    sol = solve_ivp(rhs, (0, t_eval[-1]), np.concatenate([r0.ravel(), np.zeros(3)]),
                    t_eval=t_eval, rtol=1e-10, atol=1e-12)  # fmt: skip
    rs = sol.y[:9].T.reshape(-1, 3, 3)
    return np.einsum("nji,j->ni", rs, np.array([0.0, 0.0, 1.0]))  # Rᵀ ẑ


def _mean_period(t, s):
    up = np.flatnonzero((s[:-1] < 0) & (s[1:] >= 0))
    tc = t[up] - s[up] * (t[up + 1] - t[up]) / (s[up + 1] - s[up])
    return float(np.mean(np.diff(tc)))


def test_modes_match_a_rigid_body_simulation_of_an_asymmetric_hang():
    """The paper's proof mass hung from S1: the two modal coordinates of the simulated motion
    oscillate at the two predicted periods (this checks the Schur complement and the axes)."""
    box = box_properties([200.0, 75.0, 78.0], [100.0, 37.5, 39.0], mass_kg=9.2)
    cog, pivot = np.array([100.0, 37.5, 39.0]), np.array([45.0, 20.0, 82.0])
    modes = swing_modes(box.inertia_kg_mm2, 9.2, cog, pivot, 0.0)
    assert modes.periods_s[0] / modes.periods_s[1] > 1.05  # genuinely two periods
    u_eq = modes.vertical
    r0 = Rotation.align_vectors([[0, 0, 1.0]], [u_eq])[0].as_matrix()  # body → lab at rest
    tilt = Rotation.from_rotvec(np.deg2rad(0.5) * (modes.axes[0] + 0.7 * modes.axes[1])).as_matrix()
    t = np.linspace(0.0, 12.0, 12001)
    u = _rigid_body_vertical(box.inertia_kg_mm2, 9.2, cog, pivot, r0 @ tilt, t)
    for k in range(2):
        s = (u - u_eq) @ np.cross(modes.axes[k], u_eq)
        assert _mean_period(t, s) == pytest.approx(modes.periods_s[k], rel=2e-3)
    # And the linear model's verticals follow the simulation to a small fraction of the swing.
    a = np.array([0.5, 0.35])
    lin = swing_verticals(modes, np.rad2deg(np.deg2rad(a)), [0.0, 0.0], t[:3000])
    err = np.degrees(np.linalg.norm(lin - u[:3000], axis=1)).max()
    assert err < 0.05 * 0.6


def test_damping_sets_the_decay_time():
    box = box_properties([100.0, 100.0, 100.0], [0, 0, 0], mass_kg=2.0)
    modes = swing_modes(box.inertia_kg_mm2, 2.0, [0, 0, 0], [0, 0, 50.0], 0.05)
    t = np.array([0.0, modes.decay_times_s[0]])
    u = swing_verticals(modes, [2.0, 0.0], [0.0, 0.0], t)
    # Whatever the phase at τ, the tilt there is at most e⁻¹ of the start.
    tilt = np.degrees(np.arccos(np.clip(u @ modes.vertical, -1, 1)))
    assert tilt[0] == pytest.approx(2.0, rel=1e-9)
    assert tilt[1] <= 2.0 / np.e + 1e-9


def test_a_pivot_at_the_cog_is_refused():
    with pytest.raises(ValueError, match="pivot is at the CoG"):
        swing_modes(np.eye(3), 1.0, [0, 0, 0], [0, 0, 0], 0.0)
