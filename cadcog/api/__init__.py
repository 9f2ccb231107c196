"""cadcog from Python: the main entry points, each returning the result object the CLI prints.

Every function here is what one command does, without the printing: it reads the same files,
applies the same defaults (``tests/api/`` compares them with the parsers') and returns
the same object, whose ``to_dict()`` is the command's ``--json`` and ``to_json()`` its text.
Errors are the same too: a bad file or value raises :class:`~cadcog.core.errors.CadcogError`
(its subclasses name the file, line or key), which the command prints in one line.

Lengths are mm, masses kg, angles degrees, inertia kg·mm² (the names say so).

Import them from :mod:`cadcog` itself (``cadcog.simulate``): importing cadcog stays fast, and
each function imports what it needs (the CAD layer, build123d, only for CAD work).

Examples
--------
>>> import cadcog
>>> rig = cadcog.load_rig()  # the paper's rig
>>> rig.name
'paper_rig'
>>> report = cadcog.simulate(rig, points=0, trials=200, seed=1)
>>> report.fits.n > 0
True
"""

from __future__ import annotations

from cadcog.api._checks import _one_blas_thread as _one_blas_thread  # the tests use it
from cadcog.api.bench import acquire, acquire_log, setup_init
from cadcog.api.measure import estimate, inertia, update
from cadcog.api.model import load_rig, load_setup, mass_properties
from cadcog.api.planning import balance, check, plan
from cadcog.api.simulation import campaign, simulate, validate

__all__ = [
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
