"""The raw signal of a magnet-ring speedometer, for simulated runs.

A ring of ``pulses_per_revolution / 2`` magnets on the rear wheel passes a pick-up; the signal
goes through one period per magnet, so it crosses zero ``pulses_per_revolution`` times per
revolution (the seed paper's 10-magnet ring: 20 crossings, each 1/20 of a revolution). The
reader is :func:`whipple.measurement.speedometer.speedometer_speed`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Relative size of the third harmonic: the pick-up's pulse is flatter than a sine. A pure odd
#: harmonic keeps the zero crossings exactly where the sine's are.
THIRD_HARMONIC = 0.15


def speedometer_signal(
    distance: ArrayLike,
    wheel_radius: float,
    pulses_per_revolution: int,
    amplitude: float = 1.0,
    phase: float = 0.0,
) -> NDArray[np.float64]:
    """Pick-up signal [V] as a function of the distance rolled.

    Parameters
    ----------
    distance : array_like
        Distance rolled by the wheel [m] (as the speedometer sees it: including any scale
        error of the wheel radius).
    wheel_radius : float
        Wheel radius [m].
    pulses_per_revolution : int
        Zero crossings per revolution (twice the number of magnets).
    amplitude : float
        Peak value of the signal [V].
    phase : float
        Angle of the first magnet at zero distance [rad of the signal's period].

    Returns
    -------
    ndarray
        The signal [V], zero exactly at every ``2 pi wheel_radius / pulses_per_revolution``
        of distance from ``-phase``.
    """
    theta = 0.5 * pulses_per_revolution * np.asarray(distance, dtype=float) / wheel_radius + phase
    shape = np.sin(theta) + THIRD_HARMONIC * np.sin(3 * theta)
    peak = _peak(THIRD_HARMONIC)
    return amplitude * shape / peak


def _peak(a: float) -> float:
    """Maximum of ``sin t + a sin 3t`` over t (at t = pi/2 for a <= 1/9, else inside)."""
    t = np.linspace(0.0, np.pi / 2, 2001)
    return float(np.max(np.sin(t) + a * np.sin(3 * t)))
