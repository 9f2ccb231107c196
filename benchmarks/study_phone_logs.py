"""A phone or a $10 accelerometer as the sensor (issue 34): ``cadcog acquire --log`` on logs from
an independent forward model, over many seeds.

The logs come from :mod:`support.phone_logs` (no cadcog code: the release swing of a rigid
body on a massless wire integrated in full by :mod:`support.swing_truth`, handling between
hangs, the specific force at the sensor, one sensor per log with its offsets, sensitivities,
cross-axis terms and mounting drawn once, per-sample noise, quantisation, a phone's sample
jitter and dropped samples). Each log is written as phyphox exports it and goes through the
code behind ``cadcog acquire --log``: the reader, the cutting into hangs, the readings file, the
estimate (the set-up's declared figures: the generator's own bounds). Scenarios:

- ``paper_rig``: the paper's steel proof mass and its six points (the rig file with its
  ``[inclinometer]`` replaced by an accelerometer table); the whole command path
  (:func:`cadcog.runs.acquire_log.acquire_log`);
- ``cubesat_3u``: a 3U CubeSat with six corner points and the phone on its +x face, estimated by
  the same functions (cut, readings, :func:`cadcog.method.estimate.estimate_cog` with the
  points' faces) since a rig file cannot carry its ME on a side face.

Variants: ``plain``; ``knock`` (the third hang knocked halfway through its averaging). Printed
per row: the fraction of logs cut into exactly the planned hangs, the fraction whose true CoG
(of what hangs, object + sensor) lies inside the estimate's 95 % ellipsoid (with its 95 %
binomial interval), the mean squared Mahalanobis distance (3 when calibrated), the fraction with
a line flagged inconsistent, the mean error per axis, the 95th percentile of the error's norm
and the mean stated σ (√trace). A row ``never-settles`` checks instead that every log whose
third hang never settled is refused with that hang's time span.

Run: ``.venv/bin/python benchmarks/study_phone_logs.py [--logs 200] [--seed 34]``; the table is in
``docs/bench.md``.
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

from cadcog.bench.accellog import LogError, read_log
from cadcog.bench.logsegments import segment_log
from cadcog.bench.swing import SettleCriterion
from cadcog.bench.target import target_from_rig
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox, estimate_cog
from cadcog.method.readings import read_readings
from cadcog.rig.file import load_rig
from cadcog.rig.inclinometer import InclinometerConfig
from cadcog.runs.acquire_log import acquire_log, readings_text
from support import phone_logs as pl
from support import phone_scenarios as ps
from support.rigtools import paper_rig_dict, write_rig

CHI2_95 = float(stats.chi2.ppf(0.95, 3))
#: The rig's one-wire bound (mm): the paper's 1 (a prior covering a string and a stiff wire).
WIRE_MAX_MM = 1.0


def declared(sensor: str) -> dict[str, float]:
    """The figures a team declares for ``sensor``: the generator's bounds (its datasheet)."""
    s = ps.SENSORS[sensor]
    offset = max(np.atleast_1d(s.offset_g))
    out = {
        "offset_g": float(offset),
        "scale_error_rel": float(s.scale_rel),
        "mounting_misalignment_deg": float(s.misalignment_deg),
    }
    if s.cross_axis_rel:
        out["cross_axis_rel"] = float(s.cross_axis_rel)
    return out


def rig_file(folder: Path, axes: tuple[str, str, str], sensor: str, wire_max_mm: float) -> Path:
    data = paper_rig_dict()
    data["inclinometer"] = {"device": "accelerometer", "axes": list(axes), **declared(sensor)}
    data["error_model"]["wire_offset_max_mm"] = wire_max_mm
    return write_rig(folder / "rig.toml", data)


def _spec(name: str, sensor: str, variant: str, seed: int) -> pl.LogSpec:
    spec = ps.with_play(ps.scenario(name, sensor), name, seed)
    if variant == "plain":
        return spec
    hangs = list(spec.hangs)
    h = hangs[2]
    hangs[2] = (
        replace(h, knock_after_s=h.average_s / 2)
        if variant == "knock"
        else replace(h, never_settles=True)
    )
    return replace(spec, hangs=tuple(hangs))


