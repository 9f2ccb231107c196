"""A value with its 1-σ uncertainty, for people: ``2.6000 ± 0.0010``, never ``0.0 ± 0.0``.

:mod:`cadcog.core.numformat` writes one number to significant figures; a value beside its σ
needs one more rule, so that rounding never hides what the measurement resolves (a 2.6 kg
spacecraft weighed to 1 g is ``2.6000 ± 0.0010 kg``, not ``2.6 ± 0.001``):

- σ is written to :data:`SIGMA_FIGS` significant figures;
- the value to the decimal of σ's last figure (the GUM's rule, JCGM 100:2008 §7.2.6): as many
  digits as the measurement resolves, no more (``0.0 ± 1.4``: a change the data cannot tell
  from zero is not written as ``0.01274``), no fewer (trailing zeros say so);
- a value's integer digits are never rounded away (``24388 ± 170``), and ``-0`` never shows.

The caller converts units first (``factor``: from the base unit to the one shown, as
:func:`cadcog.core.numformat.mass_unit` gives it). JSON never comes through here.

Examples
--------
>>> pm(2.6, 0.001), pm(2.5825, 0.0989), pm(24387.96, 168.14)
('2.6000 ± 0.0010', '2.583 ± 0.099', '24388 ± 170')
>>> pm(1.274e-5, 1.406e-3, factor=1e3), pm(0.0, 0.0), pm(-4.13, 5.65)
('0.0 ± 1.4', '0 ± 0', '-4.1 ± 5.7')
>>> pm(0.0, 0.0036), pm(1234.0, 12.0)
('0.0000 ± 0.0036', '1234 ± 12')
>>> signed(pm(0.874e-3, 1.406e-3, factor=1e3)), signed("-3"), signed("0")
('+0.9 ± 1.4', '-3', '0')
"""

from __future__ import annotations

import math

from cadcog.core import numformat as nf

#: Significant figures of a σ shown beside its value.
SIGMA_FIGS = 2


def _decimals_for(value: float, figures: int) -> int:
    """Decimals that write ``value`` (finite, non-zero) to ``figures`` significant figures."""
    return max(0, figures - 1 - math.floor(math.log10(abs(value))))


def pm(value: float, sigma: float, factor: float = 1.0) -> str:
    """``value ± sigma``, both multiplied by ``factor`` (the unit shown), without the unit.

    Parameters
    ----------
    value : float
        In the base unit (kg, kg·mm², mm...).
    sigma : float
        Its 1-σ uncertainty, same unit (its sign is ignored).
    factor : float
        From the base unit to the unit shown (1000 for kg → g).

    Examples
    --------
    >>> pm(0.00003, 0.000001, factor=1e3), pm(12.3456, 0.001), pm(float("nan"), 1.0)
    ('0.0300 ± 0.0010', '12.3456 ± 0.0010', 'nan ± 1.0')
    >>> pm(2.6, 0.00099996), pm(-0.0, 0.0), pm(3e-14, 0.0036), pm(3e-14, 1e-14)
    ('2.6000 ± 0.0010', '0 ± 0', '0.0000 ± 0.0036', '3.000e-14 ± 1.0e-14')
    """
    v, s = float(value) * factor, abs(float(sigma) * factor)
    if not (math.isfinite(s) and nf.PLAIN_MIN <= s < nf.PLAIN_MAX):  # 0, or exponents
        return f"{nf.sig(v)} ± {nf.sig(s, SIGMA_FIGS)}"
    s = float(f"{s:.{SIGMA_FIGS - 1}e}")  # rounded first: 0.000999 is 0.0010, not 0.00100
    sigma_decimals = _decimals_for(s, SIGMA_FIGS)
    text = nf.fixed(v, sigma_decimals) if math.isfinite(v) and abs(v) < nf.PLAIN_MAX else nf.sig(v)
    return f"{text} ± {nf.fixed(s, sigma_decimals)}"


def signed(text: str) -> str:
    """``text`` (a number written by :func:`pm` or :mod:`~cadcog.core.numformat`) with ``+``
    before a positive value: changes read as changes. Zero stays unsigned."""
    try:
        positive = float(text.split(" ", 1)[0]) > 0.0
    except ValueError:
        positive = False
    return "+" + text if positive else text


def mass_pm(value_kg: float, sigma_kg: float) -> str:
    """A mass beside its σ in the unit that suits it (g below 1 kg), or alone when exact.

    Examples
    --------
    >>> mass_pm(2.583, 0.001), mass_pm(0.0227561, 0.00108), mass_pm(9.2, 0.0)
    ('2.5830 ± 0.0010 kg', '22.8 ± 1.1 g', '9.2 kg')
    """
    if not sigma_kg > 0:
        return nf.mass(value_kg)
    name, factor = nf.mass_unit([abs(value_kg) + abs(sigma_kg)])
    return f"{pm(value_kg, sigma_kg, factor)} {name}"
