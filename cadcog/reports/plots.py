"""Figures (matplotlib, imported only when a figure is asked for)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.rig.parameters import Rig
from cadcog.uncertainty.fits import NormFits
from cadcog.uncertainty.montecarlo import NormHistogram
from cadcog.validation.verification import Validation

#: √(χ²₃ quantile at 0.95): the 95 % ellipsoid of a 3-D normal is this many σ
#: (``scipy.stats.chi2.ppf(0.95, 3)`` = 7.814727903251178; tests/reports/test_plots.py checks it).
K95_3D = 2.7954834829151074


def rayleigh_pdf(r: np.ndarray, sigma: float) -> np.ndarray:
    """Rayleigh density ``r/σ² · exp(−r²/2σ²)`` (1/mm), r in mm, shape of ``r``."""
    return np.asarray(r / sigma**2 * np.exp(-(r**2) / (2 * sigma**2)))


def maxwell_pdf(r: np.ndarray, a: float) -> np.ndarray:
    """Maxwell density ``√(2/π) r²/a³ · exp(−r²/2a²)`` (1/mm), r in mm, shape of ``r``."""
    return np.asarray(np.sqrt(2 / np.pi) * r**2 / a**3 * np.exp(-(r**2) / (2 * a**2)))


def error_histogram(hist: NormHistogram, fits: NormFits, path: Path, title: str) -> None:
    """Histogram of |e| with the two fitted PDFs closest to it (KS) and the 95 % quantile."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=120)
    # Near-collinear pairs give a long tail: show the body, say how much lies beyond.
    top = min(hist.quantile(0.999), 3.0 * fits.q95_mm)
    beyond = 1.0 - hist.fraction_below(top)
    display = np.linspace(0.0, top, 121)
    edges, cdf = hist.cdf_at_edges()
    mass = np.diff(np.interp(display, edges, cdf))
    ax.stairs(
        mass / np.diff(display),
        display,
        fill=True,
        color="#9ab",
        label=f"simulated ({beyond:.2%} beyond {top:.1f} mm)",
    )
    r = np.linspace(0, top, 400)
    candidates = [
        (fits.ks_rayleigh, "C1", "Rayleigh, ML", "σ", rayleigh_pdf(r, fits.rayleigh_sigma_mm),
         fits.rayleigh_sigma_mm),
        (fits.ks_maxwell, "C2", "Maxwell, ML", "a", maxwell_pdf(r, fits.maxwell_a_mm),
         fits.maxwell_a_mm),
        (fits.ks_rayleigh_median, "C1--", "Rayleigh, median fit", "σ",
         rayleigh_pdf(r, fits.rayleigh_sigma_median_mm), fits.rayleigh_sigma_median_mm),
        (fits.ks_maxwell_median, "C2--", "Maxwell, median fit", "a",
         maxwell_pdf(r, fits.maxwell_a_median_mm), fits.maxwell_a_median_mm),
    ]  # fmt: skip
    # the two fits closest to the data (smallest KS distance); all four are in simulation.json
    for ks, style, name, symbol, pdf, value in sorted(candidates, key=lambda c: c[0])[:2]:
        ax.plot(r, pdf, style, label=f"{name} {symbol}={value:.3f} mm (KS {ks:.3f})")
    ax.axvline(fits.q95_mm, color="k", ls="--", lw=1, label=f"95 %: {fits.q95_mm:.2f} mm")
    ax.set_xlabel("CoG error norm |e| (mm)")
    ax.set_ylabel("density (1/mm)")
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.12, top=0.92)  # no tight_layout: one draw
    fig.savefig(path)
    plt.close(fig)


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _box_edges(lo: np.ndarray, hi: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    corners = np.array(
        [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )
    edges = []
    for i in range(8):
        for j in range(i + 1, 8):
            if np.count_nonzero(corners[i] != corners[j]) == 1:
                edges.append((corners[i], corners[j]))
    return edges


def _box_path(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The 12 edges of the box ``[lo, hi]`` (mm) as one polyline, edges separated by NaN:
    shape (3, 36), rows x, y, z."""
    nan = np.full(3, np.nan)
    return np.array([p for a, b in _box_edges(lo, hi) for p in (a, b, nan)]).T


def rig_view(rig: Rig, cog_mm: np.ndarray, path: Path) -> None:
    """3-D view of the proof mass, the ME boxes, the suspension points and their plumb lines."""
    plt = _pyplot()
    fig = plt.figure(figsize=(7.5, 5.2), dpi=120)
    ax = fig.add_subplot(projection="3d")
    size = np.asarray(rig.proof_mass.size_mm)
    # one line per box (its 12 edges, NaN-separated), not one per edge: 5 artists, not 60
    ax.plot(*_box_path(np.zeros(3), size), color="#555", lw=1.2)
    for k, v in enumerate(rig.me_volumes):
        ax.plot(*_box_path(v.min_mm, v.max_mm), color=f"C{k + 2}", lw=0.9)
        ax.text(*v.max_mm, v.name, fontsize=6, color=f"C{k + 2}")
    for p in rig.suspension_points:
        w = rig.wire_exit_mm(p)
        u = (w - cog_mm) / np.linalg.norm(w - cog_mm)
        far = w - 1.6 * np.linalg.norm(w - cog_mm) * u
        ax.plot(*zip(w + 25 * u, far, strict=True), color="C0", lw=0.8, alpha=0.8)
        ax.scatter(*w, color="C3", s=14)
        ax.text(*(w + 6 * p.normal), p.id, fontsize=8, color="C3")
    ax.scatter(*cog_mm, color="k", s=40, marker="*", label="assembly CoG")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    ax.set_box_aspect((size[0], size[1], size[2] + 60))
    ax.view_init(elev=22, azim=-58)
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title("plumb lines from the suspension points meet at the CoG", fontsize=10)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.94)
    fig.savefig(path)
    plt.close(fig)


def validation_plot(simulated_mm: np.ndarray, validation: Validation, path: Path) -> None:
    """Simulated CDF, measured empirical CDF, and p̂ with its interval at each window."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
    sim = np.sort(simulated_mm)
    top = max(3.0 * float(np.quantile(sim, 0.95)), float(validation.measured_norms_mm.max()) * 1.1)
    ax.plot(sim, np.arange(1, sim.size + 1) / sim.size, color="C0", label="simulated F(ε)")
    m = np.sort(validation.measured_norms_mm)
    ax.step(
        m,
        np.arange(1, m.size + 1) / m.size,
        where="post",
        color="C1",
        label=f"measured ({m.size} pairs)",
    )
    labelled = set()
    for w in validation.windows:
        label = (
            "p̂ = k/n, 95 % interval holds F(ε)"
            if w.consistent
            else "p̂ = k/n, 95 % interval misses F(ε)"
        )
        ax.errorbar(
            w.eps_mm,
            w.p_hat,
            yerr=[[w.p_hat - w.ci_low], [w.ci_high - w.p_hat]],
            fmt="o",
            color="C3" if not w.consistent else "C2",
            capsize=4,
            label=None if label in labelled else label,
        )
        labelled.add(label)
    ax.set_xlim(0, top)
    ax.set_xlabel("error window ε (mm)")
    ax.set_ylabel("P(|e| < ε)")
    ax.set_title("p̂ = k/n with 95 % Clopper-Pearson intervals against F(ε)", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.13, top=0.92)
    fig.savefig(path)
    plt.close(fig)


def ellipse_plot(
    cog_mm: np.ndarray, cov_mm2: np.ndarray, truth_mm: np.ndarray | None, path: Path
) -> None:
    """The estimate with its 1-σ and 95 % uncertainty ellipses in the three body planes."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.4), dpi=120)
    k95 = K95_3D  # 95 % of a 3-D normal: the ellipsoid
    names = "xyz"
    t = np.linspace(0, 2 * np.pi, 200)
    for ax, (i, j) in zip(axes, [(0, 1), (0, 2), (1, 2)], strict=True):
        sub = cov_mm2[np.ix_([i, j], [i, j])]
        vals, vecs = np.linalg.eigh(sub)
        circle = np.stack([np.cos(t), np.sin(t)])
        for scale, style, label in ((1.0, "-", "1 σ"), (k95, "--", "95 % ellipsoid")):
            pts = vecs @ (np.sqrt(np.maximum(vals, 0))[:, None] * circle) * scale
            ax.plot(cog_mm[i] + pts[0], cog_mm[j] + pts[1], "C0" + style, label=label)
        ax.plot(cog_mm[i], cog_mm[j], "C0+", ms=10, label="estimate")
        if truth_mm is not None:
            ax.plot(truth_mm[i], truth_mm[j], "k*", ms=9, label="CAD truth")
        ax.set_xlabel(f"{names[i]} (mm)")
        ax.set_ylabel(f"{names[j]} (mm)")
        ax.set_aspect("equal", adjustable="datalim")
    axes[0].legend(fontsize=7)
    fig.suptitle("compensated CoG and its uncertainty (projections of the ellipsoid)", fontsize=10)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.17, top=0.86, wspace=0.38)
    fig.savefig(path)
    plt.close(fig)


#: (marker, size) of each estimate on :func:`cog_ellipses`, in order.
ESTIMATE_MARKERS = (("+", 11), ("o", 9), ("s", 13), ("D", 7))


def cog_ellipses(
    estimates: Sequence[tuple[str, np.ndarray, np.ndarray]], path: Path, title: str = ""
) -> None:
    """Several CoG estimates, each with its 95 % ellipsoid, in the three body planes.

    ``estimates`` holds ``(label, cog_mm (3,), cov_mm2 (3, 3))``: e.g. the CAD, the
    measurement and the updated budget on one figure.
    """
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.6), dpi=120)
    k95 = K95_3D
    t = np.linspace(0, 2 * np.pi, 200)
    circle = np.stack([np.cos(t), np.sin(t)])
    for ax, (i, j) in zip(axes, [(0, 1), (0, 2), (1, 2)], strict=True):
        for n, (label, cog, cov) in enumerate(estimates):
            vals, vecs = np.linalg.eigh(cov[np.ix_([i, j], [i, j])])
            pts = vecs @ (np.sqrt(np.maximum(vals, 0))[:, None] * circle) * k95
            colour = f"C{n}"
            ax.plot(cog[i] + pts[0], cog[j] + pts[1], color=colour, lw=1.2)
            # a shape of its own each, hollow: coincident points (a simulated truth that is
            # the CAD) stay visible one over the other
            marker, size = ESTIMATE_MARKERS[n % len(ESTIMATE_MARKERS)]
            ax.plot(cog[i], cog[j], marker, color=colour, mfc="none", ms=size, mew=1.5, label=label)
        ax.set_xlabel(f"{'xyz'[i]} (mm)")
        ax.set_ylabel(f"{'xyz'[j]} (mm)")
        ax.margins(0.12)  # each panel scaled to its ellipses: none squashed to a line
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(estimates), fontsize=8)
    fig.suptitle(
        title or "CoG estimates with their 95 % ellipsoids (projections; axes not to scale)",
        fontsize=10,
    )
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.25, top=0.88, wspace=0.35)
    fig.savefig(path)
    plt.close(fig)


#: Longest side over shortest side of a model view drawn to scale; flatter views are stretched.
VIEW_MAX_ASPECT = 4.0

#: Most parts named in one view.
VIEW_LABELS = 6


def model_views(
    meshes: Sequence[tuple[np.ndarray, np.ndarray, str]],
    cog_mm: np.ndarray,
    principal_axes: np.ndarray,
    path: Path,
    *,
    envelope_corners_mm: np.ndarray | None = None,
    title: str = "",
    labels: Sequence[tuple[str, np.ndarray]] = (),
) -> None:
    """Three orthographic views of a model with its CoG, principal axes and CoG envelope.

    A view whose sides differ by more than :data:`VIEW_MAX_ASPECT` (a flat board seen edge-on)
    is stretched across to that ratio, and its title says by how much: a board is not a line.

    Parameters
    ----------
    meshes : sequence of (vertices (n, 3) mm, triangles (m, 3), kind)
        ``kind`` "solid" or "surface" (surfaces drawn in another colour).
    cog_mm : ndarray, shape (3,)
    principal_axes : ndarray, shape (3, 3)
        Rows: unit principal axes (drawn from the CoG, ascending moment: C0, C1, C2).
    envelope_corners_mm : ndarray, shape (8, 3), optional
        Corners of the CoG envelope box, drawn as its projected outline.
    labels : sequence of (name, point (3,) mm)
        Parts to name at their CoG, heaviest first: each view names up to :data:`VIEW_LABELS`
        of them, skipping one that would crowd a label already placed.
    """
    from matplotlib.collections import PolyCollection

    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.4), dpi=120)
    everything = np.vstack([v for v, _, _ in meshes if len(v)] or [cog_mm[None, :]])
    extent = float(np.max(np.ptp(everything, axis=0))) or 1.0
    names = "xyz"
    for ax, (i, j) in zip(axes, [(0, 1), (0, 2), (1, 2)], strict=True):
        for v, t, kind in meshes:
            if not len(t):
                continue
            polys = v[:, [i, j]][t]
            color = "#6b7fa3" if kind == "solid" else "#d08c3a"
            ax.add_collection(
                PolyCollection(polys, facecolors=color, edgecolors="none", alpha=0.12)
            )
        if envelope_corners_mm is not None:
            from scipy.spatial import ConvexHull

            pts = envelope_corners_mm[:, [i, j]]
            hull = pts[ConvexHull(pts).vertices]
            ax.fill(hull[:, 0], hull[:, 1], fill=False, ec="C2", ls="--", lw=1.2)
        spans = np.ptp(everything, axis=0)
        length = 0.35 * float(min(spans[i], spans[j]) or extent)  # stays inside this view
        for k in range(3):
            end = cog_mm + length * principal_axes[k]
            ax.plot([cog_mm[i], end[i]], [cog_mm[j], end[j]], color=f"C{k}", lw=1.5)
        ax.plot(cog_mm[i], cog_mm[j], "r+", ms=14, mew=2)
        ax.set_xlabel(f"{names[i]} (mm)")
        ax.set_ylabel(f"{names[j]} (mm)")
        lo, hi = everything.min(axis=0), everything.max(axis=0)
        pad = 0.05 * extent
        ax.set_xlim(lo[i] - pad, hi[i] + pad)
        ax.set_ylim(lo[j] - pad, hi[j] + pad)
        placed: list[tuple[float, float]] = []
        for text, point in labels:  # heaviest first; skip one that would crowd a placed one
            x, y = float(point[i]), float(point[j])
            if len(placed) >= VIEW_LABELS or any(
                abs(x - px) < 0.5 * extent and abs(y - py) < 0.06 * extent for px, py in placed
            ):
                continue
            placed.append((x, y))
            ax.annotate(text, (x, y), fontsize=6, color="#333", ha="center", va="bottom")
        wide, tall = (hi[i] - lo[i]) + 2 * pad, (hi[j] - lo[j]) + 2 * pad
        stretch = max(wide, tall) / max(min(wide, tall), 1e-9) / VIEW_MAX_ASPECT
        if stretch > 1.0:
            ax.set_aspect(1.0 / stretch if wide < tall else stretch, adjustable="box")
            across = names[i] if wide < tall else names[j]
            ax.set_title(f"{names[i]}-{names[j]} view ({across} ×{stretch:.2g})", fontsize=9)
        else:
            ax.set_aspect("equal", adjustable="box")
            ax.set_title(f"{names[i]}-{names[j]} view", fontsize=9)
    handles = [
        plt.Line2D([], [], color="r", marker="+", ls="", ms=10, label="CoG"),
        *[plt.Line2D([], [], color=f"C{k}", label=f"principal axis {k + 1}") for k in range(3)],
    ]
    if envelope_corners_mm is not None:
        handles.append(plt.Line2D([], [], color="C2", ls="--", label="CoG envelope"))
    # A fixed legend place and layout: loc="best" and tight_layout both cost a draw over every
    # triangle of the model (seconds on a large one).
    fig.legend(handles=handles, fontsize=8, loc="lower center", ncol=len(handles))
    fig.suptitle(title, fontsize=10)
    fig.subplots_adjust(left=0.06, right=0.98, bottom=0.18, top=0.88, wspace=0.3)
    fig.savefig(path)
    plt.close(fig)
