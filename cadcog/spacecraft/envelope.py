"""The CubeSat CoG envelope: how far the CoG may sit from the geometric centre.

PocketQubes (``1p``, ``2p``, ``3p``): the CoG within 1 cm of the geometric centre on every axis
(PocketQube Standard Issue 1, 2018, PQ-Mass-04, as a secondary source quotes it; provisional
until checked against the standard's text).

CubeSat Design Specification Rev. 14.1 (Cal Poly, 2022), §3.2: the CoG within 2 cm of the
geometric centre in X and Y for 1U-3U, and in Z (along the rails) within 2 / 3 / 4.5 / 7 cm for
1U / 1.5U / 2U / 3U. The 6U and 12U rows (X 4.5 cm, Y 2 / 4.5 cm, Z 7 cm) have not been
re-checked against the CDS text: treat them as provisional. The dispenser's interface control
document governs: check it, and give your own limits where it differs.

Axes are the CDS's: origin at the geometric centre of the envelope (the centre of the model's
bounding box), Z along the rails. A model built with other axes is checked in a
:class:`cadcog.mass.inertia.Frame` that maps them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.results import JsonResult

FloatArray = npt.NDArray[np.float64]

#: CoG limits around the geometric centre (mm, x y z; z along the rails), per form factor.
CDS_COG_LIMITS_MM: dict[str, tuple[float, float, float]] = {
    "1U": (20.0, 20.0, 20.0),
    "1.5U": (20.0, 20.0, 30.0),
    "2U": (20.0, 20.0, 45.0),
    "3U": (20.0, 20.0, 70.0),
    "6U": (45.0, 20.0, 70.0),
    "12U": (45.0, 45.0, 70.0),
    # PocketQubes (50 mm units): the CoG within 10 mm of the geometric centre on every axis
    "1p": (10.0, 10.0, 10.0),
    "2p": (10.0, 10.0, 10.0),
    "3p": (10.0, 10.0, 10.0),
}

#: The PocketQube form factors among :data:`CDS_COG_LIMITS_MM`.
POCKETQUBE_FORM_FACTORS = ("1p", "2p", "3p")

CDS_SOURCE = (
    "CubeSat Design Specification Rev. 14.1 (Cal Poly), CoG location; 6U/12U provisional; "
    "the dispenser ICD governs"
)

POCKETQUBE_SOURCE = (
    "PocketQube Standard Issue 1 (Alba Orbital, TU Delft, GAUSS, 2018), PQ-Mass-04: CoG within "
    "10 mm of the geometric centre; PROVISIONAL: taken from a secondary source, not checked "
    "against the standard's text; the deployer's ICD governs"
)


def source_for(form_factor: str | None) -> str:
    """Where a form factor's limits come from (a PocketQube's are provisional).

    Examples
    --------
    >>> source_for("2p").split(",")[0], source_for("3U").split(" Rev.")[0]
    ('PocketQube Standard Issue 1 (Alba Orbital', 'CubeSat Design Specification')
    """
    return POCKETQUBE_SOURCE if form_factor in POCKETQUBE_FORM_FACTORS else CDS_SOURCE


#: Two-sided 95 % normal quantile, for the per-axis envelope check with uncertainty.
Z95 = 1.959963984540054


@dataclass(frozen=True)
class EnvelopeCheck(JsonResult):
    """A CoG checked against the envelope, nominally and at the 95 % edge of its uncertainty.

    Attributes
    ----------
    offset_mm : ndarray, shape (3,)
        CoG minus the geometric centre, in the envelope's axes.
    limits_mm : ndarray, shape (3,)
    within : bool
        ``|offset| ≤ limits`` on every axis.
    within_at_95 : bool or None
        ``|offset| + 1.96 σ ≤ limits`` on every axis (None without an uncertainty).
    margin_mm : ndarray, shape (3,)
        ``limits − |offset|``.
    """

    form_factor: str | None
    geometric_center_mm: FloatArray
    offset_mm: FloatArray
    limits_mm: FloatArray
    sigma_mm: FloatArray | None
    within: bool
    within_at_95: bool | None
    margin_mm: FloatArray
    source: str

    def to_dict(self) -> dict[str, Any]:
        return {
            "form_factor": self.form_factor,
            "geometric_center_mm": self.geometric_center_mm.tolist(),
            "offset_mm": self.offset_mm.tolist(),
            "limits_mm": self.limits_mm.tolist(),
            "sigma_mm": None if self.sigma_mm is None else self.sigma_mm.tolist(),
            "within": self.within,
            "within_at_95": self.within_at_95,
            "margin_mm": self.margin_mm.tolist(),
            "source": self.source,
        }

    def verdict(self) -> str:
        """'within the envelope', '..., but not with 95 % confidence', or 'OUTSIDE ...'."""
        text = ("within" if self.within else "OUTSIDE") + " the envelope"
        if self.within and self.within_at_95 is False:
            text += ", but not with 95 % confidence"
        return text


def limits_for(form_factor: str) -> FloatArray:
    """The CDS limits of a form factor.

    Raises
    ------
    KeyError
        For an unknown form factor.

    Examples
    --------
    >>> limits_for("3U").tolist()
    [20.0, 20.0, 70.0]
    """
    return np.array(CDS_COG_LIMITS_MM[form_factor])


def check_envelope(
    cog_mm: npt.ArrayLike,
    geometric_center_mm: npt.ArrayLike,
    limits_mm: npt.ArrayLike,
    *,
    cov_mm2: npt.ArrayLike | None = None,
    axes: npt.ArrayLike | None = None,
    form_factor: str | None = None,
    source: str | None = None,
) -> EnvelopeCheck:
    """Check a CoG against an envelope around the geometric centre.

    Parameters
    ----------
    cog_mm, geometric_center_mm : array_like, shape (3,)
        Model coordinates.
    limits_mm : array_like, shape (3,)
        Half-widths in the envelope's axes.
    cov_mm2 : array_like, shape (3, 3), optional
        CoG covariance in model axes.
    axes : array_like, shape (3, 3), optional
        Rows: the envelope's x, y, z axes in model coordinates (default: the model's).
    form_factor : str, optional
    source : str, optional
        Where the limits come from (default: :func:`source_for` the form factor).

    Examples
    --------
    >>> c = check_envelope([0, 0, 60.0], [0, 0, 0], limits_for("3U"), cov_mm2=np.eye(3) * 36)
    >>> c.within, c.within_at_95
    (True, False)
    """
    r = np.eye(3) if axes is None else np.asarray(axes, dtype=float)
    offset = r @ (np.asarray(cog_mm, dtype=float) - np.asarray(geometric_center_mm, dtype=float))
    limits = np.asarray(limits_mm, dtype=float)
    margin = limits - np.abs(offset)
    sigma = None
    at95 = None
    if cov_mm2 is not None:
        sigma = np.sqrt(np.diag(r @ np.asarray(cov_mm2, dtype=float) @ r.T))
        at95 = bool(np.all(margin - Z95 * sigma >= 0))
    return EnvelopeCheck(
        form_factor,
        np.asarray(geometric_center_mm, dtype=float),
        offset,
        limits,
        sigma,
        bool(np.all(margin >= 0)),
        at95,
        margin,
        source_for(form_factor) if source is None else source,
    )
