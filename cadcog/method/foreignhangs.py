"""Hangs of another object: readings whose points are none of the rig's suspension points
(their wire exits). ``estimate --rig`` warns of them; a validation or a rig report, which
compare the readings with the rig's own CAD, refuses them."""

from __future__ import annotations

from collections.abc import Sequence

from cadcog.core.errors import CadcogError
from cadcog.method.readings import Suspension
from cadcog.rig.geometry import same_point
from cadcog.rig.parameters import Rig


def foreign_hangs(rig: Rig, suspensions: Sequence[Suspension]) -> list[str]:
    """The ids of the hangs made from none of the rig's suspension points (their wire exits):
    readings of another object, or of another rig."""
    exits = [rig.wire_exit_mm(p) for p in rig.suspension_points]
    return [s.id for s in suspensions if not any(same_point(s.position_mm, e) for e in exits)]


def refuse_foreign_hangs(rig: Rig, suspensions: Sequence[Suspension], source: object) -> None:
    """Refuse readings with hangs from none of the rig's points, where the result compares them
    with the rig's own CAD (a validation, a rig report).

    Raises
    ------
    CadcogError
        Naming ``source``, the hangs and what to give instead.
    """
    foreign = foreign_hangs(rig, suspensions)
    if foreign:
        shown = ", ".join(foreign[:8]) + (
            f" and {len(foreign) - 8} more" if len(foreign) > 8 else ""
        )
        raise CadcogError(
            f"{source}: hang(s) {shown} are from none of rig {rig.name}'s suspension points: "
            "these readings are another object's (a spacecraft's take cadcog estimate --setup; "
            "another rig's, its --rig)"
        )
