"""cadcog: centre-of-gravity determination for small spacecraft, from CAD and from a
double-suspension measurement with a dual-axis inclinometer.

The main entry points are here (:mod:`cadcog.api`): :func:`mass_properties` of a STEP file,
:func:`estimate` the CoG from readings, :func:`simulate` the method's error, :func:`validate` a
campaign, :func:`plan` a spacecraft's test, :func:`update` its CAD from the test,
:func:`inertia` its tensor from the swings, :func:`check` requirements, :func:`campaign` a
virtual test written as a lab records it, :func:`acquire` a test run (a simulated device by
default), :func:`acquire_log` one from a phone's recorded log, :func:`setup_init` a set-up
drafted from a STEP
model; :func:`load_rig` and
:func:`load_setup` read parameter files. Each returns the result object the command prints,
with ``to_dict()`` and ``to_json()``.

Importing :mod:`cadcog` is cheap: these names are loaded on first use, and nothing imports
build123d until CAD work is asked for.

Examples
--------
>>> import cadcog
>>> cadcog.load_rig().name
'paper_rig'
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from cadcog.core.version import __version__

if TYPE_CHECKING:
    from cadcog.api import (
        acquire,
        acquire_log,
        balance,
        campaign,
        check,
        estimate,
        inertia,
        load_rig,
        load_setup,
        mass_properties,
        plan,
        setup_init,
        simulate,
        update,
        validate,
    )

__all__ = [
    "__version__",
    "acquire",
    "acquire_log",
    "balance",
    "campaign",
    "check",
    "estimate",
    "inertia",
    "load_rig",
    "load_setup",
    "mass_properties",
    "plan",
    "setup_init",
    "simulate",
    "update",
    "validate",
]
_API = frozenset(__all__) - {"__version__"}


def __getattr__(name: str) -> Any:
    if name in _API:
        from cadcog import api

        return getattr(api, name)
    raise AttributeError(f"module 'cadcog' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
