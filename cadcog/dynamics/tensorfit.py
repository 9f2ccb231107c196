"""The inertia tensor that explains every hang's swing frequencies, and its covariance.

Unknowns: the six entries ``p = [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]`` of the hung assembly's inertia
tensor about its CoG (body axes; tensor convention, off-diagonal ``−∫xy dm``). Data: each hang's
fitted frequencies (:mod:`cadcog.dynamics.modalfit`), corrected for the swing's amplitude (a
pendulum slows as ``1 − A²/16``) and given a relative model error. The fit is weighted least
squares on the frequencies (Levenberg-Marquardt from the CAD's tensor), each hang's modes
predicted by :func:`cadcog.dynamics.hungbody.hang_modes`.

Everything else is an input with an uncertainty (the *nuisances*): the object's mass, the
assembly's CoG from the plumb lines (with its covariance), each wire exit (the point's play and
the wire's offset), the wire's length and its top hinge, the sensor's position, each ME
volume's CoG and own inertia. The CoG, the hinge and the pivots come from the same hangs and
the same wire: their joint covariance (:meth:`cadcog.dynamics.context.InertiaContext.
hang_terms`) carries what they share. The object's tensor about its own CoG is the assembly's
less the ME's and the parallel-axis terms (as eq. 10 removes the ME from the CoG). Its
covariance is the frequency fit's plus every nuisance's, propagated through the whole chain
(fit and compensation) by central differences.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import DegenerateGeometryError
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.dynamics.modalfit import DRIFT_PRIOR_REL, ModalFit
from cadcog.mass.properties import MassProperties

FloatArray = npt.NDArray[np.float64]

#: Order of the six tensor entries in every vector and covariance of this package.
ENTRIES = ("xx", "yy", "zz", "xy", "xz", "yz")

#: The fit stops when a step changes the entries by less than this fraction of their size.
CONVERGED_REL = 1e-10

#: A fitted frequency drift beyond this many of its prior σ
#: (:data:`cadcog.dynamics.modalfit.DRIFT_PRIOR_REL`) is not the swing's size: what exceeds it
#: is added to the frequency's σ (on the nonlinear simulation such modes' errors were 0.3 % at
#: the median, 3 σ of the fit alone: docs/inertia_validation.md).
TRUSTED_DRIFT_PRIORS = 2.0


#: The hangs do not determine the tensor when some combination of its entries has a 1-σ
#: uncertainty (from the frequencies alone) larger than this share of the mean moment.
MAX_FREE_SHARE = 0.3


def tensor(p: npt.ArrayLike) -> FloatArray:
    """3 × 3 tensor from its six entries ``[xx, yy, zz, xy, xz, yz]``."""
    xx, yy, zz, xy, xz, yz = np.asarray(p, dtype=float)
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def entries(t: npt.ArrayLike) -> FloatArray:
    """The six entries ``[xx, yy, zz, xy, xz, yz]`` of a symmetric 3 × 3 tensor."""
    a = np.asarray(t, dtype=float)
    return np.array([a[0, 0], a[1, 1], a[2, 2], a[0, 1], a[0, 2], a[1, 2]])


def parallel_axis(mass_kg: float, offset_mm: FloatArray) -> FloatArray:
    """``m (|r|² I − r rᵀ)``: a point mass's inertia about a point ``r`` away (kg·mm²)."""
    r = np.asarray(offset_mm, dtype=float)
    return mass_kg * (float(r @ r) * np.eye(3) - np.outer(r, r))


