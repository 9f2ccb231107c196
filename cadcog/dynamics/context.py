"""What the inertia chain needs besides the data, from a rig or a spacecraft set-up: the
object's CAD and its stated uncertainty, the measurement equipment, the ``[swing]`` table, the
sensing point, the body's box, the static estimate's error model (and with it the wire)
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
from cadcog.method.wire import wire_shape_factor
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
        The static estimate's: the points' play, the wire's offset along the bolt axis (and so
        the top clamp's hinge, :meth:`top_hinge_mm`).
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
    signs: tuple[int, int]

    def top_hinge_mm(
        self, weight_n: float, scale: tuple[float, float] | None = None
    ) -> tuple[float, float]:
        """The top clamp's hinge (how far below the clamp the free wire turns) and its 1 σ, mm.

        One wire hangs the object: under the tension ``T`` it turns ``λ`` from where it is
        held at **both** ends, ``λ = √(EI/T)`` for a wire of bending stiffness ``EI`` and 0 for
        an ideal string. The hinge is therefore the same ``λ`` as the wire's offset at the exit
        (:meth:`ErrorModel.wire_prior`: one unknown of the test, ``0 … wire_offset_max_mm``
        with the default ``"one-wire"`` model, ``√(EI/T)`` within EI's spread with
        ``"elastica"``); :meth:`pivot_terms` gives its covariance with the pivots. With the
        paper's model (an independent offset a hang) the hinge is one more such draw.

        ``scale``: λ and its variance as the CoG's estimate found them (default the prior); a
        λ the noise made negative puts the hinge at the clamp.

        Examples
        --------
        >>> import cadcog
        >>> ctx = context_for_rig(cadcog.load_rig())  # the paper rig: one wire, λ in 0 … 1 mm
        >>> ctx.top_hinge_mm(90.0)
        (0.5, 0.5)
        >>> ctx.top_hinge_mm(90.0, scale=(0.2, 0.01))  # as the CoG's joint fit found it
        (0.2, 0.1)
        """
        prior = self.error_model.wire_prior(weight_n)
        if self.error_model.wire_model == "paper":
            return prior.scale_mm, float(np.sqrt(prior.scatter_var_mm2))
        lam, lam_var = (prior.scale_mm, prior.scale_var_mm2) if scale is None else scale
        return max(float(lam), 0.0), float(np.sqrt(lam_var))

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
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Each hang's pivot, shape (k, 3), the pivots' joint covariance, (3k, 3k), and each
        pivot's covariance with the top clamp's hinge, (k, 3), with the wire's offset scale λ
        **one unknown shared by every hang** and by the hinge (one wire hangs them all).

        ``scale``: λ and its variance as the CoG's estimate found them (its joint fit takes λ
        as an unknown of the test); default the error model's prior. Each hang's pivot is the
        exit moved by ``λ fᵢ`` along its bolt axis ``nᵢ``; its own covariance is the play in the
        face plane and the per-hang scatter along ``nᵢ``, and every pair of hangs shares
        ``var(λ) (fᵢnᵢ)(fⱼnⱼ)ᵀ``: an error of λ moves every pivot at once and does not average
        out over the hangs (:meth:`pivots` takes it per hang, for planning). The hinge is ``λ``
        (:meth:`top_hinge_mm`): its covariance with pivot ``i`` is ``var(λ) fᵢnᵢ``, so that a
        wire that turns further out at the exit turns as much further down at the clamp.
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
        return pivots, cov + lam_var * np.outer(along, along), lam_var * along.reshape(k, 3)


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
        _signs(rig.inclinometer),
    )


def context_for_setup(setup: Any, cad_cov_kg2_mm4: FloatArray) -> InertiaContext:
    """A spacecraft set-up: its CAD with the stated uncertainty ``cad_cov_kg2_mm4``."""
    rig = setup.rig
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
        _signs(rig.inclinometer),
    )
