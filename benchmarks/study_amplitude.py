"""How far a body mode's frequency moves with the swing's size, on the nonlinear simulation.

The inertia estimate corrects each fitted frequency for its own swing as a simple pendulum
slows, ``f₀ = f / (1 − A²/16)`` with ``A`` the mode's reading amplitude
(:func:`cadcog.dynamics.tensorfit.amplitude_factor`), and knows nothing of the wire's own
swing, which the tilt sensor does not see. This releases single hangs of the paper rig and of
the 3U CubeSat on a 300 mm wire in the nonlinear simulation (:mod:`support.swing_truth`: no
damping, no noise, 60 s at 50 samples/s), fits them with cadcog's modal fit, and prints each
body mode's shift from the linear model's frequency beside the correction the estimator made
until 2026-11-28 (each frequency held fixed, ``drift=False``: the record's mean): (a) the body
tilted 2° or 5° about its wire exit with the wire still, (b) the wire swung 1°, 5° or 10° with
the body tilted 1°. Quoted in ``docs/inertia_validation.md``.

``--backbone`` asks whether the record itself can tell: the same releases of the CubeSat on a
damped wire (decay time 20 s, 60 s recorded), each body mode fitted over the whole record (and
corrected as the estimator did) and over each half; the two halves' frequencies, extrapolated
in the squared amplitude (each half's own ``⟨A²⟩``) to zero, and the drift fit the estimator
uses since 2026-11-28, against the linear frequency.

``--campaigns N`` does the same on the first N noisy campaigns of ``study_inertia.py``'s
CubeSat row (its cached ``build/study_inertia/cubesat_ih_flex.npz``): every body mode fitted in
both halves, against the linear frequency of the hang on its true wire length at the nominal
exit (the play's ±0.5 mm left out of the reference).

``--stated N`` asks whether each frequency's **stated σ** holds, the σ the tensor fit weighs
it by (:func:`cadcog.dynamics.tensorfit.swing_data`: the fit's own, what a drift exceeds its
prior by, what its two halves disagree by, and ``frequency_model_rel``, the object's air by
default): every hang of the CubeSat's inertia row and of the paper rig's six on a 300 mm
wire, released as ``study_inertia.py``'s campaigns release (the body tilted up to the
amplitude, the wire swung, no yaw), N seeds a release size, decay time 30 s, 60 s at 50
samples/s with 0.005° of white noise, at the nominal exit (no play, no ADC): each body mode's
fitted small-swing limit against the hang's linear frequency, over its stated σ.

Run: ``.venv/bin/python benchmarks/study_amplitude.py [--backbone | --campaigns N | --stated
N]`` (~30 s; ~10 s a campaign; ``--stated 10`` ~3 min).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from cadcog.dynamics.context import InertiaContext, context_for_rig, context_for_setup  # noqa: E402
from cadcog.dynamics.hungbody import HangGeometry, hang_modes  # noqa: E402
from cadcog.dynamics.modalfit import ModalFit, fit_swing  # noqa: E402
from cadcog.dynamics.swingfile import Swing  # noqa: E402
from cadcog.dynamics.tensorfit import amplitude_factor  # noqa: E402
from support import swing_files as sf  # noqa: E402
from support import swing_truth as st  # noqa: E402

HANGS = (
    ("paper rig", ROOT / "parts" / "paper_rig.toml", "rig", ("S1", "S3")),
    ("3U CubeSat", ROOT / "parts" / "cubesat_3u_setup.toml", "setup", ("+y_-30_-150",)),
)
LENGTH_MM = 300.0
#: Every record here: 60 s at 50 samples/s.
RATE_HZ, RECORD_S = 50.0, 60.0


def _record_times() -> np.ndarray:
    """The sampling instants of a record (s)."""
    return np.arange(1, int(RECORD_S * RATE_HZ) + 1) / RATE_HZ


def _truth(path: Path, kind: str) -> sf.Truth:
    """The independent truth of a rig (``kind`` "rig") or a set-up file."""
    return sf.rig_truth(path) if kind == "rig" else sf.setup_truth(path)


def _context(path: Path, kind: str) -> InertiaContext:
    """The estimator's context of a rig (``kind`` "rig") or a set-up file."""
    import cadcog

    if kind == "rig":
        return context_for_rig(cadcog.load_rig(path))
    return context_for_setup(cadcog.load_setup(path), np.zeros((6, 6)))


def _horizontal(deg: float, azimuth_deg: float) -> np.ndarray:
    a = np.radians(azimuth_deg)
    return np.radians(deg) * np.array([np.cos(a), np.sin(a), 0.0])


def _linear_hz(truth: sf.Truth, hinge_mm: np.ndarray, length_mm: float) -> np.ndarray:
    """The hang's modes as cadcog's linear model has them (the estimator's reference)."""
    geo = HangGeometry(hinge_mm, np.asarray(truth.body.sensor_mm), length_mm, 0.0)
    b = truth.body
    return hang_modes(b.inertia_kg_mm2, b.mass_kg, b.cog_mm, geo).frequencies_hz


