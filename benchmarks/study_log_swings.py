"""The inertia tensor from a phone's or an accelerometer's log (issue 34): ``cadcog acquire --log
LOG --swings S.csv`` on logs from an independent forward model, over many seeds.

The logs come from :mod:`support.phone_logs` (no cadcog code): the release swing of a rigid
body on a massless wire integrated in full by :mod:`support.swing_truth`, handling between
hangs, the specific force at the sensor, one sensor per log with its offsets, sensitivities,
cross-axis terms, nonlinearity, drift and mounting drawn once, per-sample noise, quantisation,
a phone's sample jitter and dropped samples. What one test shares is drawn once per log: the
sensor's errors, and the wire's length, ``N(300 mm, 2 mm)`` (the estimator is told 300 ± 2).
Per hang: the wire exit within the bolt hole's 1 mm play, the release (``U(3°, 8°)`` in a
random direction, the body tilted against the wire by up to 0.3 of it, a yaw rate within
±10 °/s), the decay time ``U(10 s, 30 s)`` (left to swing: the team does not stop it), and the
team waits until the swing is below 0.05° before it averages.

Each log is written as phyphox exports it and goes through
:func:`cadcog.runs.acquire_log.acquire_log` with ``swings=``: the cut, the readings file, the
swing file, the CoG and the tensor from the files as written, on the paper rig file with its
``[inclinometer]`` an accelerometer, its measurement equipment the sensor's package as the
generator carries it and a ``[swing]`` table (wire 300 ± 2 mm, the sensing point). The truth is
the object the generator hangs without the package: the paper's steel box (9.2 kg, 200 × 75 ×
78 mm). Rows: the MPU-6050 and the ADXL355 on the six points; a phone lying on the top face,
whose two top points it covers, on the four others.

Printed per row: logs whose tensor was estimated, each principal moment's bias, 95 % absolute
error and coverage of ±1.96 σ, the tensor's χ²₆ coverage (95 % expected, with its binomial
interval), the median χ², the modes left out per log, and the CoG's coverage.

Run: ``.venv/bin/python benchmarks/study_log_swings.py [--logs 200] [--rows ...]``; the table is
in ``docs/bench.md`` §8.
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
sys.path.insert(0, str(Path(__file__).resolve().parent))

from study_phone_logs import declared

from cadcog.bench.accellog import LogError
from cadcog.bench.target import target_from_rig
from cadcog.mass.inertia import principal_axes
from cadcog.rig.file import load_rig
from cadcog.runs.acquire_log import acquire_log
from support import phone_logs as pl
from support import phone_scenarios as ps
from support.rigtools import package_rig

CHI2_6_95 = float(stats.chi2.ppf(0.95, 6))
CHI2_3_95 = float(stats.chi2.ppf(0.95, 3))
#: The sensor's package as the generator carries it: mass (kg), centre and size (mm).
PACKAGES = {
    "phone": (0.19, (100.0, 37.5, 82.5), (150.0, 71.0, 9.0)),
    "mpu6050": (0.176, (101.6, 37.5, 112.2), (68.6, 53.4, 60.0)),
    "adxl355": (0.176, (101.6, 37.5, 112.2), (68.6, 53.4, 60.0)),
}
#: The points each sensor leaves free (the phone covers the top face's two).
POINTS = {"phone": (2, 3, 4, 5), "mpu6050": (0, 1, 2, 3, 4, 5), "adxl355": (0, 1, 2, 3, 4, 5)}


def truth_entries() -> np.ndarray:
    """The object's tensor (the steel box without the package), ``[xx, yy, zz, xy, xz, yz]``."""
    j = ps._box(9.2, (200.0, 75.0, 78.0))
    return np.array([j[0, 0], j[1, 1], j[2, 2], j[0, 1], j[0, 2], j[1, 2]])


def rig_file(folder: Path, sensor: str, spec: pl.LogSpec) -> Path:
    """The paper rig with the sensor's package as its ME and a ``[swing]`` table."""
    return package_rig(
        folder / f"rig_{sensor}.toml",
        package=PACKAGES[sensor],
        volume_name=f"{sensor}_sensor",
        inclinometer={
            "device": "accelerometer",
            "axes": list(spec.sensor.axes),
            **declared(sensor),
        },
        swing={
            "wire_length_mm": 300.0,
            "wire_length_sigma_mm": 2.0,
            "sensor_position_mm": list(spec.sensor.position_mm),
        },
        points=POINTS[sensor],
    )


def test_spec(sensor: str, seed: int) -> pl.LogSpec:
    """One log's test: the scenario's points (those the sensor leaves free, each within its
    play), one wire length, and per hang a release, a decay time and a wait to below 0.05°."""
    spec = ps.with_play(ps.scenario("paper_rig", sensor), "paper_rig", seed)
    rng = np.random.default_rng([seed, 31])
    wire = float(rng.normal(300.0, 2.0))
    hangs = []
    for i in POINTS[sensor]:
        tau, release = rng.uniform(10.0, 30.0), rng.uniform(3.0, 8.0)
        settle = tau * np.log(1.3 * release / 0.05)
        hangs.append(
            replace(spec.hangs[i], wire_length_mm=wire, release_deg=release,
                    decay_time_s=tau, settle_s=float(settle))
        )  # fmt: skip
    return replace(spec, hangs=tuple(hangs))


