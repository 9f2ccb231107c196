"""Do `estimate --setup` and `update` cover the truth when the spacecraft is not its CAD?

The example 3U CubeSat's test is simulated by an independent forward model
(``support/forward_model.py``: none of cadcog's simulation code) for eight truths
(identical, item masses from their priors, camera +15 %, battery +15 %, a 40 g unmodelled
harness with no region or a wrong one, the camera's CoG 3 mm off, item CoG shifts from the
priors), ``--seeds`` campaigns each, on the plan's four recommended hangs. For each it reports:

- estimate: how often the 95 % ellipsoid (Mahalanobis² ≤ χ²₃(0.95) = 7.815) of the compensated
  CoG holds the truth's CoG, without and with the weighed mass; the z error's mean and standard
  deviation against the stated σ_z (without the weighed mass);
- update: how often the revised CoG's 95 % ellipsoid and the revised mass's ±1.96 σ hold the
  truth, and the unmodelled mass's ±1.96 σ where the truth has one and the update gives one;
- the rates of ``differs``, ``consistent`` and ``model_rejected``; how often the truly changed
  item (or ``unmodelled``, or ``none`` on the identical spacecraft) is ranked first, and the mean
  probability given to it.

``--current`` uses only what exists before the ``cadcog.update`` API: ``cadcog.estimate(csv,
setup=...)`` and the library calls behind the ``cadcog update`` command
(``estimate_for_setup``, ``items_from_bodies``, ``Measurement``, ``update_budget``, exactly as
``cadcog/cli/update.py`` makes them). There, "estimate with weighed mass" is the command's
``measured`` CoG (compensated with the weighed mass), ``consistent`` its χ² test, the first item
its ``items`` ranking by |pull| (no probabilities, no ``differs``/``model_rejected``: "-").

Run: ``.venv/bin/python benchmarks/study_spacecraft_calibration.py [--seeds 200] [--current]``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import cadcog  # noqa: E402
from support import forward_model as fm  # noqa: E402

SETUP = ROOT / "parts" / "cubesat_3u_setup.toml"
CHI2_3_95 = 7.814727903251178
Z95 = 1.959963984540054
UNMODELLED_SIGMA_KG = 0.1  # the prior 1 σ given with a region (docs/spacecraft.md's example)


def covered(err: np.ndarray, cov: np.ndarray) -> bool:
    """The error inside the 95 % ellipsoid of ``cov``."""
    return bool(err @ np.linalg.solve(cov, err) <= CHI2_3_95)


@dataclass
class Trial:
    """One campaign's verdicts (None: not available in this mode or not relevant)."""

    est: bool
    est_w: bool | None
    err_z: float
    sigma_z: float
    upd_cog: bool
    upd_mass: bool
    unmod_mass: bool | None
    differs: bool | None
    consistent: bool
    rejected: bool | None
    first: str | None
    prob_true: float | None


def _region_args(truth: fm.Truth) -> dict[str, Any]:
    if truth.region_mm is None:
        return {"unmodelled_region_mm": None, "unmodelled_sigma_kg": None}
    return {"unmodelled_region_mm": truth.region_mm, "unmodelled_sigma_kg": UNMODELLED_SIGMA_KG}


def _unmodelled_cover(truth: fm.Truth, mass: float | None, sigma: float | None) -> bool | None:
    if truth.unmodelled_mass_kg is None or mass is None or sigma is None:
        return None
    return abs(mass - truth.unmodelled_mass_kg) <= Z95 * sigma


def trial_new(setup: Any, camp: fm.Campaign, csv: Path) -> Trial:
    """The new contract: ``cadcog.estimate(..., weighed_mass_kg=...)`` and ``cadcog.update``."""
    truth = camp.truth
    est = cadcog.estimate(csv, setup=setup)
    est_w = cadcog.estimate(
        csv, setup=setup, weighed_mass_kg=camp.weighed_mass_kg, mass_sigma_kg=0.001
    )
    upd = cadcog.update(
        csv, setup, weighed_mass_kg=camp.weighed_mass_kg, mass_sigma_kg=0.001, **_region_args(truth)
    )
    post = upd.posterior
    err = est.cog_mm - truth.cog_mm
    expl = list(upd.explanations)
    prob = None
    if truth.changed is not None:
        prob = sum(float(e.probability) for e in expl if e.label == truth.changed)
    return Trial(
        est=covered(err, est.cov_mm2),
        est_w=covered(est_w.cog_mm - truth.cog_mm, est_w.cov_mm2),
        err_z=float(err[2]),
        sigma_z=float(np.sqrt(est.cov_mm2[2, 2])),
        upd_cog=covered(post.cog_mm - truth.cog_mm, upd.posterior_cog_cov_mm2),
        upd_mass=abs(post.mass_kg - truth.mass_kg) <= Z95 * upd.posterior_mass_sigma_kg,
        unmod_mass=_unmodelled_cover(truth, upd.unmodelled_mass_kg, upd.unmodelled_mass_sigma_kg),
        differs=bool(upd.differs),
        consistent=bool(upd.consistent),
        rejected=bool(upd.model_rejected),
        first=expl[0].label if expl else None,
        prob_true=prob,
    )


