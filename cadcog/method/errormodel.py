"""Error sources of the double-suspension method (docs/method.md §4), each a documented model.

- **ME CoG** (§4.1): each ME sub-volume's real CoG is uniform in a cube of edge ``a_k`` around its
  CAD CoG; the ME CoG error per axis is ``Σ w_k U_k`` with ``w_k = m_k/m_ME``: its exact PDF is
  the convolution of uniform PDFs of widths ``w_k a_k``.
- **Inclinometer** (§4.2): accuracy ±a, uniform, a bias of each hang; sensor noise and ADC
  quantisation per sample, averaged over n samples (the paper's averaged model stays available,
  see :class:`ErrorModel`).
- **Suspension point** (§4.3): a uniform square of play in the face plane, plus an outward offset
  of the virtual suspension point along the bolt axis caused by the wire's bending stiffness:
  ``one-wire`` (the default: one wire hangs every hang, so one offset scale λ for the test,
  anywhere from an ideal string's 0 to the bound, with the elastica's shape), the paper's
  uniform 0-1 mm drawn afresh for each hang, or the elastica's ``Δ(θ) = λ / cos(θ/2)``,
  ``λ = √(EI/W)`` from a stated stiffness.

All lengths mm, angles degrees, forces N.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.method.wire import elastica_length_mm, sqrt_uniform_moments
from cadcog.rig.inclinometer import InclinometerConfig, SensorModel, require_angle_sensor
from cadcog.rig.parameters import (
    INCLINOMETER_MODELS,
    WIRE_MODELS,
    ErrorOptions,
    InclinometerModel,
    Rig,
    WireModel,
    me_cog_sigma_mm,
)

FloatArray = npt.NDArray[np.float64]

SOURCES = ("me_cog", "inclinometer", "point_play", "wire_offset")


def quantisation_shared_var_deg2(lsb_deg: float, noise_deg: float) -> float:
    """Variance of the quantisation error that *all* samples of one hang share (deg²).

    A steady signal ``μ`` plus Gaussian noise of std ``σ`` read by a quantiser of step ``q``:
    each sample's quantisation error is exactly uniform ±q/2 over a uniform ``μ``, but its
    conditional mean given ``μ`` is not zero unless the noise dithers the signal. That mean is
    common to every sample of the hang, so averaging does not remove it. From the Fourier
    series of the sawtooth, its variance over ``μ`` is
    ``Σₖ (q/πk)²/2 · exp(−4π²k²σ²/q²)``: ``q²/12`` without noise (the error is then one
    uniform bias), and negligible once ``σ`` exceeds ~q/2.

    Examples
    --------
    >>> q = 0.1
    >>> round(quantisation_shared_var_deg2(q, 0.0) / (q * q / 12), 12)
    1.0
    >>> quantisation_shared_var_deg2(q, q) < 1e-15
    True
    """
    q2 = lsb_deg * lsb_deg
    if q2 == 0.0:
        return 0.0
    if noise_deg == 0.0:
        return q2 / 12.0
    k = np.arange(1, 201, dtype=float)
    terms = (q2 / (np.pi * k) ** 2) / 2.0 * np.exp(-4.0 * np.pi**2 * k * k * noise_deg**2 / q2)
    return float(terms.sum())


def _uniform(rng: np.random.Generator, half_width: float, shape: tuple[int, ...]) -> FloatArray:
    """Uniform on ±half_width in single precision (random errors need no more; twice as fast)."""
    return np.asarray(
        (rng.random(shape, dtype=np.float32) - np.float32(0.5)) * np.float32(2.0 * half_width)
    )


# --- the model ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class WirePrior:
    """What the error model says about the wire offset of the hangs of one campaign.

    The virtual suspension point of hang ``i`` lies ``λ·fᵢ + εᵢ`` above the bolt head along the
    bolt axis, with ``fᵢ`` from :func:`wire_shape_factor`.

    Attributes
    ----------
    scale_mm : float
        Expected ``λ`` (the paper's model: half the bound; the elastica: ``√(EI/W)`` averaged over
        the stiffness uncertainty).
    scale_var_mm2 : float
        Variance of ``λ``, *shared* by every hang of a campaign (one wire, one weight).
    scatter_var_mm2 : float
        Variance of ``εᵢ``, independent between hangs (the paper's uniform 0 … max).
    """

    scale_mm: float
    scale_var_mm2: float
    scatter_var_mm2: float


@dataclass(frozen=True)
class ErrorModel:
    """Every error source's parameters, with the paper's rig as defaults.

    This is the one place every command takes its error sources from: the Monte Carlo draws
    from it, the virtual campaign draws from it (sample by sample), and the estimator's
    covariance is derived from it.

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
    inclinometer_model : "hang-bias" or "paper-averaged"
        ``hang-bias`` (the default, the physics): the accuracy error is a bias of each hang,
        uniform ±a per axis, independent between hangs and not reduced by averaging; each
        sample adds sensor noise (``sensor_noise_deg``) and is quantised, and the mean of n
        samples keeps the part of the quantisation error the samples share (see
        :func:`quantisation_shared_var_deg2`). ``paper-averaged`` (the paper's): accuracy,
        quantisation and noise are independent per sample, and the mean's error is normal with
        std ``√((a²/3 + LSB²/12 + σ²)/n)`` (the exact sum of two uniforms for n = 1 without
        noise).
    sensor_noise_deg : float
        Standard deviation of the sensor noise of one raw sample (an assumption, 0.05°).
    play_mm : float
        Edge of the uniform square of suspension-point play in the face plane (paper 1).
    wire_model : "one-wire", "paper" or "elastica"
        ``one-wire`` (the default): one wire hangs every hang of a test, so the virtual point
        lies ``λ/cos(θ/2)`` above the bolt head along its axis (the elastica's shape) with one
        ``λ`` for the test, uniform in 0 … ``wire_offset_max_mm`` (an ideal string turns at the
        exit itself, a stiff wire further out); the estimator treats λ as one unknown with a
        prior of mean and σ half the bound, so both ends lie within 1 σ. ``paper``: the
        virtual suspension point lies uniform in 0 … ``wire_offset_max_mm`` above the bolt
        head along its axis, independently for every hang. ``elastica``: it
        lies at ``Δ(θ) = λ/cos(θ/2)``, ``λ = √(EI/W)``, with the stiffness uncertain by a
        uniform ±``wire_stiffness_rel_uncertainty``, one draw for the campaign (one wire).
    wire_offset_max_mm : float
        The paper's bound (1 mm): the ``paper`` and ``one-wire`` models' largest offset.
    wire_bending_stiffness_n_mm2 : float
        Cable EI (N·mm²).
    wire_stiffness_rel_uncertainty : float
    sensor_offset_deg, sensor_scale_rel, mounting_misalignment_deg : float
        What one sensor brings to every hang of a test (its ``[inclinometer]`` figures
        ``offset_deg``, ``scale_error_rel``, ``mounting_misalignment_deg``): each channel's
        zero offset and sensitivity error, uniform within ±, and the mounting rotation, uniform
        in angle up to the figure about a uniformly random axis; drawn once per test, part of
        the inclinometer source.
    device : "inclinometer" or "accelerometer"
        The sensor (:class:`~cadcog.rig.inclinometer.InclinometerConfig`): an accelerometer's
        shared parameters are :data:`cadcog.rig.accelerometer.ACCEL_SHARED_PARAMETERS`.
    sensor_offset_g : float
        An accelerometer's zero offset figure (each axis within ±, g).
    sensor_cross_axis_rel : float
        An accelerometer's cross-axis sensitivity figure (each coupling within ±).
    sources : tuple of str
        Enabled sources, from :data:`SOURCES`; a disabled source is zero in the draws and in
        the estimator's covariance alike.
    """

    me_masses_kg: tuple[float, ...]
    me_edges_mm: tuple[float, ...]
    accuracy_deg: float = InclinometerConfig.accuracy_deg
    lsb_deg: float = SensorModel().lsb_deg
    # The rest default to the rig file's [error_model] defaults.
    samples: int = ErrorOptions.samples
    inclinometer_model: InclinometerModel = ErrorOptions.inclinometer_model
    sensor_noise_deg: float = ErrorOptions.sensor_noise_deg
    play_mm: float = ErrorOptions.play_mm
    wire_model: WireModel = ErrorOptions.wire_model
    wire_offset_max_mm: float = ErrorOptions.wire_offset_max_mm
    wire_bending_stiffness_n_mm2: float = ErrorOptions.wire_bending_stiffness_n_mm2
    wire_stiffness_rel_uncertainty: float = ErrorOptions.wire_stiffness_rel_uncertainty
    sensor_offset_deg: float = InclinometerConfig.offset_deg
    sensor_scale_rel: float = InclinometerConfig.scale_error_rel
    mounting_misalignment_deg: float = InclinometerConfig.mounting_misalignment_deg
    sources: tuple[str, ...] = SOURCES
    device: str = InclinometerConfig.device
    sensor_offset_g: float = InclinometerConfig.offset_g
    sensor_cross_axis_rel: float = InclinometerConfig.cross_axis_rel

    def __post_init__(self) -> None:
        if self.inclinometer_model not in INCLINOMETER_MODELS:
            raise ValueError(
                f"unknown inclinometer model {self.inclinometer_model!r}; "
                f"known: {', '.join(INCLINOMETER_MODELS)}"
            )
        if self.wire_model not in WIRE_MODELS:
            raise ValueError(
                f"unknown wire model {self.wire_model!r}; known: {', '.join(WIRE_MODELS)}"
            )
        if self.samples < 1:
            raise ValueError(f"samples must be at least 1, got {self.samples}")
        if self.sensor_noise_deg < 0:
            raise ValueError(f"sensor noise must be non-negative, got {self.sensor_noise_deg}")

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
            sensor_noise_deg=o.sensor_noise_deg,
            play_mm=o.play_mm,
            wire_model=o.wire_model,
            wire_offset_max_mm=o.wire_offset_max_mm,
            wire_bending_stiffness_n_mm2=o.wire_bending_stiffness_n_mm2,
            wire_stiffness_rel_uncertainty=o.wire_stiffness_rel_uncertainty,
            sensor_offset_deg=rig.inclinometer.offset_deg,
            sensor_scale_rel=rig.inclinometer.scale_error_rel,
            mounting_misalignment_deg=rig.inclinometer.mounting_misalignment_deg,
            device=rig.inclinometer.device,
            sensor_offset_g=rig.inclinometer.offset_g,
            sensor_cross_axis_rel=rig.inclinometer.cross_axis_rel,
        )

    def paper(self) -> ErrorModel:
        """The paper's version of this model: readings averaged per sample, no sensor noise,
        nothing shared by the hangs but the ME (the wire offset drawn afresh for each hang).

        Used to reproduce the paper's Monte Carlo (``cadcog simulate --paper``,
        ``benchmarks/study_paper_reproduction.py``); not a description of a real rig.
        """
        return replace(
            self,
            inclinometer_model="paper-averaged",
            sensor_noise_deg=0.0,
            wire_model="paper",
            sensor_offset_deg=0.0,
            sensor_scale_rel=0.0,
            mounting_misalignment_deg=0.0,
            sensor_offset_g=0.0,
            sensor_cross_axis_rel=0.0,
        )

    def only(self, *sources: str) -> ErrorModel:
        """The same model with only ``sources`` enabled."""
        unknown = set(sources) - set(SOURCES)
        if unknown:
            raise ValueError(f"unknown error sources {sorted(unknown)}; known: {SOURCES}")
        return replace(self, sources=tuple(sources))

    # --- ME ------------------------------------------------------------------------------------
    @property
    def me_sigma_mm(self) -> float:
        """Per-axis std of the ME CoG error (0 if the source is off)."""
        if "me_cog" not in self.sources:
            return 0.0
        return me_cog_sigma_mm(self.me_masses_kg, self.me_edges_mm)

    def sample_me_errors(self, rng: np.random.Generator, n: int) -> FloatArray:
        """ME CoG errors (mm), shape (3, n): ``Σ w_k U_k`` per axis."""
        if "me_cog" not in self.sources:
            return np.zeros((3, n))
        m = np.asarray(self.me_masses_kg)
        widths = m / m.sum() * np.asarray(self.me_edges_mm)
        u = rng.random((len(widths), 3 * n), dtype=np.float32)
        # A sum, not ``widths @ u``: a BLAS call here would start threads that compete with
        # the Monte Carlo's own workers.
        e = np.full(3 * n, -0.5 * widths.sum(), dtype=np.float32)
        for w_k, u_k in zip(widths.astype(np.float32), u, strict=True):
            e += w_k * u_k
        return np.asarray(e.reshape(3, n))

    # --- inclinometer ----------------------------------------------------------------------------
    def reading_parts_deg2(self, samples: int | None = None) -> tuple[float, float, float]:
        """The three parts of one axis's error of a hang's mean reading, as variances (deg²).

        Returns ``(accuracy, shared quantisation, averaged)``: the accuracy bias (``a²/3``,
        uniform), the quantisation error the samples share (uniform), and the part averaged
        over the ``samples`` readings (normal). For ``paper-averaged`` the first two are 0.
        All three are 0 if the inclinometer source is off.
        """
        if "inclinometer" not in self.sources:
            return 0.0, 0.0, 0.0
        n = self.samples if samples is None else samples
        a2 = self.accuracy_deg**2 / 3.0
        q2 = self.lsb_deg**2 / 12.0
        s2 = self.sensor_noise_deg**2
        if self.inclinometer_model == "paper-averaged":
            return 0.0, 0.0, (a2 + q2 + s2) / n
        shared = quantisation_shared_var_deg2(self.lsb_deg, self.sensor_noise_deg)
        return a2, shared, max(s2 + q2 - shared, 0.0) / n

    def reading_var_deg2(self, samples: int | None = None) -> float:
        """Variance of one axis's error of a hang's mean reading (deg²)."""
        return float(sum(self.reading_parts_deg2(samples)))

    @property
    def reading_sigma_deg(self) -> float:
        """Std of one axis's error of a hang's mean of ``samples`` readings (degrees).

        Examples
        --------
        >>> m = ErrorModel((1.0,), (10.0,))  # the paper rig's inclinometer, 10 samples
        >>> round(m.reading_sigma_deg, 4), round(m.paper().reading_sigma_deg, 4)
        (0.0614, 0.0226)
        """
        return float(np.sqrt(self.reading_var_deg2()))

    def sample_reading_errors(self, rng: np.random.Generator, shape: tuple[int, ...]) -> FloatArray:
        """Errors of hangs' mean readings (degrees), one per element of ``shape``.

        Drawn in single precision (7 digits of an error of ~0.1°).

        ``hang-bias``: uniform accuracy bias + uniform shared quantisation + normal averaged
        part. ``paper-averaged``: normal, or for one sample without noise the exact sum of the
        accuracy and quantisation uniforms.
        """
        if "inclinometer" not in self.sources:
            return np.zeros(shape)
        _, shared, averaged = self.reading_parts_deg2()
        if self.inclinometer_model == "paper-averaged":
            if self.samples == 1 and self.sensor_noise_deg == 0.0:
                a, q = self.accuracy_deg, 0.5 * self.lsb_deg
                return np.asarray(_uniform(rng, a, shape) + _uniform(rng, q, shape))
            return np.asarray(rng.standard_normal(shape, dtype=np.float32) * np.sqrt(averaged))
        out = _uniform(rng, self.accuracy_deg, shape)
        if shared > 0.0:
            out += _uniform(rng, np.sqrt(3.0 * shared), shape)
        if averaged > 0.0:
            out += rng.standard_normal(shape, dtype=np.float32) * np.float32(np.sqrt(averaged))
        return np.asarray(out)

    # --- what one sensor shares across the hangs ------------------------------------------------
    @property
    def shared_sensor_sigmas(self) -> FloatArray:
        """Prior standard deviations of the shared sensor parameters, in the order of
        :data:`cadcog.rig.inclinometer.SHARED_SENSOR_PARAMETERS` (deg, deg, rel, rel, deg ×3),
        or for an accelerometer :data:`cadcog.rig.accelerometer.ACCEL_SHARED_PARAMETERS` (g ×3,
        rel ×3, deg ×3, rel ×6); zeros when the inclinometer source is off.

        A uniform ±a has σ = a/√3; a rotation uniform in angle on [0, m] about a random axis
        has ``E|r|² = m²/3``, so σ = m/3 per component.

        Examples
        --------
        >>> ErrorModel((1.0,), (10.0,), sensor_offset_deg=0.3).shared_sensor_sigmas.round(4)[:2]
        array([0.1732, 0.1732])
        """
        if "inclinometer" not in self.sources:
            return np.zeros(15 if self.accelerometer else 7)
        s = self.sensor_scale_rel / np.sqrt(3.0)
        m = self.mounting_misalignment_deg / 3.0
        if self.accelerometer:
            # Six couplings within ±c: a symmetric and an antisymmetric part, each of σ c/√6
            # per pair.
            c = self.sensor_cross_axis_rel / np.sqrt(6.0)
            b = self.sensor_offset_g / np.sqrt(3.0)
            return np.array([b, b, b, s, s, s, m, m, m, c, c, c, c, c, c])
        b = self.sensor_offset_deg / np.sqrt(3.0)
        return np.array([b, b, s, s, m, m, m])

    @property
    def accelerometer(self) -> bool:
        """Whether the sensor is a three-axis accelerometer (its shared parameters then are
        :data:`cadcog.rig.accelerometer.ACCEL_SHARED_PARAMETERS`, in
        :attr:`shared_sensor_sigmas`)."""
        return self.device == "accelerometer"

    @property
    def has_shared_sensor(self) -> bool:
        """Whether any shared sensor figure is declared (and the inclinometer source is on)."""
        return bool(np.any(self.shared_sensor_sigmas > 0.0))

    def require_angle_sensor(self, what: str) -> None:
        """:func:`cadcog.rig.inclinometer.require_angle_sensor` of this model's device."""
        require_angle_sensor(self.device, what)

    def sample_shared_sensor(self, rng: np.random.Generator, n: int) -> FloatArray:
        """Shared sensor parameters of ``n`` tests (one sensor each), shape (7, n).

        Offsets and sensitivities uniform within their figures; the mounting a rotation of
        angle uniform on [0, figure] about an axis uniform on the sphere. Nothing is drawn (and
        ``rng`` is not advanced) when no figure is declared.
        """
        self.require_angle_sensor("a simulated sensor")
        out = np.zeros((7, n))
        if not self.has_shared_sensor:
            return out
        out[0:2] = rng.uniform(-self.sensor_offset_deg, self.sensor_offset_deg, (2, n))
        out[2:4] = rng.uniform(-self.sensor_scale_rel, self.sensor_scale_rel, (2, n))
        axis = rng.standard_normal((3, n))
        axis /= np.linalg.norm(axis, axis=0)
        out[4:7] = axis * rng.uniform(0.0, self.mounting_misalignment_deg, n)
        return out

    # --- suspension point ------------------------------------------------------------------------
    @property
    def play_var_mm2(self) -> float:
        """Variance of the suspension point along each face tangent (mm²)."""
        return self.play_mm**2 / 12.0 if "point_play" in self.sources else 0.0

    def sample_play(self, rng: np.random.Generator, n: int, k: int) -> FloatArray:
        """Suspension-point play along the two face tangents (mm), shape (2, k, n)."""
        if "point_play" not in self.sources or self.play_mm == 0:
            return np.zeros((2, k, n))
        return _uniform(rng, 0.5 * self.play_mm, (2, k, n))

    def wire_length_mm(self, weight_n: float) -> float:
        """Nominal elastica length ``λ = √(EI/W)`` under the hung weight (mm)."""
        return elastica_length_mm(self.wire_bending_stiffness_n_mm2, weight_n)

    def wire_prior(self, weight_n: float) -> WirePrior:
        """Mean and spread of the wire offset scale, and its per-hang scatter (mm, mm²).

        Examples
        --------
        >>> ErrorModel((1.0,), (10.0,)).wire_prior(90.0)  # one wire, λ in 0 … 1 mm
        WirePrior(scale_mm=0.5, scale_var_mm2=0.25, scatter_var_mm2=0.0)
        >>> ErrorModel((1.0,), (10.0,), wire_model="paper").wire_prior(90.0)  # U(0, 1 mm) a hang
        WirePrior(scale_mm=0.5, scale_var_mm2=0.0, scatter_var_mm2=0.08333333333333333)
        """
        if "wire_offset" not in self.sources:
            return WirePrior(0.0, 0.0, 0.0)
        if self.wire_model == "one-wire":
            half = 0.5 * self.wire_offset_max_mm
            return WirePrior(half, half * half, 0.0)
        if self.wire_model == "paper":
            m = self.wire_offset_max_mm
            return WirePrior(0.5 * m, 0.0, m * m / 12.0)
        lam = self.wire_length_mm(weight_n)
        m1, var = sqrt_uniform_moments(self.wire_stiffness_rel_uncertainty)
        return WirePrior(lam * m1, lam * lam * var, 0.0)

    def sample_wire(self, rng: np.random.Generator, n: int, k: int) -> FloatArray:
        """Wire draws for ``n`` campaigns of ``k`` hangs.

        The paper's model: the offset of each hang (mm), shape (k, n). One wire: λ (mm), one
        per campaign, uniform in 0 … ``wire_offset_max_mm``, shape (1, n). The elastica: the
        factor ``√(EI/EI_nominal)`` on λ, one per campaign, shape (1, n).
        """
        if self.wire_model == "one-wire":
            if "wire_offset" not in self.sources:
                return np.zeros((1, n))
            return np.asarray(rng.random((1, n), dtype=np.float32) * self.wire_offset_max_mm)
        if self.wire_model == "paper":
            if "wire_offset" not in self.sources:
                return np.zeros((k, n))
            half = 0.5 * self.wire_offset_max_mm
            return np.asarray(_uniform(rng, half, (k, n)) + np.float32(half))
        if "wire_offset" not in self.sources:
            return np.zeros((1, n))
        rel = self.wire_stiffness_rel_uncertainty
        return np.sqrt(1.0 + _uniform(rng, rel, (1, n)).astype(float))

    # --- description -----------------------------------------------------------------------------
    def describe(self) -> dict[str, Any]:
        """The model as plain JSON: what a command assumed."""
        return {
            "inclinometer_model": self.inclinometer_model,
            "accuracy_deg": self.accuracy_deg,
            "lsb_deg": self.lsb_deg,
            "sensor_noise_deg": self.sensor_noise_deg,
            "samples": self.samples,
            "reading_sigma_deg": self.reading_sigma_deg,
            "play_mm": self.play_mm,
            "wire_model": self.wire_model,
            "wire_offset_max_mm": self.wire_offset_max_mm,
            "wire_bending_stiffness_n_mm2": self.wire_bending_stiffness_n_mm2,
            "wire_stiffness_rel_uncertainty": self.wire_stiffness_rel_uncertainty,
            "me_cog_sigma_mm": self.me_sigma_mm,
            "sensor_offset_deg": self.sensor_offset_deg,
            "sensor_scale_rel": self.sensor_scale_rel,
            "mounting_misalignment_deg": self.mounting_misalignment_deg,
            "sources": list(self.sources),
            "device": self.device,
            **(
                {
                    "sensor_offset_g": self.sensor_offset_g,
                    "sensor_cross_axis_rel": self.sensor_cross_axis_rel,
                }
                if self.accelerometer
                else {}
            ),
        }

    def summary(self) -> str:
        """One line saying which model this is, for command output."""
        if self.inclinometer_model == "hang-bias":
            incl = (
                f"inclinometer ±{self.accuracy_deg:g}° bias per hang + "
                f"{self.sensor_noise_deg:g}° noise and {self.lsb_deg:.3f}° ADC per sample"
            )
        else:
            incl = "inclinometer errors averaged per sample (the paper's model)"
        if self.wire_model == "one-wire":
            wire = f"one wire for every hang, offset scale 0-{self.wire_offset_max_mm:g} mm"
        elif self.wire_model == "paper":
            wire = f"wire offset U(0, {self.wire_offset_max_mm:g} mm) per hang"
        else:
            wire = (
                f"elastica wire (EI {self.wire_bending_stiffness_n_mm2:g} N·mm² "
                f"±{self.wire_stiffness_rel_uncertainty:.0%})"
            )
        incl += f", mean of {self.samples}"
        if self.accelerometer:
            incl = (
                f"offset ±{self.sensor_offset_g * 1000:g} mg, scale "
                f"±{self.sensor_scale_rel:.1%}, cross-axis ±{self.sensor_cross_axis_rel:.1%}, "
                f"mounting {self.mounting_misalignment_deg:g}° (one sensor for every hang)"
            )
        elif self.has_shared_sensor:
            incl += (
                f"; one sensor for every hang: offset ±{self.sensor_offset_deg:g}°, "
                f"scale ±{self.sensor_scale_rel:.1%}, mounting {self.mounting_misalignment_deg:g}°"
            )
        off = [s for s in SOURCES if s not in self.sources]
        tail = f"; off: {', '.join(off)}" if off else ""
        play = f"play {self.play_mm:g} mm square"
        kind = "accelerometer" if self.accelerometer else self.inclinometer_model
        return f"{kind} model: {incl}; {play}; {wire}{tail}"
