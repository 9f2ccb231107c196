"""Small swings of a rigid body hung by a wire: the linear model the inertia estimate inverts.

The model (``docs/method.md`` §9): a massless inextensible wire of free length ``L`` from a fixed
clamp to the body's pivot ``P``, a spherical joint at each end; the body (mass ``m``, CoG ``G``,
inertia ``I_G`` about ``G``) hangs with ``G`` on the plumb line below ``P``, at distance ``d``.
``P`` is the virtual suspension point of the static estimate (the wire exit moved along the bolt
axis by the wire's offset: the far-field wire turns about it); the wire's bending stiffness makes
the top clamp act as a hinge ``λ = √(EI/T)`` inside the wire (the elastica's boundary layer,
``T = m g``): the free length is ``L − λ``. In the hang frame (``e1, e2`` horizontal, ``u`` up,
all in body components) the coordinates are the wire's tilt ``β`` (2) and the body's small
rotation ``θ`` (3). Kinetic and potential energies to second order:

``T = ½ m |L β̇ + d θ̇_h|² + ½ θ̇ᵀ I_G θ̇``,  ``V = ½ m g (L |β|² + d |θ_h|²)``.

Gravity does not act on the rotation about the vertical ``θ_v`` (the wire's torsional stiffness
is neglected: a free mode at zero frequency), which is eliminated with its momentum (a Schur
complement of the mass matrix). Four pendulum modes remain (two with ``L → 0``: the compound
pendulum about ``P``); their frequencies carry ``I_G``.

The inclinometer is an accelerometer: it reads the direction of the *specific force* at its
point ``S`` in body axes, ``f = R(θ)ᵀ (g u + a_S)``, so a mode's reading shape is
``−θ × u + ω² (L β × u − θ × s)/g`` (``s = S − pivot``), horizontal part; the amplitude seen
depends on where the sensor is, the frequency does not.

Units: mm, kg, kg·mm², Hz and degrees at the boundary; SI inside.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.core.units import (
    KG_MM2_PER_KG_M2,
    MM_PER_M,
    STANDARD_GRAVITY_M_S2,
    rad_to_deg,
)

FloatArray = npt.NDArray[np.float64]

#: Below this free wire length (mm) the wire is a pivot: the model has two modes, not four.
PIVOT_WIRE_LENGTH_MM = 1e-3


@dataclass(frozen=True)
class HangGeometry:
    """Where a body hangs from, in body coordinates (mm).

    Attributes
    ----------
    exit_mm : ndarray, shape (3,)
        The body's pivot: where the wire leaves it, moved along the bolt axis by the wire's
        offset (the static estimate's virtual suspension point).
    sensor_mm : ndarray, shape (3,)
        The inclinometer's sensing point.
    wire_length_mm : float
        Free wire from the fixed clamp to ``exit_mm`` (0: a pivot at the exit).
    top_hinge_mm : float
        ``λ``: the top clamp's effective hinge lies this far down the wire (the free length is
        ``wire_length_mm − λ``).
    sign_x, sign_y : int
        The device's axis signs (``[inclinometer]``).
    """

    exit_mm: FloatArray
    sensor_mm: FloatArray
    wire_length_mm: float
    top_hinge_mm: float = 0.0
    sign_x: int = 1
    sign_y: int = 1

    def __post_init__(self) -> None:
        for name in ("wire_length_mm", "top_hinge_mm"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name} must be finite and ≥ 0, got {value}")


@dataclass(frozen=True)
class HangModes:
    """The pendulum modes of one hang.

    Attributes
    ----------
    frequencies_hz : ndarray, shape (n,)
        Undamped frequencies, ascending (n = 4 on a wire, 2 on a pivot).
    reading_shapes_deg : ndarray, shape (n, 2)
        Each mode's reading amplitude (inc_x, inc_y, degrees) per radian of the body's largest
        rotation component in that mode: how strongly, and along which direction, the
        inclinometer sees it.
    vertical : ndarray, shape (3,)
        Upward vertical at rest, body frame (from the CoG to the pivot).
    pivot_distance_mm : float
        ``d``: from the CoG to the body's effective pivot.
    """

    frequencies_hz: FloatArray
    reading_shapes_deg: FloatArray
    vertical: FloatArray
    pivot_distance_mm: float


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """``a × b`` of two 3-vectors (``np.cross`` costs 20 µs of argument handling a call)."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def hang_frame(vertical: FloatArray) -> FloatArray:
    """Columns ``e1, e2, u``: a right-handed frame with ``u`` the given unit vertical."""
    u = np.asarray(vertical, dtype=float)
    helper = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = _cross(helper, u)
    e1 /= np.linalg.norm(e1)
    e2 = _cross(u, e1)
    return np.stack([e1, e2, u], axis=1)


