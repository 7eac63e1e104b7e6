"""Which pairs of causes to fit jointly when no single cause explains the windows.

Fitting a pair is as costly as fitting a cause, and there are hundreds of pairs; the diagnosis
(:func:`whipple.diagnosis.evidence.diagnose_observations`) fits a few: the pairs of the leading
single causes (:func:`leading_pairs`) and those a linearised screen of every pair says the
evidence would favour (:func:`screened_pairs`). The true pair is often not among the leading
singles (docs/diagnosis.md, "Two causes together").
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.families import combined_cause, components
from whipple.diagnosis.fitting import CauseFit, Whitening, model_residuals
from whipple.diagnosis.observations import Observation
from whipple.model.fleet import Model

#: Fraction of a cause's bounds from its no-effect values to the screen's active point.
SCREEN_ACTIVE = 0.1


def leading_pairs(causes: Sequence[Cause], scored: Sequence[CauseFit], count: int = 3
                  ) -> list[tuple[Cause, list[float]]]:
    """Pairs of the ``count`` leading causes, each in its best-supported form (``PairRules.leading``).

    Each with its starting values: its members' fitted values.
    """
    order = sorted(range(len(causes)), key=lambda i: -scored[i].evidence)
    leading: list[int] = []
    for i in order:
        if causes[i].name not in {causes[j].name for j in leading} and scored[i].evidence > 0.0:
            leading.append(i)
    return [(combined_cause(causes[i], causes[j]), [*scored[i].values, *scored[j].values])
            for i, j in itertools.combinations(leading[:count], 2)]


def screened_pairs(bicycle: Model, causes: Sequence[Cause], fits: Sequence[CauseFit],
                   observations: Sequence[Observation], whitening: Whitening,
                   tried: set[str], dispersions: tuple[int, tuple[float, float]],
                   counts: tuple[int, int] = (3, 3)) -> list[tuple[Cause, list[float]]]:
    """Return the pairs, not in ``tried``, that the evidence would favour, linearised.

    ``counts[0]`` pairs linearised at the base model: both members at their no-effect
    values, scored by the least-squares step of both from the base model's residuals. Then
    ``counts[1]`` more, linearised away from it: each member at one of three points,
    its no-effect values, its values fitted alone or an active point (``SCREEN_ACTIVE`` of its
    bounds away from the no-effect values), not both at the no-effect values; the effects are
    taken to add up (a pair's residuals are those of its members at their points, less the base
    model's once), and a pair is scored by the best of these combinations. The score is the
    evidence's own measure, linearised: half the least-squares misfit (each kind of residual
    divided by its dispersion, ``dispersions``: the number of eigenvalue residuals and the two
    dispersions) plus ln(n)/2 per fitted value, less the log prior. By the misfit alone, pairs
    of payloads (six values) led the screen whatever the data, and a pair of two one-value
    causes that explained the windows was never fitted (docs/diagnosis.md, "Two effects
    together"). Some values do
    nothing at the no-effect values (a payload's position at zero mass): only the second screen
    can move them. Each pair starts from its step, within bounds. Residual derivatives are
    steps of 5% of a cause's bounds (0.5% away from the no-effect values). The true pair is
    often not among the leading singles (docs/diagnosis.md, "Two causes together").
    """
    residual = model_residuals(bicycle, observations, whitening)[0]
    split, (eigenvalue_scale, shape_scale) = dispersions
    weights = np.where(np.arange(residual.size) < split, 1.0 / eigenvalue_scale, 1.0 / shape_scale)
    root_weights = np.sqrt(weights)
    charge = 0.5 * np.log(max(residual.size, 1))
    points = []
    for cause, fit in zip(causes, fits, strict=True):
        lower, upper = cause.limits
        active = np.clip(np.array(cause.start, dtype=float) + SCREEN_ACTIVE * (upper - lower), lower, upper)
        active_residual = model_residuals(cause.apply(bicycle, [float(v) for v in active]), observations, whitening)[0]
        points.append([
            (np.array(cause.start, dtype=float), residual,
             _residual_derivatives(bicycle, cause, observations, whitening, cause.start, residual, 0.05)),
            (np.array(fit.values), fit.residuals,
             _residual_derivatives(bicycle, cause, observations, whitening, fit.values, fit.residuals, 0.005)),
            (active, active_residual,
             _residual_derivatives(bicycle, cause, observations, whitening, active, active_residual, 0.005))])
    at_base, away = [], []
    for i, j in itertools.combinations(range(len(causes)), 2):
        if causes[i].name == causes[j].name:
            continue
        pair = combined_cause(causes[i], causes[j])
        linearised = []
        for (origin_i, residual_i, columns_i), (origin_j, residual_j, columns_j) in itertools.product(points[i],
                                                                                                    points[j]):
            origin_residual = residual_i + residual_j - residual
            jacobian = np.hstack([columns_i, columns_j])
            step = np.linalg.lstsq(jacobian * root_weights[:, None], -origin_residual * root_weights, rcond=None)[0]
            misfit = float(np.sum(weights * (origin_residual + jacobian @ step) ** 2))
            score = 0.5 * misfit + charge * len(pair.parameters) - np.log(pair.prior)
            linear = np.clip(np.concatenate([origin_i, origin_j]) + step, *pair.limits)
            linearised.append((score, pair, [float(v) for v in linear]))
        at_base.append(linearised[0])
        away.append(min(linearised[1:], key=lambda entry: entry[0]))
    chosen: list[tuple[Cause, list[float]]] = []
    tried_members = {frozenset(components(name)) for name in tried}
    for ranked, count in zip((at_base, away), counts, strict=True):
        added = 0
        for _, pair, start in sorted(ranked, key=lambda entry: entry[0]):
            members = frozenset(components(pair.name))
            if added == count:
                break
            if members not in tried_members:
                chosen.append((pair, start))
                tried_members.add(members)
                added += 1
    return chosen


def _residual_derivatives(bicycle: Model, cause: Cause, observations: Sequence[Observation],
                          whitening: Whitening, values: Sequence[float] | NDArray[np.float64],
                          residual: NDArray[np.float64],
                          fraction: float) -> NDArray[np.float64]:
    """Return the derivative of the residuals by each of a cause's values at ``values`` (a column each).

    A forward step of ``fraction`` of the value's bounds (backward at the upper bound).
    """
    origin = np.array(values, dtype=float)
    columns = []
    for i, (low, high) in enumerate(cause.bounds):
        x = origin.copy()
        step = fraction * (high - low)
        x[i] = origin[i] + step if origin[i] + step <= high else origin[i] - step
        changed = model_residuals(cause.apply(bicycle, [float(v) for v in x]), observations, whitening)[0]
        columns.append((changed - residual) / (x[i] - origin[i]))
    return np.column_stack(columns)
