"""cadcog: centre-of-gravity determination for small spacecraft, from CAD and from a
double-suspension measurement with a dual-axis inclinometer.

Importing :mod:`cadcog` is cheap: nothing here imports build123d. The CAD layer lives in
:mod:`cadcog.cad` and is imported only by code paths that build or read geometry.
"""

from cadcog.core.version import __version__

__all__ = ["__version__"]
