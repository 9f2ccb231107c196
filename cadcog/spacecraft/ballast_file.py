"""The ballast file (TOML): where ballast may go, how much, in which sizes (``cadcog balance``).

::

    max_total_mass_kg = 0.3            # optional: the most ballast in all
    sizes_kg = [0.002, 0.005, 0.010]   # optional: the pieces you have (any count of each);
                                       # without it any mass is allowed
    [[points]]
    id = "B1"                          # a short label (letters, digits, . _ + -)
    position_mm = [45.0, 0.0, -150.0]  # where the ballast's own CoG sits (model axes)
    max_mass_kg = 0.1                  # optional: what the location takes

Ids are unique, and so are positions (two ids at one point are one location); sizes are
distinct and positive. Every number is checked against its unit's range
(:mod:`cadcog.core.bounds`); an unknown key is an error naming it.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from cadcog.core.paramfile import TableReader, read_toml
from cadcog.spacecraft.ballast_spec import BallastPoint, BallastSpec

#: A location's id: a label to write on the hardware.
_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]{0,39}")

#: Most locations and sizes a file may list (an integer programme has one variable per pair).
MAX_BALLAST_POINTS = 500
MAX_BALLAST_SIZES = 20

#: The lightest piece a ballast file may list (kg): 0.1 g, a small washer.
MIN_PIECE_KG = 1e-4


def load_ballast(path: str | Path) -> BallastSpec:
    """Read a ballast file (module docstring).

    Raises
    ------
    ParameterFileError
        Naming the file and the key: a missing or unknown key, a bad id, a repeated id or
        position, a non-positive or out-of-range mass, repeated sizes.
    """
    p = Path(path)
    root = TableReader(read_toml(p), p)
    total = (
        root.number("max_total_mass_kg", positive=True) if root.has("max_total_mass_kg") else None
    )
    sizes: tuple[float, ...] | None = None
    if root.has("sizes_kg"):
        values = root.vector("sizes_kg", None, positive=True)
        if len(values) > MAX_BALLAST_SIZES:
            raise root.error(
                "sizes_kg", f"{len(values)} sizes; at most {MAX_BALLAST_SIZES} are solved for"
            )
        if len(set(values)) != len(values):
            raise root.error("sizes_kg", f"{list(values)}: a size is listed twice")
        if min(values) < MIN_PIECE_KG:
            raise root.error(
                "sizes_kg",
                f"{min(values):g} kg: a piece lighter than {MIN_PIECE_KG * 1000:g} g is not "
                "ballast (is it in kg?)",
            )
        sizes = tuple(sorted(values))
    tables = root.tables("points")
    if len(tables) > MAX_BALLAST_POINTS:
        raise root.error(
            "points", f"{len(tables)} locations; at most {MAX_BALLAST_POINTS} are solved for"
        )
    points: list[BallastPoint] = []
    for t in tables:
        pid = t.string("id")
        if not _ID.fullmatch(pid):
            raise t.error(
                "id",
                f"{pid!r}: expected a short label (letters, digits, '.', '_', '+', '-'; up to 40, "
                "starting with a letter or digit)",
            )
        if any(q.id == pid for q in points):
            raise t.error("id", f"{pid!r} is listed twice")
        pos = np.array(t.vector("position_mm"))
        twin = next((q for q in points if np.allclose(q.position_mm, pos, atol=1e-6)), None)
        if twin is not None:
            raise t.error("position_mm", f"{pid!r} is at the position of {twin.id!r}")
        cap = t.number("max_mass_kg", positive=True) if t.has("max_mass_kg") else None
        if cap is not None and sizes is not None and cap < sizes[0]:
            raise t.error(
                "max_mass_kg",
                f"{cap:g} kg is less than the smallest size {sizes[0]:g} kg: the location "
                "could take nothing",
            )
        t.finish()
        points.append(BallastPoint(pid, pos, cap))
    if total is not None and sizes is not None and total < sizes[0]:
        raise root.error(
            "max_total_mass_kg",
            f"{total:g} kg is less than the smallest size {sizes[0]:g} kg: no piece could be used",
        )
    root.finish()
    return BallastSpec(tuple(points), sizes, total, str(p))