def releases() -> dict[str, st.Release]:
    """The releases, by label: the body alone, then the wire."""
    still = np.zeros(3)
    out = {
        f"body {b:g}°, wire still (azimuth {az}°)": st.Release(
            still, _horizontal(b, az), still, still
        )
        for b in (2.0, 5.0)
        for az in (0, 90)
    }
    out |= {
        f"wire {w:g}°, body 1°": st.Release(_horizontal(w, 30), _horizontal(1, 100), still, still)
        for w in (1.0, 5.0, 10.0)
    }
    return out


def backbone() -> None:
    """The CubeSat's hang on a damped wire: whole-record fit and correction against the
    two-half extrapolation to zero amplitude."""
    tau = 20.0
    t = _record_times()
    truth = sf.setup_truth(HANGS[1][1])
    pid = HANGS[1][3][0]
    hinge = truth.exit_of(pid)
    linear = _linear_hz(truth, hinge, LENGTH_MM)
    still = np.zeros(3)
    rel = {
        f"wire {w:g}°, body {b:g}° (azimuth {az}°)": st.Release(
            _horizontal(w, 30), _horizontal(b, az), still, still
        )
        for w, b, az in ((0, 5, 0), (0, 5, 90), (10, 1, 0), (8, 3, 45))
    }
    tx, ty = truth.released(hinge, list(rel.values()), LENGTH_MM, tau, t)
    print(
        "| release | mode | fitted | corrected as the estimator did | two halves, to zero "
        "| drift fit (the estimator since 2026-11-28) |"
    )
    print("|---|---|---|---|---|---|")
    half = len(t) // 2
    for k, name in enumerate(rel):
        readings = np.column_stack([tx[k], ty[k]])
        fits = [
            fit_swing(Swing(pid, t[c], readings[c]), linear, drift=False)
            for c in (slice(None), slice(None, half), slice(half, None))
        ]
        whole = fits[0]
        drifting = fit_swing(Swing(pid, t, readings), linear)
        for i, (fc, f0) in _to_zero(*fits, RECORD_S).items():
            if i < len(linear) - 2:
                continue
            f = whole.frequencies_hz[list(whole.mode_index).index(i)]
            fd = drifting.frequencies_hz[list(drifting.mode_index).index(i)]
            print(
                f"| {name} | {i} | {(f / linear[i] - 1) * 100:+.3f} % | "
                f"{(fc / linear[i] - 1) * 100:+.3f} % | {(f0 / linear[i] - 1) * 100:+.3f} % | "
                f"{(fd / linear[i] - 1) * 100:+.3f} % |"
            )


def _to_zero(whole: ModalFit, first: ModalFit, second: ModalFit, record_s: float) -> dict:
    """Per body mode fitted in all three: the whole record's frequency corrected as the
    estimator does, and the halves' extrapolated to zero squared amplitude."""
    out = {}
    shift = amplitude_factor(whole, record_s)
    for j, i in enumerate(whole.mode_index):
        if i not in first.mode_index or i not in second.mode_index:
            continue
        a, b = list(first.mode_index).index(i), list(second.mode_index).index(i)
        a2a = amplitude_factor(first, record_s / 2)[a]
        a2b = amplitude_factor(second, record_s / 2)[b]
        if not a2a > a2b:
            continue
        fa, fb = first.frequencies_hz[a], second.frequencies_hz[b]
        out[int(i)] = (
            whole.frequencies_hz[j] / (1 - shift[j]),
            fb - (fa - fb) * a2b / (a2a - a2b),
        )
    return out


def campaigns(n: int) -> None:
    """The first ``n`` campaigns of study_inertia's CubeSat row, both ways."""
    import tempfile

    sys.path.insert(0, str(ROOT / "benchmarks"))
    import study_inertia as si

    from cadcog.core.errors import CadcogError
    from cadcog.dynamics.swingfile import read_swings

    truth, camps = si.campaigns(si.ROWS["cubesat_ih_flex"])
    errors: dict[str, list[float]] = {"corrected": [], "two halves": []}
    for camp in camps[:n]:
        folder = Path(tempfile.mkdtemp())
        sf.write_campaign(camp, folder / "s.csv", folder / "r.csv")
        for sw, rec in zip(read_swings(folder / "s.csv"), camp, strict=True):
            linear = _linear_hz(truth, rec.wire_exit_mm, rec.true_wire_length_mm)
            half = len(sw.t_s) // 2
            try:
                fits = [
                    fit_swing(Swing(sw.point_id, sw.t_s[c], sw.inc_deg[c]), linear, drift=False)
                    for c in (slice(None), slice(None, half), slice(half, None))
                ]
            except CadcogError:
                continue  # a half with no mode to see
            for i, (fc, f0) in _to_zero(*fits, sw.duration_s).items():
                if i >= len(linear) - 2:
                    errors["corrected"].append(100 * (fc / linear[i] - 1))
                    errors["two halves"].append(100 * (f0 / linear[i] - 1))
    print("| way | modes | mean error | median abs. error | rms error |")
    print("|---|---|---|---|---|")
    for name, e in errors.items():
        v = np.array(e)
        print(
            f"| {name} | {len(v)} | {v.mean():+.3f} % | {np.median(np.abs(v)):.3f} % | "
            f"{np.sqrt(np.mean(v**2)):.3f} % |"
        )


