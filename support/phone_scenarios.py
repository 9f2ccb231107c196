"""Named tests for :mod:`support.phone_logs`: the sensors' figures from their data sheets, the
paper rig's and a 3U CubeSat's body with the sensor's package, their six wire exits, the bolt
hole's play; and ``python -m support.phone_scenarios``, which writes one log with its truth.

Like the generator, it imports nothing from ``cadcog``.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import numpy.typing as npt

from support.phone_logs import (
    Body,
    Hang,
    LogSpec,
    SensorSpec,
    generate,
    truth_dict,
    write_phyphox_csv,
    write_plain_csv,
)

FloatArray = npt.NDArray[np.float64]

#: Phone ("Acceleration with g"): figures typical of phone IMUs (assumptions, as briefed): offset
#: ±20 mg, sensitivity ±1 %, mounting within 1° (strapped to the object), 2 mg per sample at
#: 200 Hz, output resolution 0.6 mg, timestamps jittered by ~1 ms, rare dropped samples; a
#: quadratic nonlinearity of up to 3 mg at 1 g and an offset drifting by up to 2 mg over the
#: test (assumptions: phone IMUs publish neither).
PHONE = SensorSpec((0.0, 0.0, 0.0), nonlinearity_g=0.003, drift_g=0.002)
#: InvenSense MPU-6050 (PS-MPU-6000A-00 rev 3.4, table 6.2): ±2 g full scale, 16-bit, 16 384
#: LSB/g; sensitivity initial tolerance ±3 %; cross-axis ±2 %; zero-g ±50 mg (x, y), ±80 mg (z);
#: noise 400 µg/√Hz (at 10 Hz, ODR 1 kHz); nonlinearity 0.5 % (best-fit line), taken as 5 mg at
#: 1 g. Assumed: DLPF at 44 Hz, logged at 100 Hz.
MPU6050 = SensorSpec((0.0, 0.0, 0.0), rate_hz=100.0, drop_prob=0.001, offset_g=(0.05, 0.05, 0.08),
                     scale_rel=0.03, cross_axis_rel=0.02, noise_g=None, noise_density_ug_rthz=400.0,
                     bandwidth_hz=44.0, lsb_g=1 / 16384, range_g=2.0,
                     nonlinearity_g=0.005, drift_g=0.002)  # fmt: skip
#: Analog Devices ADXL355 (data sheet adxl354_adxl355.pdf): ±2.048 g, 20-bit, 256 000 LSB/g
#: (3.9 µg); noise density 25 µg/√Hz; 0 g offset ±25 mg typical. Bandwidth ODR/4 (its digital
#: filter) at 125 Hz. The sensitivity's min-max window is ±8 % as for the ADXL357 (47 104 …
#: 55 296 LSB/g, ez.analog.com); ±1 % and cross-axis ±1 % are assumed typical values, and a
#: nonlinearity of 2 mg at 1 g (its ±0.1 % of a ±2 g full scale, assumed half-used at 1 g).
ADXL355 = SensorSpec((0.0, 0.0, 0.0), rate_hz=125.0, drop_prob=0.001, offset_g=0.025,
                     scale_rel=0.01, cross_axis_rel=0.01, noise_g=None, noise_density_ug_rthz=25.0,
                     bandwidth_hz=31.25, lsb_g=1 / 256000, range_g=2.048,
                     nonlinearity_g=0.002, drift_g=0.001)  # fmt: skip
SENSORS = {"phone": PHONE, "mpu6050": MPU6050, "adxl355": ADXL355}


def _box(m: float, size: tuple[float, float, float]) -> FloatArray:
    a, b, c = size
    return np.diag([m * (b * b + c * c), m * (a * a + c * c), m * (a * a + b * b)]) / 12.0


def composite(parts: list[tuple[float, tuple[float, float, float], FloatArray]]) -> Body:
    """A body from parts (mass kg, centre mm, inertia kg·mm² about the centre): parallel axes."""
    m = float(sum(p[0] for p in parts))
    c = np.sum([p[0] * np.asarray(p[1], float) for p in parts], axis=0) / m
    inertia = np.zeros((3, 3))
    for mass, centre, i_c in parts:
        d = np.asarray(centre, float) - c
        inertia += np.asarray(i_c, float) + mass * (d @ d * np.eye(3) - np.outer(d, d))
    rows = tuple((float(r[0]), float(r[1]), float(r[2])) for r in inertia)
    return Body(m, (float(c[0]), float(c[1]), float(c[2])), rows)


def _exits(points: list[tuple[tuple[float, ...], tuple[float, ...]]], bolt_mm: float = 4.0) -> list:
    return [tuple((np.asarray(p) + bolt_mm * np.asarray(n)).tolist()) for p, n in points]


def scenario(name: str, sensor: str = "phone", **hang_overrides: object) -> LogSpec:
    """A named test. ``paper_rig``: the paper's steel proof mass (200 × 75 × 78 mm, 9.2 kg,
    docs/method.md §7) with the six points of parts/paper_rig.toml (wire exit 4 mm out of each
    bolt); ``cubesat_3u``: a 3U CubeSat (100 × 100 × 340.5 mm, 3 kg with its battery off-centre),
    six points near corners of six faces. The sensor package rides on the body (its mass is in
    it); ``sensor`` picks the figures (``phone``, ``mpu6050``, ``adxl355``). Hang fields can be
    overridden for every hang (e.g. ``decay_time_s=6``)."""
    if sensor not in SENSORS:
        raise ValueError(f"unknown sensor {sensor!r}: one of {sorted(SENSORS)}")
    phone = sensor == "phone"
    if name == "paper_rig":
        pkg = ((0.19, (100.0, 37.5, 82.5), _box(0.19, (150.0, 71.0, 9.0))) if phone else
               (0.176, (101.6, 37.5, 112.2), _box(0.176, (68.6, 53.4, 60.0))))  # fmt: skip
        body = composite([(9.2, (100.0, 37.5, 39.0), _box(9.2, (200.0, 75.0, 78.0))), pkg])
        pos, axes = ((120.0, 30.0, 84.0), ("-y", "+x", "+z")) if phone else \
            ((100.0, 37.5, 107.0), ("+x", "+y", "+z"))  # fmt: skip
        pts = _exits([((45, 20, 78), (0, 0, 1)), ((155, 55, 78), (0, 0, 1)),
                      ((60, 60, 0), (0, 0, -1)), ((140, 15, 0), (0, 0, -1)),
                      ((55, 0, 60), (0, -1, 0)), ((145, 75, 60), (0, 1, 0))])  # fmt: skip
    elif name == "cubesat_3u":
        pkg = (0.19, (104.5, 50.0, 170.0), _box(0.19, (9.0, 71.0, 150.0))) if phone else \
            (0.05, (105.0, 45.0, 190.0), _box(0.05, (10.0, 50.0, 50.0)))  # fmt: skip
        battery = (0.4, (65.0, 38.0, 250.0), _box(0.4, (90.0, 90.0, 20.0)))
        body = composite([(2.6, (50.0, 50.0, 170.25), _box(2.6, (100, 100, 340.5))), battery, pkg])
        pos, axes = (104.0, 45.0, 190.0), ("+y", "+z", "+x")
        pts = _exits([((8, 8, 340.5), (0, 0, 1)), ((92, 92, 0), (0, 0, -1)),
                      ((100, 8, 330), (1, 0, 0)), ((0, 92, 10), (-1, 0, 0)),
                      ((92, 100, 330), (0, 1, 0)), ((8, 0, 10), (0, -1, 0))])  # fmt: skip
    else:
        raise ValueError(f"unknown scenario {name!r}: paper_rig or cubesat_3u")
    hangs = tuple(replace(Hang(p), **hang_overrides) for p in pts)  # type: ignore[arg-type]
    return LogSpec(body, hangs, replace(SENSORS[sensor], position_mm=pos, axes=axes))


#: The body's box in each scenario (mm), from the origin: a point's face is the side it lies
#: outside of.
BOXES_MM = {"paper_rig": (200.0, 75.0, 78.0), "cubesat_3u": (100.0, 100.0, 340.5)}


def face_normal(point_mm: npt.ArrayLike, box_mm: tuple[float, float, float]) -> FloatArray:
    """The outward normal of the box face a wire exit sits above."""
    p = np.asarray(point_mm, dtype=float)
    out_of = np.concatenate([p - np.asarray(box_mm), -p])  # how far outside each face
    k = int(np.argmax(out_of))
    n = np.zeros(3)
    n[k % 3] = 1.0 if k < 3 else -1.0
    return n


def with_play(spec: LogSpec, name: str, seed: int, play_mm: float = 1.0) -> LogSpec:
    """Each hang's wire exit moved within the bolt hole's play: uniform in a square of edge
    ``play_mm`` in the plane of its face (the paper's 1 mm), drawn per hang from
    ``default_rng([seed, 7])`` (the generator itself has none; the rig's points stay where
    the readings say)."""
    rng = np.random.default_rng([seed, 7])
    hangs = []
    for h in spec.hangs:
        p = np.asarray(h.point_mm, dtype=float)
        n = face_normal(p, BOXES_MM[name])
        shift = rng.uniform(-0.5 * play_mm, 0.5 * play_mm, 3) * (1.0 - np.abs(n))
        hangs.append(replace(h, point_mm=tuple((p + shift).tolist())))
    return replace(spec, hangs=tuple(hangs))


def main(argv: list[str] | None = None) -> int:
    """``python -m support.phone_scenarios --seed N --out DIR [--scenario NAME] [--sensor KIND]
    [--knock HANG] [--never-settles HANG] [--handling-s S]``: writes ``DIR/Raw Data.csv`` (phyphox
    format), ``DIR/log.csv`` (``t_s,ax,ay,az``) and ``DIR/truth.json``. Hangs count from 1."""
    ap = argparse.ArgumentParser(prog="python -m support.phone_scenarios", description=main.__doc__)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--scenario", default="paper_rig", choices=["paper_rig", "cubesat_3u"])
    ap.add_argument("--sensor", default="phone", choices=sorted(SENSORS))
    ap.add_argument("--knock", type=int, help="knock this hang halfway through its averaging")
    ap.add_argument("--never-settles", type=int, help="this hang keeps swinging")
    ap.add_argument("--handling-s", type=float, help="handling time before every hang (s)")
    a = ap.parse_args(argv)
    spec = scenario(a.scenario, a.sensor)
    hangs = list(spec.hangs)
    for i, h in enumerate(hangs, start=1):
        if a.handling_s is not None:
            h = replace(h, handling_s=a.handling_s)
        if a.knock == i:
            h = replace(h, knock_after_s=h.average_s / 2)
        if a.never_settles == i:
            h = replace(h, never_settles=True)
        hangs[i - 1] = h
    spec = replace(spec, hangs=tuple(hangs))
    log = generate(spec, a.seed)
    a.out.mkdir(parents=True, exist_ok=True)
    write_phyphox_csv(a.out / "Raw Data.csv", log)
    write_plain_csv(a.out / "log.csv", log)
    truth = truth_dict(log, spec) | {"scenario": a.scenario, "sensor_kind": a.sensor}
    (a.out / "truth.json").write_text(json.dumps(truth, indent=2) + "\n", encoding="utf-8")
    print(f"{log.t_s.size} samples, {log.t_s[-1]:.1f} s -> {a.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
