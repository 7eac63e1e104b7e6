"""A window's white sensor noise, estimated from its samples.

For white noise of standard deviation s, the second difference ``y[i+1] - 2 y[i] + y[i-1]`` has
standard deviation ``s sqrt(6)``, while a free response sampled well above its frequencies
barely moves it (a weave of 5 rad/s at 100 Hz adds 0.25% of its amplitude). The median
absolute deviation keeps a few spikes from setting the estimate. Used to weigh a window's
signals against each other and to judge how far a fitted curve leaves them
(:mod:`whipple.measurement.free_motion`, :mod:`whipple.diagnosis.samples`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: A signal with at least this share of its successive samples equal is recorded in steps (an
#: encoder; the bundled steer angle in steps of 2 pi / 8192 rad, 58% of them equal).
QUANTISED = 0.2
#: A signal's noise is at least this fraction of its spread over the window: a signal recorded
#: without noise (or quantised coarsely) would otherwise weigh without limit.
NOISE_FLOOR = 1e-6


def second_difference_noise(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return each signal's white-noise standard deviation from its second differences (robust).

    ``values``: shape (k, n), the k signals of one window (signal units); the result has the
    same units. A signal recorded in steps (an encoder: many successive samples equal) has at
    least the rounding's noise, a step over sqrt(12), the step being its smallest change; every
    signal at least ``NOISE_FLOOR`` times its spread.
    """
    values = np.atleast_2d(np.asarray(values, dtype=float))
    second = values[:, 2:] - 2.0 * values[:, 1:-1] + values[:, :-2]
    noise = robust_scale(second) / np.sqrt(6.0)
    steps = np.abs(np.diff(values, axis=1))
    for k, row in enumerate(steps):
        moved = row[row > 0]
        if moved.size and np.mean(row == 0) >= QUANTISED:
            noise[k] = max(noise[k], float(moved.min()) / np.sqrt(12.0))
    return np.maximum(noise, noise_floor(values))


def noise_floor(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the least noise of each signal (k, n): ``NOISE_FLOOR`` times its spread."""
    return NOISE_FLOOR * np.maximum(values.std(axis=1), np.finfo(float).tiny)


def robust_scale(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return each row's standard deviation from its median absolute deviation (robust to a tail)."""
    centre = np.median(values, axis=-1, keepdims=True)
    return np.asarray(1.4826 * np.median(np.abs(values - centre), axis=-1), dtype=float)