def hang_modes(
    inertia_cog_kg_mm2: npt.ArrayLike,
    mass_kg: float,
    cog_mm: npt.ArrayLike,
    geometry: HangGeometry,
    *,
    with_shapes: bool = True,
) -> HangModes:
    """Pendulum modes of a body hung as ``geometry`` says.

    Parameters
    ----------
    inertia_cog_kg_mm2 : array_like, shape (3, 3)
        Inertia tensor about the CoG (off-diagonal ``−∫xy dm``), body axes.
    mass_kg : float
        Mass of everything that hangs.
    cog_mm : array_like, shape (3,)
        CoG of everything that hangs, body frame.
    geometry : HangGeometry
    with_shapes : bool
        Compute the reading shapes too (the frequencies alone are what the tensor fit needs;
        without them ``reading_shapes_deg`` is all NaN).

    Returns
    -------
    HangModes

    Examples
    --------
    A point mass 1 m below a pivot is a simple pendulum, f = √(g/L)/2π:

    >>> g = HangGeometry(np.array([0, 0, 1000.0]), np.zeros(3), 0.0)
    >>> m = hang_modes(np.zeros((3, 3)), 1.0, [0, 0, 0], g)
    >>> round(float(m.frequencies_hz[0]), 5), round(float(np.sqrt(9.80665) / 2 / np.pi), 5)
    (0.4984, 0.4984)
    """
    if not (np.isfinite(mass_kg) and mass_kg > 0):
        raise ValueError(f"mass_kg must be positive, got {mass_kg}")
    g = STANDARD_GRAVITY_M_S2
    cog = np.asarray(cog_mm, dtype=float)
    pivot = np.asarray(geometry.exit_mm, dtype=float)
    r0 = pivot - cog
    d0 = float(np.linalg.norm(r0))
    if d0 == 0.0:
        raise ValueError("the wire exit is at the CoG: the body does not swing back")
    u = r0 / d0
    basis = hang_frame(u)
    d = d0 / MM_PER_M
    wire = max(geometry.wire_length_mm - geometry.top_hinge_mm, 0.0) / MM_PER_M
    s = basis.T @ (np.asarray(geometry.sensor_mm, dtype=float) - pivot) / MM_PER_M
    i_g = basis.T @ np.asarray(inertia_cog_kg_mm2, dtype=float) @ basis / KG_MM2_PER_KG_M2
    m = float(mass_kg)
    body = i_g + m * d * d * np.diag([1.0, 1.0, 0.0])
    on_wire = wire * MM_PER_M > PIVOT_WIRE_LENGTH_MM
    nb = 2 if on_wire else 0
    n = nb + 3
    mass = np.zeros((n, n))
    mass[nb:, nb:] = body
    stiff = np.zeros(n)
    stiff[nb : nb + 2] = m * g * d
    if on_wire:
        mass[:2, :2] = m * wire * wire * np.eye(2)
        mass[:2, 2:4] = mass[2:4, :2] = m * wire * d * np.eye(2)
        stiff[:2] = m * g * wire
    # Eliminate the free rotation about the vertical (last coordinate) with its momentum.
    a = slice(0, n - 1)
    m_vv = mass[-1, -1]
    coupling = mass[a, -1]
    if m_vv > 1e-12 * np.trace(mass):
        eff = mass[a, a] - np.outer(coupling, coupling) / m_vv
        follow = -coupling / m_vv  # θ_v per unit of each remaining coordinate
    else:  # no inertia about the vertical (a point mass): nothing to eliminate
        eff = mass[a, a]
        follow = np.zeros(n - 1)
    k = stiff[a]
    # K x = ω² M x with K diagonal positive: symmetric form K^-1/2 M K^-1/2.
    k_isqrt = 1.0 / np.sqrt(k)
    sym = k_isqrt[:, None] * eff * k_isqrt[None, :]
    inv_omega2, vecs = np.linalg.eigh(0.5 * (sym + sym.T))
    omega2 = 1.0 / inv_omega2
    shapes_q = k_isqrt[:, None] * vecs  # columns: mode shapes in (β, θ_h)
    order = np.argsort(omega2)
    omega2 = omega2[order]
    shapes_q = shapes_q[:, order]
    readings = np.full((n - 1, 2), np.nan)
    for j in range(n - 1 if with_shapes else 0):
        q = shapes_q[:, j]
        theta = np.array([q[nb], q[nb + 1], follow @ q])
        beta = np.array([q[0], q[1], 0.0]) if on_wire else np.zeros(3)
        scale = np.max(np.abs(theta[:2])) or 1.0
        zhat = np.array([0.0, 0.0, 1.0])
        df = -_cross(theta, zhat) + omega2[j] * (wire * _cross(beta, zhat) - _cross(theta, s)) / g
        df_body = basis[:, :2] @ df[:2]
        cos_x = np.sqrt(max(1.0 - u[0] ** 2, 1e-12))
        cos_y = np.sqrt(max(1.0 - u[1] ** 2, 1e-12))
        readings[j] = rad_to_deg(
            np.array([geometry.sign_x * df_body[0] / cos_x, geometry.sign_y * df_body[1] / cos_y])
            / scale
        )
    freqs = np.sqrt(omega2) / (2.0 * np.pi)
    return HangModes(freqs, readings, u, d0)
