"""Virtual swings from the linear model: what ``cadcog campaign`` writes beside its readings.

Each hang's swing is the superposition of the model's modes (:func:`hang_modes`) from a random
release (each mode's amplitude uniform in ``amplitude_deg``, random phase), every mode decaying
as ``exp(−t/decay_time_s)`` (mass-proportional damping: a wire's swing dies in 5-30 s at the
bench, docs/bench.md), seen with the hang's settled readings as offset, white noise per sample
and sample-time jitter. This is the estimator's own model, for rehearsal and tests of the plumbing;
the estimator is validated against an independent nonlinear simulation
(``tests/inertia/``, ``docs/inertia_validation.md``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.dynamics.context import InertiaContext
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.dynamics.swingfile import Swing
from cadcog.mass.properties import combine
from cadcog.method.readings import Suspension

FloatArray = npt.NDArray[np.float64]


def virtual_swing(
    point_id: str,
    settled_deg: npt.ArrayLike,
    inertia_cog_kg_mm2: npt.ArrayLike,
    mass_kg: float,
    cog_mm: npt.ArrayLike,
    geometry: HangGeometry,
    rng: np.random.Generator,
    *,
    duration_s: float = 60.0,
    rate_hz: float = 50.0,
    amplitude_deg: tuple[float, float] = (0.5, 3.0),
    decay_time_s: float = 20.0,
    noise_deg: float = 0.01,
    jitter_s: float = 0.001,
    start_s: float = 0.0,
) -> Swing:
    """One hang's swing from release (see the module docstring).

    Parameters
    ----------
    settled_deg : array_like, shape (2,)
        The readings the swing settles to (device signs applied).
    rng : numpy.random.Generator
    decay_time_s : float
        Every mode's amplitude falls by e in this time (its damping ratio is
        ``1/(2π f decay_time_s)``; 20 s: a 2.4 Hz mode at ζ = 0.0033, long enough for each half
        of a minute's record to show it, as the modal fit's halves check wants).
    """
    modes = hang_modes(inertia_cog_kg_mm2, mass_kg, cog_mm, geometry)
    n = round(duration_s * rate_hz) + 1
    t = start_s + np.arange(n) / rate_hz + rng.uniform(-jitter_s, jitter_s, n)
    t.sort()
    tau = t - t[0]
    y = np.tile(np.asarray(settled_deg, dtype=float), (n, 1))
    lo, hi = amplitude_deg
    for f, shape in zip(modes.frequencies_hz, modes.reading_shapes_deg, strict=True):
        w = 2.0 * np.pi * f
        zeta = 1.0 / (w * decay_time_s)
        amp = rng.uniform(lo, hi) / max(float(np.max(np.abs(shape))), 1e-12)  # rad
        phase = rng.uniform(0.0, 2.0 * np.pi)
        wave = np.exp(-tau / decay_time_s) * np.cos(w * np.sqrt(1 - zeta**2) * tau + phase)
        y += amp * np.outer(wave, shape)
    y += rng.normal(0.0, noise_deg, y.shape)
    return Swing(point_id, t, y)


def virtual_swings(
    context: InertiaContext,
    suspensions: Sequence[Suspension],
    seed: int | np.random.Generator,
    *,
    pivots_mm: npt.ArrayLike | None = None,
    me_cog_error_mm: npt.ArrayLike | None = None,
    top_hinge_mm: float | None = None,
    **options: Any,
) -> list[Swing]:
    """A swing for each of a virtual campaign's hangs, the CAD as the truth.

    Each hang swings about its expected pivot (the wire exit moved by the wire's expected
    offset) and settles to its hang's mean readings; the hangs follow one another on the
    device's clock (a minute of swing, then half a minute to re-hang). Given what the
    campaign's readings were drawn with (:class:`cadcog.validation.campaign.CampaignTruth`:
    each hang's true pivot (k, 3), the ME's CoG error (3,), the wire's ``λ`` as the top
    clamp's hinge), the hangs swing about those instead, with the ME moved by its error: the
    swings and the readings then tell of one campaign. ``options`` go to
    :func:`virtual_swing`.
    """
    rng = np.random.default_rng(seed)
    me = tuple(context.me_parts)
    if me_cog_error_mm is not None:
        shift = np.asarray(me_cog_error_mm, dtype=float)
        me = tuple(replace(part, cog_mm=part.cog_mm + shift) for part in me)
    truth = combine([context.object_cad, *me])
    weight_n = truth.mass_kg * STANDARD_GRAVITY_M_S2
    top = context.top_hinge_mm(weight_n)[0] if top_hinge_mm is None else top_hinge_mm
    if pivots_mm is None:
        positions = np.array([s.position_mm for s in suspensions], dtype=float)
        pivots, _ = context.pivots(positions, truth.cog_mm, weight_n)
    else:
        pivots = np.asarray(pivots_mm, dtype=float)
    out = []
    start = 0.0
    for s, pivot in zip(suspensions, pivots, strict=True):
        geo = HangGeometry(
            pivot, context.sensor_mm, context.swing.wire_length_mm, top, *context.signs
        )
        sw = virtual_swing(
            s.id,
            [s.inc_x_deg, s.inc_y_deg],
            truth.inertia_kg_mm2,
            truth.mass_kg,
            truth.cog_mm,
            geo,
            rng,
            start_s=start,
            **options,
        )
        out.append(sw)
        start = float(sw.t_s[-1]) + 30.0
    return out