def stated(seeds: int) -> None:
    """Each body mode's error over the σ the tensor fit states for it (module docstring)."""
    from cadcog.core.errors import CadcogError
    from cadcog.dynamics.tensorfit import swing_data

    sys.path.insert(0, str(ROOT / "benchmarks"))
    import study_inertia_rows as si
    from study_inertia import rate

    t = _record_times()
    objects = (
        ("3U CubeSat", si.SETUP, "setup", si.CUBESAT_INERTIA_PLAN6),
        ("paper rig", si.RIG, "rig", si.RIG6),
    )
    print(
        "| object | release up to | body modes | refused | median \\|error\\| | "
        "median \\|error\\|/σ | beyond 3 σ [CP 95 %] | beyond 5 σ |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for label, path, kind, points in objects:
        truth = _truth(path, kind)
        model_rel = _context(path, kind).frequency_model_rel  # what the estimator states
        for amp in (3.0, 5.0, 10.0):
            cfg = sf.SwingConfig(amplitude_deg=amp, yaw_rate_deg_s=0.0)
            err, z, refused = [], [], 0
            for pid in points:
                hinge = truth.exit_of(pid)
                body = truth.hung_from(hinge)
                linear = _linear_hz(truth, hinge, LENGTH_MM)
                rngs = [np.random.default_rng([31, seed, int(amp)]) for seed in range(seeds)]
                releases = [sf._release(body, LENGTH_MM, cfg, rng) for rng in rngs]
                tx, ty = truth.released(hinge, releases, LENGTH_MM, 30.0, t)  # one batch
                for k, rng in enumerate(rngs):
                    y = np.column_stack([tx[k], ty[k]]) + rng.normal(0.0, 0.005, (len(t), 2))
                    try:
                        fit = fit_swing(Swing(pid, t.copy(), y), linear)
                    except CadcogError:
                        refused += 1
                        continue
                    data = swing_data([fit], [RECORD_S], model_rel)
                    sigma = np.sqrt(np.diag(data.cov_hz2))
                    for f, s_hz, i in zip(data.frequencies_hz, sigma, fit.mode_index, strict=True):
                        if i >= len(linear) - 2:
                            err.append(f / linear[i] - 1)
                            z.append((f - linear[i]) / s_hz)
            e, zz = np.abs(np.array(err)), np.abs(np.array(z))
            k3, n = int(np.sum(zz > 3)), len(zz)
            print(
                f"| {label} | {amp:g}° | {n} | {refused} | {100 * np.median(e):.3f} % | "
                f"{np.median(zz):.2f} | {rate(k3, n)} | {int(np.sum(zz > 5))} |"
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--backbone", action="store_true", help="the two-half extrapolation")
    ap.add_argument("--campaigns", type=int, help="the same on N noisy CubeSat campaigns")
    ap.add_argument("--stated", type=int, help="each mode over its stated σ, N seeds a size")
    args = ap.parse_args()
    if args.stated:
        stated(args.stated)
        return
    if args.campaigns:
        campaigns(args.campaigns)
        return
    if args.backbone:
        backbone()
        return
    t = _record_times()
    print(
        "| object, hang | release | mode | linear Hz | reading amplitude | shift | "
        "estimator's correction (−A²/16) | shift / correction |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for label, path, kind, points in HANGS:
        truth = _truth(path, kind)
        for pid in points:
            hinge = truth.exit_of(pid)
            linear = _linear_hz(truth, hinge, LENGTH_MM)
            rel = releases()
            tx, ty = truth.released(hinge, list(rel.values()), LENGTH_MM, 1e9, t)
            for k, name in enumerate(rel):
                swing = Swing(pid, t, np.column_stack([tx[k], ty[k]]))
                fit = fit_swing(swing, linear, drift=False)  # the record's mean frequency
                modes = zip(fit.frequencies_hz, fit.mode_index, fit.amplitudes_deg, strict=True)
                for f, i, a in modes:
                    if i < len(linear) - 2:
                        continue  # the wire's own pendulum: not used
                    shift = f / linear[i] - 1
                    corr = -(np.radians(a) ** 2) / 16
                    ratio = f"{shift / corr:.1f}" if abs(corr) > 1e-5 else "-"
                    print(
                        f"| {label}, {pid} | {name} | {i} | {linear[i]:.4f} | {a:.2f}° | "
                        f"{shift * 100:+.3f} % | {corr * 100:+.3f} % | {ratio} |"
                    )


if __name__ == "__main__":
    main()
