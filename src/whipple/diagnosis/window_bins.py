"""Each window's samples averaged in bins, and the noise each signal is weighed by.

Models are compared with a window's samples (:mod:`whipple.diagnosis.samples`) averaged in bins
of about :data:`BIN_DURATION`; each signal is divided by its noise (:func:`signal_noise`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.observations import WindowSignals
from whipple.measurement.noise import noise_floor, second_difference_noise

#: Samples are averaged in bins of about this duration [s] before models are compared with
#: them. A model's response averaged over a bin is its response at the bin's first sample times
#: a factor per mode (``mean_q e^{lambda q dt}``), so the comparison stays exact for every
#: model; what is lost is the samples' variation within a bin, which the models' responses
#: share (to second order in their differences) and the noise alone fills. It makes a model's
#: comparison several times cheaper.
BIN_DURATION = 0.04
#: A window's signal is weighed by at least this share of its weave fit's residual RMS as its
#: noise (:func:`signal_noise`). In clean simulated windows the residual is 1.0-1.5 times the
#: noise from the second differences, so this leaves them at their noise; a window holding part
#: of a push or a catch is left 2-30 times its noise off and counts 1 to 200 times less.
FIT_RESIDUAL_SHARE = 0.5


def signal_noise(signals: WindowSignals) -> NDArray[np.float64]:
    """Return the noise each signal of a window is weighed by [signal unit].

    The stated noise where given (a noise-free twin's); otherwise the noise from the second
    differences (:func:`second_difference_noise`), or ``FIT_RESIDUAL_SHARE`` times the window's
    weave-fit residual RMS where that is larger: a window that the fitting function leaves
    several times its noise off holds more than one free coasting (part of a push, a catch, a
    signal in coarse steps), and counts correspondingly less.
    """
    values = np.atleast_2d(np.asarray(signals.values, dtype=float))
    if signals.noise is not None:
        return np.maximum(np.asarray(signals.noise, dtype=float), noise_floor(values))
    noise = second_difference_noise(values)
    if signals.residual_rms is not None:
        noise = np.maximum(noise, FIT_RESIDUAL_SHARE * np.asarray(signals.residual_rms, dtype=float))
    return noise


def binned_window(signals: WindowSignals, duration: float = BIN_DURATION
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int, float]:
    """Return a window's bins: first sample times [s] from the window's start, means, noise, size, interval [s].

    Bins of about ``duration`` [s] where the sampling is uniform (intervals within 1% of their
    median); the samples after the last whole bin are left out. One sample a bin otherwise.
    """
    time, values = np.asarray(signals.time, dtype=float), np.atleast_2d(np.asarray(signals.values, dtype=float))
    noise = signal_noise(signals)
    steps = np.diff(time)
    step = float(np.median(steps)) if steps.size else 0.0
    size = max(1, int(round(duration / step))) if step > 0 else 1
    if size == 1 or np.any(np.abs(steps - step) > 0.01 * step) or time.size < 2 * size:
        return time - time[0], values, noise, 1, step
    count = time.size // size
    means = values[:, :count * size].reshape(values.shape[0], count, size).mean(axis=2)
    return time[:count * size:size] - time[0], means, noise / np.sqrt(size), size, step
