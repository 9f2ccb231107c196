"""Error sources of the double-suspension method (METHOD.md §4), each a documented model.

- **ME CoG** (§4.1): each ME sub-volume's real CoG is uniform in a cube of edge ``a_k`` around its
  CAD CoG; the ME CoG error per axis is ``Σ w_k U_k`` with ``w_k = m_k/m_ME``: its exact PDF is
  the convolution of uniform PDFs of widths ``w_k a_k``.
- **Inclinometer** (§4.2): accuracy ±a, uniform, plus ADC quantisation ±LSB/2, uniform, averaged
  over n samples, in two models (see :class:`ErrorModel`).
- **Suspension point** (§4.3): a uniform square of play in the face plane, plus an outward offset
  of the virtual suspension point caused by the wire's bending stiffness: the paper's uniform
  0-1 mm, or the elastica's ``Δ(θ) = λ / cos(θ/2)``, ``λ = √(EI/W)``.

All lengths mm, angles degrees, forces N.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Literal

import numpy as np
import numpy.typing as npt
from scipy import stats

from cadcog.inclinometer import InclinometerConfig, SensorModel
from cadcog.units import deg_to_rad

if TYPE_CHECKING:
    from cadcog.rig import Rig

FloatArray = npt.NDArray[np.float64]

#: Standard gravity (m/s²), to turn masses into the wire tension W.
STANDARD_GRAVITY_M_S2 = 9.80665

SOURCES = ("me_cog", "inclinometer", "point_play", "wire_offset")

InclinometerModel = Literal["paper", "conservative"]
WireModel = Literal["paper", "elastica"]


# --- ME CoG ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MECogPdf:
    """Exact per-axis PDF of the ME CoG error on a grid.

    Attributes
    ----------
    x_mm : ndarray
        Grid (mm), symmetric about 0.
    pdf : ndarray
        Density (1/mm), integrates to 1.
    sigma_mm : float
        Standard deviation, exactly ``√(Σ (w_k a_k)²/12)``.
    max_cdf_difference_from_normal : float
        ``max |F(x) − Φ(x/σ)|``: how close the PDF is to a normal of the same σ.
    """

    x_mm: FloatArray
    pdf: FloatArray
    sigma_mm: float
    max_cdf_difference_from_normal: float

    @property
    def cdf(self) -> FloatArray:
        dx = self.x_mm[1] - self.x_mm[0]
        c = np.cumsum(self.pdf) * dx
        return np.asarray(c - 0.5 * self.pdf * dx)


def me_cog_sigma_mm(masses_kg: npt.ArrayLike, edges_mm: npt.ArrayLike) -> float:
    """Per-axis standard deviation of the ME CoG error: ``√(Σ (m_k/m_ME)² a_k² / 12)``.

    Examples
    --------
    >>> round(me_cog_sigma_mm([1, 1, 1, 1], [10, 10, 10, 10]), 6)  # 10/√12 · √(4/16)
    1.443376
    """
    m = np.asarray(masses_kg, dtype=float)
    a = np.asarray(edges_mm, dtype=float)
    return float(np.sqrt(np.sum((m / m.sum() * a) ** 2) / 12.0))


def me_cog_pdf(
    masses_kg: npt.ArrayLike, edges_mm: npt.ArrayLike, points_per_mm: int = 400
) -> MECogPdf:
    """Exact per-axis PDF of the ME CoG error by numerical convolution of uniform PDFs.

    Each uniform PDF (width ``w_k a_k``) is discretised as a box on a common grid of spacing
    ``1/points_per_mm`` and convolved; the grid error is O(dx²) in σ.
    """
    m = np.asarray(masses_kg, dtype=float)
    widths = m / m.sum() * np.asarray(edges_mm, dtype=float)
    dx = 1.0 / points_per_mm
    pdf = np.array([1.0 / dx])  # a delta at 0
    for w in widths[widths > 0]:
        n = max(round(w / dx), 1)
        box = np.full(n, 1.0 / (n * dx))
        pdf = np.convolve(pdf, box) * dx
    half = (len(pdf) - 1) / 2.0
    x = (np.arange(len(pdf)) - half) * dx
    sigma = me_cog_sigma_mm(m, edges_mm)
    result = MECogPdf(np.asarray(x, dtype=float), np.asarray(pdf, dtype=float), sigma, 0.0)
    diff = float(np.max(np.abs(result.cdf - stats.norm.cdf(x, scale=sigma)))) if sigma else 0.0
    return replace(result, max_cdf_difference_from_normal=diff)


# --- wire bending ------------------------------------------------------------------------------
def elastica_length_mm(bending_stiffness_n_mm2: float, tension_n: float) -> float:
    """``λ = √(EI/W)``: the length over which the wire straightens under tension (mm)."""
    return float(np.sqrt(bending_stiffness_n_mm2 / tension_n))


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


# --- the model ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class ErrorOptions:
    """The ``[error_model]`` table of a rig file: everything not already in its other tables.

    Defaults are the paper's, or documented assumptions (``docs/montecarlo.md``).
    """

    samples: int = 10
    inclinometer_model: InclinometerModel = "paper"
    dither_noise_deg: float = 0.0
    play_mm: float = 1.0
    wire_model: WireModel = "paper"
    wire_offset_max_mm: float = 1.0
    wire_bending_stiffness_n_mm2: float = 30.0
    wire_stiffness_rel_uncertainty: float = 0.5


@dataclass(frozen=True)
class ErrorModel:
    """Every error source's parameters, with the paper's values as defaults.

    Attributes
    ----------
    me_masses_kg, me_edges_mm : tuple of float
        ME sub-volume masses and uncertainty-cube edges.
    accuracy_deg : float
        Inclinometer accuracy half-width (paper 0.1).
    lsb_deg : float
        ADC step in degrees.
    samples : int
        Readings averaged per suspension.
    inclinometer_model : "paper" or "conservative"
        ``paper``: accuracy and quantisation are independent per sample, the mean's error has
        std ``√(a²/3 + LSB²/12)/√n`` (normal for n > 1, by the central limit theorem, as the
        paper does; the exact sum of two uniforms for n = 1). ``conservative``: the accuracy
        error is a bias of each hang, uniform ±a, not reduced by averaging; quantisation
        averages out only with dither noise (``dither_noise_deg`` > 0), otherwise it is a
        uniform ±LSB/2 bias as well.
    dither_noise_deg : float
        Sensor noise std before the ADC (conservative model).
    play_mm : float
        Edge of the uniform square of suspension-point play in the face plane (paper 1).
    wire_model : "paper" or "elastica"
        ``paper``: the virtual suspension point lies uniform in 0 … ``wire_offset_max_mm``
        above the bolt head along its axis. ``elastica``: it lies at ``Δ(θ)`` with ``λ`` from
        ``wire_bending_stiffness_n_mm2`` and the weight, the stiffness uncertain by a uniform
        ±``wire_stiffness_rel_uncertainty``.
    wire_offset_max_mm : float
        The paper's bound (1 mm).
    wire_bending_stiffness_n_mm2 : float
        Cable EI (N·mm²).
    wire_stiffness_rel_uncertainty : float
    sources : tuple of str
        Enabled sources, from :data:`SOURCES`.
    """

    me_masses_kg: tuple[float, ...]
    me_edges_mm: tuple[float, ...]
    accuracy_deg: float = InclinometerConfig.accuracy_deg
    lsb_deg: float = SensorModel().lsb_deg
    # The rest default to the rig file's [error_model] defaults.
    samples: int = ErrorOptions.samples
    inclinometer_model: InclinometerModel = ErrorOptions.inclinometer_model
    dither_noise_deg: float = ErrorOptions.dither_noise_deg
    play_mm: float = ErrorOptions.play_mm
    wire_model: WireModel = ErrorOptions.wire_model
    wire_offset_max_mm: float = ErrorOptions.wire_offset_max_mm
    wire_bending_stiffness_n_mm2: float = ErrorOptions.wire_bending_stiffness_n_mm2
    wire_stiffness_rel_uncertainty: float = ErrorOptions.wire_stiffness_rel_uncertainty
    sources: tuple[str, ...] = SOURCES

    @classmethod
    def from_rig(cls, rig: Rig) -> ErrorModel:
        """The rig's error model: ME cubes, inclinometer and ``[error_model]`` options."""
        o = rig.error_options
        return cls(
            me_masses_kg=tuple(v.mass_kg for v in rig.me_volumes),
            me_edges_mm=tuple(v.cog_uncertainty_cube_mm for v in rig.me_volumes),
            accuracy_deg=rig.inclinometer.accuracy_deg,
            lsb_deg=rig.inclinometer.sensor.lsb_deg,
            samples=o.samples,
            inclinometer_model=o.inclinometer_model,
            dither_noise_deg=o.dither_noise_deg,
            play_mm=o.play_mm,
            wire_model=o.wire_model,
            wire_offset_max_mm=o.wire_offset_max_mm,
            wire_bending_stiffness_n_mm2=o.wire_bending_stiffness_n_mm2,
            wire_stiffness_rel_uncertainty=o.wire_stiffness_rel_uncertainty,
        )

    def only(self, *sources: str) -> ErrorModel:
        """The same model with only ``sources`` enabled."""
        unknown = set(sources) - set(SOURCES)
        if unknown:
            raise ValueError(f"unknown error sources {sorted(unknown)}; known: {SOURCES}")
        return replace(self, sources=tuple(sources))

    @property
    def me_sigma_mm(self) -> float:
        return me_cog_sigma_mm(self.me_masses_kg, self.me_edges_mm)

    @property
    def reading_sigma_deg(self) -> float:
        """Std of one axis's averaged reading error under the chosen model."""
        quant_var = self.lsb_deg**2 / 12.0
        if self.inclinometer_model == "paper":
            return float(np.sqrt((self.accuracy_deg**2 / 3.0 + quant_var) / self.samples))
        if self.dither_noise_deg > 0:
            quant_var = (self.dither_noise_deg**2 + quant_var) / self.samples
        return float(np.sqrt(self.accuracy_deg**2 / 3.0 + quant_var))

    def sample_reading_errors(self, rng: np.random.Generator, shape: tuple[int, ...]) -> FloatArray:
        """Errors of averaged readings (degrees), one per element of ``shape``."""
        if "inclinometer" not in self.sources:
            return np.zeros(shape)
        a, q = self.accuracy_deg, 0.5 * self.lsb_deg
        if self.inclinometer_model == "paper":
            if self.samples == 1:
                return rng.uniform(-a, a, shape) + rng.uniform(-q, q, shape)
            return rng.normal(0.0, self.reading_sigma_deg, shape)
        bias = rng.uniform(-a, a, shape)
        if self.dither_noise_deg > 0:
            sd = np.sqrt((self.dither_noise_deg**2 + q * q / 3.0) / self.samples)
            return bias + rng.normal(0.0, sd, shape)
        return bias + rng.uniform(-q, q, shape)

    def sample_me_errors(self, rng: np.random.Generator, n: int) -> FloatArray:
        """ME CoG errors (mm), shape (3, n): ``Σ w_k U_k`` per axis."""
        if "me_cog" not in self.sources:
            return np.zeros((3, n))
        m = np.asarray(self.me_masses_kg)
        widths = m / m.sum() * np.asarray(self.me_edges_mm)
        u = rng.random((len(widths), 3 * n))
        return np.asarray((widths @ u - 0.5 * widths.sum()).reshape(3, n))
