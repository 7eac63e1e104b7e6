"""Whether a fitted cause holds across speeds: its spread over speed groups, its drift with speed.

A physical cause has the same values at every speed. :func:`jackknife_std` measures how much the
values move when one speed is left out (errors shared by a speed's windows); :func:`speed_dependence`
fits the cause to the low and the high speeds apart and weighs whether its values differ;
:func:`lead_of_one_speed` finds a lead over a rival that the windows of one speed carry.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.fitting import (
    ROBUST_SCALE,
    CauseFit,
    Whitening,
    fit_cause,
    model_residuals,
    models_residuals,
    robust_chi2,
    robust_squares,
    window_whitening,
)
from whipple.diagnosis.instrument import INSTRUMENT_VALUES, InstrumentErrors
from whipple.diagnosis.observations import Observation, speed_groups
from whipple.errors import AnalysisError
from whipple.model.fleet import Model


@dataclass(frozen=True)
class SpeedDependence:
    """A cause fitted to the low and the high speeds apart.

    Attributes
    ----------
    split : float
        Speed between the two halves [m/s].
    low, high : tuple of float
        The cause's values fitted to the windows below and above ``split`` (units of the cause).
    evidence : float
        Approximate log Bayes factor of separate values for the two halves over one set:
        ``(chi2_one - chi2_low - chi2_high) / (2 D) - (k / 2) ln n``.
    design_effect : float
        D, the design effect of the two halves' residuals by speed group (>= 1): how much more
        the residuals of one speed's windows move together than independent noise would.
    """

    split: float
    low: tuple[float, ...]
    high: tuple[float, ...]
    evidence: float
    design_effect: float = 1.0


def jackknife_std(bicycle: Model, cause: Cause, observations: Sequence[Observation],
                  values: Sequence[float], scales: tuple[float, float] = (1.0, 1.0),
                  comparison: str = "eigenvalues", instrument: InstrumentErrors | None = None) -> NDArray[np.float64]:
    """Leave-one-speed-group-out jackknife standard deviation of a cause's values.

    The fit's own standard deviation assumes independent windows; errors shared by the windows
    of one speed (a fitting-function bias that depends on speed, a speed error) are not in it.
    The jackknife over speed groups is robust to such errors. Zero with fewer than 3 groups.
    ``comparison``: how models are compared with the windows
    (:data:`~whipple.diagnosis.fitting.COMPARISONS`; a fitting function's bias already taken out).
    With the samples, each left-out fit is a few Gauss-Newton steps from ``values``
    (:func:`gauss_newton_refits`): a full local refit of every window's samples per group cost
    most of a diagnosis. ``instrument``: the roll gyro's errors fitted with every model compared
    with the samples (:mod:`whipple.diagnosis.instrument`; None: not).
    """
    if len(speed_groups(observations)) < 3:
        return np.zeros(len(values))
    kept = left_out_groups(observations)
    if comparison == "samples":
        estimates = gauss_newton_refits(bicycle, cause, observations, values, kept, scales, instrument)
    else:
        estimates = refits_without(bicycle, cause, observations, values, kept, scales, comparison, instrument)
    if len(estimates) < 3:
        return np.zeros(len(values))
    estimates_array = np.array(estimates)
    g = len(estimates_array)
    return np.asarray(np.sqrt((g - 1) / g * np.sum((estimates_array - estimates_array.mean(axis=0)) ** 2, axis=0)))


def left_out_groups(observations: Sequence[Observation]) -> list[list[int]]:
    """Return the speed groups (indices) that can be left out in turn: each leaves at least 2 windows."""
    return [group for group in speed_groups(observations) if len(observations) - len(group) >= 2]


def without(observations: Sequence[Observation], group: Sequence[int]) -> list[Observation]:
    """Return the observations whose indices are not in `group`."""
    left_out = set(group)
    return [o for i, o in enumerate(observations) if i not in left_out]


def refits_without(bicycle: Model, cause: Cause, observations: Sequence[Observation], values: Sequence[float],
                   groups: Sequence[Sequence[int]], scales: tuple[float, float] = (1.0, 1.0),
                   comparison: str = "eigenvalues", instrument: InstrumentErrors | None = None
                   ) -> list[tuple[float, ...]]:
    """Return the cause's values refitted with each group of windows (indices) left out in turn.

    A local refit from `values` (fitted to all windows): it measures how those values move when
    a group is left out, not which other optimum a search could find. Each group must leave at
    least 2 windows. ``comparison`` and ``instrument`` as in :func:`jackknife_std`.
    """
    return [fit_cause(bicycle, cause, kept, window_whitening(kept, bicycle, scales, comparison, instrument), [values],
                      grid=False).values
            for kept in (without(observations, group) for group in groups)]


#: Step of the finite differences of :func:`gauss_newton_refits`, as a fraction of each value's bounds.
GAUSS_NEWTON_DIFFERENCE = 1e-4
#: Gauss-Newton steps of each left-out fit of :func:`gauss_newton_refits` (one step alone
#: understated the spread of a tyre relaxation length four times: its fit is far from linear).
GAUSS_NEWTON_STEPS = 3


def gauss_newton_refits(bicycle: Model, cause: Cause, observations: Sequence[Observation], values: Sequence[float],
                        groups: Sequence[Sequence[int]], scales: tuple[float, float] = (1.0, 1.0),
                        instrument: InstrumentErrors | None = None) -> list[tuple[float, ...]]:
    """Return the cause's values refitted to the samples with each group of windows left out.

    ``GAUSS_NEWTON_STEPS`` Gauss-Newton steps from `values` (fitted to all windows) on the
    windows kept, each ``(J^T W J)^-1 J^T W r`` with J the residuals' derivative by the values
    (forward differences of ``GAUSS_NEWTON_DIFFERENCE`` of the bounds) and W the robust loss's
    weights (soft L1: ``1 / sqrt(1 + r^2 / c^2)``), clipped to the bounds. Like the local refits
    of :func:`refits_without`, it measures how the values move when a group is left out, at a
    fraction of their cost (they were most of a diagnosis with the samples). ``instrument`` as in
    :func:`jackknife_std`.
    """
    lower, upper = cause.limits
    estimates = []
    for group in groups:
        kept = without(observations, group)
        whitening = window_whitening(kept, bicycle, scales, "samples", instrument)
        point = np.array(values, dtype=float)
        for _ in range(GAUSS_NEWTON_STEPS):
            difference = GAUSS_NEWTON_DIFFERENCE * (upper - lower)
            moved = np.where(point + difference <= upper, point + difference, point - difference)
            points = [point] + [np.where(np.arange(point.size) == i, moved, point) for i in range(point.size)]
            # The point and each one-value change of it in one evaluation of all their windows.
            rows = models_residuals([cause.apply(bicycle, list(x)) for x in points], kept, whitening,
                                    predict=False)[0]
            residual = rows[0]
            jacobian = ((rows[1:] - residual) / (moved - point)[:, None]).T
            weights = 1.0 / np.sqrt(1.0 + residual**2 / ROBUST_SCALE**2)
            # r = measured - model and J = dr/dvalues: the step that zeroes the weighted gradient.
            step = -np.linalg.lstsq(jacobian.T @ (weights[:, None] * jacobian), jacobian.T @ (weights * residual),
                                    rcond=None)[0]
            point = np.clip(point + step, lower, upper)
        estimates.append(tuple(float(v) for v in point))
    return estimates


def speed_group_sums(residuals: NDArray[np.float64], observations: Sequence[Observation],
                     whitening: Whitening) -> tuple[float, float]:
    """Return the sum of squares of the residuals summed per speed group and kind, and their count.

    ``residuals`` as :func:`~whipple.diagnosis.fitting.model_residuals` returns them. For
    independent unit noise the first is about the second; errors shared by a speed's windows
    (a fitting bias that depends on speed) make it larger: their ratio is the design effect.
    """
    windows, kinds = whitening.residual_layout()
    cells = _group_of_window(speed_groups(observations), len(observations))[windows] * 4 + kinds
    sums = np.bincount(cells, weights=residuals)
    return float(np.sum(sums**2)), float(len(residuals))


def _group_of_window(groups: Sequence[Sequence[int]], n_windows: int) -> NDArray[np.int_]:
    """Return each window's speed group (the index into `groups`, lists of window indices)."""
    group_of = np.empty(n_windows, dtype=int)
    for g, group in enumerate(groups):
        group_of[list(group)] = g
    return group_of


def speed_dependence(bicycle: Model, cause: Cause, observations: Sequence[Observation],
                     values: Sequence[float], scales: tuple[float, float],
                     comparison: str = "eigenvalues", instrument: InstrumentErrors | None = None
                     ) -> SpeedDependence | None:
    """Fit a cause to the low and the high speeds apart, to see whether its values depend on speed.

    A physical cause (a mass, a damper, a wrong parameter) has the same values at every speed.
    When the error's true form lies outside the cause's (a roll damping mimicked by a front
    payload), the values that fit best drift with speed: one set fits all speeds only by
    trading the low speeds against the high ones. The speed groups are split in two halves, the
    cause refitted to each from ``values`` (its fit to all windows; a local refit, so the
    evidence is never overstated), and the chi-squares compared at the diagnosis' dispersions
    ``scales``, charged for the k extra values like any cause (see the module's evidence), and
    for the instrument's values where they are fitted (each half has its own);
    ``comparison`` and ``instrument`` as in :func:`jackknife_std`.
    None where a half has fewer windows than values, or a refit fails.
    """
    groups = speed_groups(observations)
    halves = [[i for group in groups[:len(groups) // 2] for i in group],
              [i for group in groups[len(groups) // 2:] for i in group]]
    k = len(values)
    if min(len(half) for half in halves) <= k:
        return None
    whitening = window_whitening(observations, bicycle, scales, comparison, instrument)
    one = robust_chi2(model_residuals(cause.apply(bicycle, values), observations, whitening)[0])
    n = whitening.charged
    fits, shared, independent = [], 0.0, 0.0
    for half in halves:
        kept = [observations[i] for i in half]
        kept_whitening = window_whitening(kept, bicycle, scales, comparison, instrument)
        try:
            fit = fit_cause(bicycle, cause, kept, kept_whitening, [values], grid=False)
        except AnalysisError:
            return None
        fits.append(fit)
        squares, count = speed_group_sums(fit.residuals, kept, kept_whitening)
        shared, independent = shared + squares, independent + count
    # Residuals that a speed's windows share, left after each half has its own values, are not
    # a drift the split could explain: they make every chi-square difference larger by about
    # this design effect, so the evidence is discounted by it.
    design_effect = max(1.0, shared / independent)
    speeds = [[observations[i].speed for i in half] for half in halves]
    # Fitted apart, the halves free the instrument's values as well as the cause's (each half is
    # compared at its own best roll gyro), and are charged for both.
    fitted_instrument = whitening.samples is not None and whitening.samples.instrument_row() is not None
    freed = k + (INSTRUMENT_VALUES if fitted_instrument else 0)
    evidence = (one - fits[0].chi2 - fits[1].chi2) / (2.0 * design_effect) - 0.5 * freed * np.log(n)
    return SpeedDependence(float((max(speeds[0]) + min(speeds[1])) / 2.0), fits[0].values, fits[1].values,
                           float(evidence), design_effect)


def lead_of_one_speed(scored: Sequence[CauseFit], whitening: Whitening, observations: Sequence[Observation],
                       required: float) -> tuple[tuple[str, ...], str] | None:
    """Return the rivals whose lead by the best rests on the windows of one speed, and why; None if none.

    A rival's lead is the evidence difference; each speed group's share of it is half its part
    of the two fits' chi-square difference (at the values fitted to every window). A lead that
    falls below ``required`` once the largest share is taken away rests on that speed. Needs
    three speed groups at least (as the jackknife does: with two, every lead rests on one).
    """
    groups = speed_groups(observations)
    if len(groups) < 3:
        return None
    best = scored[0]
    windows, _ = whitening.residual_layout()
    cells = _group_of_window(groups, len(observations))[windows]
    own = robust_squares(best.residuals)
    rivals, shares = [], []
    for fit in scored[1:]:
        if fit.residuals.shape != best.residuals.shape:
            continue
        by_speed = 0.5 * np.bincount(cells, weights=robust_squares(fit.residuals) - own, minlength=len(groups))
        g = int(np.argmax(by_speed))
        if best.evidence - fit.evidence - by_speed[g] < required:
            rivals.append(fit.cause)
            shares.append((best.evidence - fit.evidence, float(by_speed[g]), g))
    if not rivals:
        return None
    lead, share, g = shares[0]
    speeds = [observations[i].speed for i in groups[g]]
    at = f"{min(speeds):.2f} m/s" if max(speeds) - min(speeds) < 0.005 else f"{min(speeds):.2f}-{max(speeds):.2f} m/s"
    return tuple(rivals), (f"{best.cause} leads {rivals[0]} by {lead:.1f} in evidence, but the windows at {at} give "
                           f"{share:.1f} of it: without them {rivals[0]} would fit about as well, so the lead rests "
                           "on one speed, not on the data as a whole")
