"""Forward speed from a raw speedometer signal, and its linear regression over a window.

The speedometer of the seed paper is a ring of magnets on the rear wheel passing a pick-up: the
signal oscillates once per magnet, so each zero crossing marks ``1 / pulses_per_revolution`` of
a wheel revolution (a 10-magnet ring gives 20 crossings per revolution). The time between
successive crossings gives the mean speed over that piece of road: a staircase.

Limits
------
* The signal's fundamental, ``pulses_per_revolution / 2`` cycles per revolution, must stay
  below half the sample rate. Above it the samples alias to a lower frequency and the speed is
  silently wrong; nothing in the samples can reveal it. (20 crossings per revolution, 0.35 m
  wheel, 100 Hz: the limit is 11 m/s; at 5 m/s the signal is a 22.7 Hz wave, 4.4 samples per
  cycle, and 45 crossings per second.)
* Near that limit a half cycle may hold a single sample, so the hysteresis band must stay below
  ``amplitude * cos(pi f / fs)``; the default (10 % of the amplitude) is safe up to
  ``f / fs = 0.47``. Noise must stay well inside the band.
* A single step of the staircase is only as good as the interpolated crossing times (a fraction
  of the sample interval near Nyquist) and the evenness of the magnets. Timing errors of the
  crossings telescope, so the mean over many steps, weighted by their duration (which is what
  :func:`speed_regression` does with the sampled staircase), is accurate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.ndimage import uniform_filter1d

from whipple.errors import RunFileError


@dataclass(frozen=True)
class SpeedometerSpeed:
    """Staircase speed from a speedometer signal.

    Attributes
    ----------
    crossing_times : ndarray, shape (k,)
        Times of the zero crossings [s] (interpolated between samples).
    speeds : ndarray, shape (k - 1,)
        Mean speed [m/s] between successive crossings.
    distance_per_crossing : float
        Road distance between two crossings [m].
    """

    crossing_times: NDArray[np.float64]
    speeds: NDArray[np.float64]
    distance_per_crossing: float

    def at(self, time: ArrayLike) -> NDArray[np.float64]:
        """Return the staircase speed [m/s] at `time` [s] (held constant beyond the first/last step)."""
        step = np.searchsorted(self.crossing_times, np.asarray(time, dtype=float), side="right") - 1
        return self.speeds[np.clip(step, 0, self.speeds.size - 1)]

    def sampled(self, time: ArrayLike) -> NDArray[np.float64]:
        """Mean speed [m/s] over each sample's interval (between midpoints of sample times [s]).

        Unlike :meth:`at`, these values integrate exactly to the distance travelled, so their
        average over a window is not biased by where the samples fall on the staircase (which
        matters when a step lasts only one or two samples).
        """
        t = np.asarray(time, dtype=float)
        if t.size < 2:
            return self.at(t)
        edges = np.concatenate(([1.5 * t[0] - 0.5 * t[1]], 0.5 * (t[1:] + t[:-1]),
                                [1.5 * t[-1] - 0.5 * t[-2]]))
        return np.diff(self.distance(edges)) / np.diff(edges)

    def distance(self, time: ArrayLike) -> NDArray[np.float64]:
        """Distance travelled since the first crossing [m] at `time` [s] (piecewise linear)."""
        t = np.asarray(time, dtype=float)
        marks = np.arange(self.crossing_times.size) * self.distance_per_crossing
        inside = np.interp(t, self.crossing_times, marks)
        before = (t - self.crossing_times[0]) * self.speeds[0]
        after = marks[-1] + (t - self.crossing_times[-1]) * self.speeds[-1]
        return np.where(t < self.crossing_times[0], before,
                        np.where(t > self.crossing_times[-1], after, inside))


@dataclass(frozen=True)
class SpeedRange:
    """Linear regression of the forward speed over a time window.

    Attributes
    ----------
    start, stop : float
        The window [s].
    start_speed, stop_speed : float
        The regression line at the window's start and stop [m/s].
    mean : float
        Mean speed over the window [m/s] (the regression line at its centre).
    slope : float
        Slope of the regression line [m/s^2].
    """

    start: float
    stop: float
    start_speed: float
    stop_speed: float
    mean: float
    slope: float

    @property
    def low(self) -> float:
        """The lower end of the speed range [m/s]."""
        return min(self.start_speed, self.stop_speed)

    @property
    def high(self) -> float:
        """The upper end of the speed range [m/s]."""
        return max(self.start_speed, self.stop_speed)


def speedometer_speed(
    time: ArrayLike,
    signal: ArrayLike,
    wheel_radius: float,
    pulses_per_revolution: float,
    hysteresis: float = 0.1,
    source: str | None = None,
) -> SpeedometerSpeed:
    """Speed from the zero crossings of a speedometer signal.

    The signal's offset is removed with a moving average over a whole number of its cycles;
    crossings are counted with a hysteresis band (so noise near zero does not add crossings)
    and timed by linear interpolation between the two samples around zero.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times [s], increasing.
    signal : array_like, shape (n,)
        Speedometer signal (any unit, e.g. V).
    wheel_radius : float
        Radius of the wheel carrying the magnets [m].
    pulses_per_revolution : float
        Zero crossings per wheel revolution (twice the number of magnets).
    hysteresis : float
        Half-width of the hysteresis band as a fraction of the signal's amplitude.
    source : str, optional
        Name of the file the signal came from, for error messages.

    Raises
    ------
    RunFileError
        If the signal has fewer than three crossings or the geometry is not positive.
    """
    t = np.asarray(time, dtype=float)
    x = np.asarray(signal, dtype=float)
    if wheel_radius <= 0 or pulses_per_revolution <= 0:
        raise RunFileError("wheel_radius and pulses_per_revolution must be positive", source)
    x = x - np.median(x)
    first = _crossings(t, x, hysteresis)
    if first.size < 3:
        raise RunFileError("speedometer signal has fewer than 3 zero crossings", source)
    # Two crossings per cycle: averaging over a whole number of cycles removes the wave and
    # leaves the offset (a drifting DC level would otherwise shift every crossing).
    samples_per_cycle = 2 * np.median(np.diff(first)) / np.median(np.diff(t))
    length = max(3, int(round(4 * samples_per_cycle)))
    x = x - uniform_filter1d(x, size=length, mode="nearest")
    crossings = _crossings(t, x, hysteresis)
    if crossings.size < 3:
        raise RunFileError("speedometer signal has fewer than 3 zero crossings", source)
    distance = 2 * np.pi * wheel_radius / pulses_per_revolution
    return SpeedometerSpeed(crossings, distance / np.diff(crossings), float(distance))


def _crossings(t: NDArray[np.float64], x: NDArray[np.float64], hysteresis: float) -> NDArray[np.float64]:
    """Interpolated times at which `x` passes through zero and on beyond the hysteresis band."""
    # A sinusoid's median absolute value is amplitude * sin(pi / 4).
    band = hysteresis * np.median(np.abs(x)) / np.sin(np.pi / 4)
    index = np.arange(x.size)
    state = np.where(x > band, 1, np.where(x < -band, -1, 0))
    # Inside the band the state is the last one outside it.
    last_outside = np.maximum.accumulate(np.where(state != 0, index, 0))
    held = state[last_outside]
    flips = np.flatnonzero((held[1:] != held[:-1]) & (held[:-1] != 0)) + 1
    if flips.size == 0:
        return np.empty(0)
    # The crossing lies after the last sample on the old side of zero before the flip.
    last_negative = np.maximum.accumulate(np.where(x < 0, index, 0))
    last_positive = np.maximum.accumulate(np.where(x >= 0, index, 0))
    j = np.where(held[flips] > 0, last_negative[flips - 1], last_positive[flips - 1])
    x0, x1 = x[j], x[j + 1]
    fraction = np.where(x1 != x0, -x0 / np.where(x1 != x0, x1 - x0, 1.0), 0.0)
    return t[j] + fraction * (t[j + 1] - t[j])


def speed_regression(time: ArrayLike, speed: ArrayLike, start: float, stop: float) -> SpeedRange:
    """Least-squares line through the speed samples of a window.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times [s], increasing.
    speed : array_like, shape (n,)
        Forward speed at the samples [m/s] (e.g. a speedometer staircase sampled at `time`).
    start, stop : float
        The window [s].

    Raises
    ------
    RunFileError
        If the window holds fewer than two samples.
    """
    t = np.asarray(time, dtype=float)
    v = np.asarray(speed, dtype=float)
    # The window's samples found by bisection: a long run's windows each cost their own length.
    inside = slice(int(np.searchsorted(t, start, side="left")), int(np.searchsorted(t, stop, side="right")))
    if inside.stop - inside.start < 2:
        raise RunFileError(f"speed window {start:g}-{stop:g} s holds fewer than 2 samples")
    centre = 0.5 * (start + stop)
    # Centred time keeps the intercept equal to the value at the centre.
    slope, at_centre = np.polyfit(t[inside] - centre, v[inside], 1)
    half = 0.5 * (stop - start)
    return SpeedRange(
        start=float(start),
        stop=float(stop),
        start_speed=float(at_centre - slope * half),
        stop_speed=float(at_centre + slope * half),
        mean=float(at_centre),
        slope=float(slope),
    )
