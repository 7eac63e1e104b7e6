"""The diagnosis' nearest modes by eig of the first-order state matrices (tests and benchmarks).

The method :func:`whipple.stability.nearest_modes.nearest_modes` used before it took the roots of
the characteristic quartic (:mod:`whipple.stability.quartic`): the independent check of that
closed form, and the baseline of ``benchmarks/bench_modes.py``.
"""

from __future__ import annotations

import numpy as np

from whipple.model.assembly import linear_model
from whipple.stability.nearest_modes import MODE_SHAPE_STATES


def nearest_modes_by_eig(bicycle, speeds, targets, signals):
    """Return the eigenvalue nearest each target [1/s] and its mode shape, from eig of A(v).

    As :func:`whipple.stability.nearest_modes.nearest_modes`, with a shape for every window
    (``signals`` one pair of state names per window).
    """
    values, vectors = np.linalg.eig(linear_model(bicycle).state_matrix(bicycle.model_speed(speeds)))
    lower = values.imag < 0
    values = np.where(lower, np.conj(values), values)
    nearest = np.argmin(np.abs(values - np.asarray(targets)[:, None]), axis=1)
    rows = np.arange(len(speeds))
    # The eigenvector of the upper-half-plane eigenvalue: conjugated where eig gave the lower.
    vector = np.where(lower[rows, nearest][:, None], np.conj(vectors[rows, :, nearest]), vectors[rows, :, nearest])
    numerator = [MODE_SHAPE_STATES[pair[0]] for pair in signals]
    denominator = [MODE_SHAPE_STATES[pair[1]] for pair in signals]
    return values[rows, nearest], vector[rows, numerator] / vector[rows, denominator]
