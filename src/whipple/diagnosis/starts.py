"""Starting values for fitting a cause: fixed points, quick ones, and the best points of a coarse grid.

A cause's fit (:func:`whipple.diagnosis.fitting.fit_cause`) is a local least-squares search;
several starts guard against local minima. The fixed starts sit near the cause's no-effect
values; for causes with two or three values, the best points of a coarse grid over the bounds
reach the rest of them.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.causes import Cause

#: Points per fitted value of the coarse grid over a cause's bounds (the centres of equal cells).
GRID_POINTS = 4
#: How many of the grid's best points start a fit of their own.
GRID_STARTS = 2
#: Causes with at most this many fitted values get the grid (4^3 = 64 model evaluations, about
#: the cost of one started fit); pairs start from their members' fitted values instead.
GRID_MAX_VALUES = 3
#: Causes with more fitted values than this (more than any pair) start from their no-effect values only.
LOCAL_VALUES = 8


def default_starts(cause: Cause) -> list[NDArray[np.float64]]:
    """Return the fixed starts, in the values' units.

    The no-effect values, steps of 2% and 10% of the bounds from them, and for a cause with
    several values three points spread over the bounds. A cause with more values than
    :data:`LOCAL_VALUES` (the calibration of every parameter) starts at its no-effect values only:
    its priors hold it near them, and each start costs a fit of that many values.
    """
    lower, upper = cause.limits
    start = np.array(cause.start, dtype=float)
    if len(cause.parameters) > LOCAL_VALUES:
        return [start]
    tries = [start] + [np.clip(start + (upper - lower) * f, lower, upper) for f in (0.02, 0.1)]
    if len(cause.parameters) > 1:
        tries += [lower + (upper - lower) * np.resize(np.array(f), len(lower))
                  for f in ((0.02, 0.1, 0.5), (0.1, 0.3, 0.4), (0.4, 0.05, 0.6))]
    return tries


def quick_starts(cause: Cause) -> list[list[float]]:
    """Return the no-effect values and 5% of the bounds away (a fit started on a bound can stall).

    A cause with more values than :data:`LOCAL_VALUES` (the calibration) starts at its no-effect
    values only, as in :func:`default_starts`: they are its priors' centres, inside its bounds, and
    a second start costs another fit of every parameter.
    """
    lower, upper = cause.limits
    start = np.array(cause.start, dtype=float)
    if len(cause.parameters) > LOCAL_VALUES:
        return [list(start)]
    return [list(start), [float(v) for v in np.clip(start + 0.05 * (upper - lower), lower, upper)]]


def grid_starts(cause: Cause, chi2: Callable[[list[NDArray[np.float64]]], Sequence[float]]
                ) -> list[NDArray[np.float64]]:
    """Return the ``GRID_STARTS`` points of a coarse grid over the bounds with the smallest ``chi2``.

    ``chi2(points)``: the misfit of the cause at each point's values (robust chi-square; not
    finite where the cause cannot take them), all points evaluated at once. Only for
    causes with 2 to ``GRID_MAX_VALUES`` values (one value is well served by the fixed starts),
    or, for a refinement (``cause.refines``), the values it refines, the rest held at their start.
    A payload's position does nothing at zero mass, so fits started at the no-effect values,
    near the frame's mass centre, stay in the basin around it: a basket's load ahead of the
    steer axis was fitted at the front frame's rear bound with chi-square 1476 where the load's
    own position gives 2.1 (Browser bicycle, hidden-effect trial basket 0), and other causes
    were blamed. The grid reaches every part of the bounds at the cost of ``GRID_POINTS ** k``
    model evaluations, no fits.
    """
    spanned = list(range(len(cause.parameters) if cause.refines is None else len(cause.refines)))
    if not 2 <= len(spanned) <= GRID_MAX_VALUES:
        return []
    lower, upper = cause.limits
    cells = (np.arange(GRID_POINTS) + 0.5) / GRID_POINTS
    points = []
    for fractions in itertools.product(cells, repeat=len(spanned)):
        point = np.array(cause.start, dtype=float)
        point[spanned] = lower[spanned] + (upper[spanned] - lower[spanned]) * np.array(fractions)
        points.append(point)
    scored = [(misfit, point) for misfit, point in zip(chi2(points), points, strict=True) if np.isfinite(misfit)]
    scored.sort(key=lambda entry: entry[0])
    return [point for _, point in scored[:GRID_STARTS]]


def refinement_starts(cause: Cause, simpler: Sequence[float]) -> list[list[float]]:
    """Return starts of a cause that refines a simpler form (``cause.refines``) fitted at ``simpler``.

    The simpler form's values, the extra values at 10% and at half of their bounds from their
    no-effect starts: not at the start itself, where an added inertia m k^2 has no slope in k.
    """
    lower, upper = cause.limits
    extra = slice(len(simpler), len(cause.parameters))
    start = np.array(cause.start, dtype=float)[extra]
    return [[*map(float, simpler), *map(float, np.clip(start + f * (upper[extra] - lower[extra]), lower[extra],
                                                       upper[extra]))]
            for f in (0.1, 0.5)]
