"""The roll gyro's scale error and misalignment fitted with every model (issue 51).

A window of the true model seen through a roll gyro that reads 5 % high (or is pitched by 3
degrees and picks up the yaw rate) is left far above its noise by the true model when the
signals are taken as read; with the instrument's errors fitted, at its noise again.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from whipple.diagnosis.instrument import InstrumentErrors
from whipple.diagnosis.observations import Observation, WindowSignals
from whipple.diagnosis.samples import SampleComparison
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle

ROLL_NOISE, STEER_NOISE = 0.015, 0.002  # rad/s, rad


def _windows(bicycle, scale, misalignment, rng, speeds=(4.5, 5.0, 5.5, 6.0), duration=3.0, rate=100.0):
    model = linear_model(bicycle)
    p = bicycle.parameters
    time = np.arange(0.0, duration, 1.0 / rate)
    windows = []
    for speed in speeds:
        A = model.state_matrix(np.array([speed]))[0]
        start = rng.normal(size=A.shape[0]) * np.array([0.05, 0.05, 0.8, 1.5])
        states = np.array([expm(A * t) @ start for t in time])
        yaw = (speed * states[:, 1] + p["c"] * states[:, 3]) * np.cos(p["lam"]) / p["w"]
        roll = scale * (np.cos(misalignment) * states[:, 2] - np.sin(misalignment) * yaw)
        values = np.array([roll + ROLL_NOISE * rng.normal(size=time.size),
                           states[:, 1] + STEER_NOISE * rng.normal(size=time.size)])
        signals = WindowSignals(time, values, ("roll_rate", "steer_angle"), "offset",
                                noise=np.array([ROLL_NOISE, STEER_NOISE]))
        windows.append(Observation("run", 0.0, float(time[-1]), speed, (speed, speed), 0j, np.eye(2),
                                   signals=signals))
    return windows


@pytest.mark.parametrize("scale, misalignment", [(1.05, 0.0), (0.95, 0.0), (1.0, np.radians(3.0)),
                                                 (1.04, np.radians(-3.0))])
def test_the_true_model_is_at_its_noise_with_the_instrument_fitted(scale, misalignment):
    bicycle = load_bicycle("benchmark")
    windows = _windows(bicycle, scale, misalignment, np.random.default_rng(0))
    as_read = SampleComparison.of(windows, bicycle=bicycle).chi2_per_sample(bicycle)
    fitted = SampleComparison.of(windows, bicycle=bicycle, instrument=InstrumentErrors()).chi2_per_sample(bicycle)
    clean = SampleComparison.of(_windows(bicycle, 1.0, 0.0, np.random.default_rng(0)),
                                bicycle=bicycle).chi2_per_sample(bicycle)
    assert as_read > 1.4  # at least 7 standard deviations of a chi-square per sample of 600
    assert fitted < 1.1
    assert fitted <= clean * 1.0 + 0.02  # the fit cannot do worse than a perfect instrument


def test_a_perfect_instrument_is_left_as_it_is():
    bicycle = load_bicycle("benchmark")
    windows = _windows(bicycle, 1.0, 0.0, np.random.default_rng(1))
    as_read = SampleComparison.of(windows, bicycle=bicycle).chi2_per_sample(bicycle)
    fitted = SampleComparison.of(windows, bicycle=bicycle, instrument=InstrumentErrors()).chi2_per_sample(bicycle)
    # Two values fitted to thousands of residuals: the chi-square falls by about 2 in all.
    samples = SampleComparison.of(windows, bicycle=bicycle).samples
    assert 0.0 <= (as_read - fitted) * samples < 10.0
