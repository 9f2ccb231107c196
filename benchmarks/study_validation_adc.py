"""Size of `cadcog validate`'s verdict on null campaigns from an independent generator, with and
without per-sample ADC quantisation (issue 19, item 5).

The campaigns come from :mod:`support.rig_campaigns`, written from the documented physics
without cadcog's campaign, Monte Carlo or error-model code: ME cubes and the one wire's offset
scale drawn once per campaign, suspension play per hang, an inclinometer bias per hang,
Gaussian noise per sample and (when quantised) the 10-bit ADC per sample (noise 0.05° against a
0.146° step: partial dither).

Part 1, the command's path: each campaign is written as a readings CSV (counts, or degrees when
unquantised), read back by :func:`cadcog.method.readings.read_readings` and validated by
:func:`cadcog.validation.verification.validate_campaign` against the command's own null (seed 0,
2000 campaigns on the same points). A third set writes counts through a round-to-nearest ADC
(every reading half an LSB high once read back with cadcog's bin-centre convention): a negative
control showing what a convention mismatch of the generator does.

Part 2, regimes of dither: the same generator in memory (the mean of each hang's samples, as the
reader takes it), the statistic T against the 95 % quantile of 200 000 null campaigns, for weaker
dither and more samples than the paper rig's.

Run: ``.venv/bin/python benchmarks/study_validation_adc.py [--campaigns 2000] [--bulk 10000]``;
the tables are in ``docs/validation.md``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy import stats

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from cadcog.method.errormodel import ErrorModel
from cadcog.method.readings import read_readings
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.validation.verification import (
    campaign_null,
    line_statistic,
    validate_campaign,
)
from support.rig_campaigns import RigPhysics, generate, write_csv

LEVEL = 0.05


def rate(k: int, n: int) -> str:
    lo, hi = stats.binomtest(k, n).proportion_ci(0.95)
    return f"{k}/{n} = {k / n:.1%} [{lo:.1%}, {hi:.1%}]"


def command_path(n: int, seed: int) -> None:
    rig = load_rig(default_rig_path())
    phys = RigPhysics.from_file(default_rig_path())
    print(f"## Part 1: {n} null campaigns per row, CSV → read_readings → validate_campaign\n")
    print("| campaigns | alarms at 5 % [95 % CI] | p-values: KS distance from uniform |")
    print("|---|---|---|")
    null = None
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "campaign.csv"
        for name, quantise, rounding in (
            ("every sample quantised (10-bit ADC, bin reported)", True, "floor"),
            ("unquantised (degrees to 9 decimals)", False, "floor"),
            ("negative control: round-to-nearest ADC (+½ LSB)", True, "nearest"),
        ):
            t = time.perf_counter()
            p = np.empty(n)
            for i in range(n):
                write_csv(phys, generate(phys, seed, i), path, quantise=quantise, rounding=rounding)
                v = validate_campaign(rig, read_readings(path, rig.inclinometer), null=null)
                null = v.null
                p[i] = v.verdict.p_value
            k = int(np.count_nonzero(p < LEVEL))
            ks = stats.kstest(p, "uniform").statistic
            print(f"| {name} | {rate(k, n)} | {ks:.3f} |", flush=True)
            print(f"  ({time.perf_counter() - t:.0f} s)", file=sys.stderr)


def bulk(n: int, seed: int) -> None:
    rig = load_rig(default_rig_path())
    phys = RigPhysics.from_file(default_rig_path())
    sensor = rig.inclinometer.sensor
    sc = Scenario.from_rig(rig)
    base = ErrorModel.from_rig(rig)
    print(f"\n## Part 2: {n} campaigns per cell against the 95 % quantile of 200 000 null ones\n")
    print("| noise (deg) | samples | noise/LSB | quantised | unquantised |")
    print("|---|---|---|---|---|")
    notes = []
    for noise, samples in ((0.05, 10), (0.02, 10), (0.0, 10), (0.05, 100), (0.02, 100)):
        model = replace(base, sensor_noise_deg=noise, samples=samples)
        big = campaign_null(sc, model, 200_000, seed=777).line_stat
        q95 = np.quantile(big, 1 - LEVEL)
        if (noise, samples) == (base.sensor_noise_deg, base.samples):
            # The command's null (seed 0, 2000 campaigns) against the large one: every campaign
            # validated by the command shares its sampling error.
            cmd = campaign_null(sc, model, 2000, seed=0).line_stat
            ks = stats.ks_2samp(cmd, big)
            notes.append(
                f"command's null (seed 0, 2000) vs 200 000: KS D = {ks.statistic:.3f}, "
                f"p = {ks.pvalue:.3f}; its 95 % quantile is the large null's "
                f"{np.mean(big < np.quantile(cmd, 1 - LEVEL)):.2%} quantile"
            )
        cells = []
        for quantise in (True, False):
            u = np.empty((3, len(phys.ids), n))
            for i in range(n):
                c = generate(phys, seed, i, noise_deg=noise, samples=samples)
                s = sensor.counts_to_deg(phys.counts(c.samples_deg)) if quantise else c.samples_deg
                mean = np.radians(s.mean(axis=1))
                sx, sy = np.sin(mean[:, 0]), np.sin(mean[:, 1])
                u[:, :, i] = [sx, sy, np.sign(c.u_true[:, 2]) * np.sqrt(1 - sx * sx - sy * sy)]
            k = int(np.count_nonzero(line_statistic(sc, model, u) > q95))
            cells.append(rate(k, n))
        print(
            f"| {noise:g} | {samples} | {noise / phys.lsb_deg:.2f} | {cells[0]} | {cells[1]} |",
            flush=True,
        )
    print("\n" + "\n".join(notes))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--campaigns", type=int, default=2000)
    parser.add_argument("--bulk", type=int, default=10_000)
    parser.add_argument("--seed", type=int, default=2026)
    args = parser.parse_args()
    command_path(args.campaigns, args.seed)
    if args.bulk:
        bulk(args.bulk, args.seed)


if __name__ == "__main__":
    main()
