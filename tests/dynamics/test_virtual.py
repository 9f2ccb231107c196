"""``cadcog campaign --swings``: the virtual swings tell of the same campaign as its readings."""

from __future__ import annotations

import numpy as np

import cadcog
from cadcog.dynamics.context import context_for_rig
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.dynamics.modalfit import fit_swing
from cadcog.dynamics.virtual import virtual_swings
from cadcog.mass.properties import combine
from cadcog.method.errormodel import ErrorModel
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.validation.campaign import campaign_suspensions, simulated_campaign

RIG = cadcog.load_rig()
CTX = context_for_rig(RIG)


def _modes(pivot_mm, top_mm):
    """The hang's modes as the virtual swing draws them: each decaying in 20 s, at
    ``f √(1 − ζ²)`` with ``ζ = 1/(2π f · 20 s)``."""
    truth = combine([CTX.object_cad, *CTX.me_parts])
    geo = HangGeometry(pivot_mm, CTX.sensor_mm, CTX.swing.wire_length_mm, top_mm, *CTX.signs)
    modes = hang_modes(truth.inertia_kg_mm2, truth.mass_kg, truth.cog_mm, geo).frequencies_hz
    zeta = 1.0 / (2.0 * np.pi * modes * 20.0)
    return modes * np.sqrt(1 - zeta**2)


def test_the_swings_swing_about_the_pivots_the_readings_were_drawn_with():
    """The campaign's drawn pivots (its play and its wire) are where its swings turn: the fitted
    body modes match the linear model about the drawn pivot within 4 σ, and miss the model
    about the expected pivot (what the swings used before) by many σ."""
    rows, truth = simulated_campaign(
        Scenario.from_rig(RIG), ErrorModel.from_rig(RIG), RIG.inclinometer, 3
    )
    hangs = campaign_suspensions(rows, RIG.inclinometer)
    assert truth.pivots_mm.shape == (len(hangs), 3) and truth.wire_lambda_mm is not None
    swings = virtual_swings(
        CTX,
        hangs,
        seed=3,
        pivots_mm=truth.pivots_mm,
        me_cog_error_mm=np.zeros(3),
        top_hinge_mm=truth.wire_lambda_mm,
        noise_deg=0.002,
    )
    weight = combine([CTX.object_cad, *CTX.me_parts]).mass_kg * 9.80665
    expected, _ = CTX.pivots(
        np.array([h.position_mm for h in hangs]), CTX.object_cad.cog_mm, weight
    )
    far = 0
    for i in range(3):
        drawn = _modes(truth.pivots_mm[i], truth.wire_lambda_mm)
        nominal = _modes(expected[i], CTX.top_hinge_mm(weight)[0])
        fit = fit_swing(swings[i], drawn, halves=False)
        sigma = np.sqrt(np.diag(fit.frequency_cov_hz2))
        body = fit.mode_index >= len(drawn) - 2
        z_drawn = (fit.frequencies_hz - drawn[fit.mode_index]) / sigma
        z_nominal = (fit.frequencies_hz - nominal[fit.mode_index]) / sigma
        assert np.all(np.abs(z_drawn[body]) < 4.0), (i, z_drawn)
        far += int(np.any(np.abs(z_nominal[body]) > 10.0))
    assert far >= 2
