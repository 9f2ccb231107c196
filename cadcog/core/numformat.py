"""Numbers for people: significant figures and a unit that fits, for text and HTML alike.

Every table and line that a person reads (``massprops``, ``update``, the HTML reports) formats
its masses and inertias here, so that a 30 mg screw does not print as ``0.00003 kg`` and a
board's inertia not as ``0.0000``. JSON never comes through here: it keeps full precision in
kg, mm and kg·mm².

- :func:`sig` writes a number to a number of significant figures, in plain decimals (no
  exponent between 1e-6 and 1e12), never ``-0``;
- :func:`mass_unit` / :func:`inertia_unit` choose one unit for a set of values (a table's
  column shares one unit): g below 1 kg, kg from 1 kg; g·mm² when every inertia is below
  1 kg·mm², else kg·mm²;
- :func:`mass` / :func:`inertia` format one value with its unit;
- :func:`share` writes a fraction as a percentage with enough figures to be non-zero.

Examples
--------
>>> sig(0.000031234), sig(1234.5678), sig(-0.0), sig(12345678.9)
('0.00003123', '1235', '0', '12345679')
>>> mass(0.00003), mass(2.5), mass(0.48213)
('0.03 g', '2.5 kg', '482.1 g')
>>> inertia(0.00004567), inertia(12.3456)
('0.04567 g·mm²', '12.35 kg·mm²')
>>> share(0.4821), share(0.000012), share(0.0)
('48.2 %', '0.0012 %', '0 %')
"""

from __future__ import annotations

import math
from collections.abc import Iterable

#: Significant figures of masses and inertias in text and HTML (JSON keeps every digit).
SIG_FIGS = 4

#: Below this magnitude (or at and above :data:`PLAIN_MAX`) a number is written with an
#: exponent, which is rarer than a long run of zeros.
PLAIN_MIN = 1e-6
PLAIN_MAX = 1e12

#: (unit label, factor from kg) for masses.
GRAM = ("g", 1e3)
KILOGRAM = ("kg", 1.0)
#: (unit label, factor from kg·mm²) for moments and products of inertia.
G_MM2 = ("g·mm²", 1e3)
KG_MM2 = ("kg·mm²", 1.0)
#: (unit label, factor from mm²) for areas.
MM2 = ("mm²", 1.0)
M2 = ("m²", 1e-6)


def sig(value: float, digits: int = SIG_FIGS) -> str:
    """``value`` to ``digits`` significant figures, in plain decimals.

    Integers of more digits keep them all (``12345678.9`` → ``12345679``); trailing zeros after
    the point are dropped; zero and round-off below the precision print ``0``, never ``-0``.

    Parameters
    ----------
    value : float
    digits : int
        Significant figures, at least 1.

    Examples
    --------
    >>> sig(2.0), sig(0.1 + 0.2), sig(-1.23456e-9), sig(float("nan"))
    ('2', '0.3', '-1.235e-09', 'nan')
    """
    v = float(value)
    if not math.isfinite(v):
        return str(v)
    if v == 0.0:
        return "0"
    magnitude = abs(v)
    if magnitude < PLAIN_MIN or magnitude >= PLAIN_MAX:
        return f"{v:.{digits - 1}e}"
    decimals = max(0, digits - 1 - math.floor(math.log10(magnitude)))
    text = f"{round(v, decimals) + 0.0:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def fixed(value: float, decimals: int) -> str:
    """``value`` with a fixed number of decimals, never ``-0.00`` (coordinates in mm).

    Examples
    --------
    >>> fixed(-0.0004, 3), fixed(12.3456, 2)
    ('0.000', '12.35')
    """
    return f"{round(float(value), decimals) + 0.0:.{decimals}f}"


def signed(value: float, decimals: int) -> str:
    """``value`` with its sign and a fixed number of decimals, never ``-0.0`` (a difference,
    a number of σ).

    Examples
    --------
    >>> signed(-0.04, 1), signed(0.04, 1), signed(-2.25, 2), signed(3, 0)
    ('+0.0', '+0.0', '-2.25', '+3')
    """
    return f"{round(float(value), decimals) + 0.0:+.{decimals}f}"


def vector(values: Iterable[float], decimals: int = 3) -> str:
    """``[x, y, z]`` with fixed decimals (coordinates in mm share a resolution).

    Examples
    --------
    >>> vector([1, -0.00001, 2.34567], 2)
    '[1.00, 0.00, 2.35]'
    """
    return "[" + ", ".join(fixed(v, decimals) for v in values) + "]"


def mass_unit(values_kg: Iterable[float]) -> tuple[str, float]:
    """(label, factor from kg) for a set of masses: g when all are below 1 kg, else kg.

    Examples
    --------
    >>> mass_unit([0.2, 0.9]), mass_unit([0.2, 1.5])
    (('g', 1000.0), ('kg', 1.0))
    """
    largest = max((abs(float(v)) for v in values_kg), default=0.0)
    return GRAM if largest < 1.0 else KILOGRAM


def inertia_unit(values_kg_mm2: Iterable[float]) -> tuple[str, float]:
    """(label, factor from kg·mm²): g·mm² when every value is below 1 kg·mm², else kg·mm².

    Examples
    --------
    >>> inertia_unit([0.002, -0.5]), inertia_unit([3.0, 0.001])
    (('g·mm²', 1000.0), ('kg·mm²', 1.0))
    """
    largest = max((abs(float(v)) for v in values_kg_mm2), default=0.0)
    return G_MM2 if largest < 1.0 else KG_MM2


def area_unit(values_mm2: Iterable[float]) -> tuple[str, float]:
    """(label, factor from mm²): mm² when every area is below 0.1 m², else m².

    Examples
    --------
    >>> area_unit([250.0, 9e4]), area_unit([250.0, 3.2e5])
    (('mm²', 1.0), ('m²', 1e-06))
    """
    largest = max((abs(float(v)) for v in values_mm2), default=0.0)
    return MM2 if largest < 1e5 else M2


def in_unit(value: float, unit: tuple[str, float], digits: int = SIG_FIGS) -> str:
    """``value`` (in the base unit) converted by ``unit`` and written to ``digits`` figures."""
    return sig(float(value) * unit[1], digits)


def mass(value_kg: float, digits: int = SIG_FIGS) -> str:
    """A mass with the unit that fits it (g below 1 kg)."""
    unit = mass_unit([value_kg])
    return f"{in_unit(value_kg, unit, digits)} {unit[0]}"


def inertia(value_kg_mm2: float, digits: int = SIG_FIGS) -> str:
    """A moment or product of inertia with the unit that fits it (g·mm² below 1 kg·mm²)."""
    unit = inertia_unit([value_kg_mm2])
    return f"{in_unit(value_kg_mm2, unit, digits)} {unit[0]}"


def share(fraction: float, digits: int = 3) -> str:
    """A fraction as a percentage: one decimal from 1 %, else ``digits`` significant figures.

    Examples
    --------
    >>> share(1.0), share(0.0531), share(0.00531)
    ('100 %', '5.3 %', '0.531 %')
    """
    pct = 100.0 * float(fraction)
    if abs(pct) >= 1.0:
        text = fixed(pct, 1)
        text = text.rstrip("0").rstrip(".") if "." in text else text
    else:
        text = sig(pct, digits)
    return f"{text} %"
