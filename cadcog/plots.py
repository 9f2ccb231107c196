"""Figures (matplotlib, imported only when a figure is asked for)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cadcog.fits import NormFits


def error_histogram(norms_mm: np.ndarray, fits: NormFits, path: Path, title: str) -> None:
    """Histogram of |e| with the fitted Rayleigh and Maxwell PDFs and the 95 % quantile."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from scipy import stats

    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=120)
    # Near-collinear pairs give a long tail: show the body, say how much lies beyond.
    top = min(float(np.quantile(norms_mm, 0.999)), 3.0 * fits.q95_mm)
    beyond = float(np.mean(norms_mm > top))
    ax.hist(
        norms_mm,
        bins=120,
        range=(0, top),
        density=True,
        color="#9ab",
        label=f"simulated ({beyond:.2%} beyond {top:.1f} mm)",
    )
    r = np.linspace(0, top, 400)
    ax.plot(
        r,
        stats.rayleigh.pdf(r, scale=fits.rayleigh_sigma_mm),
        "C1",
        label=f"Rayleigh, ML σ={fits.rayleigh_sigma_mm:.3f} mm (KS {fits.ks_rayleigh:.3f})",
    )
    ax.plot(
        r,
        stats.maxwell.pdf(r, scale=fits.maxwell_a_mm),
        "C2",
        label=f"Maxwell, ML a={fits.maxwell_a_mm:.3f} mm (KS {fits.ks_maxwell:.3f})",
    )
    ax.plot(
        r,
        stats.rayleigh.pdf(r, scale=fits.rayleigh_sigma_median_mm),
        "C1--",
        label=f"Rayleigh, median fit σ={fits.rayleigh_sigma_median_mm:.3f} mm "
        f"(KS {fits.ks_rayleigh_median:.3f})",
    )
    ax.plot(
        r,
        stats.maxwell.pdf(r, scale=fits.maxwell_a_median_mm),
        "C2--",
        label=f"Maxwell, median fit a={fits.maxwell_a_median_mm:.3f} mm "
        f"(KS {fits.ks_maxwell_median:.3f})",
    )
    ax.axvline(fits.q95_mm, color="k", ls="--", lw=1, label=f"95 %: {fits.q95_mm:.2f} mm")
    ax.set_xlabel("CoG error norm |e| (mm)")
    ax.set_ylabel("density (1/mm)")
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
