"""Finite differences of a CoG fit with respect to each assumed suspension point: what
``point_gain`` (``∂(G, λ)/∂pᵢ``) is checked against."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def numeric_point_gain(
    fit: Callable[[np.ndarray], tuple[np.ndarray, float]], points_mm: np.ndarray, h_mm: float
) -> np.ndarray:
    """Central differences, shape (4, k, 3), of ``fit(points) -> (cog_mm, λ_mm)`` with each
    coordinate of each of ``points_mm`` (k, 3) moved by ±``h_mm``."""
    out = np.zeros((4, *points_mm.shape))
    for i in range(len(points_mm)):
        for a in range(3):
            hi, lo = points_mm.copy(), points_mm.copy()
            hi[i, a] += h_mm
            lo[i, a] -= h_mm
            (g_hi, l_hi), (g_lo, l_lo) = fit(hi), fit(lo)
            out[:3, i, a] = (np.asarray(g_hi) - np.asarray(g_lo)) / (2 * h_mm)
            out[3, i, a] = (l_hi - l_lo) / (2 * h_mm)
    return out
