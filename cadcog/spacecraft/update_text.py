"""``cadcog update``'s numbers as a person reads them: the same cells for its text and its page.

Masses and inertias go through :mod:`cadcog.core.numformat` (significant figures, one unit
that fits a column: g or kg, g·mm² or kg·mm²) and, beside their σ, through
:func:`cadcog.core.plusminus.pm`, as ``massprops``'s outputs do; CoG positions keep fixed
decimals in mm (2 for a CoG, 1 for an item's shift), as ``massprops``'s budget does. The inertia
is named as ``massprops`` names it: moments ``Ixx``..., products ``Pxy = +∫ x·y dm`` (the
convention of its text's default) and the tensor with its own convention (``−∫ x·y dm``).
JSON never comes through here (``UpdateResult.to_dict`` keeps kg, mm and kg·mm²).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from cadcog.core import numformat as nf
from cadcog.core.plusminus import pm, signed
from cadcog.mass.inertia import ProductConvention, products_of_inertia
from cadcog.spacecraft.update import ItemChange, UpdateResult

#: Index pairs of the three products of inertia, by their names' suffix.
PRODUCT_INDEX = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}


def _sd(cov: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(np.diag(cov), 0.0))


def mass_cog_rows(r: UpdateResult) -> list[list[str]]:
    """Rows ``[what, CAD, measured, updated]``: the mass (one unit for the three), then the CoG
    along x, y, z in mm (2 decimals), each ``value ± 1 σ``."""
    masses = (r.cad.mass_kg, r.measured_mass_kg, r.posterior.mass_kg)
    unit = nf.mass_unit(masses)
    rows = [
        [
            f"mass ({unit[0]})",
            pm(r.cad.mass_kg, r.cad_mass_sigma_kg, unit[1]),
            pm(r.measured_mass_kg, r.measured_mass_sigma_kg, unit[1]) + " (weighed)",
            pm(r.posterior.mass_kg, r.posterior_mass_sigma_kg, unit[1]),
        ]
    ]
    sds = [_sd(r.cad_cog_cov_mm2), _sd(r.measured_cog_cov_mm2), _sd(r.posterior_cog_cov_mm2)]
    cogs = [r.cad.cog_mm, r.measured_cog_mm, r.posterior.cog_mm]
    for k, axis in enumerate("xyz"):
        rows.append(
            [f"CoG {axis} (mm)"]
            + [f"{nf.fixed(c[k], 2)} ± {nf.fixed(s[k], 2)}" for c, s in zip(cogs, sds, strict=True)]
        )
    return rows


def _shift(value_mm: float, sigma_mm: float) -> str:
    return f"{signed(nf.fixed(value_mm, 1))} ± {nf.fixed(sigma_mm, 1)}"


def item_table(
    items: Sequence[ItemChange], *, prior: bool = False
) -> tuple[list[str], list[list[str]]]:
    """Headers and rows of the items: key, P (the one off), CAD mass, [prior σ,] relative change
    ± σ, mass change ± σ, CoG shift ± σ (mm). Each mass column has one unit (in its header)."""
    mass_unit = nf.mass_unit(c.cad_mass_kg for c in items)
    change_unit = nf.mass_unit(abs(c.delta_kg) + c.cad_mass_kg * c.delta_sigma_rel for c in items)
    rows = []
    for c in items:
        row = [c.key, f"{c.probability:.1%}", nf.in_unit(c.cad_mass_kg, mass_unit)]
        if prior:
            row.append(nf.share(c.prior_sigma_rel))
        row += [
            signed(pm(100.0 * c.delta_rel, 100.0 * c.delta_sigma_rel)),
            signed(pm(c.delta_kg, c.cad_mass_kg * c.delta_sigma_rel, change_unit[1])),
            "["
            + ", ".join(
                _shift(v, e) for v, e in zip(c.cog_shift_mm, c.cog_shift_sigma_mm, strict=True)
            )
            + "]",
        ]
        rows.append(row)
    headers = ["item", "P(the one off)", f"CAD mass ({mass_unit[0]})"]
    if prior:
        headers.append("prior σ")
    headers += ["change (%)", f"change ({change_unit[0]})", "CoG shift (mm)"]
    return headers, rows


def unmodelled_summary(r: UpdateResult) -> str:
    """``"142.7 ± 27 g at [19.6 ± 11.5, …] mm"``: the unmodelled mass and where it is (1 σ);
    empty without an unmodelled mass."""
    if r.unmodelled_mass_kg is None:
        return ""
    sigma_kg = r.unmodelled_mass_sigma_kg or 0.0
    unit = nf.mass_unit([r.unmodelled_mass_kg + sigma_kg])
    text = f"{pm(r.unmodelled_mass_kg, sigma_kg, unit[1])} {unit[0]}"
    if r.unmodelled_probability < 0.999:
        text = f"if there is one (P = {r.unmodelled_probability:.1%}): " + text
    if r.unmodelled_cog_mm is not None and r.unmodelled_cog_cov_mm2 is not None:
        sd = _sd(r.unmodelled_cog_cov_mm2)
        cells = (
            f"{nf.fixed(c, 1)} ± {nf.fixed(e, 1)}"
            for c, e in zip(r.unmodelled_cog_mm, sd, strict=True)
        )
        text += " at [" + ", ".join(cells) + "] mm"
    else:
        text += " (not resolved from zero: its position is not estimated)"
    if r.unmodelled_negative:
        text += "; the data wanted it negative: held at 0"
    return text


def inertia_unit(r: UpdateResult) -> tuple[str, float]:
    """The one unit of the updated inertia's entries and their σ (g·mm² or kg·mm²)."""
    return nf.inertia_unit(r.posterior.inertia_kg_mm2.ravel())


def moment_cells(r: UpdateResult) -> list[str]:
    """``["Ixx 24388 ± 170", ...]``: the updated moments about the CoG, in :func:`inertia_unit`."""
    j, s = r.posterior.inertia_kg_mm2, r.posterior_inertia_sigma_kg_mm2
    factor = inertia_unit(r)[1]
    return [f"I{a}{a} {pm(j[i, i], s[i, i], factor)}" for i, a in enumerate("xyz")]


def product_cells(r: UpdateResult, convention: ProductConvention = "positive") -> list[str]:
    """The updated products of inertia ± 1 σ in ``convention``, without their names
    (``Pxy`` in the positive convention, ``Ixy`` in the negative one; xy, xz, yz)."""
    products = products_of_inertia(r.posterior.inertia_kg_mm2, convention)
    s = r.posterior_inertia_sigma_kg_mm2
    factor = inertia_unit(r)[1]
    return [pm(products[k], s[i, j], factor) for k, (i, j) in PRODUCT_INDEX.items()]


def tensor_rows(r: UpdateResult) -> list[list[str]]:
    """The updated tensor (its own convention: off-diagonal −∫ x·y dm) ± 1 σ, rows x, y, z."""
    j, s = r.posterior.inertia_kg_mm2, r.posterior_inertia_sigma_kg_mm2
    factor = inertia_unit(r)[1]
    return [["xyz"[i], *[pm(j[i, k], s[i, k], factor) for k in range(3)]] for i in range(3)]
