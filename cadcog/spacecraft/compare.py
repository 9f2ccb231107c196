"""A measured CoG against the CAD's, each with its own uncertainty, and the CubeSat envelope.

The question is "is the spacecraft within what its CAD says, uncertainties included?". The
difference ``d = r_measured − G_CAD`` then varies for two reasons: the measurement's errors
(hangs, ME, the mass used to remove the ME) and the CAD's own uncertainty (each item's mass and
CoG, :mod:`cadcog.spacecraft.items`). Under that null, to first order in the items'
parameters ``θ``,

    Cov d = C_meas + (J_G − a J_M) P (J_G − a J_M)ᵀ

with ``C_meas`` the measurement's covariance with the object mass exact, ``J_G``, ``J_M`` the
CAD CoG's and mass's Jacobians in ``θ``, ``P`` their prior covariance, and ``a = ∂r/∂m_obj``
the compensation's sensitivity to the object mass *when the CAD mass is the one used* (the same
items then move both the true CoG and the compensation: the terms are correlated, which this
form keeps). With a weighed mass, ``a`` is 0 here (the weighing's σ is in ``C_meas``) and the
weighed mass is compared with the CAD's too: 4 degrees of freedom instead of 3.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from cadcog.core.fittest import FitTest
from cadcog.method.plumblines import Compensation
from cadcog.spacecraft.envelope import check_envelope
from cadcog.spacecraft.items import LinearPrior

FloatArray = npt.NDArray[np.float64]


class CadSetup(Protocol):
    """What the comparison needs of a set-up (:class:`cadcog.spacecraft.setup.Setup` has it)."""

    @property
    def cog_limits_mm(self) -> FloatArray | None: ...

    @property
    def geometric_center_mm(self) -> FloatArray: ...

    @property
    def form_factor(self) -> str | None: ...

    def cad_prior(self) -> LinearPrior: ...


#: What the comparison's σ contain, as the JSON and the text say.
COVARIANCE_NOTE = (
    "σ of measurement and CAD combined: the measurement's covariance and the CAD's stated "
    "item mass and CoG uncertainties, with their correlation through the mass used to remove "
    "the measurement equipment"
)


def compare_with_cad(
    setup: CadSetup,
    cog_mm: npt.ArrayLike,
    cov_mm2: npt.ArrayLike,
    compensation: Compensation | None = None,
) -> dict[str, Any]:
    """The measured CoG (and weighed mass) against the CAD, and the CubeSat envelope check.

    Parameters
    ----------
    setup : Setup
        Its CAD's stated uncertainty and CubeSat envelope.
    cog_mm, cov_mm2 : array_like
        The compensated CoG and its covariance (``CogEstimate.cog_mm``/``cov_mm2``).
    compensation : Compensation, optional
        How the ME was removed: which mass (``object_mass_source`` "weighed" or "CAD") and its
        sensitivity to that mass. Without it the mass is taken as exact and independent of
        the CAD.

    Returns
    -------
    dict
        ``difference_mm`` and its covariance ``difference_cov_mm2`` (measurement + CAD),
        ``difference_sigma`` per axis in those σ, ``measurement_sigma`` per axis in the
        measurement's σ alone, ``mahalanobis``, ``chi2``/``dof``/``p_value`` of the joint test
        (the weighed mass included when there is one), ``consistent`` (p at least
        :data:`cadcog.core.fittest.TEST_LEVEL`), ``cad_cog_cov_mm2``,
        ``cad_mass_kg``/``cad_mass_sigma_kg``, ``covariance`` (what the σ contain) and, with a
        form factor, ``cubesat``.
    """
    cog = np.asarray(cog_mm, dtype=float)
    cov = np.asarray(cov_mm2, dtype=float)
    prior = setup.cad_prior()
    weighed = compensation is not None and compensation.object_mass_source == "weighed"
    if compensation is not None and compensation.cov_given_mass_mm2 is not None and not weighed:
        c_meas = compensation.cov_given_mass_mm2
        a = compensation.mass_gradient_mm_kg
    else:
        c_meas, a = cov, np.zeros(3)
    jac = prior.jac_cog - np.outer(a, prior.jac_mass)
    diff_cov = c_meas + jac @ prior.prior_cov @ jac.T
    diff = cog - prior.cog_mm
    # A joint test: the CoG difference, and with a weighing the mass difference too.
    resid, joint = diff, diff_cov
    mass_fields: dict[str, float] = {}
    if weighed and compensation is not None:
        dm = compensation.object_mass_kg - prior.mass_kg
        var_m = compensation.object_mass_sigma_kg**2 + prior.mass_sigma_kg**2
        cross = prior.jac_cog @ prior.prior_cov @ prior.jac_mass
        joint = np.zeros((4, 4))
        joint[:3, :3] = diff_cov
        joint[3, 3] = var_m
        # The true CoG and mass move together with the items: Cov(r − G_CAD, M_w − M_CAD) is
        # Cov(G_true, M_true) = J_G P J_Mᵀ under the null.
        joint[:3, 3] = joint[3, :3] = cross
        resid = np.concatenate([diff, [dm]])
        mass_fields["mass_difference_kg"] = dm
        mass_fields["mass_difference_sigma"] = dm / np.sqrt(var_m) if var_m > 0 else float("inf")
    test = FitTest(float(resid @ np.linalg.solve(joint, resid)), int(resid.size))
    sigma = np.sqrt(np.diag(diff_cov))
    meas_sigma = np.sqrt(np.diag(cov))
    out: dict[str, Any] = {
        "cad_cog_mm": prior.cog_mm.tolist(),
        "cad_cog_cov_mm2": prior.cog_cov_mm2.tolist(),
        "cad_mass_kg": prior.mass_kg,
        "cad_mass_sigma_kg": prior.mass_sigma_kg,
        "mass_used": "weighed" if weighed else "CAD",
        "difference_mm": diff.tolist(),
        "difference_cov_mm2": diff_cov.tolist(),
        "difference_sigma": (diff / sigma).tolist(),
        "measurement_sigma": (diff / meas_sigma).tolist(),
        "mahalanobis": float(np.sqrt(diff @ np.linalg.solve(diff_cov, diff))),
        **mass_fields,
        "chi2": test.chi2,
        "dof": test.dof,
        "p_value": test.p,
        "covariance": COVARIANCE_NOTE,
        "consistent": test.passes,
    }
    if setup.cog_limits_mm is not None:
        out["cubesat"] = check_envelope(
            cog,
            setup.geometric_center_mm,
            setup.cog_limits_mm,
            cov_mm2=cov,
            form_factor=setup.form_factor,
        ).to_dict()
    return out
