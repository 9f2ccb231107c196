"""What the inertia chain needs besides the data, from a rig or a spacecraft set-up: the
object's CAD and its stated uncertainty, the measurement equipment, the ``[swing]`` table, the
sensing point, the body's box, the static estimate's error model and the wire's stiffness
(:class:`InertiaContext`, built by :func:`context_for_rig` and :func:`context_for_setup`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import ReadingsError
from cadcog.mass.properties import MassProperties, box_properties
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox
from cadcog.method.wire import elastica_length_mm, sqrt_uniform_moments, wire_shape_factor
from cadcog.rig.parameters import MEVolume, Rig, SwingOptions

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class InertiaContext:
    """Everything besides the data that the chain needs, from a rig or a set-up.

    Attributes
    ----------
    object_cad : MassProperties
        The object (without ME) as its CAD says.
    cad_cov_kg2_mm4 : ndarray, shape (6, 6)
        The CAD tensor's stated uncertainty (zeros for a rig's exact proof mass).
    me_parts : tuple of MassProperties
        Each ME volume (a homogeneous box).
    me_cog_sigma_mm : tuple of float
        Per-axis 1 σ of each volume's CoG (its uncertainty cube's edge / √12).
    swing : SwingOptions
    sensor_mm : ndarray, shape (3,)
    body : BodyBox
        The box the suspension points sit on: each bolt's axis.
    error_model : ErrorModel
        The static estimate's: the points' play, the wire's offset along the bolt axis.
    bending_stiffness_n_mm2, bending_rel_sigma : float
        The wire's EI and how far off it may be (relative, uniform ±): the top clamp's hinge
        (:meth:`top_hinge_mm`).
    signs : (int, int)
    """

    object_cad: MassProperties
    cad_cov_kg2_mm4: FloatArray
    me_parts: tuple[MassProperties, ...]
    me_cog_sigma_mm: tuple[float, ...]
    swing: SwingOptions
    sensor_mm: FloatArray
    body: BodyBox
    error_model: ErrorModel
    bending_stiffness_n_mm2: float
    bending_rel_sigma: float
    signs: tuple[int, int]

    def top_hinge_mm(self, weight_n: float) -> tuple[float, float]:
        """The top clamp's hinge (how far below the clamp the free wire turns) and its 1 σ, mm.

        A wire of bending stiffness ``EI`` under the tension ``T`` turns ``λ = √(EI/T)`` below
        the clamp; an ideal string turns at the clamp. The hinge follows the error model's wire
        model, as the wire's offset at the exit does (:meth:`ErrorModel.wire_prior`): with
        ``"elastica"`` the wire's ``EI`` is known and the hinge is ``λ`` (σ from EI's relative
        uncertainty, λ ∝ √EI); with ``"one-wire"`` and ``"paper"`` the wire may be anything
        from a string to the declared stiffness, so the hinge is somewhere in ``0 … λ``:
        ``λ/2 ± λ/2`` (a 1 σ that reaches both ends, as the exit's one-wire prior).

        Examples
        --------
        >>> from dataclasses import replace
        >>> import cadcog
        >>> ctx = context_for_rig(cadcog.load_rig())  # the paper rig: 30 N·mm² within ±50 %
        >>> [round(v, 4) for v in ctx.top_hinge_mm(30.0)]  # one wire: λ = 1 mm, the hinge 0 … 1
        [0.5, 0.5]
        >>> stiff = replace(ctx, error_model=replace(ctx.error_model, wire_model="elastica"))
        >>> [round(v, 4) for v in stiff.top_hinge_mm(30.0)]  # the declared wire: λ, σ from EI's
        [0.989, 0.1476]
        """
        lam = elastica_length_mm(self.bending_stiffness_n_mm2, weight_n)
        if self.error_model.wire_model == "elastica":
            m1, var = sqrt_uniform_moments(self.bending_rel_sigma)
            return lam * m1, lam * float(np.sqrt(var))
        return 0.5 * lam, 0.5 * lam

    def pivots(
        self, positions_mm: FloatArray, cog_mm: FloatArray, weight_n: float
    ) -> tuple[FloatArray, FloatArray]:
        """Each hang's pivot and its covariance, shapes (k, 3) and (k, 3, 3).

        The pivot is the static estimate's virtual suspension point: the wire exit moved along
        the bolt axis ``n`` by the wire's expected offset (the far-field wire turns about it);
        its covariance is the point's play in the face plane and the offset's spread along
        ``n`` (the elastica's shared scale taken per hang: a planning approximation).
        """
        model = self.error_model
        prior = model.wire_prior(weight_n)
        pos = np.asarray(positions_mm, dtype=float).reshape(-1, 3)
        pivots = np.empty_like(pos)
        covs = np.empty((len(pos), 3, 3))
        for i, p in enumerate(pos):
            n = self.body.normal_at(p)
            u = p - np.asarray(cog_mm, dtype=float)
            u = u / np.linalg.norm(u)
            f = float(wire_shape_factor(np.array([n @ u]), model.wire_model)[0])
            pivots[i] = p + prior.scale_mm * f * n
            var_n = prior.scatter_var_mm2 + prior.scale_var_mm2 * f * f
            covs[i] = model.play_var_mm2 * (np.eye(3) - np.outer(n, n)) + var_n * np.outer(n, n)
        return pivots, covs

    def pivot_terms(
        self,
        positions_mm: FloatArray,
        cog_mm: FloatArray,
        weight_n: float,
        scale: tuple[float, float] | None = None,
    ) -> tuple[FloatArray, FloatArray]:
        """Each hang's pivot, shape (k, 3), and the pivots' joint covariance, (3k, 3k), with the
        wire's offset scale λ **one unknown shared by every hang** (one wire hangs them all).

        ``scale``: λ and its variance as the CoG's estimate found them (its joint fit takes λ
        as an unknown of the test); default the error model's prior. Each hang's pivot is the
        exit moved by ``λ fᵢ`` along its bolt axis ``nᵢ``; its own covariance is the play in the
        face plane and the per-hang scatter along ``nᵢ``, and every pair of hangs shares
        ``var(λ) (fᵢnᵢ)(fⱼnⱼ)ᵀ``: an error of λ moves every pivot at once and does not average
        out over the hangs (:meth:`pivots` takes it per hang, for planning).
        """
        model = self.error_model
        prior = model.wire_prior(weight_n)
        lam, lam_var = (prior.scale_mm, prior.scale_var_mm2) if scale is None else scale
        pos = np.asarray(positions_mm, dtype=float).reshape(-1, 3)
        k = len(pos)
        pivots = np.empty_like(pos)
        cov = np.zeros((3 * k, 3 * k))
        along = np.zeros(3 * k)
        for i, p in enumerate(pos):
            n = self.body.normal_at(p)
            u = p - np.asarray(cog_mm, dtype=float)
            u = u / np.linalg.norm(u)
            f = float(wire_shape_factor(np.array([n @ u]), model.wire_model)[0])
            pivots[i] = p + lam * f * n
            own = model.play_var_mm2 * (np.eye(3) - np.outer(n, n))
            cov[3 * i : 3 * i + 3, 3 * i : 3 * i + 3] = own + prior.scatter_var_mm2 * np.outer(n, n)
            along[3 * i : 3 * i + 3] = f * n
        return pivots, cov + lam_var * np.outer(along, along)


#: An ME volume whose name holds one of these words is the sensor (its centre is the sensing
#: point when ``[swing] sensor_position_mm`` is not given).
SENSOR_VOLUME_WORDS = ("inclinometer", "accelerometer", "phone")


def sensor_position_mm(
    options: SwingOptions, volumes: Sequence[MEVolume], source: str
) -> FloatArray:
    """``[swing] sensor_position_mm``; else the centre of the one ME volume whose name holds a
    word of :data:`SENSOR_VOLUME_WORDS`; else the ME's centre of mass. Where the sensor senses
    sets how large each mode reads (what a simulated swing draws), not its frequency: the
    tensor measured from the frequencies does not depend on it.

    Raises
    ------
    ReadingsError
        No sensing point given, none named, and no ME volume to stand in.
    """
    if options.sensor_position_mm is not None:
        return np.asarray(options.sensor_position_mm, dtype=float)
    named = [v for v in volumes if any(w in v.name.lower() for w in SENSOR_VOLUME_WORDS)]
    if len(named) == 1:
        return np.asarray(named[0].center_mm, dtype=float)
    masses = np.array([v.mass_kg for v in volumes], dtype=float)
    if not len(volumes) or not masses.sum() > 0:
        words = " or ".join(repr(w) for w in SENSOR_VOLUME_WORDS)
        raise ReadingsError(
            f"{source}: [swing] sensor_position_mm is not given and no measurement-equipment "
            f"volume has {words} in its name: say where the sensor senses (mm, object frame)"
        )
    centres = np.array([v.center_mm for v in volumes], dtype=float)
    return np.asarray(masses @ centres / masses.sum())


def _signs(inclinometer: Any) -> tuple[int, int]:
    """The swing readings' axis signs: the device's; an accelerometer's swings are written in
    object axes (:func:`cadcog.rig.accelerometer.swing_angles_deg`)."""
    if inclinometer.accelerometer:
        return 1, 1
    return inclinometer.sign_x, inclinometer.sign_y


def context_for_rig(rig: Rig, swing: SwingOptions | None = None) -> InertiaContext:
    """The paper rig (or another): the proof mass is the object, exact."""
    opts = rig.error_options
    sw = swing or rig.swing
    return InertiaContext(
        rig.analytic_proof_mass,
        np.zeros((6, 6)),
        tuple(rig.analytic_me_volume(v) for v in rig.me_volumes),
        tuple(v.cog_uncertainty_cube_mm / np.sqrt(12.0) for v in rig.me_volumes),
        sw,
        sensor_position_mm(sw, rig.me_volumes, f"rig {rig.source}"),
        BodyBox.of_rig(rig),
        ErrorModel.from_rig(rig),
        opts.wire_bending_stiffness_n_mm2,
        opts.wire_stiffness_rel_uncertainty,
        _signs(rig.inclinometer),
    )


def context_for_setup(setup: Any, cad_cov_kg2_mm4: FloatArray) -> InertiaContext:
    """A spacecraft set-up: its CAD with the stated uncertainty ``cad_cov_kg2_mm4``."""
    rig = setup.rig
    opts = rig.error_options
    sw = setup.swing
    return InertiaContext(
        setup.mass,
        np.asarray(cad_cov_kg2_mm4, dtype=float),
        tuple(box_properties(v.size_mm, v.center_mm, mass_kg=v.mass_kg) for v in setup.me_volumes),
        tuple(v.cog_uncertainty_cube_mm / np.sqrt(12.0) for v in setup.me_volumes),
        sw,
        sensor_position_mm(sw, setup.me_volumes, f"setup {setup.source}"),
        setup.body(),
        setup.error_model(),
        opts.wire_bending_stiffness_n_mm2,
        opts.wire_stiffness_rel_uncertainty,
        _signs(rig.inclinometer),
    )
