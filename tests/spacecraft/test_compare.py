"""``cadcog.spacecraft.compare``: the measured CoG against the CAD's is calibrated under its null.

An independent simulation of the null: the items' parameters drawn from the CAD's prior move
the true mass and CoG together; the spacecraft hangs on its ME (the assembly's CoG is the
mass-weighted mean); the hangs measure that CoG with their covariance; the ME is removed with
the CAD's mass (the same items then move the truth and the compensation: correlated) or with a
weighed one. The joint test must then pass 95 % of the time, with χ² averaging its dof.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pytest
from scipy import stats

from cadcog.core.fittest import TEST_LEVEL
from cadcog.method.plumblines import compensate_me
from cadcog.spacecraft.compare import compare_with_cad
from cadcog.spacecraft.items import LinearPrior

DRAWS = 2000
M_ME_KG, R_ME_MM = 0.176, np.array([50.0, 50.0, 380.0])


@dataclass
class _Cad:
    prior: LinearPrior
    cog_limits_mm: None = None
    form_factor: None = None
    geometric_center_mm: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def cad_prior(self) -> LinearPrior:
        return self.prior


#: The CAD's uncertainty: "broad" (items' masses move the CoG by ~30 mm/kg, an item's CoG known
#: to a few mm: the CAD's CoG σ dwarfs the rest) or "tight" (1 mm/kg, 0.1 mm: the mass used to
#: remove the ME then matters as much as the hangs, and its correlation with the CAD's CoG too).
PRIORS = {"broad": (30.0, 1.0), "tight": (1.0, 0.025)}


def _prior(rng: np.random.Generator, kind: str) -> LinearPrior:
    mm_per_kg, offset_scale = PRIORS[kind]
    # θ: three items' masses (kg), then one item's CoG offsets (mm).
    jac_mass = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    jac_cog = np.hstack([rng.normal(0.0, mm_per_kg, (3, 3)), np.eye(3) * 0.2])
    prior_cov = np.diag([0.02, 0.01, 0.03, *(offset_scale * np.array([4.0, 4.0, 9.0]))]) ** 2
    return LinearPrior(3.0, np.array([50.0, 50.0, 170.0]), jac_mass, jac_cog, prior_cov)


C_ASM_MM2 = np.diag([0.12, 0.10, 0.15]) ** 2  # what the hangs measure the assembly's CoG to


def _spacecraft(prior: LinearPrior, rng: np.random.Generator):
    """Spacecraft that are their CAD: (true mass, measured assembly CoG), one per draw."""
    chol_p, chol_a = np.linalg.cholesky(prior.prior_cov), np.linalg.cholesky(C_ASM_MM2)
    for _ in range(DRAWS):
        theta = chol_p @ rng.normal(size=prior.prior_cov.shape[0])
        m_true = prior.mass_kg + prior.jac_mass @ theta
        g_true = prior.cog_mm + prior.jac_cog @ theta
        r_asm = (m_true * g_true + M_ME_KG * R_ME_MM) / (m_true + M_ME_KG)
        yield m_true, r_asm + chol_a @ rng.normal(size=3)


def _draws(kind: str, weighed: bool, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    prior = _prior(rng, kind)
    cad = _Cad(prior)
    p_values, chi2 = np.empty(DRAWS), np.empty(DRAWS)
    for k, (m_true, r_est) in enumerate(_spacecraft(prior, rng)):
        if weighed:
            sigma_w = 0.001
            mass, sigma, source = m_true + sigma_w * rng.normal(), sigma_w, "weighed"
        else:
            mass, sigma, source = prior.mass_kg, prior.mass_sigma_kg, "CAD"
        comp = compensate_me(
            r_est, C_ASM_MM2, object_mass_kg=mass, me_mass_kg=M_ME_KG, me_cog_mm=R_ME_MM,
            object_mass_sigma_kg=sigma, object_mass_source=source,
        )  # fmt: skip
        out = compare_with_cad(cad, comp.cog_mm, comp.cov_mm2, comp)
        assert out["dof"] == (4 if weighed else 3)
        p_values[k], chi2[k] = out["p_value"], out["chi2"]
    return p_values, chi2


@pytest.mark.parametrize("kind", sorted(PRIORS))
@pytest.mark.parametrize("weighed", [False, True], ids=["CAD mass", "weighed"])
def test_the_joint_test_passes_95_percent_of_spacecraft_that_are_their_cad(kind, weighed):
    p_values, chi2 = _draws(kind, weighed, seed=11 if weighed else 7)
    dof = 4 if weighed else 3
    passed = np.mean(p_values >= TEST_LEVEL)
    # 2000 draws: the binomial σ of 95 % is 0.49 %; ±1.5 % is three of them.
    assert abs(passed - (1 - TEST_LEVEL)) < 0.015, passed
    assert np.mean(chi2) == pytest.approx(dof, rel=0.08)  # its σ: √(2·dof/2000) ≈ 1.5 %
    assert stats.kstest(p_values, "uniform").pvalue > 1e-3


@pytest.mark.parametrize("sign", [0.0, 1.0], ids=["mass effect left out", "its sign flipped"])
def test_a_wrong_correlation_with_the_cad_mass_would_be_seen(sign):
    """The test has power against the mistakes the module must avoid: the same spacecraft
    scored with ``(J_G + sign·a J_M)`` in place of ``(J_G − a J_M)`` (``sign`` 1 was the code
    until 2026-11-28) give a mean χ² beyond 5 σ of its sampling error."""
    rng = np.random.default_rng(7)
    prior = _prior(rng, "tight")
    chi2 = []
    for _, r_est in _spacecraft(prior, rng):
        comp = compensate_me(
            r_est, C_ASM_MM2, object_mass_kg=prior.mass_kg, me_mass_kg=M_ME_KG, me_cog_mm=R_ME_MM
        )
        jac = prior.jac_cog + sign * np.outer(comp.mass_gradient_mm_kg, prior.jac_mass)
        d = comp.cog_mm - prior.cog_mm
        chi2.append(d @ np.linalg.solve(comp.cov_mm2 + jac @ prior.prior_cov @ jac.T, d))
    # 3 dof over 2000 draws: the mean's σ is √(6/2000) = 0.055; five of them above 3.
    assert np.mean(chi2) > 3.0 + 5 * np.sqrt(6 / DRAWS), np.mean(chi2)


def test_cubesat_envelope_with_uncertainty(cubesat_setup):
    from cadcog.spacecraft.compare import compare_with_cad

    centre = cubesat_setup.geometric_center_mm
    cov = np.eye(3) * 1.0
    inside = compare_with_cad(cubesat_setup, centre + np.array([19.0, 0.0, 0.0]), cov)["cubesat"]
    assert inside["within"] and not inside["within_at_95"]  # 19 mm + 1.96 σ > 20 mm
    outside = compare_with_cad(cubesat_setup, centre + np.array([0.0, 21.0, 0.0]), cov)["cubesat"]
    assert not outside["within"]
    clear = compare_with_cad(cubesat_setup, centre + np.array([0.0, 0.0, 60.0]), cov)["cubesat"]
    assert clear["within"] and clear["within_at_95"]
