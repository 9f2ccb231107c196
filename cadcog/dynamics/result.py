"""What ``cadcog inertia`` reports: the object's tensor, its principal moments and axes, each
with its uncertainty, the fit's consistency and the comparison with the CAD."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.fittest import FitTest
from cadcog.core.results import JsonResult
from cadcog.dynamics.tensorfit import ENTRIES, tensor
from cadcog.mass.inertia import TENSOR_CONVENTION, principal_axes

FloatArray = npt.NDArray[np.float64]

#: An axis's 1 σ is reported at most this (degrees): the axis is then undetermined.
AXIS_UNDETERMINED_DEG = 90.0


@dataclass(frozen=True)
class PrincipalWithSigma:
    """Principal moments and axes with their first-order uncertainty.

    Attributes
    ----------
    moments_kg_mm2, moments_sigma_kg_mm2 : ndarray, shape (3,)
        Ascending moments and their 1 σ.
    axes : ndarray, shape (3, 3)
        Row ``i``: the axis of moment ``i`` (model frame; sign rule of
        :func:`cadcog.mass.inertia.principal_axes`).
    axes_sigma_deg : ndarray, shape (3,)
        1 σ of each axis's direction (degrees): the root of the summed variances of its
        rotation towards the other two axes, ``(v_jᵀ δJ v_i)/(λ_i − λ_j)``; at most
        :data:`AXIS_UNDETERMINED_DEG` (beyond, the first order means nothing: the axis is
        undetermined).
    """

    moments_kg_mm2: FloatArray
    moments_sigma_kg_mm2: FloatArray
    axes: FloatArray
    axes_sigma_deg: FloatArray


def bilinear_gradient(a: FloatArray, b: FloatArray) -> FloatArray:
    """``∂(aᵀ J b)/∂p``: the gradient of a bilinear form of the tensor in its six entries
    ``[xx, yy, zz, xy, xz, yz]`` (an off-diagonal entry sits twice in ``J``).

    Examples
    --------
    >>> a, b = np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0])
    >>> bilinear_gradient(a, b).tolist() == [a @ tensor(e) @ b for e in np.eye(6)]
    True
    """
    return np.array(
        [a[0] * b[0], a[1] * b[1], a[2] * b[2], a[0] * b[1] + a[1] * b[0],
         a[0] * b[2] + a[2] * b[0], a[1] * b[2] + a[2] * b[1]]
    )  # fmt: skip


def principal_with_sigma(p: FloatArray, cov: FloatArray) -> PrincipalWithSigma:
    """First-order perturbation of the eigen-decomposition of ``tensor(p)``."""
    pa = principal_axes(tensor(p))
    lam, v = pa.moments_kg_mm2, pa.axes
    grad = bilinear_gradient
    sig_m = np.array(
        [np.sqrt(max(float(grad(v[i], v[i]) @ cov @ grad(v[i], v[i])), 0.0)) for i in range(3)]
    )
    sig_a = np.zeros(3)
    for i in range(3):
        var = 0.0
        for j in range(3):
            if j == i:
                continue
            gap = lam[i] - lam[j]
            if abs(gap) <= np.finfo(float).eps * float(np.max(np.abs(lam))):
                # equal moments (to the last bits): the axis turns freely in their plane
                var = np.inf
                break
            g = grad(v[j], v[i]) / gap
            var += float(g @ cov @ g)
        sig_a[i] = min(float(np.rad2deg(np.sqrt(max(var, 0.0)))), AXIS_UNDETERMINED_DEG)
    return PrincipalWithSigma(lam, sig_m, v, sig_a)


#: Two adjacent principal moments closer than this many standard deviations of their split
#: are reported as not told apart (:func:`close_pairs`).
CLOSE_PAIR_SIGMAS = 2.0


@dataclass(frozen=True)
class ClosePair:
    """Two adjacent principal moments the measurement does not tell apart.

    Sorted, the eigenvalues of a nearly equal pair are pushed apart by the noise alone (the
    larger reads high, the smaller low, by up to ~0.4 of the pair's noise each) and their axes
    are not determined; the pair's mean is not biased so.

    Attributes
    ----------
    lower : int
        Index of the smaller moment (ascending order); the pair is ``(lower, lower + 1)``.
    split_kg_mm2 : float
        Their difference.
    split_sigma_kg_mm2 : float
        What the noise alone makes of the split of two equal moments (1 σ): the root of the
        variances of their difference and of twice their coupling ``v_iᵀ δJ v_j``.
    mean_kg_mm2, mean_sigma_kg_mm2 : float
        The pair's mean and its 1 σ.
    """

    lower: int
    split_kg_mm2: float
    split_sigma_kg_mm2: float
    mean_kg_mm2: float
    mean_sigma_kg_mm2: float


def close_pairs(principal: PrincipalWithSigma, cov: FloatArray) -> list[ClosePair]:
    """The adjacent principal moments closer than :data:`CLOSE_PAIR_SIGMAS` of their split.

    Parameters
    ----------
    principal : PrincipalWithSigma
    cov : ndarray, shape (6, 6)
        Covariance of the tensor's entries ``[xx, yy, zz, xy, xz, yz]``.

    Examples
    --------
    An axisymmetric tensor measured to 1 kg·mm² an entry: its two equal moments are a pair.

    >>> p = np.array([10.0, 50.0, 50.0, 0.0, 0.0, 0.0])
    >>> pairs = close_pairs(principal_with_sigma(p, np.eye(6)), np.eye(6))
    >>> [(c.lower, round(c.mean_kg_mm2, 6)) for c in pairs]
    [(1, 50.0)]
    """
    lam, v = principal.moments_kg_mm2, principal.axes
    g_moment = [bilinear_gradient(a, a) for a in v]
    out = []
    for i in range(2):
        g_diff = g_moment[i + 1] - g_moment[i]
        g_couple = bilinear_gradient(v[i], v[i + 1])
        var = float(g_diff @ cov @ g_diff) + 4.0 * float(g_couple @ cov @ g_couple)
        noise = float(np.sqrt(max(var, 0.0)))
        split = float(lam[i + 1] - lam[i])
        if split < CLOSE_PAIR_SIGMAS * noise:
            g_mean = 0.5 * (g_moment[i] + g_moment[i + 1])
            mean_sigma = float(np.sqrt(max(float(g_mean @ cov @ g_mean), 0.0)))
            out.append(ClosePair(i, split, noise, float(lam[i : i + 2].mean()), mean_sigma))
    return out


@dataclass(frozen=True)
class HangSwing:
    """One hang's fitted modes against the model at the estimate.

    Attributes
    ----------
    point_id : str
    frequencies_hz, sigma_hz, model_hz : ndarray, shape (k,)
        Measured (each fitted frequency's small-swing limit), its 1 σ, and the model's at the
        estimate.
    damping_ratios : ndarray, shape (k,)
    amplitudes_deg : ndarray, shape (k,)
    samples : int
    duration_s : float
    """

    point_id: str
    frequencies_hz: FloatArray
    sigma_hz: FloatArray
    model_hz: FloatArray
    damping_ratios: FloatArray
    amplitudes_deg: FloatArray
    samples: int
    duration_s: float


@dataclass(frozen=True, repr=False)
class InertiaResult(JsonResult):
    """Result of :func:`cadcog.dynamics.measure.measure_inertia`.

    Attributes
    ----------
    inertia_kg_mm2 : ndarray, shape (3, 3)
        The object's inertia tensor about its own CoG, model axes (tensor convention).
    cov_kg2_mm4 : ndarray, shape (6, 6)
        Covariance of its entries ``[xx, yy, zz, xy, xz, yz]``.
    cov_frequencies_kg2_mm4 : ndarray, shape (6, 6)
        The part of it from the swings' frequencies alone.
    principal : PrincipalWithSigma
    cog_mm : ndarray, shape (3,)
        The object's CoG the tensor is about (compensated).
    mass_kg : float
        The object's mass used.
    mass_sigma_kg : float
        Its 1 σ.
    mass_source : str
    hangs : tuple of HangSwing
    chi2 : float
        Weighted squared residuals of all frequencies at the estimate.
    dof : int
        Frequencies less six.
    budget : tuple of (str, float)
        Each input's share of the summed variance of the principal moments (largest first).
    cad : dict or None
        The CAD's tensor and the difference in σ (:func:`cadcog.dynamics.measure.compare_inertia`).
    warnings : tuple of str
    sigma_scale : float
        The factor the covariance's σ were multiplied by because the frequencies fit worse than
        their σ say: ``√(χ²/dof)`` when above 1 (the Birge ratio), else 1.
    """

    inertia_kg_mm2: FloatArray
    cov_kg2_mm4: FloatArray
    cov_frequencies_kg2_mm4: FloatArray
    principal: PrincipalWithSigma
    cog_mm: FloatArray
    mass_kg: float
    mass_sigma_kg: float
    mass_source: str
    hangs: tuple[HangSwing, ...]
    chi2: float
    dof: int
    budget: tuple[tuple[str, float], ...]
    cad: dict[str, Any] | None
    warnings: tuple[str, ...] = ()
    sigma_scale: float = 1.0

    @property
    def sigma_kg_mm2(self) -> FloatArray:
        """1 σ of each tensor entry, as a symmetric 3 × 3 array."""
        return tensor(np.sqrt(np.maximum(np.diag(self.cov_kg2_mm4), 0.0)))

    @property
    def consistency_p(self) -> float:
        """P(χ² ≥ observed) with ``dof`` degrees of freedom (1.0 when dof is 0)."""
        return FitTest(self.chi2, self.dof).p

    def to_dict(self) -> dict[str, Any]:
        pr = self.principal
        return {
            "inertia_kg_mm2": self.inertia_kg_mm2.tolist(),
            "inertia_about": "the object's centre of gravity, model axes",
            "inertia_convention": TENSOR_CONVENTION,
            "inertia_sigma_kg_mm2": self.sigma_kg_mm2.tolist(),
            "inertia_cov_entries": list(ENTRIES),
            "inertia_cov": self.cov_kg2_mm4.tolist(),
            "inertia_cov_frequencies_only": self.cov_frequencies_kg2_mm4.tolist(),
            "principal_moments_kg_mm2": pr.moments_kg_mm2.tolist(),
            "principal_moments_sigma_kg_mm2": pr.moments_sigma_kg_mm2.tolist(),
            "principal_axes": pr.axes.tolist(),
            "principal_axes_sigma_deg": pr.axes_sigma_deg.tolist(),
            "cog_mm": self.cog_mm.tolist(),
            "mass_kg": self.mass_kg,
            "mass_sigma_kg": self.mass_sigma_kg,
            "mass_source": self.mass_source,
            "consistency": {
                "chi2": self.chi2,
                "dof": self.dof,
                "p": self.consistency_p,
                "sigma_scale": self.sigma_scale,
            },
            "hangs": [
                {
                    "point_id": h.point_id,
                    "frequencies_hz": h.frequencies_hz.tolist(),
                    "sigma_hz": h.sigma_hz.tolist(),
                    "model_hz": h.model_hz.tolist(),
                    "damping_ratios": h.damping_ratios.tolist(),
                    "amplitudes_deg": h.amplitudes_deg.tolist(),
                    "samples": h.samples,
                    "duration_s": h.duration_s,
                }
                for h in self.hangs
            ],
            "budget": [{"source": s, "share": f} for s, f in self.budget],
            "cad": self.cad,
            "warnings": list(self.warnings),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> InertiaResult:
        """The result whose :meth:`to_dict` is ``d`` (its inverse, for results read back from
        the cache: ``from_dict(r.to_dict()).to_dict() == r.to_dict()``, every float exact)."""

        def arr(v: Any) -> FloatArray:
            return np.array(v, dtype=float)

        c = d["consistency"]
        return cls(
            inertia_kg_mm2=arr(d["inertia_kg_mm2"]),
            cov_kg2_mm4=arr(d["inertia_cov"]),
            cov_frequencies_kg2_mm4=arr(d["inertia_cov_frequencies_only"]),
            principal=PrincipalWithSigma(
                arr(d["principal_moments_kg_mm2"]),
                arr(d["principal_moments_sigma_kg_mm2"]),
                arr(d["principal_axes"]),
                arr(d["principal_axes_sigma_deg"]),
            ),
            cog_mm=arr(d["cog_mm"]),
            mass_kg=float(d["mass_kg"]),
            mass_sigma_kg=float(d["mass_sigma_kg"]),
            mass_source=str(d["mass_source"]),
            hangs=tuple(
                HangSwing(
                    str(h["point_id"]),
                    arr(h["frequencies_hz"]),
                    arr(h["sigma_hz"]),
                    arr(h["model_hz"]),
                    arr(h["damping_ratios"]),
                    arr(h["amplitudes_deg"]),
                    int(h["samples"]),
                    float(h["duration_s"]),
                )
                for h in d["hangs"]
            ),
            chi2=float(c["chi2"]),
            dof=int(c["dof"]),
            budget=tuple((str(b["source"]), float(b["share"])) for b in d["budget"]),
            cad=d["cad"],
            warnings=tuple(str(w) for w in d["warnings"]),
            sigma_scale=float(c["sigma_scale"]),
        )