@dataclass(frozen=True)
class Nuisances:
    """Every uncertain input besides the frequencies, as one vector with its covariance.

    Attributes
    ----------
    names : tuple of str
        One name per entry of ``values`` (for the error budget).
    values : ndarray, shape (n,)
    cov : ndarray, shape (n, n)
    n_hangs, n_me : int
        Layout: object mass, assembly CoG (3), wire length, the top clamp's hinge, sensor (3),
        the pivots (3 per hang), then per ME volume its CoG (3) and own-inertia scale (1).
    """

    names: tuple[str, ...]
    values: FloatArray
    cov: FloatArray
    n_hangs: int
    n_me: int

    def unpack(self, v: FloatArray) -> dict[str, object]:
        k, e = self.n_hangs, self.n_me
        i = 9
        return {
            "object_mass_kg": v[0],
            "cog_mm": v[1:4],
            "wire_length_mm": v[4],
            "top_hinge_mm": v[5],
            "sensor_mm": v[6:9],
            "exits_mm": v[i : i + 3 * k].reshape(k, 3),
            "me_cog_mm": v[i + 3 * k : i + 3 * k + 3 * e].reshape(e, 3),
            "me_scale": v[i + 3 * k + 3 * e : i + 3 * k + 4 * e],
        }


def nuisances(
    *,
    object_mass_kg: float,
    object_mass_sigma_kg: float,
    cog_mm: FloatArray,
    wire_length_mm: float,
    wire_length_sigma_mm: float,
    top_hinge_mm: float,
    sensor_mm: FloatArray,
    sensor_sigma_mm: float,
    exits_mm: FloatArray,
    geometry_cov_mm2: FloatArray,
    me_parts: Sequence[MassProperties],
    me_cog_sigma_mm: Sequence[float],
    me_inertia_rel: float,
) -> Nuisances:
    """Assemble the nuisance vector and its covariance; ``geometry_cov_mm2``, shape
    (4 + 3k, 4 + 3k), is the joint covariance of the assembly's CoG, the top clamp's hinge and
    the k pivots (:class:`cadcog.dynamics.context.HangTerms`: one wire turns as far from both
    of its ends, and the CoG comes from the same hangs as the pivots)."""
    exits = np.asarray(exits_mm, dtype=float).reshape(-1, 3)
    k, e = len(exits), len(me_parts)
    values = np.concatenate(
        [
            [object_mass_kg],
            np.asarray(cog_mm, dtype=float),
            [wire_length_mm, top_hinge_mm],
            np.asarray(sensor_mm, dtype=float),
            exits.ravel(),
            np.array([p.cog_mm for p in me_parts]).reshape(-1),
            np.ones(e),
        ]
    )
    n = len(values)
    cov = np.zeros((n, n))
    cov[0, 0] = object_mass_sigma_kg**2
    cov[4, 4] = wire_length_sigma_mm**2
    cov[6:9, 6:9] = sensor_sigma_mm**2 * np.eye(3)
    i = 9
    geo = np.asarray(geometry_cov_mm2, dtype=float)
    if geo.shape != (4 + 3 * k, 4 + 3 * k):
        raise ValueError(f"geometry_cov_mm2 has shape {geo.shape}, expected {(4 + 3 * k,) * 2}")
    at = np.r_[1:4, 5, i : i + 3 * k]  # the CoG, the hinge and the pivots in the vector
    cov[np.ix_(at, at)] = geo
    i += 3 * k
    for j in range(e):
        cov[i + 3 * j : i + 3 * j + 3, i + 3 * j : i + 3 * j + 3] = me_cog_sigma_mm[
            j
        ] ** 2 * np.eye(3)
    i += 3 * e
    cov[i : i + e, i : i + e] = me_inertia_rel**2 * np.eye(e)
    names = (
        ["object mass", "CoG x", "CoG y", "CoG z", "wire length", "wire top hinge"]
        + [f"sensor {a}" for a in "xyz"]
        + [f"exit {h + 1} {a}" for h in range(k) for a in "xyz"]
        + [f"ME {j + 1} CoG {a}" for j in range(e) for a in "xyz"]
        + [f"ME {j + 1} own inertia" for j in range(e)]
    )
    return Nuisances(tuple(names), values, cov, k, e)


