"""Error-source models: the reading errors, inclinometer averaging (the ME's CoG error and the
wire's offset have their own files: test_mecog.py, test_wire.py)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.method.errormodel import ErrorModel

PAPER_MASSES = (0.025, 0.085, 0.020, 0.046)


def test_reading_error_models():
    paper = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=10, inclinometer_model="paper-averaged")
    bias = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=10, inclinometer_model="hang-bias")
    rng = np.random.default_rng(11)
    for model in (paper, bias, paper.paper()):
        e = model.sample_reading_errors(rng, (200_000,))
        assert np.std(e) == pytest.approx(model.reading_sigma_deg, rel=0.01)
    # Averaging helps the paper model by √n, not the per-hang bias.
    q = paper.lsb_deg
    assert paper.reading_sigma_deg == pytest.approx(
        np.sqrt((0.1**2 / 3 + q**2 / 12 + 0.05**2) / 10)
    )
    assert paper.paper().reading_sigma_deg == pytest.approx(np.sqrt((0.1**2 / 3 + q**2 / 12) / 10))
    assert bias.reading_sigma_deg > np.sqrt(0.1**2 / 3)
    single = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=1).paper()
    e = single.sample_reading_errors(rng, (100_000,))
    assert np.max(np.abs(e)) <= 0.1 + single.lsb_deg / 2  # bounded: sum of two uniforms
    assert stats.kurtosis(e) < 0  # platykurtic, unlike a normal
    with pytest.raises(ValueError, match="unknown inclinometer model 'paper'"):
        ErrorModel(PAPER_MASSES, (10.0,) * 4, inclinometer_model="paper")  # type: ignore[arg-type]


@pytest.mark.parametrize(("noise_deg", "samples"), [(0.0, 10), (0.02, 10), (0.05, 10), (0.03, 3)])
def test_hang_mean_reading_against_a_simulated_adc(noise_deg, samples):
    """The closed form of a hang's mean reading error (bias + shared quantisation + averaged
    part) against an ADC simulated sample by sample, as the virtual campaign does."""
    model = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=samples, sensor_noise_deg=noise_deg)
    q = model.lsb_deg
    rng = np.random.default_rng(2)
    hangs = 100_000
    true = rng.uniform(-40, 40, hangs)  # where the signal falls on the ADC grid: anywhere
    bias = rng.uniform(-0.1, 0.1, hangs)
    noisy = true[:, None] + bias[:, None] + rng.normal(0, noise_deg, (hangs, samples))
    mean = (q * np.round(noisy / q)).mean(axis=1)
    err = mean - true
    assert np.var(err) == pytest.approx(model.reading_var_deg2(), rel=0.02)
    _, shared, averaged = model.reading_parts_deg2()
    # The part the samples share: the variance of the mean minus the accuracy bias's, once the
    # averaged part is taken out (only testable where it is not negligible).
    if shared > 1e-4:
        assert np.var(err - bias) - averaged == pytest.approx(shared, rel=0.05)
