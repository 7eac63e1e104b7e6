"""Random torques on a coasting bicycle: a road's roughness, a belt's, gusts of wind.

No bicycle coasts free of them: the road's unevenness and the wind push its frames about, and
its measured motion is the free response plus its response to these pushes. On real runs the
fitted weave function leaves a residual that changes slowly from sample to sample (the bundled
treadmill runs' residuals are correlated from one sample to the next by 0.4-0.97, where white
sensor noise leaves 0), and a diagnosis that reads every sample as independent is too sure of
itself there. Simulated runs take such disturbances on request (``RunScenario.disturbance``):
a roll and a steer torque, each first-order low-pass filtered white noise of a given
root-mean-square and corner frequency, stationary from the run's first sample, held over each
sample interval and acting throughout the run (the hand holding the bicycle resists them too).
They draw from a random stream of their own, so that a run with them has the noise, wobble
and pushes of the run without them.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.signal import lfilter

#: Second entry of the seed of the disturbances' own random stream (the first is the run's seed).
DISTURBANCE_STREAM = 52


def disturbance_torque(disturbance: tuple[float, float], band: float, sample_rate: float, intervals: int,
                       seed: int) -> NDArray[np.float64]:
    """Return the roll and steer disturbance torques [N m] over each sample interval, shape (intervals, 2).

    Parameters
    ----------
    disturbance : tuple of float
        Root-mean-square roll and steer torques [N m].
    band : float
        Corner frequency [Hz] of the first-order low-pass filter shaping each.
    sample_rate : float
        [Hz].
    intervals : int
        Number of sample intervals.
    seed : int
        The run's seed; the torques draw from ``default_rng([seed, DISTURBANCE_STREAM])``.
    """
    if intervals <= 0 or not any(disturbance):
        return np.zeros((max(intervals, 0), 2))
    rng = np.random.default_rng([seed, DISTURBANCE_STREAM])
    # The exact discretisation of the filter: each value keeps `memory` of the last, and the
    # innovations keep the variance stationary from a stationary first value.
    memory = math.exp(-2.0 * math.pi * band / sample_rate)
    innovations = rng.standard_normal((intervals, 2))
    innovations[1:] *= math.sqrt(1.0 - memory**2)
    shaped = lfilter([1.0], [1.0, -memory], innovations, axis=0)
    return np.asarray(shaped * np.asarray(disturbance, dtype=float), dtype=float)


def disturbance_metadata(disturbance: tuple[float, float], band: float) -> dict[str, str]:
    """Return the run-file metadata of the disturbances (none: an empty dict)."""
    if not any(disturbance):
        return {}
    return {"disturbance": f"{disturbance[0]:g},{disturbance[1]:g}", "disturbance_band": f"{band:g}"}
