"""Swings of a noisy oscillating signal: the moves between its successive extremes.

The signal is low-passed (a zero-phase Bessel filter at five times its dominant frequency,
which barely rings), its noise estimated from the median absolute deviation of what the filter
removes (what the low-passed signal keeps of it as read in the band of a record sampled at
:data:`ANALYSIS_RATE`), and its extremes found by a zig-zag rule: an extreme counts once the
signal has retreated from it by more than five noise standard deviations (of the low-passed
signal).
Where the signal stays still for half a period (the bicycle held, or at rest before a
release), the moment it moves again also counts as an extreme, a "wake", so that no swing
reaches back across a still stretch. Where each still stretch begins is kept too, whether or
not the signal moves again before the record ends.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter1d, minimum_filter1d
from scipy.signal import bessel, sosfiltfilt, welch

from whipple.measurement.noise import robust_scale

#: The rate [Hz] at whose band the noise is read (:func:`swings_of`): the levels that tell a
#: swing from the noise and a still stretch from motion were set on records sampled at it.
ANALYSIS_RATE = 100.0


@dataclass(frozen=True)
class Swings:
    """The swings of a signal and the levels that tell them apart.

    Attributes
    ----------
    smooth : ndarray, shape (n,)
        The low-passed signal (signal units).
    extremes : ndarray of int, shape (m,)
        Sample indices of the extremes (and wakes); swing j runs from extremes[j] to
        extremes[j + 1].
    rest : ndarray of int, shape (m,)
        For a wake, the sample at which the still stretch before it began; -1 otherwise.
    stills : ndarray of int
        The first sample of every still stretch, increasing: also of those the signal does
        not wake from before the record ends, and of those whose wake merged with another's
        (a stretch interrupted by a brief wobble).
    heights : ndarray, shape (m - 1,)
        Height of each swing (signal units).
    noise : float
        Standard deviation of the signal's noise (signal units).
    threshold : float
        Smallest retreat that confirms an extreme: the noise floor of swing heights.
    background : float
        Height of the swings of the undisturbed signal.
    loud : float
        Smallest swing that can be a push.
    frequency : float
        Dominant frequency [Hz].
    cutoff : float
        Cutoff of the low-pass filter [Hz].
    """

    smooth: NDArray[np.float64]
    extremes: NDArray[np.intp]
    rest: NDArray[np.intp]
    stills: NDArray[np.intp]
    heights: NDArray[np.float64]
    noise: float
    threshold: float
    background: float
    loud: float
    frequency: float
    cutoff: float


def swings_of(x: NDArray[np.float64], fs: float) -> Swings:
    """Return the swings of signal `x` sampled at `fs` [Hz], with levels derived from the signal."""
    frequency = _dominant_frequency(x, fs)
    cutoff = min(5 * frequency, 0.4 * fs)
    smooth = sosfiltfilt(bessel(4, cutoff, fs=fs, output="sos", norm="mag"), x)
    noise = _band_noise(x - smooth, cutoff, 0.5 * fs)
    smooth_noise = noise * np.sqrt(cutoff / (0.5 * fs))
    # What the low-passed signal keeps of the noise is read in the band from the cutoff up to
    # about half of ANALYSIS_RATE, as a record sampled at that rate shows it: there a held
    # bicycle's wobble counts with the sensor's noise. Sampled several times faster, white noise
    # spread up to half the sample rate would swamp the wobble's share, and a hold that wobbles
    # more than the noise would never be still (simulated runs at 500 Hz). The band's top: half
    # the sample rate divided by the whole number of times ANALYSIS_RATE goes into it (below
    # twice ANALYSIS_RATE, the whole band). The larger of the two readings counts: for white
    # noise alone they agree but for the filter's gradual roll-off, which reads the band's a
    # little low.
    band = 0.5 * fs / analysis_bin(fs)
    if band < 0.5 * fs:
        seen = sosfiltfilt(bessel(4, band, fs=fs, output="sos", norm="mag"), x) - smooth
        smooth_noise = max(smooth_noise, _band_noise(seen, cutoff, band) * np.sqrt(cutoff / band))
    scale = np.percentile(np.abs(smooth - np.median(smooth)), 99)
    threshold = max(5 * smooth_noise, 1e-2 * scale)
    half = max(3, int(0.5 * fs / frequency))
    extremes, rest, stills = _extremes(smooth, threshold, half)
    heights = np.abs(np.diff(smooth[extremes]))
    if heights.size == 0:
        return Swings(smooth, extremes, rest, stills, heights, float(noise), float(threshold),
                      float(threshold), float(2 * threshold), frequency, cutoff)
    # The background is the typical swing, weighted by time (a quiet record may have few, long
    # swings), unless the signal's range over half a period is lower a fifth of the time (a
    # record that oscillates most of the time, quiet only while the bicycle is held).
    order = np.argsort(heights)
    weight = np.cumsum(np.diff(extremes)[order])
    typical = heights[order][np.searchsorted(weight, 0.5 * weight[-1])]
    local = maximum_filter1d(smooth, half) - minimum_filter1d(smooth, half)
    background = max(min(typical, np.percentile(local, 20)), threshold)
    # A push stands out from the typical swing, or is at least a quarter of the record's large
    # swings (when the typical swing is the oscillation itself).
    loud = max(2 * threshold, min(2 * typical, 0.25 * np.percentile(heights, 95)))
    return Swings(smooth, extremes, rest, stills, heights, float(noise), float(threshold),
                  float(background), float(loud), frequency, cutoff)


def analysis_bin(fs: float) -> int:
    """Return how many samples at `fs` [Hz] make one at :data:`ANALYSIS_RATE` (at least 1; whole samples)."""
    return max(1, int(fs / ANALYSIS_RATE + 1e-9))


def _band_noise(removed: NDArray[np.float64], cutoff: float, band: float) -> float:
    """Return the white noise's standard deviation from what a low-pass at `cutoff` removed below `band` [Hz].

    The filter keeps a fraction cutoff / band of white noise in the band and removes the rest;
    the median absolute deviation keeps the signal's own sharp moves from setting the estimate.
    """
    return float(robust_scale(removed)) / np.sqrt(max(1 - cutoff / band, 1e-3))


def _dominant_frequency(x: NDArray[np.float64], fs: float) -> float:
    """Frequency [Hz] of the largest spectral peak above 0.1 Hz (and below fs / 4)."""
    length = int(min(x.size, 2 ** np.ceil(np.log2(10 * fs))))
    frequencies, power = welch(x - x.mean(), fs, nperseg=length)
    band = (frequencies >= 0.1) & (frequencies <= fs / 4)
    if not band.any():
        return fs / 20
    return float(frequencies[band][np.argmax(power[band])])


def _extremes(
    x: NDArray[np.float64], threshold: float, still: int
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]]:
    """Return the indices of extremes, each confirmed by a retreat of more than `threshold`.

    Where the signal has stayed within twice the threshold for `still` samples (the bicycle
    held, or at rest before a release), the moment it starts moving again also counts as an
    extreme (a "wake"): a swing never reaches back across a still stretch.

    Returns
    -------
    extremes : ndarray of int
        Sample indices, increasing.
    rest : ndarray of int
        For a wake, the sample at which the still stretch began; -1 for other extremes.
    stills : ndarray of int
        The sample at which each still stretch began, increasing (with or without a wake).
    """
    found = _zigzag(x, threshold)
    span = maximum_filter1d(x, still) - minimum_filter1d(x, still)
    quiet = span <= 2 * threshold
    # The filter window is centred: a still stretch runs half a window beyond its centres.
    wakes = np.flatnonzero(quiet[:-1] & ~quiet[1:]) + still // 2
    sleeps = np.maximum(np.flatnonzero(~quiet[:-1] & quiet[1:]) + 1 - still // 2, 0)
    if quiet[0]:
        sleeps = np.r_[0, sleeps]
    if quiet[-1]:
        # Still to the end: the record's last sample closes the still stretch.
        wakes = np.r_[wakes, x.size - 1]
    wakes = wakes[wakes < x.size]
    began = sleeps[np.searchsorted(sleeps, wakes, side="right") - 1] if sleeps.size else wakes
    keep = np.ones(wakes.size, dtype=bool)
    if found.size:
        keep = np.abs(found[_nearest(found, wakes)] - wakes) > max(1, still // 8)
    extremes = np.unique(np.concatenate([found, wakes[keep]]))
    # A wake that falls on an extreme makes that extreme the wake.
    rest = np.full(extremes.size, -1, dtype=np.intp)
    rest[_nearest(extremes, wakes)] = began
    return extremes, rest, sleeps.astype(np.intp)


def _nearest(sorted_values: NDArray[np.intp], points: NDArray[np.intp]) -> NDArray[np.intp]:
    """Index into `sorted_values` (increasing, not empty) of the value nearest each of `points`.

    A search in the sorted values, so that memory and time grow with the number of values, not
    with its product by the number of points (a long record holds tens of thousands of each).
    Ties go to the lower value.
    """
    above = np.clip(np.searchsorted(sorted_values, points), 1, max(sorted_values.size - 1, 1))
    below = above - 1
    if sorted_values.size == 1:
        return np.zeros(points.size, dtype=np.intp)
    closer_above = np.abs(sorted_values[above] - points) < np.abs(points - sorted_values[below])
    return np.where(closer_above, above, below).astype(np.intp)


def _zigzag(x: NDArray[np.float64], threshold: float) -> NDArray[np.intp]:
    """Return the indices of alternating extremes, each confirmed by a retreat of more than `threshold`."""
    found = []
    high = low = 0
    direction = 0
    for i in range(1, x.size):
        if direction >= 0 and x[i] > x[high]:
            high = i
        if direction <= 0 and x[i] < x[low]:
            low = i
        if direction >= 0 and x[high] - x[i] > threshold:
            found.append(high)
            direction, low = -1, i
        elif direction <= 0 and x[i] - x[low] > threshold:
            found.append(low)
            direction, high = 1, i
    # The last extreme is never confirmed by a retreat; it still ends the last swing (a catch
    # that brings the signal to rest leaves exactly this).
    last = high if direction > 0 else low
    if direction and found and last != found[-1] and abs(x[last] - x[found[-1]]) > threshold:
        found.append(last)
    return np.asarray(found, dtype=np.intp)
