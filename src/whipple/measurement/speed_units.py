"""Whether a run's speed has the model's units, judged by the weave's eigenvalues.

The weave's eigenvalue moves with speed along a curve of the model's. A speed column in km/h
read as m/s puts every window at 3.6 times its speed, where the model's weave is another
oscillation altogether; the measured eigenvalues then lie on the model's curve, to within the
model's own error, at 0.278 times the logged speeds (mph: 0.447), and every cause fitted to
them is a fit to the unit. :func:`speed_unit_problem` finds that: for each window, the speed at
which the model's oscillating mode nearest the measured eigenvalue comes closest to it, as a
multiple of the window's logged speed; a problem when most windows agree on one multiple
outside the range the diagnosis can explain (:data:`SPEED_SCALE_RANGE`, the ``speed_scale``
cause's) and lie close to the curve there.

A cause of the bicycle can move the weave as far along the speed axis (a heavy front load: to
half the speed) off the curve, and yet come within a few percent of it (a front load of 13 kg
on the Browser: 6-8 % at half the logged speed); so the finding is a caveat of the diagnosis
and a note of ``whipple fit``, not a refusal.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from whipple.measurement.experiment import WindowMeasurement
from whipple.model.fleet import Model
from whipple.model.parameters import Bicycle
from whipple.stability.nearest_modes import nearest_oscillations

#: The factors on the logged speed the diagnosis explains (the ``speed_scale`` cause's bounds).
SPEED_SCALE_RANGE = (0.5, 2.0)
#: Share of the windows that must agree on the multiple (within :data:`AGREEMENT` of their median).
AGREEING = 2 / 3
#: Relative spread of the windows' multiples counted as agreeing.
AGREEMENT = 0.25
#: Largest median distance, relative to the measured eigenvalue, of the model's mode at the
#: agreed multiple: a speed in other units leaves the model's own error (simulated runs: 0.2-1.7 %
#: at 0.279 and 0.448 times the logged speed); a cause that bends the curve as much leaves more
#: (a front load of 9 kg on the Browser: 21-23 % at 0.49 times the logged speed; of 13 kg,
#: 6-8 %: the rule cannot tell every such load from a unit, hence a caveat).
MATCH = 0.1
#: Speeds searched, as multiples of each window's logged speed: from a tenth to five times
#: (km/h read as m/s: 0.278; m/s scaled as if km/h: 3.6).
MULTIPLES = np.geomspace(0.1, 5.0, 241)


def speed_multiples(bicycle: Bicycle, speeds: NDArray[np.float64], eigenvalues: NDArray[np.complex128]
                    ) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """Return, per window, the multiple of its speed where the model's mode comes closest, whether it is near, how near.

    Parameters
    ----------
    bicycle : Bicycle
        The model.
    speeds : ndarray, shape (N,)
        The windows' logged speeds [m/s].
    eigenvalues : ndarray of complex, shape (N,)
        The windows' measured eigenvalues [1/s].

    Returns
    -------
    multiples : ndarray, shape (N,)
        The multiple of :data:`MULTIPLES` at which the model's oscillating mode nearest the
        measured eigenvalue is closest to it (NaN where the model never oscillates).
    near : ndarray of bool, shape (N,)
        Whether that mode is near the measured eigenvalue there
        (:func:`~whipple.stability.nearest_modes.near_oscillation`).
    distance : ndarray, shape (N,)
        Its distance from the measured eigenvalue there, relative to the measured eigenvalue's
        magnitude (inf where the model never oscillates).
    """
    grid = speeds[:, None] * MULTIPLES[None, :]
    targets = np.broadcast_to(eigenvalues[:, None], grid.shape)
    predicted, near_grid = nearest_oscillations(bicycle, grid.ravel(), targets.ravel())
    predicted, near_grid = predicted.reshape(grid.shape), near_grid.reshape(grid.shape)
    distance = np.where(np.isfinite(predicted), np.abs(predicted - targets), np.inf)
    best = np.argmin(distance, axis=1)
    rows = np.arange(speeds.size)
    closest = distance[rows, best]
    found = np.isfinite(closest)
    return np.where(found, MULTIPLES[best], np.nan), found & near_grid[rows, best], closest / np.abs(eigenvalues)


def speed_unit_problem(bicycle: Model, measurements: Sequence[WindowMeasurement]) -> str | None:
    """Say why the usable windows' speeds seem to be in other units than the model's, or None.

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The model (a fleet, whose windows have bicycles of their own, is not checked).
    measurements : sequence of WindowMeasurement
        The windows; the usable ones with a fitted eigenvalue and a speed are compared.

    Returns
    -------
    str or None
        A sentence when at most a third of the windows have a model mode near their eigenvalue at
        their logged speed, and at least :data:`AGREEING` of them come near it at one multiple of
        that speed (within :data:`AGREEMENT`) outside :data:`SPEED_SCALE_RANGE`, within
        :data:`MATCH` of it (median); else None.
    """
    if not isinstance(bicycle, Bicycle):
        return None
    pairs = [(m.speed.mean, m.fit.eigenvalue) for m in measurements
             if m.usable and m.fit is not None and m.speed is not None and m.speed.mean > 0]
    if len(pairs) < 2:
        return None
    speeds = np.array([speed for speed, _ in pairs], dtype=np.float64)
    eigenvalues = np.array([eigenvalue for _, eigenvalue in pairs], dtype=np.complex128)
    _, near_logged = nearest_oscillations(bicycle, speeds, eigenvalues)
    if np.mean(near_logged) > 1 - AGREEING:
        return None
    multiples, near, distance = speed_multiples(bicycle, speeds, eigenvalues)
    if not near.any():
        return None
    median = float(np.median(multiples[near]))
    agreeing = near & (np.abs(multiples / median - 1) <= AGREEMENT)
    low, high = SPEED_SCALE_RANGE
    if np.mean(agreeing) < AGREEING or low <= median <= high or np.median(distance[agreeing]) > MATCH:
        return None
    return (f"the measured weave matches the model's at {median:.3g} times the logged speed in {int(agreeing.sum())} "
            f"of {len(pairs)} windows, and at the logged speed in {int(near_logged.sum())}"
            ": is the speed in other units? (km/h read as m/s gives 0.278, mph 0.447; a layout's [scale] converts it)")
