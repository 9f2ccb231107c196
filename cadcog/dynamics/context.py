"""What the inertia chain needs besides the data, from a rig or a spacecraft set-up: the
object's CAD and its stated uncertainty, the measurement equipment, the ``[swing]`` table, the
sensing point, the body's box, the static estimate's error model (and with it the wire)
(:class:`InertiaContext`, built by :func:`context_for_rig` and :func:`context_for_setup`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import ReadingsError
from cadcog.core.units import AIR_DENSITY_KG_M3, MM3_PER_M3
from cadcog.mass.properties import MassProperties, box_properties
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox
from cadcog.method.gls import LineErrors
from cadcog.method.plumblines import JointEstimate
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.parameters import MEVolume, Rig, SwingOptions

if TYPE_CHECKING:
    from cadcog.spacecraft.setup import Setup

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

    @property
    def frequency_model_rel(self) -> float:
        """Relative 1 σ of every modelled frequency for what the linear model leaves out: the
        ``[swing]`` table's ``frequency_model_rel`` when declared, else the air the object
        carries, ``ρ_air V/(4 m)`` with ``V`` the body's box and ``m`` the object's mass (an
        added mass of about half the air it displaces; a pendulum mode moves by half the
        relative inertia added). A light, large body carries more: the 3U CubeSat example
        (2.6 kg in its 3.4 l box) 4.0·10⁻⁴, the paper rig's steel block 3.8·10⁻⁵.

        Examples
        --------
        >>> import cadcog
        >>> f"{context_for_rig(cadcog.load_rig()).frequency_model_rel:.2e}"
        '3.83e-05'
        """
        if self.swing.frequency_model_rel is not None:
            return self.swing.frequency_model_rel
        volume_m3 = float(np.prod(self.body.hi_mm - self.body.lo_mm)) / MM3_PER_M3
        return AIR_DENSITY_KG_M3 * volume_m3 / (4.0 * self.object_cad.mass_kg)

    def top_hinge_mm(
        self, weight_n: float, scale: tuple[float, float] | None = None
    ) -> tuple[float, float]:
        """The top clamp's hinge (how far below the clamp the free wire turns) and its 1 σ, mm.

        One wire hangs the object: under the tension ``T`` it turns ``λ`` from where it is
        held at **both** ends, ``λ = √(EI/T)`` for a wire of bending stiffness ``EI`` and 0 for
        an ideal string. The hinge is therefore the same ``λ`` as the wire's offset at the exit
        (:meth:`ErrorModel.wire_prior`: one unknown of the test, ``0 … wire_offset_max_mm``
        with the default ``"one-wire"`` model, ``√(EI/T)`` within EI's spread with
        ``"elastica"``); :meth:`hang_terms` gives its covariance with the pivots. With the
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

    def hang_terms(
        self,
        positions_mm: FloatArray,
        cog_mm: FloatArray,
        weight_n: float,
        joint: JointEstimate | None = None,
        lines: Sequence[int] | None = None,
    ) -> HangTerms:
        """Each hang's pivot, the top clamp's hinge, and the joint covariance of the assembly's
        CoG, the hinge and the pivots, with the wire's offset scale λ **one unknown shared by
        every hang** and by the hinge (one wire hangs them all), as the CoG's fit ``joint``
        found it (its λ, and how its CoG and λ follow each hang's point).

        Each hang's pivot is the exit moved by ``λ fᵢ`` along its bolt axis ``nᵢ``; its own
        error ``eᵢ`` is the play in the face plane and the per-hang scatter along ``nᵢ``
        (covariance ``Σᵢ``, as the CoG fit took it: ``joint.point_cov_mm2``, else the
        model's). An error of λ moves every pivot at once (``var(λ) fᵢnᵢ fⱼnⱼᵀ``, it does not
        average out over the hangs) and the hinge by as much (``var(λ) fᵢnᵢ``: a wire that
        turns further out at the exit turns as much further down at the clamp). The CoG comes
        from the same hangs: it follows each point by ``Aᵢ = ∂G/∂pᵢ``
        (``joint.point_gain``), so its error shares ``Aᵢ Σᵢ`` with pivot ``i``'s,
        and λ's shares ``a_λ,ᵢ Σᵢ``. The swing sees the moment arms ``pᵢ − G``: taking the
        CoG independent of the pivots counts the play twice (the paper rig's products of
        inertia were stated with 1.5-3 times their variance).

        ``cog_mm``: the assembly's CoG (the fit's); ``lines``: the index in ``joint``'s lines
        of each of ``positions_mm`` (default: the same order). Without ``joint`` (what a test
        expects before it is run: λ at its prior, the CoG exact) or without its
        ``point_gain`` (a fit that gives none) the CoG is taken independent of the pivots.

        Examples
        --------
        >>> import cadcog
        >>> rig = cadcog.load_rig()
        >>> ctx = context_for_rig(rig)
        >>> exits = [rig.wire_exit_mm(p) for p in rig.suspension_points[:3]]
        >>> t = ctx.hang_terms(exits, rig.analytic_assembly.cog_mm, 90.0)
        >>> t.pivots_mm.shape, t.top_mm, t.cov_mm2.shape  # the prior: λ = 0.5 ± 0.5 mm
        ((3, 3), 0.5, (13, 13))
        """
        model = self.error_model
        prior = model.wire_prior(weight_n)
        ws = None if joint is None else joint.wire
        lam, lam_var = (
            (prior.scale_mm, prior.scale_var_mm2) if ws is None else (ws.scale_mm, ws.sigma_mm**2)
        )
        top, top_sigma = self.top_hinge_mm(weight_n, (lam, lam_var))
        shared_hinge = model.wire_model != "paper"  # the paper's: the hinge is its own draw
        pos = np.asarray(positions_mm, dtype=float).reshape(-1, 3)
        k = len(pos)
        idx = list(range(k)) if lines is None else list(lines)
        gain = np.zeros((4, k, 3))
        if joint is not None and joint.point_gain is not None:
            gain = np.asarray(joint.point_gain, dtype=float)[:, idx]
        cog_lam = np.zeros(3)
        if joint is not None and joint.cog_scale_cov_mm2 is not None:
            cog_lam = np.asarray(joint.cog_scale_cov_mm2, dtype=float)
        cog = np.asarray(cog_mm, dtype=float)
        normals = np.array([self.body.normal_at(p) for p in pos]).reshape(k, 3)
        u = pos - cog
        u /= np.linalg.norm(u, axis=1)[:, None]
        cos_theta = np.array([n @ v for n, v in zip(normals, u, strict=True)])
        f = np.broadcast_to(wire_shape_factor(cos_theta, model.wire_model), (k,))
        along = f[:, None] * normals  # fᵢnᵢ
        pivots = pos + (lam * f)[:, None] * normals
        if joint is not None and joint.point_cov_mm2 is not None:
            # the points' covariance the CoG fit took (the play, or an override): what its gain
            # carries into the CoG, so the joint covariance is one model's (and PSD)
            own = np.asarray(joint.point_cov_mm2, dtype=float)[idx]
        else:
            own = LineErrors.from_model(model).point_cov_mm2(normals)
        cog_own = np.einsum("rkb,kbc->rkc", gain[:3], own).reshape(3, 3 * k)  # Aᵢ Σᵢ
        lam_own = np.einsum("kb,kbc->kc", gain[3], own).reshape(3 * k)  # a_λ,ᵢ Σᵢ
        flat = along.reshape(3 * k)
        cov = np.zeros((4 + 3 * k, 4 + 3 * k))
        if joint is not None:
            cov[:3, :3] = joint.cov_mm2
        cov[3, 3] = top_sigma**2
        piv = lam_var * np.outer(flat, flat) + np.outer(flat, lam_own) + np.outer(lam_own, flat)
        for i in range(k):
            piv[3 * i : 3 * i + 3, 3 * i : 3 * i + 3] += own[i]
        cov[4:, 4:] = piv
        if shared_hinge:
            cov[:3, 3] = cov[3, :3] = cog_lam
            cov[3, 4:] = cov[4:, 3] = lam_var * flat + lam_own
        cov[:3, 4:] = np.outer(cog_lam, flat) + cog_own
        cov[4:, :3] = cov[:3, 4:].T
        return HangTerms(pivots, top, cov)


@dataclass(frozen=True)
class HangTerms:
    """Where the swing's geometry sits and how well it is known (:meth:`InertiaContext.
    hang_terms`).

    Attributes
    ----------
    pivots_mm : ndarray, shape (k, 3)
        Each hang's pivot.
    top_mm : float
        The top clamp's hinge below the clamp.
    cov_mm2 : ndarray, shape (4 + 3k, 4 + 3k)
        Joint covariance of the assembly's CoG (3), the hinge (1) and the pivots (3 a hang).
    """

    pivots_mm: FloatArray
    top_mm: float
    cov_mm2: FloatArray

    def only(self, hangs: Sequence[int]) -> HangTerms:
        """These hangs alone, in this order (the CoG and the hinge kept)."""
        rows = [0, 1, 2, 3] + [4 + 3 * i + a for i in hangs for a in range(3)]
        return HangTerms(self.pivots_mm[list(hangs)], self.top_mm, self.cov_mm2[np.ix_(rows, rows)])


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


def context_for_setup(setup: Setup, cad_cov_kg2_mm4: FloatArray) -> InertiaContext:
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
