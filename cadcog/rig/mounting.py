"""Where the measurement equipment is mounted on the object under test.

A set-up file places the ME so that its base sits at ``base_center_mm``; that point must touch
the model, within :data:`cadcog.core.tolerances.ME_BASE_MAX_GAP_MM` of its bounding box (issue
21: a base 10 m from a 340 mm spacecraft was accepted, and every plan made from it was
nonsense).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from cadcog.core import tolerances


def me_base_problem(
    base_center_mm: Sequence[float] | np.ndarray,
    bbox_lo_mm: Sequence[float] | np.ndarray,
    bbox_hi_mm: Sequence[float] | np.ndarray,
) -> str | None:
    """Why the ME base cannot be at ``base_center_mm`` on a model with this bounding box, or
    None when it can (within the gap the tolerance allows).

    Examples
    --------
    >>> me_base_problem([0, 0, 170.25], [-50, -50, -170.25], [50, 50, 170.25]) is None
    True
    >>> me_base_problem([0, 0, 10000], [-50, -50, -170.25], [50, 50, 170.25])[-45:]
    'it is 9829.75 mm away (a length in m or in.?)'
    """
    p = np.asarray(base_center_mm, dtype=float)
    lo = np.asarray(bbox_lo_mm, dtype=float)
    hi = np.asarray(bbox_hi_mm, dtype=float)
    gap_mm = float(np.linalg.norm(np.maximum(0.0, np.maximum(lo - p, p - hi))))
    if gap_mm <= tolerances.ME_BASE_MAX_GAP_MM:
        return None
    box = f"[{', '.join(f'{v:g}' for v in lo)}] … [{', '.join(f'{v:g}' for v in hi)}] mm"
    return (
        f"expected the ME base on the model, within {tolerances.ME_BASE_MAX_GAP_MM:g} mm of its "
        f"bounding box {box}; it is {gap_mm:.2f} mm away (a length in m or in.?)"
    )