def run_row(sensor: str, seeds: list[int], work: Path, chunk: int) -> dict:
    truth = truth_entries()
    rig = None
    moments_true = principal_axes(ps._box(9.2, (200.0, 75.0, 78.0))).moments_kg_mm2
    rel, inside, chi2, dropped, cog_in, cut, failed = [], [], [], [], 0, 0, []
    for lo in range(0, len(seeds), chunk):
        part = seeds[lo : lo + chunk]
        specs = [test_spec(sensor, s) for s in part]
        logs = pl.generate_many(specs, part)
        for seed, spec, log in zip(part, specs, logs, strict=True):
            if rig is None:
                rig = load_rig(rig_file(work, sensor, spec))
            path = work / f"{sensor}_{seed}.csv"
            pl.write_phyphox_csv(path, log)
            out, sw = work / f"r_{sensor}_{seed}.csv", work / f"s_{sensor}_{seed}.csv"
            try:
                run = acquire_log(target_from_rig(rig), path, out, swings=sw)
            except LogError as exc:
                failed.append(f"{seed}: {exc}")
                continue
            finally:
                path.unlink()
            cut += 1
            est = run.estimate
            e = est.joint.cog_mm - log.cog_mm
            cog_in += float(e @ np.linalg.solve(est.joint.cov_mm2, e)) < CHI2_3_95
            out.unlink()
            sw.unlink()
            res = run.inertia
            if res is None:
                failed.append(f"{seed}: {run.inertia_note}")
                continue
            j = res.inertia_kg_mm2
            got = np.array([j[0, 0], j[1, 1], j[2, 2], j[0, 1], j[0, 2], j[1, 2]])
            d = got - truth
            chi2.append(float(d @ np.linalg.solve(res.cov_kg2_mm4, d)))
            m = res.principal.moments_kg_mm2
            s = res.principal.moments_sigma_kg_mm2
            rel.append((m - moments_true) / moments_true)
            inside.append(np.abs(m - moments_true) <= 1.96 * s)
            dropped.append(sum("left out" in w for w in res.warnings))
    n = len(seeds)
    r = np.array(rel)
    c = np.array(chi2)
    k = int(np.sum(c <= CHI2_6_95))
    lo_ci, hi_ci = stats.binomtest(k, len(c)).proportion_ci(0.95)
    return {
        "row": f"paper rig, {sensor}, {len(POINTS[sensor])} hangs",
        "logs": n,
        "estimated": len(c),
        "bias": 100 * r.mean(axis=0),
        "q95": 100 * np.quantile(np.abs(r), 0.95, axis=0),
        "inside": 100 * np.mean(inside, axis=0),
        "chi2_cov": (k / len(c), lo_ci, hi_ci),
        "chi2_median": float(np.median(c)),
        "dropped": float(np.mean(dropped)),
        "cog": cog_in / max(cut, 1),
        "failed": failed,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--logs", type=int, default=200)
    ap.add_argument("--seed", type=int, default=341)
    ap.add_argument("--rows", default="mpu6050,phone,adxl355")
    ap.add_argument("--chunk", type=int, default=10, help="logs integrated per batch")
    a = ap.parse_args(argv)
    seeds = list(range(a.seed * 10_000, a.seed * 10_000 + a.logs))
    print(
        "| row | logs | tensor estimated | bias I₁/I₂/I₃ | 95 % \\|error\\| | in ±1.96 σ "
        "| tensor χ²₆ ≤ 95 % quantile [CP 95 %] | median χ² (5.35) | modes left out per log "
        "| CoG inside its 95 % |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for sensor in a.rows.split(","):
            t0 = time.time()
            r = run_row(sensor, seeds, Path(tmp), a.chunk)

            def three(v: np.ndarray, fmt: str) -> str:
                return "/".join(format(x, fmt) for x in v)

            cov, lo, hi = r["chi2_cov"]
            print(
                f"| {r['row']} | {r['logs']} | {r['estimated']} | {three(r['bias'], '+.2f')} % "
                f"| {three(r['q95'], '.2f')} % | {three(r['inside'], '.1f')} % | {cov:.1%} "
                f"[{lo:.1%}, {hi:.1%}] | {r['chi2_median']:.2f} | {r['dropped']:.2f} "
                f"| {r['cog']:.1%} |",
                flush=True,
            )
            for f in r["failed"][:10]:
                print(f"  not estimated: {f[:300]}", file=sys.stderr)
            print(f"  ({time.time() - t0:.0f} s)", file=sys.stderr, flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
