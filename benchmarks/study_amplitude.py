"""How far a body mode's frequency moves with the swing's size, on the nonlinear simulation.

The inertia estimate corrects each fitted frequency for its own swing as a simple pendulum
slows, ``f₀ = f / (1 − A²/16)`` with ``A`` the mode's reading amplitude
(:func:`cadcog.dynamics.tensorfit.amplitude_factor`), and knows nothing of the wire's own
swing, which the tilt sensor does not see. This releases single hangs of the paper rig and of
the 3U CubeSat on a 300 mm wire in the nonlinear simulation (:mod:`support.swing_truth`: no
damping, no noise, 60 s at 50 samples/s), fits them with cadcog's modal fit, and prints each
body mode's shift from the linear model's frequency beside the correction the estimator would
make: (a) the body tilted 2° or 5° about its wire exit with the wire still, (b) the wire swung
1°, 5° or 10° with the body tilted 1°. Quoted in ``docs/inertia_validation.md``.

``--backbone`` asks whether the record itself can tell: the same releases of the CubeSat on a
damped wire (decay time 20 s, 60 s recorded), each body mode fitted over the whole record (and
corrected as the estimator does) and over each half; the two halves' frequencies, extrapolated
in the squared amplitude (each half's own ``⟨A²⟩``) to zero, against the linear frequency.

Run: ``.venv/bin/python benchmarks/study_amplitude.py [--backbone]`` (~30 s).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from cadcog.dynamics.hungbody import HangGeometry, hang_modes  # noqa: E402
from cadcog.dynamics.modalfit import fit_swing  # noqa: E402
from cadcog.dynamics.swingfile import Swing  # noqa: E402
from cadcog.dynamics.tensorfit import amplitude_factor  # noqa: E402
from support import swing_files as sf  # noqa: E402
from support import swing_truth as st  # noqa: E402

HANGS = (
    ("paper rig", ROOT / "parts" / "paper_rig.toml", "rig", ("S1", "S3")),
    ("3U CubeSat", ROOT / "parts" / "cubesat_3u_setup.toml", "setup", ("+y_-30_-150",)),
)
LENGTH_MM = 300.0


def _horizontal(deg: float, azimuth_deg: float) -> np.ndarray:
    a = np.radians(azimuth_deg)
    return np.radians(deg) * np.array([np.cos(a), np.sin(a), 0.0])


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
    fs, duration, tau = 50.0, 60.0, 20.0
    t = np.arange(1, int(duration * fs) + 1) / fs
    truth = sf.setup_truth(HANGS[1][1])
    pid = HANGS[1][3][0]
    hinge = truth.exit_of(pid)
    body = truth.hung_from(hinge)
    geo = HangGeometry(hinge, np.asarray(truth.body.sensor_mm), LENGTH_MM, 0.0)
    linear = hang_modes(
        truth.body.inertia_kg_mm2, truth.body.mass_kg, truth.body.cog_mm, geo
    ).frequencies_hz
    still = np.zeros(3)
    rel = {
        f"wire {w:g}°, body {b:g}° (azimuth {az}°)": st.Release(
            _horizontal(w, 30), _horizontal(b, az), still, still
        )
        for w, b, az in ((0, 5, 0), (0, 5, 90), (10, 1, 0), (8, 3, 45))
    }
    n = len(rel)
    y0 = np.array([st.initial_state(body, LENGTH_MM, r) for r in rel.values()]).T
    batch = st.make_batch([body] * n, [LENGTH_MM] * n, [tau] * n)
    dt = min(4e-3, 0.15 / st.highest_frequency_rad_s(body, LENGTH_MM))
    tx, ty = st.inclinations_deg(st.integrate(batch, y0, np.tile(t, (n, 1)), dt, 10.0).force)
    print("| release | mode | fitted | corrected as the estimator does | two halves, to zero |")
    print("|---|---|---|---|---|")
    half = len(t) // 2
    for k, name in enumerate(rel):
        readings = np.column_stack([tx[k], ty[k]])
        whole = fit_swing(Swing(pid, t, readings), linear)
        first = fit_swing(Swing(pid, t[:half], readings[:half]), linear)
        second = fit_swing(Swing(pid, t[half:], readings[half:]), linear)
        shift = amplitude_factor(whole, duration)
        for j, i in enumerate(whole.mode_index):
            if i < len(linear) - 2:
                continue
            f = whole.frequencies_hz[j]
            a = list(first.mode_index).index(i)
            b = list(second.mode_index).index(i)
            a2a = amplitude_factor(first, duration / 2)[a]
            a2b = amplitude_factor(second, duration / 2)[b]
            fa, fb = first.frequencies_hz[a], second.frequencies_hz[b]
            f0 = fb - (fa - fb) * a2b / (a2a - a2b)
            print(
                f"| {name} | {i} | {(f / linear[i] - 1) * 100:+.3f} % | "
                f"{(f / (1 - shift[j]) / linear[i] - 1) * 100:+.3f} % | "
                f"{(f0 / linear[i] - 1) * 100:+.3f} % |"
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--backbone", action="store_true", help="the two-half extrapolation")
    if ap.parse_args().backbone:
        backbone()
        return
    fs, duration = 50.0, 60.0
    t = np.arange(1, int(duration * fs) + 1) / fs
    print(
        "| object, hang | release | mode | linear Hz | reading amplitude | shift | "
        "estimator's correction (−A²/16) | shift / correction |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for label, path, kind, points in HANGS:
        truth = sf.rig_truth(path) if kind == "rig" else sf.setup_truth(path)
        for pid in points:
            hinge = truth.exit_of(pid)
            body = truth.hung_from(hinge)
            geo = HangGeometry(hinge, np.asarray(truth.body.sensor_mm), LENGTH_MM, 0.0)
            linear = hang_modes(
                truth.body.inertia_kg_mm2, truth.body.mass_kg, truth.body.cog_mm, geo
            ).frequencies_hz
            rel = releases()
            y0 = np.array([st.initial_state(body, LENGTH_MM, r) for r in rel.values()]).T
            n = len(rel)
            batch = st.make_batch([body] * n, [LENGTH_MM] * n, [1e9] * n)
            dt = min(4e-3, 0.15 / st.highest_frequency_rad_s(body, LENGTH_MM))
            traj = st.integrate(batch, y0, np.tile(t, (n, 1)), dt, 10.0)
            tx, ty = st.inclinations_deg(traj.force)
            for k, name in enumerate(rel):
                fit = fit_swing(Swing(pid, t, np.column_stack([tx[k], ty[k]])), linear)
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
