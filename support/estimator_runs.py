"""Running ``cadcog inertia`` on simulated campaigns, and scoring its answer against the truth.

Shared by ``tests/inertia/test_inertia_validation.py`` and ``benchmarks/study_inertia.py``.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path
from typing import Any

import numpy as np

from support import swing_files as sf


def estimator_available() -> bool:
    """True when this cadcog has the ``inertia`` command (issue 20)."""
    import cadcog

    return hasattr(cadcog, "inertia")


def swing_table(cfg: sf.SwingConfig, sensor_mm: np.ndarray) -> str:
    """The ``[swing]`` table of a rig or set-up file for a campaign's configuration."""
    s = ", ".join(f"{v:.4f}" for v in sensor_mm)
    return (
        f"\n[swing]\nwire_length_mm = {cfg.wire_length_mm}\n"
        f"wire_length_sigma_mm = {cfg.wire_length_sigma_mm}\nsensor_position_mm = [{s}]\n"
    )


def parameter_file(
    src: Path, kind: str, cfg: sf.SwingConfig, truth: sf.Truth, directory: Path, extra: str = ""
) -> Path:
    """A copy of a rig (``kind`` "rig") or set-up ("setup") file with the ``[swing]`` table of
    ``cfg`` (any existing one replaced) and the ``[swing]`` lines ``extra``; relative paths in a
    set-up are made absolute."""
    text = re.sub(r"(?ms)^\[swing\].*?(?=^\[|\Z)", "", src.read_text(encoding="utf-8"))
    if kind == "setup":
        text = re.sub(
            r'(?m)^(model|model_step|materials|rig)\s*=\s*"([^"]+)"',
            lambda m: f'{m[1]} = "{(src.parent / m[2]).as_posix()}"',
            text,
        )
    sensor = np.asarray(truth.body.sensor_mm, float)
    # the [swing] table goes before the first table header, so top-level keys stay top-level
    first = re.search(r"(?m)^\[", text)
    pos = first.start() if first else len(text)
    text = text[:pos] + swing_table(cfg, sensor).lstrip("\n") + extra + "\n" + text[pos:]
    out = directory / src.name
    out.write_text(text, encoding="utf-8")
    return out


def run_estimator(
    swings: Path, readings: Path, params: Path, kind: str, extra: tuple[str, ...] = ()
) -> dict[str, Any]:
    """``cadcog inertia SWINGS --readings READINGS (--rig|--setup) PARAMS --json [EXTRA]``,
    in-process, with one BLAS thread as the console command runs (numpy is imported already,
    so its environment variables come too late: two studies side by side on two cores with
    the default pools took 10-27 s a campaign where one thread takes 1.2-2.5 s)."""
    from threadpoolctl import threadpool_limits

    from cadcog.cli._main import main

    option = "--rig" if kind == "rig" else "--setup"
    buf, err = io.StringIO(), io.StringIO()
    argv = ["inertia", str(swings), "--readings", str(readings), option, str(params), "--json"]
    argv += list(extra)
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(err):
        with threadpool_limits(limits=1, user_api="blas"):
            code = main(argv)
    if code in (130, 143):  # Ctrl-C or SIGTERM, cleaned up: stop the study, not this campaign
        raise KeyboardInterrupt(f"cadcog inertia stopped by a signal (exit {code})")
    if code not in (0, None):
        last = (err.getvalue().strip().splitlines() or [""])[-1]
        raise RuntimeError(f"cadcog inertia exited {code}: {last}")
    result: dict[str, Any] = json.loads(buf.getvalue())
    return result


def placeholder(truth: sf.Truth, rng: np.random.Generator) -> dict[str, Any]:
    """Stand-in estimator: the truth with a 1 % normal draw of each entry, reported σ 1 %."""
    j = truth.object_inertia_kg_mm2
    sd = 0.01 * np.trace(j) / 3
    d = rng.normal(0, sd, 6)
    est = j + np.array([[d[0], d[3], d[4]], [d[3], d[1], d[5]], [d[4], d[5], d[2]]])
    w, v = np.linalg.eigh(est)
    return {
        "inertia_kg_mm2": est.tolist(),
        "inertia_cov": (sd**2 * np.eye(6)).tolist(),
        "principal_moments_kg_mm2": w.tolist(),
        "principal_moments_sigma_kg_mm2": [sd] * 3,
        "principal_axes": v.T.tolist(),
    }


def vec6(t: np.ndarray) -> np.ndarray:
    """``[xx, yy, zz, xy, xz, yz]`` of a symmetric 3 × 3 tensor."""
    return np.array([t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]])


def score(result: dict[str, Any], truth: sf.Truth) -> dict[str, Any]:
    """Errors of one estimate against the truth, principal quantities sorted by moment:
    ``rel`` (relative errors of the moments), ``z`` (errors over the reported σ), ``chi2`` (the
    tensor's 6 entries against the reported covariance), ``axis_deg`` (angle between estimated
    and true principal axes, sign-free), ``rel_true_axes`` and ``z_true_axes`` (the estimated
    tensor's moments about the true principal axes: the sorted eigenvalues of a nearly equal
    pair are biased apart by the noise alone), ``sigma_scale`` (the Birge ratio the result applied
    to its σ: ``z·scale`` and ``chi2·scale²`` are what the σ would have given before it),
    ``freq_chi2`` (the frequencies' own χ², the result's ``consistency.chi2``)."""
    from cadcog.dynamics.result import bilinear_gradient

    true_t = truth.object_inertia_kg_mm2
    tw, tv = np.linalg.eigh(true_t)
    est_t = np.asarray(result["inertia_kg_mm2"], float)
    cov = np.asarray(result["inertia_cov"], float)
    d = vec6(est_t - true_t)
    chi2 = float(d @ np.linalg.solve(cov, d))
    w = np.asarray(result["principal_moments_kg_mm2"], float)
    sw = np.asarray(result["principal_moments_sigma_kg_mm2"], float)
    axes = np.asarray(result["principal_axes"], float)
    order = np.argsort(w)
    w, sw, axes = w[order], sw[order], axes[order]
    ang = np.degrees(np.arccos(np.clip(np.abs(np.sum(axes * tv.T, axis=1)), 0, 1)))
    # the estimated tensor about the true principal axes: unbiased when the tensor is, where
    # sorted eigenvalues of a nearly equal pair are pushed apart by the noise itself
    along = np.array([tv[:, i] @ est_t @ tv[:, i] for i in range(3)])
    grads = [bilinear_gradient(tv[:, i], tv[:, i]) for i in range(3)]
    s_along = np.sqrt([g @ cov @ g for g in grads])
    return {
        "rel": ((w - tw) / tw).tolist(),
        "z": ((w - tw) / sw).tolist(),
        "rel_true_axes": ((along - tw) / tw).tolist(),
        "z_true_axes": ((along - tw) / s_along).tolist(),
        "chi2": chi2,
        "axis_deg": ang.tolist(),
        "sigma_scale": float(result.get("consistency", {}).get("sigma_scale", 1.0)),
        "freq_chi2": float(result.get("consistency", {}).get("chi2", np.nan)),
    }
