"""Do ``cadcog.estimate(..., weighed_mass_kg=...)`` and ``cadcog.update`` cover the truth when
the spacecraft is not its CAD?

The example 3U CubeSat's test on the plan's four recommended hangs is simulated by the
independent forward model (:mod:`support.forward_model`) for the eight scenarios of
``forward_model.SCENARIOS``, ``SEEDS`` campaigns each, with a fixed seed. Every rate is checked
with a tolerance from binomial noise: the two-sided 95 % Clopper-Pearson interval of the observed
rate must reach into the target band. The full table (with the power: ``differs``,
``consistent``, ``model_rejected``, the true cause ranked first) is
``benchmarks/study_spacecraft_calibration.py``; the rates are printed here too and recorded as
the test's user properties.

Skipped until ``cadcog.update`` exists (the API these tests are written against).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy import stats

import cadcog
from support import forward_model as fm

SETUP = Path(__file__).resolve().parents[2] / "parts" / "cubesat_3u_setup.toml"
#: Campaigns per scenario in the suite (the suite's time budget); the docs' table is the
#: benchmark's 200 (``benchmarks/study_spacecraft_calibration.py``). 60 still rejects a coverage
#: near 83 % against a 93 % target, and a test of size 15 % against 5 %.
SEEDS = 60
CHI2_3_95 = 7.814727903251178
Z95 = 1.959963984540054
MASS_SIGMA_KG = 0.001
UNMODELLED_SIGMA_KG = 0.1

if not hasattr(cadcog, "update"):
    pytest.skip("cadcog.update is not there yet (the new update API)", allow_module_level=True)


def clopper_pearson(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Two-sided exact binomial interval of the rate ``k/n``."""
    a = 1.0 - level
    lo = 0.0 if k == 0 else float(stats.beta.ppf(a / 2, k, n - k + 1))
    hi = 1.0 if k == n else float(stats.beta.ppf(1 - a / 2, k + 1, n - k))
    return lo, hi


def overlaps(flags: list[bool], lo: float, hi: float) -> tuple[bool, str]:
    """Whether the 95 % interval of the rate of ``flags`` meets [lo, hi], and a description."""
    k, n = int(sum(flags)), len(flags)
    a, b = clopper_pearson(k, n)
    return a <= hi and b >= lo, f"{k}/{n} = {k / n:.1%} (95 % CI {a:.1%}-{b:.1%})"


@dataclass
class Outcome:
    est_w: bool
    upd_cog: bool
    upd_mass: bool
    unmod_mass: bool | None
    differs: bool
    consistent: bool
    rejected: bool
    first: str | None
    prob_true: float | None


def _covered(err: np.ndarray, cov: np.ndarray) -> bool:
    return bool(err @ np.linalg.solve(cov, err) <= CHI2_3_95)


#: Campaigns per scenario on which ``cadcog.estimate`` itself is run and compared with the
#: update's measured CoG (the same compensation with the weighed mass); the coverage of the
#: rest uses the update's, to halve the test's time.
ESTIMATE_CHECKED = 20


def _one(setup: Any, camp: fm.Campaign, csv: Path, check_estimate: bool = True) -> Outcome:
    truth = camp.truth
    region = truth.region_mm
    upd = cadcog.update(
        csv,
        setup,
        weighed_mass_kg=camp.weighed_mass_kg,
        mass_sigma_kg=MASS_SIGMA_KG,
        unmodelled_region_mm=region,
        unmodelled_sigma_kg=None if region is None else UNMODELLED_SIGMA_KG,
    )
    est_cog, est_cov = np.asarray(upd.measured_cog_mm), np.asarray(upd.measured_cog_cov_mm2)
    if check_estimate:
        est = cadcog.estimate(
            csv, setup=setup, weighed_mass_kg=camp.weighed_mass_kg, mass_sigma_kg=MASS_SIGMA_KG
        )
        np.testing.assert_allclose(est.cog_mm, est_cog, rtol=0, atol=1e-9)
        np.testing.assert_allclose(est.cov_mm2, est_cov, rtol=1e-9, atol=1e-12)
    post = upd.posterior
    unmod = None
    if truth.unmodelled_mass_kg is not None and upd.unmodelled_mass_kg is not None:
        unmod = bool(
            abs(upd.unmodelled_mass_kg - truth.unmodelled_mass_kg)
            <= Z95 * upd.unmodelled_mass_sigma_kg
        )
    expl = list(upd.explanations)
    prob = None
    if truth.changed is not None:
        prob = sum(float(e.probability) for e in expl if e.cause == truth.changed)
    return Outcome(
        est_w=_covered(est_cog - truth.cog_mm, est_cov),
        upd_cog=_covered(
            np.asarray(post.cog_mm) - truth.cog_mm, np.asarray(upd.posterior_cog_cov_mm2)
        ),
        upd_mass=bool(abs(post.mass_kg - truth.mass_kg) <= Z95 * upd.posterior_mass_sigma_kg),
        unmod_mass=unmod,
        differs=bool(upd.differs),
        consistent=bool(upd.consistent),
        rejected=bool(upd.model_rejected),
        first=expl[0].cause if expl else None,
        prob_true=prob,
    )


