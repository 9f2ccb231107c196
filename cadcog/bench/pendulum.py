"""The swing of a hung rigid body: a damped compound pendulum about its suspension point.

Model (an assumption, ``docs/bench.md``): the suspension point is a fixed pivot (the wire's own
pendulum motion is left out), the swing is small, and each mode is damped viscously with the
same damping ratio ζ. Small rotations ``φ`` of the body about the two horizontal axes through
the pivot obey ``M φ'' + C φ' + m g d φ = 0`` (C gives each mode the damping ratio ζ), where ``d``
is the distance from the pivot to the CoG and ``M`` the effective 2 × 2 inertia: the pivot
inertia tensor in a frame whose third axis is the vertical, with the free rotation about the
vertical eliminated (its Schur complement
``M_hh − M_hv M_vv⁻¹ M_vh``, as the angular momentum about the vertical stays zero). The two
modes have periods ``T_k = 2π √(I_k / (m g d))``, with ``I_k`` the eigenvalues of ``M``: the
textbook compound pendulum ``T = 2π √(I_pivot / (m g d))`` when the body is symmetric.

Units: mm, kg, kg·mm², s, degrees at the boundary.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.core.units import STANDARD_GRAVITY_M_S2, deg_to_rad

FloatArray = npt.NDArray[np.float64]

#: kg·mm² in one kg·m².
_KG_MM2_PER_KG_M2 = 1.0e6


@dataclass(frozen=True)
class SwingModes:
    """The two small-swing modes of a body hanging from a point.

    Attributes
    ----------
    periods_s : ndarray, shape (2,)
        Undamped periods (s), longest first.
    axes : ndarray, shape (2, 3)
        Unit rotation axis of each mode, body frame, perpendicular to ``vertical``.
    vertical : ndarray, shape (3,)
        Upward vertical at rest (body frame): from the CoG to the pivot.
    damping_ratio : float
    """

    periods_s: FloatArray
    axes: FloatArray
    vertical: FloatArray
    damping_ratio: float

    @property
    def decay_times_s(self) -> FloatArray:
        """Amplitude time constants ``τ_k = 1/(ζ ω_k) = T_k/(2π ζ)`` (s)."""
        return np.asarray(self.periods_s / (2.0 * np.pi * self.damping_ratio))


def swing_modes(
    inertia_cog_kg_mm2: npt.ArrayLike,
    mass_kg: float,
    cog_mm: npt.ArrayLike,
    pivot_mm: npt.ArrayLike,
    damping_ratio: float,
) -> SwingModes:
    """Small-swing modes of a body of given mass properties hanging from ``pivot_mm``.

    Parameters
    ----------
    inertia_cog_kg_mm2 : array_like, shape (3, 3)
        Inertia tensor about the CoG, body axes.
    mass_kg : float
    cog_mm, pivot_mm : array_like, shape (3,)
        Body frame.
    damping_ratio : float
        ζ of each mode, in [0, 1).

    Examples
    --------
    A point mass 1 m below the pivot is a simple pendulum, T = 2π √(L/g):

    >>> m = swing_modes(np.zeros((3, 3)), 1.0, [0, 0, 0], [0, 0, 1000.0], 0.0)
    >>> round(float(m.periods_s[0]), 4), round(2 * float(np.pi) * (1 / 9.80665) ** 0.5, 4)
    (2.0064, 2.0064)
    """
    if not 0.0 <= damping_ratio < 1.0:
        raise ValueError(f"damping_ratio must be in [0, 1), got {damping_ratio}")
    c = np.asarray(cog_mm, dtype=float)
    p = np.asarray(pivot_mm, dtype=float)
    r = p - c
    d = float(np.linalg.norm(r))
    if d == 0.0:
        raise ValueError("the pivot is at the CoG: the body does not swing back")
    u = r / d
    helper = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = np.cross(u, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    basis = np.stack([e1, e2, u], axis=1)  # columns
    i_pivot = np.asarray(inertia_cog_kg_mm2, dtype=float) + mass_kg * (
        d * d * np.eye(3) - np.outer(r, r)
    )
    m3 = basis.T @ i_pivot @ basis
    if m3[2, 2] > 1e-12 * np.trace(m3):
        eff = m3[:2, :2] - np.outer(m3[:2, 2], m3[2, :2]) / m3[2, 2]
    else:  # no inertia about the vertical (a point mass): nothing to eliminate
        eff = m3[:2, :2]
    inertia_k, vecs = np.linalg.eigh(0.5 * (eff + eff.T))
    stiffness = mass_kg * STANDARD_GRAVITY_M_S2 * d / 1000.0  # N·m per rad
    periods = 2.0 * np.pi * np.sqrt(inertia_k / _KG_MM2_PER_KG_M2 / stiffness)
    axes = (np.stack([e1, e2], axis=1) @ vecs).T
    order = np.argsort(periods)[::-1]
    return SwingModes(periods[order], axes[order], u, damping_ratio)


def swing_verticals(
    modes: SwingModes,
    amplitudes_deg: npt.ArrayLike,
    phases_rad: npt.ArrayLike,
    t_s: npt.ArrayLike,
) -> FloatArray:
    """Upward verticals in body components while swinging: shape (n, 3).

    Each mode k rotates the body about its axis by
    ``a_k e^(−ζ ω_k t) cos(ω_k √(1−ζ²) t + ψ_k)``; the lab vertical seen from the body turns the
    opposite way.

    Parameters
    ----------
    amplitudes_deg, phases_rad : array_like, shape (2,)
        Initial amplitude and phase of each mode.
    t_s : array_like, shape (n,)
        Time since the swing started (s).
    """
    t = np.atleast_1d(np.asarray(t_s, dtype=float))
    omega = 2.0 * np.pi / modes.periods_s
    zeta = modes.damping_ratio
    a = deg_to_rad(amplitudes_deg)
    ang = (
        a[None, :]
        * np.exp(-zeta * omega[None, :] * t[:, None])
        * np.cos(omega[None, :] * np.sqrt(1.0 - zeta**2) * t[:, None] + np.asarray(phases_rad))
    )  # (n, 2)
    rot = -(ang @ modes.axes)  # rotation vectors (n, 3), body frame
    theta = np.linalg.norm(rot, axis=1, keepdims=True)
    safe = np.where(theta > 0, theta, 1.0)
    k = rot / safe
    v = modes.vertical[None, :]
    # Rodrigues: v cosθ + (k × v) sinθ + k (k·v)(1 − cosθ)
    out = (
        v * np.cos(theta)
        + np.cross(k, v) * np.sin(theta)
        + k * np.sum(k * v, axis=1, keepdims=True) * (1.0 - np.cos(theta))
    )
    return np.asarray(out)
