"""The truth's physics beyond the estimator's model: the wire's own swing raises the body modes.

The wire's tension averaged over its swing is ``m g (1 + A²/4)``; a body mode's frequency goes as
the square root of that "gravity", so it rises by up to ``A²/8``. The tilt sensor on the object
does not see the wire's swing (docs/inertia_validation.md, 2026-11-27): this checks that the
nonlinear simulation (:mod:`support.swing_truth`) has it, within the bound.
"""

from __future__ import annotations

import numpy as np

import cadcog
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.dynamics.modalfit import fit_swing
from cadcog.dynamics.swingfile import Swing
from support import swing_files as sf
from support import swing_truth as st


def _horizontal(deg: float, azimuth_deg: float) -> np.ndarray:
    a = np.radians(azimuth_deg)
    return np.radians(deg) * np.array([np.cos(a), np.sin(a), 0.0])


def test_a_swinging_wire_raises_the_body_modes_by_at_most_a_squared_over_8():
    """The paper rig on a 300 mm wire, the body tilted 1° about its exit, the wire swung 1° or
    10° (no damping, noise-free readings, 60 s): at 10° no body mode falls, none rises by more
    than ``A²/8`` (0.38 %) and a quarter, and the larger of each hang's two rises by more than
    half of it; at 1° they move by under 0.02 %. (Measured: S1 +0.02/+0.30 %, S3 +0.29/+0.35 %;
    the fitted rise depends on the record's length, the tension beating at twice the wire's
    frequency: S1's larger is +0.42 % over 40 s.)"""
    truth = sf.rig_truth(cadcog.load_rig().source)
    length, fs = 300.0, 50.0
    t = np.arange(1, int(60 * fs) + 1) / fs
    bound = np.radians(10.0) ** 2 / 8
    for pid in ("S1", "S3"):
        hinge = truth.exit_of(pid)
        geo = HangGeometry(hinge, np.asarray(truth.body.sensor_mm), length, 0.0)
        linear = hang_modes(truth.body.inertia_kg_mm2, truth.body.mass_kg, truth.body.cog_mm, geo)
        releases = [
            st.Release(_horizontal(w, 30), _horizontal(1, 100), np.zeros(3), np.zeros(3))
            for w in (1.0, 10.0)
        ]
        tx, ty = truth.released(hinge, releases, length, 1e9, t)
        rises = []
        for k in range(2):
            # each frequency held fixed: the record's mean, which is what the wire's swing
            # raises (undamped, the swing never fades, so no drift to its limit is seen)
            swing = Swing(pid, t, np.column_stack([tx[k], ty[k]]))
            fit = fit_swing(swing, linear.frequencies_hz, drift=False)
            body_modes = fit.mode_index >= len(linear.frequencies_hz) - 2
            f = fit.frequencies_hz[body_modes]
            rises.append(f / linear.frequencies_hz[fit.mode_index[body_modes]] - 1)
        small, large = rises
        assert np.all(np.abs(small) < 2e-4), (pid, small)
        assert np.all(large > -5e-4) and np.all(large < 1.25 * bound), (pid, large, bound)
        assert large.max() > bound / 2, (pid, large, bound)