@dataclass(frozen=True)
class SwingData:
    """The fitted swings' frequencies as one vector, their covariance and the weighting.

    Attributes
    ----------
    fits : tuple of ModalFit
    frequencies_hz : ndarray, shape (N,)
        Every hang's fitted frequencies in turn, at their small-swing limit (fitted so, or
        corrected for amplitude where the fit held them fixed).
    cov_hz2 : ndarray, shape (N, N)
        Their covariance: the fits', the amplitude correction's, an untrusted drift's and the
        model error's.
    whitening : ndarray, shape (N, N)
        ``W`` with ``Wᵀ W`` the inverse of the covariance the fit weighs by (``cov_hz2``, or
        that plus what the nuisances do to the modelled frequencies: :func:`reweighted`).
    """

    fits: tuple[ModalFit, ...]
    frequencies_hz: FloatArray
    cov_hz2: FloatArray
    whitening: FloatArray

    def per_hang(self, values: FloatArray) -> list[FloatArray]:
        """Split a vector over the frequencies into hangs."""
        cuts = np.cumsum([len(f.frequencies_hz) for f in self.fits])[:-1]
        return list(np.split(values, cuts))


def amplitude_factor(fit: ModalFit, record_s: float) -> FloatArray:
    """``⟨A²⟩/16`` per mode: the relative slowing of a pendulum at the record's mean squared
    amplitude, weighted as least squares weighs it (by the signal's energy)."""
    a0 = np.deg2rad(fit.amplitudes_deg)
    s = np.maximum(fit.decay_per_s, 1e-9)
    t = record_s
    mean_a2 = a0**2 * (1 - np.exp(-4 * s * t)) / (1 - np.exp(-2 * s * t)) / 2.0
    return np.asarray(mean_a2 / 16.0)


def _whitening(cov: FloatArray) -> FloatArray:
    return np.asarray(np.linalg.cholesky(np.linalg.inv(cov)).T)


def swing_data(fits: Sequence[ModalFit], record_s: Sequence[float], model_rel: float) -> SwingData:
    """Each fit's small-swing frequencies, weighed by their own covariance.

    A fit that followed each frequency's drift (:func:`cadcog.dynamics.modalfit.fit_swing`'s
    default) gives the small-swing limit itself; what a drift exceeds
    :data:`TRUSTED_DRIFT_PRIORS` of its prior by is added to the frequency's σ. A fit that held
    each frequency fixed is corrected, ``f₀ = f / (1 − ⟨A²⟩/16)`` with the reading amplitude
    taken as the body's (an approximation: the accelerometer sees a mode scaled), half of it
    kept as its 1 σ. What the fit's two halves disagree by beyond their noise
    (:attr:`~cadcog.dynamics.modalfit.ModalFit.halves_excess_hz2`, where checked) is added to
    the variance, and every frequency carries the relative ``model_rel`` besides.
    """
    freqs, covs = [], []
    for fit, rec in zip(fits, record_s, strict=True):
        if fit.drift_hz is None:  # held fixed: the record's mean, corrected for amplitude
            shift = np.minimum(amplitude_factor(fit, rec), 0.05)
            f0 = fit.frequencies_hz / (1.0 - shift)
            extra = (f0 * (0.5 * shift)) ** 2
        else:  # the small-swing limit itself; a drift beyond what the swing's size explains is
            # the fit following something else (energy passing between modes): the excess is
            # the frequency's model error
            f0 = fit.frequencies_hz
            limit = TRUSTED_DRIFT_PRIORS * DRIFT_PRIOR_REL * f0
            extra = np.maximum(np.abs(fit.drift_hz) - limit, 0.0) ** 2
        if fit.halves_excess_hz2 is not None:  # a mode a half did not show: not checked
            extra = extra + np.nan_to_num(fit.halves_excess_hz2, nan=0.0)
        covs.append(fit.frequency_cov_hz2 + np.diag(extra + (f0 * model_rel) ** 2))
        freqs.append(f0)
    n = sum(len(f) for f in freqs)
    cov = np.zeros((n, n))
    at = 0
    for c in covs:
        cov[at : at + len(c), at : at + len(c)] = c
        at += len(c)
    return SwingData(tuple(fits), np.concatenate(freqs), cov, _whitening(cov))


