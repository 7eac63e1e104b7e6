"""A catch at a window's end, found in the fit's residual.

The window finder reads the roll rate swing by swing, so a window can only end at a swing's
extreme: a hand that catches the bicycle part-way through a swing (the bicycle leaning too
far, a growing weave) leaves the rest of that swing inside the window. The free motion ends
there, and the fitted function cannot follow the hand: its residual leaves the noise abruptly
and stays out of it to the window's end, and the eigenvalue fitted across it is biased. On
simulated runs, whose true free segments are known, 7% of the windows found so held part of
a catch, and the true model left them 5 times their noise off (median), where it leaves
clean windows at their noise.

:func:`catch_onset` finds such a tail: the end of the window where the residual's variance
is several times that of the rest, by more than chance allows (a change in variance,
located where it is most likely). :func:`whipple.measurement.experiment.measure_window`
cuts the window before it and fits again.

A hand that catches the bicycle a few samples before the window's end leaves too short a tail
inside it to stand out (the fit bends towards it), though its mark is plain right after: the
hand holds the bicycle still where the free motion would have swung on. The fit's continuation
is therefore compared with the samples after the window too, for :data:`LOOK_PAST` of a fitted
period (``after`` of :func:`catch_onset`): the tail may reach into them, and a catch is cut
where it starts inside the window. A window that ends where its free motion ends (a push, the
record's end) or that the free motion outlasts keeps its end: the tail starts at its end or
not at all.

The fitted function (a damped sinusoid on a constant) lacks the bicycle's slow modes: near a
window's end their drift can leave the residual a noise standard deviation or so to one side,
and a hand that takes hold there and moves the roll rate by as much to the other side leaves a
residual that barely changes variance until the held bicycle and the free motion have parted
far (on simulated runs the change was then placed 0.13 s after the catch). The test therefore
looks a second time (``terms`` of :func:`catch_onset`): before each possible catch it fits the
free motion again, at the fitted eigenvalue and with a quadratic baseline that follows the
drift (:data:`DRIFT_DEGREE`), to the samples before it alone, so that neither the drift nor
the hand bends the curve the samples after it are compared with. A catch is cut where either
look finds one inside the window, at the earlier.

A hand that takes hold while the free motion still swings and then holds the bicycle still
leaves no louder tail when the window runs on into the hold (the window finder ends a window
at a still stretch only where it sees the bicycle move again, and a coast shorter than a weave
cycle ends where its last swing does, well past the catch): the fit bends its damping to die
out into the held stretch, and its residual there is at the noise. It is the fit before the
hold that no longer follows the samples. :func:`hold_evidence` weighs the two readings of such
a window: one free motion throughout, or a free motion up to where the roll rate comes to rest
and a bicycle held still (a constant) from there. A free motion that decays into the noise
fits both alike; a hold makes the single free motion misfit the samples before it, by far
more than chance allows (:data:`HOLD_EVIDENCE`). Where the fitted function lacks some of the
bicycle's modes a free decay can do so too: a hold also needs the free motion fitted up to
the catch to leave the held samples a swing off (:data:`HOLD_MARK`; see
:func:`whipple.measurement.experiment.measure_window`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from whipple.measurement.noise import robust_scale
from whipple.measurement.swings import analysis_bin

#: A catch's residual variance is at least this many times the rest of the window's.
TAIL_VARIANCE = 4.0
#: Log-likelihood ratio of a tail of another variance against one variance throughout that a
#: catch needs: the best of a window's possible starts reaches a few units by chance, so 20
#: is out of reach of the noise of any window (a few thousand samples).
TAIL_EVIDENCE = 20.0
#: A catch is looked for in the window's second half only: the rest must hold the free motion.
KEPT_FRACTION = 0.5
#: Seconds [s] cut before the tail's first sample: the hand's force builds up from zero, so
#: its first samples stand out from the noise only a little.
ONSET_MARGIN = 0.02
#: Share of a fitted weave period after the window's end over which the fit's continuation is
#: compared with the samples: a quarter period, in which a held bicycle and the free motion
#: it stopped part by the free motion's amplitude whatever its phase at the catch.
LOOK_PAST = 0.25
#: Degree of the baseline of the free motion fitted before each possible catch in the second
#: look (quadratic: the fit's baseline that follows the slow capsize mode).
DRIFT_DEGREE = 2
#: Log-likelihood ratio of a free motion followed by a held, still bicycle against one free motion
#: throughout that a hold needs (as for a catch's louder tail: chance gives a few units).
HOLD_EVIDENCE = TAIL_EVIDENCE
#: Root-mean-square departure, in the fit's residual RMS, of the free motion fitted up to a
#: hand's catch from the held samples after it (over ``LOOK_PAST`` of a period) that a hold
#: needs: the free motion would have swung on well above the noise. Fits that lack some of
#: the bicycle's modes part from a free decay into the noise by up to 2.5 (simulated trials).
HOLD_MARK = 4.0


def look_past_samples(frequency: float, sample_rate: float) -> int:
    """Return how many samples :data:`LOOK_PAST` of a period spans (`frequency` [rad/s], `sample_rate` [Hz])."""
    return int(np.ceil(LOOK_PAST * 2 * np.pi / max(frequency, 1e-9) * sample_rate))


def catch_onset(time: NDArray[np.float64], residual: NDArray[np.float64], after: int = 0,
                terms: NDArray[np.float64] | None = None) -> int | None:
    """Return the index of the first sample of a catch at the window's end, or None.

    As :func:`_catch_onset_binned` (which documents the arguments and the test), on the samples
    averaged to at most :data:`~whipple.measurement.swings.ANALYSIS_RATE` (well above the
    weave's frequency and a hand's; the rate the test's levels were set at): a window's bins end
    at its last sample, and the samples past it fill bins of their own. A catch's mark and the
    weave lie below a few hertz, while white sensor noise spreads over the whole band up to half
    the sample rate: the more samples per second, the less a mark stands out of each sample's
    noise (a held bicycle's wobble, plain at 100 Hz, sank into it at 500 Hz on simulated runs),
    and averaging restores the contrast. Up to twice that rate, every sample is its own bin.
    """
    time = np.asarray(time, dtype=float)
    residual = np.atleast_2d(np.asarray(residual, dtype=float))
    step = float(np.median(np.diff(time))) if time.size > 1 else 0.0
    size = analysis_bin(1.0 / step) if step > 0 else 1
    if size <= 1:
        return _catch_onset_binned(time, residual, after, terms)
    inside = residual.shape[1] - after
    # Whole bins only: the window's first samples (far from any catch) and the last samples
    # past its end are left out.
    lead, past = inside % size, after // size
    stop = inside + past * size

    def binned(values: NDArray[np.float64]) -> NDArray[np.float64]:
        return values[..., lead:stop].reshape(*values.shape[:-1], -1, size).mean(axis=-1)

    binned_terms = None if terms is None else binned(np.asarray(terms, dtype=float).T).T
    onset = _catch_onset_binned(time[lead:stop:size], binned(residual), past, binned_terms)
    return None if onset is None else lead + onset * size


def _catch_onset_binned(time: NDArray[np.float64], residual: NDArray[np.float64], after: int = 0,
                        terms: NDArray[np.float64] | None = None) -> int | None:
    """Return the index of the first sample (or bin) of a catch at the window's end, or None.

    Parameters
    ----------
    time : ndarray, shape (n,)
        Sample times of the window [s], followed by those of the `after` samples past its end.
    residual : ndarray, shape (k, n)
        The fit's residual of each of the k fitted signals (signal units): the fitted curve's
        continuation for the samples past the window's end.
    after : int
        How many of the n samples lie past the window's end (0: none). The tail may start
        among them; a catch is only returned where it starts inside the window.
    terms : ndarray, shape (n, m), optional
        The terms of a free motion at every sample, whose span holds the fitted curve (the
        fit's terms with a baseline of :data:`DRIFT_DEGREE`,
        :meth:`~whipple.measurement.weavefit.WeaveFit.terms`): the second look, which fits
        them again before each possible catch. None: the first look alone.

    Returns
    -------
    int or None
        Where the window's free motion ends: the first sample kept out of it, ``ONSET_MARGIN``
        before the start of the tail. The tail is where the residual's variance changes most
        likely (a Gaussian residual of one variance before and another after, each signal
        scaled by its own robust spread over the window), in the window's second half or past
        its end; it is a catch when its variance is at least ``TAIL_VARIANCE`` times the rest's
        and the change's log-likelihood ratio exceeds ``TAIL_EVIDENCE``. The first look takes
        the residual as given; the second (with `terms`) the residual of the free motion
        fitted to the samples before each possible start. The earlier of the catches the two
        looks find; None when neither finds a tail that starts inside the window (a push or a
        catch right after the window starts at or past its end).
    """
    residual = np.atleast_2d(np.asarray(residual, dtype=float))
    signals, n = residual.shape
    inside = n - after
    first = int(np.ceil(KEPT_FRACTION * inside))
    if n - first < 2 or first < 2 or inside < 1:
        return None
    # The noise's scale from the window alone: the samples past it may be all catch.
    scale = robust_scale(residual[:, :inside])
    if not np.all(scale > 0):
        return None
    z = residual / scale[:, None]
    cuts = np.arange(first, n - 1)
    looks = [_as_given(z, cuts)]
    if terms is not None:
        looks.append(_refitted(z, np.asarray(terms, dtype=float), cuts, inside))
    starts = [_tail_start(cuts, head, tail, whole, signals, n, inside) for head, tail, whole in looks]
    found = [start for start in starts if start is not None]
    if not found:
        return None
    step = float(np.median(np.diff(time)))
    margin = int(np.ceil(ONSET_MARGIN / step)) if step > 0 else 0
    return max(min(found) - margin, 1)


def _as_given(z: NDArray[np.float64], cuts: NDArray[np.intp]) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """Mean squared residual (over the signals) before and from each cut, and over all samples."""
    z2 = np.mean(z**2, axis=0)
    before = np.cumsum(z2)
    n = z2.size
    return before[cuts - 1] / cuts, (before[-1] - before[cuts - 1]) / (n - cuts), float(before[-1] / n)


def _refitted(z: NDArray[np.float64], terms: NDArray[np.float64], cuts: NDArray[np.intp],
              inside: int) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """As :func:`_as_given`, the free motion's terms fitted again to the samples before each cut.

    The null (one variance throughout) takes them fitted to the whole window. Least squares
    through running sums of the normal equations: one small solve per cut.
    """
    signals, n = z.shape
    # Columns of one size keep the normal equations well conditioned.
    x = terms / np.maximum(np.max(np.abs(terms), axis=0), 1e-300)
    gram = np.cumsum(x[:, :, None] * x[:, None, :], axis=0)
    moment = np.cumsum(x[:, :, None] * z.T[:, None, :], axis=0)
    square = np.cumsum(z.T**2, axis=0)

    def fitted(stop: NDArray[np.intp]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Squared residual summed over the signals: before `stop`, and over all samples."""
        coefficients = np.linalg.pinv(gram[stop - 1]) @ moment[stop - 1]
        head = square[stop - 1].sum(-1) - np.sum(moment[stop - 1] * coefficients, axis=(-2, -1))
        total = (square[-1].sum() - 2 * np.sum(moment[-1] * coefficients, axis=(-2, -1))
                 + np.sum(coefficients * (gram[-1] @ coefficients), axis=(-2, -1)))
        return np.maximum(head, 0.0), np.maximum(total, head)

    head, total = fitted(cuts)
    _, null = fitted(np.array([inside]))
    return head / (signals * cuts), (total - head) / (signals * (n - cuts)), float(null[0] / (signals * n))


def _tail_start(cuts: NDArray[np.intp], head: NDArray[np.float64], tail: NDArray[np.float64],
                whole: float, signals: int, n: int, inside: int) -> int | None:
    """Return the first sample of the tail most likely of another variance, if a catch inside the window.

    `head` and `tail` are the mean squared residuals before and from each of `cuts`, `whole`
    over all n samples (one variance throughout).
    """
    with np.errstate(divide="ignore"):
        log_likelihood = -0.5 * signals * (cuts * np.log(head) + (n - cuts) * np.log(tail))
    best = int(np.argmax(log_likelihood))
    if not (np.isfinite(log_likelihood[best]) and tail[best] >= TAIL_VARIANCE * head[best]):
        return None
    evidence = log_likelihood[best] + 0.5 * signals * n * np.log(whole)
    if evidence < TAIL_EVIDENCE or cuts[best] >= inside:
        return None
    return int(cuts[best])


def hold_evidence(free: NDArray[np.float64], head: NDArray[np.float64], still: NDArray[np.float64]) -> float:
    """Return the log-likelihood ratio of a window held still from some sample on against one free motion.

    Parameters
    ----------
    free : ndarray, shape (k, n)
        Residual of the free motion fitted to the whole window, for each of the k fitted signals
        (signal units).
    head : ndarray, shape (k, m)
        Residual of the free motion fitted to the window's first m samples alone: those before
        the roll rate comes to rest.
    still : ndarray, shape (k, n - m)
        The samples from there to the window's end (signal units): a held bicycle keeps each
        signal at a constant.

    Returns
    -------
    float
        ``n / 2`` times the sum over the signals of the log of the whole fit's squared residual
        over that of the free motion before the stillness and the constant after it (each
        signal Gaussian with its own variance, profiled out). Near zero or below when the free
        motion decays into the noise there; at least :data:`HOLD_EVIDENCE` for a hold. Infinite
        when the second reading leaves no residual at all.
    """
    free, head, still = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (free, head, still))
    whole = np.sum(free**2, axis=1)
    split = np.sum(head**2, axis=1) + np.sum((still - still.mean(axis=1, keepdims=True))**2, axis=1)
    if not np.all(split > 0):
        return np.inf
    with np.errstate(divide="ignore"):
        return float(0.5 * free.shape[1] * np.sum(np.log(whole / split)))
