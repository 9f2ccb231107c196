"""From averaged readings to the compensated CoG with its uncertainty and diagnostics.

This is the library behind ``cadcog estimate``: readings → verticals (eq. 2) → plumb lines →
weighted joint estimate of the assembly CoG (docs/method.md §2) → ME compensation (eqs. 10, 16).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.errors import DegenerateGeometryError
from cadcog.core.units import STANDARD_GRAVITY_M_S2, deg_to_rad
from cadcog.method import gls, sharedfit, sym3
from cadcog.method.bodybox import BodyBox
from cadcog.method.cogestimate import CogEstimate
from cadcog.method.errormodel import ErrorModel
from cadcog.method.foreignhangs import foreign_hangs
from cadcog.method.medata import MEData
from cadcog.method.plumblines import (
    Compensation,
    JointEstimate,
    PlumbLine,
    WireScale,
    _check_normal_matrix,
    compensate_me,
    line_consistency,
    pair_diagnostics,
)
from cadcog.method.readings import Suspension, suspension_verticals
from cadcog.rig.geometry import FloatArray, axes_beyond_range
from cadcog.rig.inclinometer import InclinometerConfig
from cadcog.rig.parameters import Rig


def default_model(config: InclinometerConfig | None = None) -> ErrorModel:
    """The error model without a rig: the inclinometer's, the paper's other defaults."""
    cfg = config or InclinometerConfig()
    return ErrorModel(
        (1.0,),
        (0.0,),
        accuracy_deg=cfg.accuracy_deg,
        lsb_deg=0.0 if cfg.accelerometer else cfg.sensor.lsb_deg,
        sensor_offset_deg=cfg.offset_deg,
        sensor_scale_rel=cfg.scale_error_rel,
        mounting_misalignment_deg=cfg.mounting_misalignment_deg,
        device=cfg.device,
        sensor_offset_g=cfg.offset_g,
        sensor_cross_axis_rel=cfg.cross_axis_rel,
    )


def accelerometer_variances(
    suspensions: Sequence[Suspension], cfg: InclinometerConfig, mdl: ErrorModel
) -> FloatArray:
    """Each accelerometer hang's variance, shape (k,): its vertical's along each direction ⊥ u
    (rad²) and its gravity norm's (g²) alike.

    The mean of n readings has the noise its samples show: the largest axis's sample variance
    over n (the error model's sensor noise where a hang has one sample), plus what the shared
    figures do not model, each axis within ±``accuracy_g`` (uniform): its variance along each
    direction ⊥ u (rad² per g² at 1 g) and along u (the norm) alike.
    """
    noise = np.array(
        [
            max(s.std_acc_g) ** 2 / s.n_samples
            if s.std_acc_g is not None
            else float(deg_to_rad(mdl.sensor_noise_deg)) ** 2
            for s in suspensions
        ]
    )
    return np.asarray(noise + cfg.accuracy_g**2 / 3.0)


def estimate_cog(
    suspensions: Sequence[Suspension],
    config: InclinometerConfig | None = None,
    me: MEData | None = None,
    *,
    model: ErrorModel | None = None,
    body: BodyBox | None = None,
    wire_correction: bool = True,
    self_calibrate: bool = False,
    angle_sigma_deg: float | None = None,
    point_sigma_mm: float | None = None,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> CogEstimate:
    """Compensated CoG of an object from its averaged suspensions, with its covariance.

    The generalised least squares of :func:`cadcog.method.gls.plumb_gls`, the very estimator every
    Monte Carlo runs: each line weighted by its lateral covariance from the error model (play
    in the face plane, wire-offset scatter along the bolt axis, reading errors through eq. 2
    at the distance of the CoG), each point moved along its bolt axis by the expected wire
    offset, then the ME compensation (eqs. 10, 16).

    Parameters
    ----------
    suspensions : sequence of Suspension
        At least two, with distinct ids.
    config : InclinometerConfig, optional
        Axis signs and range (the paper's rig if omitted).
    me : MEData, optional
        Without it the result is the assembly CoG and says so in its warnings.
    model : ErrorModel, optional
        The error sources (default: :func:`default_model`).
    body : BodyBox, optional
        Gives each point's bolt axis. Without it the wire offset cannot be corrected: its mean
        is then counted as an isotropic point error, and a warning says so.
    wire_correction : bool
        Correct the expected wire offset (default). False: take the points as given (the paper).
    self_calibrate : bool
        Estimate the wire offset scale λ with the CoG (three or more hangs).
    angle_sigma_deg, point_sigma_mm : float, optional
        Overrides: per-axis reading std, isotropic point std.
    min_angle_deg : float
        Pairs of plumb lines closer to parallel are left out of the pair diagnostics.

    Raises
    ------
    cadcog.core.errors.IllConditionedError
        If every pair of plumb lines is ill-conditioned.
    cadcog.core.errors.DegenerateGeometryError
        If the wire scale cannot be estimated (bolt axes along their verticals).
    ValueError
        Self-calibration with fewer than three hangs, or without a body.
    """
    cfg = config or InclinometerConfig()
    mdl = model or default_model(cfg)
    _check_self_calibration(len(suspensions), self_calibrate, body, wire_correction)
    v = suspension_verticals(suspensions, cfg)
    warnings = _reading_warnings(suspensions, v.normalized, cfg) + _reversal_warnings(suspensions)
    weight_n = None if me is None else (me.object_mass_kg + me.me_mass_kg) * STANDARD_GRAVITY_M_S2
    normals, wire, errors, acc_var = _line_model(
        suspensions, cfg, mdl, body, weight_n, warnings,
        wire_correction=wire_correction, self_calibrate=self_calibrate,
        angle_sigma_deg=angle_sigma_deg, point_sigma_mm=point_sigma_mm,
    )  # fmt: skip
    p = np.array([s.position_mm for s in suspensions], dtype=float).T[:, :, None]
    u = v.u.T[:, :, None]
    nrm = normals.T[:, :, None]
    # Pair diagnostics first: they name the ill-conditioned case before any arithmetic on it.
    pair_diagnostics(
        [PlumbLine(s.id, p[:, j, 0], v.u[j]) for j, s in enumerate(suspensions)], min_angle_deg
    )
    shared_info: dict[str, Any] | None = None
    if mdl.has_shared_sensor or cfg.accelerometer:
        joint, verticals, shared_info = _joint_with_shared_sensor(
            suspensions, cfg, mdl, normals, errors, wire, body is not None, min_angle_deg,
            warnings, acc_var,
        )  # fmt: skip
    else:
        joint = _joint(suspensions, p, u, nrm, errors, wire, body is not None, min_angle_deg,
                       warnings)  # fmt: skip
        verticals = v.u
    warnings += _joint_warnings(joint, suspensions, min_angle_deg)
    comp = _compensation(joint, me, body, warnings)
    info = {
        "estimator": "generalised least squares over all plumb lines",
        "error_model": mdl.describe(),
        "wire_correction": body is not None and wire_correction,
        "wire_self_calibration": self_calibrate,
        "angle_sigma_deg_override": angle_sigma_deg,
        "point_sigma_mm_override": point_sigma_mm,
        "bolt_axes": None if body is None else body.source,
    }
    if shared_info is not None:
        info["shared_sensor"] = shared_info
    return CogEstimate(
        tuple(suspensions), verticals, joint, comp, info, v.n_normalized, tuple(warnings)
    )


def _check_self_calibration(
    k: int, self_calibrate: bool, body: BodyBox | None, wire_correction: bool
) -> None:
    """Self-calibration of the wire needs three hangs and the bolt axes."""
    if self_calibrate and k < 3:
        raise ValueError(
            f"self-calibration of the wire needs three or more suspensions, got {k}: "
            "with two, the CoG and the wire scale use up every measurement"
        )
    if self_calibrate and (body is None or not wire_correction):
        raise ValueError("self-calibration of the wire needs the bolt axes (a rig or a set-up)")


def _reversal_warnings(suspensions: Sequence[Suspension]) -> list[str]:
    """A hang named as another's reversal (``S3~``) but read as a plain hang."""
    ids = {s.id for s in suspensions}
    return [
        f"suspension {s.id} is named as the reversal of {s.id[:-1]} but is read as a "
        "plain hang: give the readings a sensor_turned column, true on its rows "
        "(docs/estimate.md)"
        for s in suspensions
        if s.id.endswith("~") and s.id[:-1] in ids and not s.sensor_turned
    ]


def _line_model(
    suspensions: Sequence[Suspension],
    cfg: InclinometerConfig,
    mdl: ErrorModel,
    body: BodyBox | None,
    weight_n: float | None,
    warnings: list[str],
    *,
    wire_correction: bool,
    self_calibrate: bool,
    angle_sigma_deg: float | None,
    point_sigma_mm: float | None,
) -> tuple[FloatArray, gls.WireTerm, gls.LineErrors, FloatArray | None]:
    """What the estimate takes of each line: its bolt axis (zeros without a body), the wire
    term, the line errors (an accelerometer's per-hang reading variances, when it is one, also
    returned) and, without a body, the wire's mean offset counted as an isotropic point error
    (warned of)."""
    k = len(suspensions)
    samples = [s.n_samples for s in suspensions]
    if body is not None:
        normals = body.normals(suspensions)
        if mdl.wire_model == "elastica" and weight_n is None and wire_correction:
            raise ValueError("the elastica wire model needs the hung mass: give the ME data")
        wire = gls.WireTerm.from_model(
            mdl, weight_n or 1.0, correct=wire_correction, estimate=self_calibrate
        )
        errors = gls.LineErrors.from_model(
            mdl, samples, angle_sigma_deg=angle_sigma_deg, point_sigma_mm=point_sigma_mm
        )
    else:
        normals = np.zeros((k, 3))
        wire = gls.WireTerm(mdl.wire_model)
        prior = mdl.wire_prior(weight_n or 1.0)
        iso = mdl.play_var_mm2 + prior.scatter_var_mm2 + prior.scale_var_mm2 + prior.scale_mm**2
        errors = gls.LineErrors.from_model(
            mdl,
            samples,
            angle_sigma_deg=angle_sigma_deg,
            point_sigma_mm=np.sqrt(iso) if point_sigma_mm is None else point_sigma_mm,
        )
        if prior.scale_mm > 0:
            warnings.append(
                "no rig or set-up: the bolt axes are unknown, so the expected wire offset "
                f"({prior.scale_mm:.2f} mm) is not corrected; it is counted as an isotropic "
                "point error instead"
            )
    acc_var = accelerometer_variances(suspensions, cfg, mdl) if cfg.accelerometer else None
    if acc_var is not None and angle_sigma_deg is None:
        # (k, 1): a line per row, as LineErrors.from_model shapes per-line variances
        errors = replace(errors, reading_var_rad2=acc_var[:, None], isotropic_reading=True)
    elif acc_var is not None:
        errors = replace(errors, isotropic_reading=True)
    return normals, wire, errors, acc_var


def _joint_warnings(
    joint: JointEstimate, suspensions: Sequence[Suspension], min_angle_deg: float
) -> list[str]:
    """The joint estimate's ill-conditioned pairs (but a point and its reversal, which hang
    alike by design) and its inconsistent lines."""
    reversal_pairs = {
        frozenset((s.id, t.id))
        for s in suspensions
        for t in suspensions
        if s.sensor_turned != t.sensor_turned and s.position_mm == t.position_mm
    }
    out = [
        f"pair {a} & {b}: plumb lines meet at {angle:.2f}° (< {min_angle_deg:g}°), "
        "ill-conditioned; left out of the pair table"
        for a, b, angle in joint.skipped_pairs
        if frozenset((a, b)) not in reversal_pairs
    ]
    out += [
        f"suspension {r.id}: its line passes {r.distance_mm:.2f} mm from the joint "
        f"estimate ({r.normalized:.1f} σ, p = {r.p_value:.2g}): "
        "inconsistent with the others"
        for r in joint.residuals
        if r.inconsistent
    ]
    return out


def _compensation(
    joint: JointEstimate, me: MEData | None, body: BodyBox | None, warnings: list[str]
) -> Compensation | None:
    """The ME removed from the joint CoG (eqs. 10, 16), refused outside the object's box;
    without the ME's data None, and a warning that the CoG is the assembly's."""
    if me is None:
        warnings.append(
            "no measurement-equipment data: cog_mm is the CoG of the assembly (object + ME), "
            "not compensated"
        )
        return None
    comp = compensate_me(
        joint.cog_mm,
        joint.cov_mm2,
        object_mass_kg=me.object_mass_kg,
        me_mass_kg=me.me_mass_kg,
        me_cog_mm=me.me_cog_mm,
        me_cog_cov_mm2=me.me_cog_cov_mm2,
        object_mass_sigma_kg=me.object_mass_sigma_kg,
        object_mass_source=me.object_mass_source,
    )
    if body is not None:
        _refuse_outside(body, comp, me)
    return comp


def _refuse_outside(body: BodyBox, comp: Compensation, me: MEData) -> None:
    """Refuse an object CoG outside the object's box by more than
    :data:`~cadcog.core.tolerances.OUTSIDE_BODY_SIGMAS` σ and
    :data:`~cadcog.core.tolerances.OUTSIDE_BODY_MARGIN_MM` on an axis: no rigid body has its
    CoG there."""
    sigma = np.sqrt(np.maximum(np.diag(comp.cov_mm2), 0.0))
    out = body.outside_by_mm(comp.cog_mm)
    far = out > tolerances.OUTSIDE_BODY_SIGMAS * sigma + tolerances.OUTSIDE_BODY_MARGIN_MM
    if not far.any():
        return
    axes = ", ".join(
        f"{a} by {d:.1f} mm ({d / s:.0f} σ)" if s > 0 else f"{a} by {d:.1f} mm"
        for a, d, s, f in zip("xyz", out, sigma, far, strict=True)
        if f
    )
    raise DegenerateGeometryError(
        f"the object CoG [{', '.join(f'{v:.1f}' for v in comp.cog_mm)}] mm is outside the "
        f"object along {axes}: the test did not locate it; check the object mass "
        f"({me.object_mass_kg:g} kg, {me.object_mass_source}; ME {me.me_mass_kg:g} kg), that "
        "the readings are of this object, and the point of each hang"
    )


def _joint(
    suspensions: Sequence[Suspension],
    p: FloatArray,
    u: FloatArray,
    nrm: FloatArray,
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    has_body: bool,
    min_angle_deg: float,
    warnings: list[str],
) -> JointEstimate:
    """The lines' joint estimate when nothing is shared but the wire (the per-hang GLS)."""
    batch = gls.plumb_gls(p, u, nrm, errors, wire)
    _check_normal_matrix(sym3.sym_to_full(batch.weights.sum(axis=1))[0])
    wire_scale = None
    if has_body and (wire.scale_mm or wire.estimate):
        wire_scale = _wire_scale(
            float(batch.scale_mm[0]),
            float(batch.scale_var_mm2[0]),
            bool(gls.scale_identifiable(batch)[0]),
            wire,
            warnings,
        )
    virtual = batch.points_mm
    lines = [PlumbLine(s.id, virtual[:, j, 0], u[:, j, 0]) for j, s in enumerate(suspensions)]
    pairs, skipped = pair_diagnostics(lines, min_angle_deg)
    cog = batch.cog_mm[:, 0]
    residuals, chi2, dof = line_consistency(
        [s.id for s in suspensions], p, u, nrm, batch.shape, batch.weights,
        batch.lateral_cov_mm2, wire, cog,
    )  # fmt: skip
    gain, cog_lam = _gls_point_gain(batch, u, nrm, wire)
    return JointEstimate(
        cog,
        sym3.sym_to_full(batch.cov_mm2[:, 0]),
        tuple(residuals),
        tuple(pairs),
        tuple(skipped),
        chi2,
        dof,
        wire_scale,
        gain,
        cog_lam,
        errors.point_cov_mm2(nrm[:, :, 0].T),
    )


def _gls_point_gain(
    batch: gls.GLSBatch, u: FloatArray, nrm: FloatArray, wire: gls.WireTerm
) -> tuple[FloatArray, FloatArray]:
    """``∂(G, λ)/∂pᵢ`` of one trial's GLS, shape (4, k, 3), and the CoG's covariance with λ
    (λ's row and covariance 0 when λ is known)."""
    cov = sym3.sym_to_full(batch.cov_mm2[:, 0])
    var_lam = float(batch.scale_var_mm2[0])
    with_lam = not wire.fixed and bool(np.isfinite(var_lam))
    cross = np.asarray(batch.cov_cog_scale_mm2[:, 0], dtype=float) if with_lam else np.zeros(3)
    if with_lam:
        cov = np.block([[cov, cross[:, None]], [cross[None, :], np.array([[var_lam]])]])
    design = gls.line_design(u[:, :, 0].T, nrm[:, :, 0].T, batch.shape[:, 0], with_lam)
    weights = sym3.sym_to_full(batch.weights[:, :, 0])
    return gls.point_gain(cov, design, weights, with_lam), cross


def _joint_with_shared_sensor(
    suspensions: Sequence[Suspension],
    cfg: InclinometerConfig,
    mdl: ErrorModel,
    normals: FloatArray,
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    has_body: bool,
    min_angle_deg: float,
    warnings: list[str],
    norm_var: FloatArray | None = None,
) -> tuple[JointEstimate, FloatArray, dict[str, Any]]:
    """The joint estimate with the sensor's shared offsets, sensitivities and mounting
    estimated alongside (:func:`cadcog.method.sharedfit.fit_shared`): the estimate, the
    corrected verticals and what became of each shared parameter. An accelerometer's hangs
    come with ``norm_var`` (:func:`accelerometer_variances`), their gravity norms' variance."""
    acc: FloatArray | None = None
    if cfg.accelerometer:
        # (read with an accelerometer's configuration, every suspension has its reading)
        acc = np.array([s.acc_g if s.acc_g is not None else (np.nan,) * 3 for s in suspensions])
    fit = sharedfit.fit_shared(
        [s.position_mm for s in suspensions],
        [s.inc_x_deg for s in suspensions],
        [s.inc_y_deg for s in suspensions],
        [s.top_face_up for s in suspensions],
        normals,
        errors,
        wire,
        mdl.shared_sensor_sigmas,
        cfg,
        [s.id for s in suspensions],
        sensor_turned=[s.sensor_turned for s in suspensions],
        acc_g=acc,
        norm_var_g2=norm_var,
    )
    _check_normal_matrix(np.asarray(np.linalg.inv(fit.cov_mm2), dtype=float))
    wire_scale = None
    if has_body and (wire.scale_mm or wire.estimate):
        wire_scale = _wire_scale(
            fit.scale_mm, fit.scale_sigma_mm**2, fit.scale_identified, wire, warnings
        )
    # An accelerometer reads the whole vector: no hang is ambiguous.
    near = 0.0 if cfg.accelerometer else np.sin(np.radians(mdl.mounting_misalignment_deg))
    for s, u in zip(suspensions, fit.verticals, strict=True):
        if near > 0 and abs(u[2]) < near:
            warnings.append(
                f"suspension {s.id}: its vertical lies within the sensor's mounting angle "
                f"({mdl.mounting_misalignment_deg:g}°) of the horizontal, where which way up the "
                "sensor reads is ambiguous; hang it from a point whose vertical is steeper"
            )
    names = sharedfit.shared_parameter_names(cfg)
    n_ch = 3 if cfg.accelerometer else 2  # channels: offsets and sensitivities each
    offset_bound = mdl.sensor_offset_g if cfg.accelerometer else mdl.sensor_offset_deg
    bounds = np.array([offset_bound] * n_ch + [mdl.sensor_scale_rel] * n_ch)
    beyond = [
        f"{name} = {fit.shared[j]:+.3g}"
        for j, name in enumerate(names[: 2 * n_ch])
        if bounds[j] > 0 and abs(fit.shared[j]) > bounds[j]
    ]
    angle = float(np.linalg.norm(fit.shared[2 * n_ch : 2 * n_ch + 3]))
    # An accelerometer's mounting carries its couplings' rotation too: each of its three
    # components within the cross-axis figure (radians).
    turn = mdl.mounting_misalignment_deg + float(
        np.degrees(np.sqrt(3.0) * mdl.sensor_cross_axis_rel) if cfg.accelerometer else 0.0
    )
    if mdl.mounting_misalignment_deg > 0 and angle > turn:
        beyond.append(f"mounting {angle:.3g}°")
    if beyond:
        warnings.append(
            f"the fit puts the sensor's {', '.join(beyond)} beyond its declared figures: a hang "
            "is probably wrong (look at the flagged ones), or the figures are too small"
        )
    lines = [PlumbLine(s.id, fit.points_mm[j], fit.verticals[j]) for j, s in enumerate(suspensions)]
    pairs, skipped = pair_diagnostics(lines, min_angle_deg)
    joint = JointEstimate(
        fit.cog_mm, fit.cov_mm2, fit.residuals, tuple(pairs), tuple(skipped), fit.chi2, fit.dof,
        wire_scale, fit.point_gain, fit.cog_scale_cov_mm2, errors.point_cov_mm2(normals),
    )  # fmt: skip
    carried = [
        f"{name} (σ {sigma:.2g} of {prior:.2g})"
        for name, c, sigma, prior in zip(
            names, fit.calibrated, fit.shared_sigma, fit.prior_sigma, strict=True
        )
        if prior > 0 and not c
    ]
    if carried:
        if cfg.accelerometer:
            hint = (
                "; hangs in more orientations, or a reversal, calibrate an accelerometer's "
                "offsets and sensitivities: docs/bench.md"
            )
        elif any(s.sensor_turned for s in suspensions):
            hint = ""
        else:
            hint = "; a reversal calibrates the offsets: docs/bench.md"
        warnings.append(
            "these hangs do not calibrate the sensor's shared "
            f"{', '.join(carried)}: what is left of their declared figures is carried into "
            f"the CoG's σ (docs/estimate.md: what one sensor shares across the hangs{hint})"
        )
    return joint, fit.verticals, fit.to_dict()


def _reading_warnings(
    suspensions: Sequence[Suspension], normalized: npt.NDArray[np.bool_], cfg: InclinometerConfig
) -> list[str]:
    warnings = []
    for s, norm in zip(suspensions, normalized, strict=True):
        if norm:
            warnings.append(
                f"suspension {s.id}: sin²X + sin²Y > 1 (X = {s.inc_x_deg:.3f}°, "
                f"Y = {s.inc_y_deg:.3f}°); the sines were normalised, the vertical is horizontal"
            )
        beyond = axes_beyond_range(s.inc_x_deg, s.inc_y_deg, cfg.range_deg)
        if beyond:
            warnings.append(
                f"suspension {s.id}: {', '.join(beyond)} beyond the inclinometer's "
                f"±{cfg.range_deg:g}° range; the reading may be saturated"
            )
    return warnings


def _wire_scale(
    scale_mm: float,
    var_mm2: float,
    identified: bool,
    wire: gls.WireTerm,
    warnings: list[str],
) -> WireScale:
    """The wire scale of an estimate (λ, its variance, whether the lines determine it); raises
    if self-calibration cannot determine it. A λ more than 3 σ of its prior from the prior's
    mean (the one wire: 0.5 ± 0.5 mm) is warned of: the lines then meet only with the points
    moved, which a wire does not do."""
    prior_sigma = float(np.sqrt(max(wire.scale_var_mm2, 0.0)))
    if prior_sigma > 0 and abs(scale_mm - wire.scale_mm) > 3.0 * prior_sigma:
        warnings.append(
            f"the wire offset λ = {scale_mm:.2f} mm lies far from its prior "
            f"({wire.scale_mm:.2f} ± {prior_sigma:.2f} mm): the lines meet only with the points "
            "moved along their bolts; is a point's position where the wire leaves the object "
            "(a set-up lists it so), and is the sensor's orientation right?"
        )
    if wire.estimate:
        if not identified:
            raise DegenerateGeometryError(
                "the wire offset scale cannot be estimated from these suspensions: the bolt "
                "axes lie (nearly) along their verticals, or the CoG can absorb the offsets, so "
                "a wire offset does not change the plumb lines' meeting; hang from points whose "
                "bolt axes are tilted from the vertical, or drop --self-calibrate-wire"
            )
        sigma = float(np.sqrt(var_mm2))
        if sigma > max(wire.scale_mm, 0.1):
            warnings.append(f"wire scale poorly determined: λ = {scale_mm:.2f} ± {sigma:.2f} mm")
        return WireScale(scale_mm, sigma, True, wire.scale_mm)
    return WireScale(scale_mm, float(np.sqrt(max(var_mm2, 0.0))), False, wire.scale_mm)


def estimate_for_rig(
    rig: Rig,
    suspensions: Sequence[Suspension],
    *,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
    wire_correction: bool = True,
    self_calibrate: bool = False,
    angle_sigma_deg: float | None = None,
    point_sigma_mm: float | None = None,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> CogEstimate:
    """The rig's compensated CoG, as ``cadcog estimate --rig`` computes it: its inclinometer,
    error model, bolt axes and measurement equipment, the object's weighed mass
    (± ``mass_sigma_kg``) when given, else the rig's; a warning when a hang is from none of the
    rig's suspension points (readings of another object). The other options are
    :func:`estimate_cog`'s."""
    me = MEData.from_rig(rig)
    if weighed_mass_kg is not None:
        me = me.weighed(weighed_mass_kg, mass_sigma_kg)
    result = estimate_cog(
        suspensions,
        rig.inclinometer,
        me,
        model=ErrorModel.from_rig(rig),
        body=BodyBox.of_rig(rig),
        wire_correction=wire_correction,
        self_calibrate=self_calibrate,
        angle_sigma_deg=angle_sigma_deg,
        point_sigma_mm=point_sigma_mm,
        min_angle_deg=min_angle_deg,
    )
    foreign = foreign_hangs(rig, suspensions)
    if not foreign:
        return result
    return replace(
        result,
        warnings=(
            *result.warnings,
            f"suspension(s) {', '.join(foreign)} hang from none of rig {rig.name}'s "
            "suspension points (their wire exits): is this the rig these readings were taken "
            "on? (a spacecraft's readings take --setup)",
        ),
    )
