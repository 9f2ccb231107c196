"""The wire's bending stiffness (docs/method.md §4.3): it moves the virtual suspension point out
along the bolt axis by ``λ f(θ)``, ``λ = √(EI/W)`` (the elastica's length), ``f`` the shape of the
wire model. All lengths mm, angles degrees, forces N."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from cadcog.core.units import deg_to_rad
from cadcog.rig.parameters import WireModel

FloatArray = npt.NDArray[np.float64]


def elastica_length_mm(bending_stiffness_n_mm2: float, tension_n: float) -> float:
    """``λ = √(EI/W)``: the length over which the wire straightens under tension (mm)."""
    return float(np.sqrt(bending_stiffness_n_mm2 / tension_n))


def sqrt_uniform_moments(rel: float) -> tuple[float, float]:
    """Mean and variance of ``√(1 + U)``, ``U`` uniform on ±``rel``: the elastica length's
    factor when EI is known within ±``rel`` (λ ∝ √EI).

    Examples
    --------
    >>> sqrt_uniform_moments(0.0)
    (1.0, 0.0)
    >>> [round(v, 5) for v in sqrt_uniform_moments(0.5)]
    [0.98904, 0.02179]
    """
    if rel == 0.0:
        return 1.0, 0.0
    m1 = ((1.0 + rel) ** 1.5 - (1.0 - rel) ** 1.5) / (3.0 * rel)
    return m1, max(1.0 - m1 * m1, 0.0)


def wire_offset_mm(theta_deg: npt.ArrayLike, length_mm: float | FloatArray) -> FloatArray:
    """Offset of the virtual suspension point along the bolt axis: ``Δ = λ / cos(θ/2)``.

    The wire leaves the clamp along the bolt axis, at ``θ`` from the upward vertical, and under
    tension W it bends to vertical (elastica ``EI φ'' = W sin φ``). Far away it is a vertical line
    offset sideways by ``2λ sin(θ/2)``, which meets the bolt axis at ``Δ`` above the clamp: the
    CoG hangs below that virtual point. Verified against a numerical solution in the tests.

    Examples
    --------
    >>> float(wire_offset_mm(0.0, 0.5))
    0.5
    >>> round(float(wire_offset_mm(90.0, 0.5)), 6)
    0.707107
    """
    half = 0.5 * deg_to_rad(theta_deg)
    return np.asarray(length_mm / np.cos(half))


def wire_shape_factor(cos_theta: npt.ArrayLike, wire_model: WireModel) -> FloatArray:
    """How the wire offset scales with the angle θ between the bolt axis and the vertical.

    The offset along the bolt axis is ``λ·f(θ)``: ``f = 1`` for the paper's model (λ is then the
    mean offset), ``f = 1/cos(θ/2) = √(2/(1 + cos θ))`` for the elastica.

    Examples
    --------
    >>> wire_shape_factor(0.0, "elastica").round(6).tolist()  # θ = 90°: 1/cos 45°
    1.414214
    >>> wire_shape_factor(0.3, "paper").tolist()
    1.0
    """
    c = np.asarray(cos_theta, dtype=float)
    if wire_model == "paper":
        return np.ones_like(c)
    return np.asarray(np.sqrt(2.0 / np.maximum(1.0 + c, 1e-12)))