@pytest.fixture(scope="module")
def setup() -> Any:
    return cadcog.load_setup(SETUP)


@pytest.fixture(scope="module")
def cad(setup: Any) -> fm.Cad:
    return fm.cad_from_setup(setup)


@pytest.fixture(scope="module")
def outcomes(
    setup: Any, cad: fm.Cad, tmp_path_factory: pytest.TempPathFactory
) -> dict[str, list[Outcome]]:
    """Every scenario's ``SEEDS`` campaigns, estimated and updated once for all tests."""
    tmp = tmp_path_factory.mktemp("calibration")
    out: dict[str, list[Outcome]] = {}
    for name in fm.SCENARIOS:
        rows = []
        for seed in range(SEEDS):
            camp = fm.campaign(cad, name, seed)
            csv = camp.write_csv(tmp / f"s{fm.SCENARIO_NUMBER[name]}_{seed}.csv")
            rows.append(_one(setup, camp, csv, check_estimate=seed < ESTIMATE_CHECKED))
        out[name] = rows
    return out


def _rate(flags: list[bool | None]) -> float:
    v = [f for f in flags if f is not None]
    return float(np.mean(v)) if v else float("nan")


@pytest.mark.parametrize("scenario", list(fm.SCENARIOS))
def test_coverage(
    scenario: str, cad: fm.Cad, outcomes: dict[str, list[Outcome]], record_property: Any
) -> None:
    """Estimate (weighed mass) covers 93-97 %; update's CoG and mass cover at least 93 %."""
    rows = outcomes[scenario]
    power = {
        "estimate_cog_coverage": _rate([o.est_w for o in rows]),
        "update_cog_coverage": _rate([o.upd_cog for o in rows]),
        "update_mass_coverage": _rate([o.upd_mass for o in rows]),
        "unmodelled_mass_coverage": _rate([o.unmod_mass for o in rows]),
        "differs": _rate([o.differs for o in rows]),
        "consistent": _rate([o.consistent for o in rows]),
        "model_rejected": _rate([o.rejected for o in rows]),
    }
    changed = fm.SCENARIOS[scenario](cad, fm.rng_for(scenario, 0)).changed
    if changed is not None:
        power["true_cause_first"] = _rate([o.first == changed for o in rows])
        probs = [o.prob_true for o in rows if o.prob_true is not None]
        power["mean_probability_true_cause"] = float(np.mean(probs)) if probs else float("nan")
    for key, value in power.items():
        record_property(key, value)
    print(f"\n{scenario}: " + ", ".join(f"{k} {v:.3f}" for k, v in power.items()))

    failures = []
    for what, flags, lo, hi in (
        ("estimate CoG (weighed mass)", [o.est_w for o in rows], 0.93, 0.97),
        ("update CoG", [o.upd_cog for o in rows], 0.93, 1.0),
        ("update mass", [o.upd_mass for o in rows], 0.93, 1.0),
    ):
        ok, text = overlaps(flags, lo, hi)
        if not ok:
            failures.append(f"{what} coverage {text}, target {lo:.0%}-{hi:.0%}")
    assert not failures, f"{scenario}: " + "; ".join(failures)


def test_differs_is_a_5_percent_test_on_the_identical_spacecraft(
    outcomes: dict[str, list[Outcome]],
) -> None:
    ok, text = overlaps([o.differs for o in outcomes["identical"]], 0.03, 0.07)
    assert ok, f"differs on an identical spacecraft: {text}, target 3-7 %"
