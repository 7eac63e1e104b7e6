"""Glitches: isolated wild samples of a signal, found and left out as gaps.

A logger's bit error or a loose connector leaves a single sample far from its neighbours (a roll
rate of 1e6 rad/s, or of 50 rad/s in a run whose weave swings by 1 rad/s). Fitted as data, such a
sample ruins the fit of its window and the noise figure of the run, and through them every
other window; left out (NaN, a gap), it is filled from its neighbours when the run is read
(:mod:`whipple.measurement.short_gaps`) and costs no window.

The rule, for each sample x[i] of one signal:

1. Its *residual* r[i] = x[i] - p[i], where p[i] is the cubic through its four neighbours
   x[i-2], x[i-1], x[i+1], x[i+2] evaluated at i: (-x[i-2] + 4 x[i-1] + 4 x[i+1] - x[i+2]) / 6.
   A smooth signal sampled a few times per oscillation leaves a residual of order
   (w h)^4 / 6 of its amplitude (w its angular frequency, h the sample interval: below 2e-4 of
   the weave's amplitude at 100 Hz), so the residual is the sensor's noise, with standard
   deviation sqrt(1 + 34/36) = 1.39 times the noise's.
2. Its *noise scale*: the robust spread (1.4826 times the median absolute residual) of the
   residuals of its block of :attr:`GlitchRule.block` samples, but at least
   :attr:`GlitchRule.floor_share` of the median of all blocks' spreads (a block of a quantised,
   still signal has a spread of zero) and at least the signal's resolution (its least
   significant bit, for a quantised signal).
3. It is a glitch if |r[i]| exceeds :attr:`GlitchRule.threshold` noise scales, it stands
   apart on both sides (x[i] - x[i-1] and x[i] - x[i+1] have the same sign and both exceed half
   of |r[i]|), and it is alone: with x[i] replaced by p[i], none of its four neighbours' residuals
   exceeds :attr:`GlitchRule.neighbour_threshold` noise scales. A step or a kink (a catch, a
   push) moves the samples after it too, a peak of the oscillation moves its neighbours nearly
   as much, and the impact of a push makes the signal ring over several samples: none passes.

Samples within two of an end or of a gap are not tested (their four neighbours are not all
there). The rule is tested on the simulator's runs and the bundled measured runs (no sample
flagged) and on runs with glitches added (tests/test_glitches.py).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: Spread of the residual of pure white noise, in units of the noise's standard deviation.
RESIDUAL_NOISE_GAIN = float(np.sqrt(1 + 34 / 36))


@dataclass(frozen=True)
class GlitchRule:
    """How far a sample must stand out to be a glitch.

    Attributes
    ----------
    threshold : float
        Smallest residual of a glitch, in noise scales (the residual's robust spread). Residuals
        of Gaussian noise pass 12 scales with a probability of 4e-33 per sample.
    block : int
        Samples per block over which the noise scale is measured (2.56 s at 100 Hz: the noise
        may change during a run, e.g. when a motor switches on).
    floor_share : float
        Least noise scale of a block, as a share of the median scale of all blocks.
    neighbour_threshold : float
        Largest residual of a glitch's neighbours once the glitch is replaced by its prediction,
        in noise scales: a glitch is one sample out of line, a push's impact rings over several.
    """

    threshold: float = 25.0
    block: int = 256
    floor_share: float = 0.25
    neighbour_threshold: float = 5.0

    def __post_init__(self) -> None:
        if not (np.isfinite(self.threshold) and self.threshold > 0):
            raise ValueError(f"threshold must be positive, got {self.threshold}")
        if not (isinstance(self.block, int) and self.block >= 8):
            raise ValueError(f"block must be an integer of at least 8 samples, got {self.block}")
        if not (np.isfinite(self.floor_share) and self.floor_share >= 0):
            raise ValueError(f"floor_share must be >= 0, got {self.floor_share}")


#: The rule :func:`whipple.measurement.runs.read_run` applies by default.
DEFAULT_RULE = GlitchRule()


def residuals(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return each sample minus the cubic through its four neighbours (NaN where one is missing)."""
    x = np.asarray(values, dtype=float)
    r = np.full(x.shape, np.nan)
    if x.size >= 5:
        r[2:-2] = x[2:-2] - (-x[:-4] + 4 * x[1:-3] + 4 * x[3:-1] - x[4:]) / 6
    return r


def noise_scale(r: NDArray[np.float64], values: NDArray[np.float64], rule: GlitchRule) -> NDArray[np.float64]:
    """Return the noise scale of every sample's residual (see the module notes), NaN if none can be told."""
    n = r.size
    blocks = -(-n // rule.block)
    padded = np.full(blocks * rule.block, np.nan)
    padded[:n] = np.abs(r)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # blocks without residuals: NaN
        spread = 1.4826 * np.nanmedian(padded.reshape(blocks, rule.block), axis=1)
    usable = spread[np.isfinite(spread)]
    if not usable.size:
        return np.full(n, np.nan)
    floor = rule.floor_share * float(np.median(usable))
    resolution = _resolution(values)
    scale = np.fmax(np.fmax(spread, floor), resolution)
    return np.repeat(scale, rule.block)[:n]


def _resolution(values: NDArray[np.float64]) -> float:
    """Return the smallest step of a quantised signal (its least significant bit), about 0 for others.

    The smallest step between two samples, among the steps larger than a hundredth of their
    median: a quantised value computed in floating point (a rate from encoder counts) also
    steps by rounding errors, far below its least significant bit.
    """
    steps = np.abs(np.diff(values))
    steps = steps[np.isfinite(steps) & (steps > 0)]
    if not steps.size:
        return 0.0
    steps = steps[steps > 0.01 * np.median(steps)]
    return float(steps.min())


def _alone(x: NDArray[np.float64], i: int, limit: float) -> bool:
    """Return whether sample i is the only one out of line.

    With it replaced by its prediction, no neighbour's residual may exceed `limit` (a push's
    ringing moves several samples).
    """
    lo, hi = max(i - 4, 0), min(i + 5, x.size)
    local = x[lo:hi].copy()
    k = i - lo
    if k < 2 or k + 2 >= local.size:
        return False
    local[k] = (-local[k - 2] + 4 * local[k - 1] + 4 * local[k + 1] - local[k + 2]) / 6
    r = residuals(local)
    r[k] = 0.0
    return bool(np.nanmax(np.abs(r), initial=0.0) <= limit)


def find_glitches(values: NDArray[np.float64], rule: GlitchRule = DEFAULT_RULE) -> NDArray[np.intp]:
    """Return the indices of the isolated wild samples of a signal (see the module notes).

    Parameters
    ----------
    values : ndarray, shape (n,)
        One signal's samples, at a constant sample rate (NaN for gaps), in any unit.
    rule : GlitchRule
        The threshold and the noise blocks.

    Returns
    -------
    ndarray of int
        Indices of the glitches, increasing.
    """
    x = np.asarray(values, dtype=float)
    r = residuals(x)
    scale = noise_scale(r, x, rule)
    with np.errstate(invalid="ignore"):
        candidates = np.flatnonzero(np.abs(r) > rule.threshold * scale)
    if not candidates.size:
        return candidates
    size = np.abs(r[candidates])
    before = x[candidates] - x[candidates - 1]
    after = x[candidates] - x[candidates + 1]
    apart = (np.sign(before) == np.sign(after)) & (np.abs(before) > size / 2) & (np.abs(after) > size / 2)
    found = [int(i) for i in candidates[apart]
             if _alone(x, int(i), rule.neighbour_threshold * scale[int(i)])]
    return np.array(found, dtype=np.intp)