class CurrentUpdate:
    """What ``cadcog update`` computes today, from the library, with one loaded set-up."""

    def __init__(self, setup: Any) -> None:
        from cadcog.spacecraft.update import items_from_bodies

        self.setup = setup
        self.items, self.fixed = items_from_bodies(setup.bodies)

    def __call__(self, camp: fm.Campaign, csv: Path) -> Trial:
        from cadcog.spacecraft.update import Measurement, UnmodelledPrior, update_budget

        s, truth = self.setup, camp.truth
        estimate = cadcog.estimate(csv, setup=s)  # estimate_for_setup, as the command
        unmod = None
        if truth.region_mm is not None:
            box = np.array(truth.region_mm)
            unmod = UnmodelledPrior(box[:3], box[3:], 0.0, UNMODELLED_SIGMA_KG)
        meas = Measurement(
            estimate.assembly_cog_mm,
            estimate.joint.cov_mm2,
            camp.weighed_mass_kg,
            0.001,
            s.me_mass_kg,
            s.me_cog_mm,
            s.me_cog_cov_mm2,
        )
        r = update_budget(self.items, self.fixed, meas, unmodelled=unmod)
        err = estimate.cog_mm - truth.cog_mm
        ranked = r.ranked_items()
        return Trial(
            est=covered(err, estimate.cov_mm2),
            est_w=covered(r.measured_cog_mm - truth.cog_mm, r.measured_cog_cov_mm2),
            err_z=float(err[2]),
            sigma_z=float(np.sqrt(estimate.cov_mm2[2, 2])),
            upd_cog=covered(r.posterior.cog_mm - truth.cog_mm, r.posterior_cog_cov_mm2),
            upd_mass=abs(r.posterior.mass_kg - truth.mass_kg) <= Z95 * r.posterior_mass_sigma_kg,
            unmod_mass=_unmodelled_cover(truth, r.unmodelled_mass_kg, r.unmodelled_mass_sigma_kg),
            differs=None,
            consistent=bool(r.consistent),
            rejected=None,
            first=ranked[0].key if ranked else None,
            prob_true=None,
        )


def run_scenario(
    cad: fm.Cad, name: str, seeds: int, fn: Callable[[fm.Campaign, Path], Trial], tmp: Path
) -> list[Trial]:
    out = []
    for seed in range(seeds):
        camp = fm.campaign(cad, name, seed)
        csv = camp.write_csv(tmp / f"s{fm.SCENARIO_NUMBER[name]}_{seed}.csv")
        out.append(fn(camp, csv))
    return out


def _rate(values: list[bool | None]) -> str:
    v = [x for x in values if x is not None]
    return f"{100.0 * np.mean(v):.1f} %" if v else "-"


def row(name: str, changed: str | None, trials: list[Trial]) -> str:
    z = np.array([t.err_z for t in trials])
    sz = np.mean([t.sigma_z for t in trials])
    current = all(t.prob_true is None for t in trials)
    if changed is None or (current and changed in (fm.NONE, fm.UNMODELLED)):
        first, prob = "-", "-"  # no such label in today's item ranking
    else:
        short = changed.rsplit("/", 1)[-1]
        first = f"{_rate([t.first == changed for t in trials])} ({short})"
        probs = [t.prob_true for t in trials if t.prob_true is not None]
        prob = f"{np.mean(probs):.2f}" if probs else "-"
    cells = [
        name,
        _rate([t.est for t in trials]),
        _rate([t.est_w for t in trials]),
        _rate([t.upd_cog for t in trials]),
        _rate([t.upd_mass for t in trials]),
        _rate([t.unmod_mass for t in trials]),
        _rate([t.differs for t in trials]),
        _rate([t.consistent for t in trials]),
        _rate([t.rejected for t in trials]),
        first,
        prob,
        f"{z.mean():+.2f} / {z.std(ddof=1):.2f} / {sz:.2f}",
    ]
    return "| " + " | ".join(cells) + " |"


HEADER = (
    "| scenario | estimate CoG | estimate CoG, weighed | update CoG | update mass | "
    "unmodelled mass | differs | consistent | model rejected | true cause first | "
    "mean P(true) | estimate z err mean / std / stated σ (mm) |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|"
)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=200)
    ap.add_argument("--current", action="store_true", help="only the API that exists today")
    ap.add_argument("--only", help="comma-separated scenario names")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    setup = cadcog.load_setup(SETUP)
    cad = fm.cad_from_setup(setup)
    if args.current:
        fn: Callable[[fm.Campaign, Path], Trial] = CurrentUpdate(setup)
    else:
        if not hasattr(cadcog, "update"):
            print("cadcog.update does not exist yet: use --current", file=sys.stderr)
            return 2

        def fn(camp: fm.Campaign, csv: Path) -> Trial:
            return trial_new(setup, camp, csv)

    names = list(fm.SCENARIOS) if args.only is None else args.only.split(",")
    print(
        f"{'current code' if args.current else 'new API'}, {args.seeds} seeds per scenario, "
        f"hangs {', '.join(fm.RECOMMENDED_POINTS)}; 95 % regions\n"
    )
    print(HEADER)
    with tempfile.TemporaryDirectory() as d:
        for name in names:
            truth0 = fm.SCENARIOS[name](cad, fm.rng_for(name, 0))
            trials = run_scenario(cad, name, args.seeds, fn, Path(d))
            print(row(name, truth0.changed, trials), flush=True)
    print(f"\n{time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