def reweighted(data: SwingData, model_jacobian: FloatArray, nuis_cov: FloatArray) -> SwingData:
    """Weigh by the frequencies' covariance plus what the nuisances do to the model
    (``M Σ_v Mᵀ``, ``M = ∂f_model/∂v``): the efficient weights, and the covariance the fit's χ²
    is judged against."""
    total = data.cov_hz2 + model_jacobian @ nuis_cov @ model_jacobian.T
    return SwingData(
        data.fits, data.frequencies_hz, data.cov_hz2, _whitening(0.5 * (total + total.T))
    )


@dataclass(frozen=True)
class Geometry:
    """What the model needs per hang besides the tensor (one nuisance vector unpacked)."""

    mass_kg: float
    cog_mm: FloatArray
    hangs: tuple[HangGeometry, ...]


def hang_geometry(
    nuis: Nuisances, v: FloatArray, me_mass_kg: float, signs: tuple[int, int]
) -> Geometry:
    u = nuis.unpack(v)
    hangs = tuple(
        HangGeometry(
            np.asarray(e),
            np.asarray(u["sensor_mm"]),
            max(float(u["wire_length_mm"]), 0.0),  # type: ignore[arg-type]
            max(float(u["top_hinge_mm"]), 0.0),  # type: ignore[arg-type]
            signs[0],
            signs[1],
        )
        for e in u["exits_mm"]  # type: ignore[attr-defined]
    )
    return Geometry(float(u["object_mass_kg"]) + me_mass_kg, np.asarray(u["cog_mm"]), hangs)  # type: ignore[arg-type]


def model_frequencies(p: FloatArray, data: SwingData, geo: Geometry) -> FloatArray:
    """The model's frequencies of the fitted modes at tensor entries ``p``, shape (N,)."""
    out = []
    for fit, h in zip(data.fits, geo.hangs, strict=True):
        model = hang_modes(tensor(p), geo.mass_kg, geo.cog_mm, h, with_shapes=False).frequencies_hz
        out.append(model[fit.mode_index])
    return np.concatenate(out)


def _residuals(p: FloatArray, data: SwingData, geo: Geometry) -> FloatArray:
    return np.asarray(data.whitening @ (data.frequencies_hz - model_frequencies(p, data, geo)))


def _model_jacobian(p: FloatArray, data: SwingData, geo: Geometry, scale: float) -> FloatArray:
    """``∂f_model/∂p`` by central differences, shape (N, 6)."""
    h = 1e-6 * scale
    cols = []
    for j in range(6):
        dp = np.zeros(6)
        dp[j] = h
        cols.append(
            (model_frequencies(p + dp, data, geo) - model_frequencies(p - dp, data, geo)) / (2 * h)
        )
    return np.column_stack(cols)