def _estimate_3u(spec: pl.LogSpec, log_path: Path, out: Path, sensor: str) -> object:
    """The 3U: cut, readings, estimate (the functions behind acquire --log)."""
    cfg = InclinometerConfig(
        range_deg=90.0, device="accelerometer", axes=spec.sensor.axes, accuracy_deg=0.0,
        **declared(sensor),
    )  # fmt: skip
    seg = segment_log(read_log(log_path), SettleCriterion())
    if len(seg.hangs) != len(spec.hangs):
        raise LogError(f"{len(seg.hangs)} hangs for {len(spec.hangs)}")
    nominal = ps.scenario("cubesat_3u", sensor).hangs  # where the team thinks it hung
    faces = [
        (np.asarray(h.point_mm), ps.face_normal(h.point_mm, ps.BOXES_MM["cubesat_3u"]))
        for h in nominal
    ]

    class _Hang:
        def __init__(self, i: int, p: np.ndarray) -> None:
            self.id, self.position_mm, self.sensor_turned = f"P{i + 1}", tuple(p), False

    planned = [_Hang(i, f[0]) for i, f in enumerate(faces)]
    out.write_text(readings_text(planned, seg.hangs, log_path))
    sus = read_readings(out, cfg)
    model = replace(
        ErrorModel((0.19,), (10.0,)),
        device="accelerometer",
        accuracy_deg=0.0,
        lsb_deg=0.0,
        sensor_offset_g=cfg.offset_g,
        sensor_cross_axis_rel=cfg.cross_axis_rel,
        sensor_scale_rel=cfg.scale_error_rel,
        mounting_misalignment_deg=cfg.mounting_misalignment_deg,
    )
    box = BodyBox(np.zeros(3), np.array([100.0, 100.0, 340.5]), "3U", tuple(faces))
    return estimate_cog(sus, cfg, None, model=model, body=box)


def run_row(name: str, sensor: str, variant: str, seeds: list[int], work: Path) -> dict:
    specs = [_spec(name, sensor, variant, seed) for seed in seeds]
    logs = pl.generate_many(specs, seeds)
    rig = None
    if name == "paper_rig":
        rig = load_rig(rig_file(work, specs[0].sensor.axes, sensor, WIRE_MAX_MM))
    d2, err, sig, flagged, cut, refused_ok = [], [], [], 0, 0, 0
    for seed, spec, log in zip(seeds, specs, logs, strict=True):
        path = work / f"{name}_{sensor}_{variant}_{seed}.csv"
        pl.write_phyphox_csv(path, log)
        out = work / f"r_{name}_{sensor}_{variant}_{seed}.csv"  # a log's readings are new files
        try:
            if rig is not None:
                target = target_from_rig(rig)
                est = acquire_log(target, path, out).estimate
            else:
                est = _estimate_3u(spec, path, out, sensor)
        except LogError as exc:
            if variant == "never-settles":
                t = log.hangs[2]
                refused_ok += f"{t.release_t_s:.0f}" in str(exc) or "never settled" in str(exc)
            continue
        cut += 1
        g = est.joint.cog_mm
        cov = est.joint.cov_mm2
        e = g - log.cog_mm
        d2.append(float(e @ np.linalg.solve(cov, e)))
        err.append(e)
        sig.append(float(np.sqrt(np.trace(cov))))
        flagged += any(r.inconsistent for r in est.joint.residuals)
        path.unlink()
        out.unlink()
    n = len(seeds)
    row = {"row": f"{name} {sensor} {variant}", "logs": n, "cut": cut / n}
    if variant == "never-settles":
        row["refused_naming_span"] = refused_ok / n
        return row
    d2a = np.array(d2)
    inside = int(np.sum(d2a < CHI2_95))
    lo, hi = stats.binomtest(inside, len(d2a)).proportion_ci(0.95)
    e = np.array(err)
    row.update(
        coverage=inside / len(d2a),
        ci=(lo, hi),
        mean_d2=float(d2a.mean()),
        flagged=flagged / len(d2a),
        bias_mm=e.mean(axis=0).round(3).tolist(),
        q95_mm=float(np.quantile(np.linalg.norm(e, axis=1), 0.95)),
        sigma_mm=float(np.mean(sig)),
    )
    return row


