"""Sensor faults of an instrumented bicycle: what the sensors see of the true signals.

A :class:`whipple.simulation.scenario.SensorFaults` acts on the true signals before each
sensor's white noise and constant bias are added (:func:`whipple.simulation.procedure.sense`):

- an IMU pitched by a small angle about the lateral axis mixes the yaw rate into the roll
  gyro and the roll rate into the yaw gyro (a rotation of the two rates);
- a scale error multiplies both gyro axes;
- the roll gyro's bias drifts, linearly and as a random walk;
- the steer angle carries a constant offset.

Other signals (speed, speedometer, roll angle, steer rate) are left as they are.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from whipple.simulation.scenario import SensorFaults

#: Second entry of the seed of the bias random walk's own random stream (the first is the
#: run's seed): the walk draws no number from the run's generator, so a run with it has the
#: same noise, wobble and speedometer phase as the run without it.
BIAS_WALK_STREAM = 51


def faulty_signals(truth: Mapping[str, NDArray[np.float64]], faults: SensorFaults, sample_rate: float,
                   seed: int) -> dict[str, NDArray[np.float64]]:
    """Return the signals as the faulty sensors see them, before noise and bias.

    Parameters
    ----------
    truth : mapping of str to ndarray
        True signals sampled at ``k / sample_rate`` (``roll_rate`` and ``yaw_rate`` [rad/s],
        ``steer_angle`` [rad], others in their units).
    faults : SensorFaults
        The faults; without any, ``truth``'s arrays are returned unchanged (the same objects).
    sample_rate : float
        [Hz].
    seed : int
        The run's seed; the bias random walk draws from ``default_rng([seed, BIAS_WALK_STREAM])``.

    Returns
    -------
    dict of str to ndarray
        Every signal of ``truth``; only the roll rate, yaw rate and steer angle may differ.
    """
    seen = dict(truth)
    if faults.is_none:
        return seen
    roll_rate, yaw_rate = truth["roll_rate"], truth["yaw_rate"]
    if faults.misalignment:
        cos, sin = np.cos(faults.misalignment), np.sin(faults.misalignment)
        roll_rate, yaw_rate = cos * roll_rate - sin * yaw_rate, sin * roll_rate + cos * yaw_rate
    if faults.gyro_scale != 1.0:
        roll_rate, yaw_rate = faults.gyro_scale * roll_rate, faults.gyro_scale * yaw_rate
    drift = roll_rate_bias_drift(faults, roll_rate.size, sample_rate, seed)
    seen["roll_rate"], seen["yaw_rate"] = roll_rate + drift, yaw_rate
    if faults.steer_offset:
        seen["steer_angle"] = truth["steer_angle"] + faults.steer_offset
    return seen


def roll_rate_bias_drift(faults: SensorFaults, n: int, sample_rate: float, seed: int) -> NDArray[np.float64]:
    """Return the roll gyro's bias change [rad/s] at the n samples ``k / sample_rate`` [Hz]: 0 at t = 0.

    ``bias_drift t`` plus a random walk of density ``bias_walk`` (independent Gaussian steps of
    variance ``bias_walk^2 / sample_rate`` per sample interval).
    """
    time = np.arange(n) / sample_rate
    drift = faults.bias_drift * time
    if faults.bias_walk > 0 and n > 1:
        steps = np.random.default_rng([seed, BIAS_WALK_STREAM]).standard_normal(n - 1)
        drift = drift + np.concatenate(([0.0], np.cumsum(steps))) * (faults.bias_walk / np.sqrt(sample_rate))
    return drift


def fault_metadata(faults: SensorFaults) -> dict[str, str]:
    """Return the run-file metadata of the faults that are present (none: an empty dict), SI units."""
    values = {"imu_misalignment": (faults.misalignment, 0.0), "gyro_scale": (faults.gyro_scale, 1.0),
              "roll_rate_bias_drift": (faults.bias_drift, 0.0), "roll_rate_bias_walk": (faults.bias_walk, 0.0),
              "steer_offset": (faults.steer_offset, 0.0)}
    return {key: f"{value:.9g}" for key, (value, none) in values.items() if value != none}