def fit_tensor(data: SwingData, geo: Geometry, start: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Weighted least squares (Levenberg-Marquardt) for the assembly's six entries.

    Returns
    -------
    p : ndarray, shape (6,)
    gain : ndarray, shape (6, N)
        ``A = (JᵀJ)⁻¹ Jᵀ W`` (``J = W ∂f_model/∂p``): how ``p`` moves with the frequencies, and
        with the model's frequencies the other way; ``A Σ Aᵀ`` is its covariance for any
        frequency covariance ``Σ``.

    Raises
    ------
    DegenerateGeometryError
        When the frequencies leave a combination of the entries (nearly) free, or the best fit
        is no rigid body's tensor.
    """
    from scipy.optimize import least_squares

    p0 = np.asarray(start, dtype=float).copy()
    scale = float(np.trace(tensor(p0)))
    w = data.whitening
    _check_determined(w @ _model_jacobian(p0, data, geo, scale), p0)

    def fun(p: FloatArray) -> FloatArray:
        if not is_physical(p):  # outside the rigid bodies: a wall the step cannot cross
            return np.full(len(data.frequencies_hz), 1e6)
        return -_residuals(p, data, geo)

    def jac(p: FloatArray) -> FloatArray:
        return w @ _model_jacobian(p, data, geo, scale)

    sol = least_squares(fun, p0, jac=jac, method="lm", xtol=CONVERGED_REL, ftol=1e-14)
    p = sol.x
    if not is_physical(p) or not sol.success:
        raise DegenerateGeometryError(
            "the swings' frequencies fit no rigid body's tensor: these hangs determine the "
            "tensor too poorly (add hangs whose plumb lines point in other directions), or the "
            "wire length is wrong"
        )
    j = w @ _model_jacobian(p, data, geo, scale)
    _check_determined(j, p)
    return p, np.asarray(np.linalg.solve(j.T @ j, j.T @ w))


def is_physical(p: FloatArray) -> bool:
    """Whether entries ``p`` are a rigid body's tensor: positive principal moments that satisfy
    the triangle inequality (``I₁ + I₂ ≥ I₃``)."""
    if not np.all(np.isfinite(p)):
        return False
    m = np.linalg.eigvalsh(tensor(p))
    return bool(m[0] > 0 and m[0] + m[1] >= m[2])


def _check_determined(jac: FloatArray, p: FloatArray) -> None:
    """Refuse frequencies that leave a combination of the six entries (nearly) free."""
    mean_moment = float(np.trace(tensor(p))) / 3.0
    if jac.shape[0] >= 6:
        sv = np.linalg.svd(jac, compute_uv=False)
        free = 1.0 / sv[-1] if sv[-1] > 0 else np.inf
    if jac.shape[0] < 6:
        raise DegenerateGeometryError(
            f"these hangs do not determine the whole inertia tensor ({jac.shape[0]} usable "
            "frequencies for six entries): add hangs from points whose plumb lines point in "
            "other directions"
        )
    if not free < MAX_FREE_SHARE * mean_moment:
        raise DegenerateGeometryError(
            f"these hangs do not determine the whole inertia tensor (their {jac.shape[0]} usable "
            "frequencies leave a combination of the six entries free: plumb lines too alike): "
            "add hangs from points whose plumb lines point in other directions"
        )


def deleted_chi2(
    p: FloatArray, data: SwingData, geo: Geometry, groups: Sequence[Sequence[int]]
) -> FloatArray:
    """How much the fit's χ² falls if each group of frequencies is left out, shape (len(groups),):
    the deleted residuals of generalised least squares with correlated errors,
    ``u_gᵀ (P_gg)⁻¹ u_g``, ``u = P r``, ``P = C⁻¹ − C⁻¹J(JᵀC⁻¹J)⁻¹JᵀC⁻¹`` (``C`` the covariance
    the fit weighs by, ``r`` the residuals at the fit ``p``, ``J = ∂f_model/∂p``): exact for the
    linearised fit, χ² with ``len(g)`` dof when the group agrees with the others. A group is one
    frequency, or every frequency of a hang (a hang whose swing is off as a whole).
    """
    w = data.whitening
    c_inv = w.T @ w
    jac = _model_jacobian(p, data, geo, float(np.trace(tensor(p))))
    cj = c_inv @ jac
    proj = c_inv - cj @ np.linalg.solve(jac.T @ cj, cj.T)
    u = proj @ (data.frequencies_hz - model_frequencies(p, data, geo))
    out = np.zeros(len(groups))
    for i, g in enumerate(groups):
        idx = np.asarray(g)
        block = proj[np.ix_(idx, idx)]
        try:
            out[i] = max(float(u[idx] @ np.linalg.solve(block, u[idx])), 0.0)
        except np.linalg.LinAlgError:
            out[i] = 0.0  # the others do not determine these: nothing to test against
    return out


def weighted_chi2(p: FloatArray, data: SwingData, geo: Geometry) -> float:
    """Weighted squared residuals at ``p``."""
    r = _residuals(p, data, geo)
    return float(r @ r)


def model_nuisance_jacobian(
    p: FloatArray,
    data: SwingData,
    nuis: Nuisances,
    me_mass_kg: float,
    signs: tuple[int, int],
) -> FloatArray:
    """``M = ∂f_model/∂v`` at tensor ``p``: the modelled frequencies' change with each nuisance
    (central differences, steps of 0.1 σ), shape (N, n). A hang's exit moves only its own
    frequencies; the ME's CoGs and own inertia do not enter the swing model (only the
    compensation)."""
    sig = np.sqrt(np.diag(nuis.cov))
    out = np.zeros((len(data.frequencies_hz), len(nuis.values)))
    cuts = np.concatenate([[0], np.cumsum([len(f.frequencies_hz) for f in data.fits])])
    t = tensor(p)
    for i, (name, s) in enumerate(zip(nuis.names, sig, strict=True)):
        if s == 0.0 or name.startswith("ME "):
            continue
        hangs = range(nuis.n_hangs)
        if name.startswith("exit "):
            hangs = range(int(name.split()[1]) - 1, int(name.split()[1]))
        dv = np.zeros(len(nuis.values))
        dv[i] = 0.1 * s
        hi = hang_geometry(nuis, nuis.values + dv, me_mass_kg, signs)
        lo = hang_geometry(nuis, nuis.values - dv, me_mass_kg, signs)
        for h in hangs:
            idx = data.fits[h].mode_index
            up = hang_modes(t, hi.mass_kg, hi.cog_mm, hi.hangs[h], with_shapes=False)
            down = hang_modes(t, lo.mass_kg, lo.cog_mm, lo.hangs[h], with_shapes=False)
            diff = up.frequencies_hz[idx] - down.frequencies_hz[idx]
            out[cuts[h] : cuts[h + 1], i] = diff / (0.2 * s)
    return out


def compensate(
    p_assembly: FloatArray,
    nuis: Nuisances,
    v: FloatArray,
    me_parts: Sequence[MassProperties],
) -> tuple[FloatArray, FloatArray]:
    """The object's tensor entries about its own CoG, and that CoG (mm)."""
    u = nuis.unpack(v)
    m_o = float(u["object_mass_kg"])  # type: ignore[arg-type]
    g_a = np.asarray(u["cog_mm"])
    me_cogs = np.asarray(u["me_cog_mm"])
    scales = np.asarray(u["me_scale"])
    m_me = sum(p.mass_kg for p in me_parts)
    c_me = sum(p.mass_kg * c for p, c in zip(me_parts, me_cogs, strict=True)) / m_me
    g_o = ((m_o + m_me) * g_a - m_me * c_me) / m_o
    t = tensor(p_assembly) - parallel_axis(m_o, g_o - g_a)
    for part, c, s in zip(me_parts, me_cogs, scales, strict=True):
        t = t - s * np.asarray(part.inertia_kg_mm2) - parallel_axis(part.mass_kg, c - g_a)
    return entries(t), g_o


def direct_jacobian(function: Callable[[FloatArray], FloatArray], nuis: Nuisances) -> FloatArray:
    """Central-difference Jacobian of ``function`` w.r.t. the nuisances (steps of 0.1 σ)."""
    sig = np.sqrt(np.diag(nuis.cov))
    base = function(nuis.values)
    jac = np.zeros((len(base), len(nuis.values)))
    for i, s in enumerate(sig):
        if s == 0.0:
            continue
        dv = np.zeros(len(nuis.values))
        dv[i] = 0.1 * s
        jac[:, i] = (function(nuis.values + dv) - function(nuis.values - dv)) / (0.2 * s)
    return jac