def predictions() -> None:
    """What ``cadcog budget`` and ``cadcog plan`` predict for each sensor, on the paper rig and
    on the example 3U CubeSat (parts/cubesat_3u_setup.toml), every figure as declared here."""
    from cadcog.rig.file import default_rig_path
    from cadcog.runs.plan import run_accel_plan
    from cadcog.spacecraft.setup import load_setup
    from cadcog.uncertainty.accel_budget import Hangs, accelerometer_budget
    from cadcog.uncertainty.trials import Scenario

    paper = load_rig(default_rig_path())
    cubesat = load_setup(default_rig_path().parent / "cubesat_3u_setup.toml")
    print(
        "| sensor | object | 4 hangs | 6 hangs | 8 hangs (with reversals) | 6 hangs, uncalibrated |"
    )
    print("|---|---|---|---|---|---|")
    for sensor in ("phone", "mpu6050", "adxl355"):
        cfg = InclinometerConfig(range_deg=90.0, device="accelerometer", **declared(sensor))
        rig = replace(paper, inclinometer=cfg)
        sc = Scenario.from_rig(rig)
        hangs = Hangs(sc.ids, sc.points_mm, sc.normals, sc.assembly_cog_mm, sc.weight_n)
        b = accelerometer_budget(hangs, cfg, ErrorModel.from_rig(rig), max_hangs=8)
        sat = replace(cubesat, rig=replace(cubesat.rig, inclinometer=cfg))
        _, c = run_accel_plan(sat, max_set=8)
        for name, budget in (("paper rig", b), ("3U CubeSat", c)):
            by = {len(s.hangs): s for s in budget.sizes}
            print(
                f"| {sensor} | {name} | {by[4].q95_mm:.2f} | {by[6].q95_mm:.2f} | "
                f"{by[8].q95_mm:.2f} ({', '.join(by[8].hangs)}) | "
                f"{by[6].q95_uncalibrated_mm:.2f} |"
            )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--logs", type=int, default=200)
    ap.add_argument("--seed", type=int, default=34)
    ap.add_argument(
        "--rows",
        default="paper_rig:phone:plain,paper_rig:phone:knock,paper_rig:mpu6050:plain,"
        "paper_rig:adxl355:plain,cubesat_3u:phone:plain,cubesat_3u:mpu6050:plain,"
        "paper_rig:phone:never-settles",
    )
    ap.add_argument(
        "--wire-max-mm",
        type=float,
        default=1.0,
        help="the rig's wire_offset_max_mm (default the paper's 1; 0: a string declared as one)",
    )
    ap.add_argument(
        "--predict",
        action="store_true",
        help="print what budget and plan predict for each sensor (95 %% error, mm), and stop",
    )
    a = ap.parse_args(argv)
    if a.predict:
        predictions()
        return 0
    global WIRE_MAX_MM
    WIRE_MAX_MM = a.wire_max_mm
    seeds = list(range(a.seed * 10_000, a.seed * 10_000 + a.logs))
    print(
        "| scenario | logs | cut as planned | CoG inside 95 % | mean d² | flagged | bias mm "
        "| 95 % error mm | stated σ mm |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for spec in a.rows.split(","):
            name, sensor, variant = spec.split(":")
            t0 = time.time()
            r = run_row(name, sensor, variant, seeds, Path(tmp))
            if variant == "never-settles":
                print(
                    f"| {r['row']} | {r['logs']} | refused naming the hang's span: "
                    f"{r['refused_naming_span']:.1%} | | | | | | |"
                )
            else:
                print(
                    f"| {r['row']} | {r['logs']} | {r['cut']:.1%} | {r['coverage']:.1%} "
                    f"({r['ci'][0]:.1%}-{r['ci'][1]:.1%}) | {r['mean_d2']:.2f} | "
                    f"{r['flagged']:.1%} | {r['bias_mm']} | {r['q95_mm']:.3f} | "
                    f"{r['sigma_mm']:.3f} |"
                )
            print(f"  ({time.time() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
