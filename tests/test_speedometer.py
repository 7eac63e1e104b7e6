"""Speed from a raw speedometer signal; linear regression of the speed over a window."""

from __future__ import annotations

import numpy as np
import pytest

from whipple.errors import InputError
from whipple.measurement.speedometer import speed_regression, speedometer_speed

RADIUS = 0.35
PULSES = 20  # a 10-magnet ring: 20 zero crossings per revolution


def true_speed(t, v0, decay):
    return v0 * (1 - decay * t)


def synthesize(fs, v0, duration=20.0, decay=0.005, noise=0.05, offset=0.8, seed=0):
    """Speedometer signal of a wheel slowing down linearly, with offset drift and noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, duration, 1 / fs)
    distance = v0 * (t - 0.5 * decay * t**2)
    # PULSES / 2 cycles per revolution of 2 pi r.
    phase = PULSES * distance / (2 * RADIUS)
    signal = np.sin(phase + 0.3) + offset + 0.1 * np.sin(0.2 * t)
    return t, signal + noise * rng.standard_normal(t.size)


@pytest.mark.parametrize(
    ("fs", "v0"),
    [
        (500, 5.0),
        (100, 5.0),  # a 22.7 Hz wave, 4.4 samples per cycle, 45 crossings per second
        (100, 8.3),  # the seed's top speed: 37.7 Hz, 2.6 samples per cycle
        (500, 1.0),
    ],
)
def test_regression_recovers_speed_within_one_percent(fs, v0):
    t, signal = synthesize(fs, v0)
    staircase = speedometer_speed(t, signal, RADIUS, PULSES)
    measured = staircase.sampled(t)
    for start, stop in ((2.0, 4.0), (9.4, 11.0), (15.0, 19.0)):
        fit = speed_regression(t, measured, start, stop)
        truth_start, truth_stop = true_speed(np.array([start, stop]), v0, 0.005)
        assert fit.start_speed == pytest.approx(truth_start, rel=0.01)
        assert fit.stop_speed == pytest.approx(truth_stop, rel=0.01)
        assert fit.mean == pytest.approx(true_speed(0.5 * (start + stop), v0, 0.005), rel=0.01)
        assert fit.low <= fit.high


def test_every_crossing_is_counted_and_timed_to_a_fraction_of_a_sample():
    fs, v0 = 100, 5.0
    t, signal = synthesize(fs, v0, decay=0.0, noise=0.02, offset=0.0)
    staircase = speedometer_speed(t, signal, RADIUS, PULSES)
    phase = PULSES * v0 * t / (2 * RADIUS) + 0.3
    expected = np.arange(np.ceil(phase[0] / np.pi), np.floor(phase[-1] / np.pi) + 1) * np.pi
    truth = (expected - 0.3) * 2 * RADIUS / (PULSES * v0)
    assert staircase.crossing_times.size == truth.size
    assert np.abs(staircase.crossing_times - truth).max() < 0.5 / fs
    # One step is one 20th of a revolution.
    assert staircase.distance_per_crossing == pytest.approx(2 * np.pi * RADIUS / PULSES)


def test_point_staircase_is_noisy_near_nyquist_but_its_sampled_mean_is_not():
    # At 2.6 samples per cycle a single step is only as good as the interpolation; the
    # sample-interval means integrate exactly to the distance.
    fs, v0 = 100, 8.3
    t, signal = synthesize(fs, v0, decay=0.0, noise=0.02)
    staircase = speedometer_speed(t, signal, RADIUS, PULSES)
    assert np.std(staircase.speeds) / v0 > 0.02
    assert staircase.sampled(t)[100:-100].mean() == pytest.approx(v0, rel=1e-3)


def test_aliased_signal_reads_too_slow():
    # Documented limit: above fs/2 the samples alias and the speed is silently wrong.
    fs, v0 = 100, 12.0  # 54.6 Hz wave sampled at 100 Hz
    t, signal = synthesize(fs, v0, decay=0.0, noise=0.0)
    measured = speedometer_speed(t, signal, RADIUS, PULSES).sampled(t)
    assert measured.mean() < 0.95 * v0


def test_regression_of_a_linear_speed_is_exact():
    t = np.linspace(0, 10, 1001)
    fit = speed_regression(t, 5.6 - 0.0625 * t, 9.4, 11.0)
    assert fit.start_speed == pytest.approx(5.6 - 0.0625 * 9.4)
    assert fit.slope == pytest.approx(-0.0625)


def test_errors():
    t = np.arange(0, 2, 0.01)
    with pytest.raises(InputError, match="fewer than 3 zero crossings"):
        speedometer_speed(t, np.sin(0.5 * t), RADIUS, PULSES)
    with pytest.raises(InputError, match="positive"):
        speedometer_speed(t, np.sin(50 * t), -RADIUS, PULSES)
    with pytest.raises(InputError, match="fewer than 2 samples"):
        speed_regression(t, np.ones_like(t), 5.0, 6.0)
