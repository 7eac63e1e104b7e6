"""Which mode crosses the imaginary axis at a critical speed, decided at the root alone.

:mod:`whipple.stability.modes` names branches tracked over a whole speed grid. The critical-speed
solver has no grid, so the crossing eigenvalue is named from the eigenvalues and eigenvectors at
the root, with the same rules read locally:

* a complex pair (Hopf root) is the ``weave`` when it has the lowest frequency of the complex
  pairs there, else ``mode_<k>`` (k its column after the weave pair and the real modes);
* a real eigenvalue belongs to the weave group when, followed over speed from the root (a short
  fixed path, :data:`PATH_POINTS` speeds up to ``max(3 v, v + 10 m/s)``), it merges with another
  real eigenvalue into a complex pair: then it is ``weave_real_upper`` or ``weave_real_lower`` by
  its rank against that partner; this is needed only where no complex pair exists at the root;
* otherwise, of the real eigenvalues outside the weave group, ``capsize`` is the one with the
  largest real part among the roll-dominated ones (``|roll| >= |steer|`` in the eigenvector, both
  in rad; among all if none is), ``castering`` the most steer-dominated of the rest, anything
  else ``mode_<k>``.

These reproduce the grid labels on the bicycles of the tests; the labels only name crossings,
the speeds and stable ranges never depend on them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from whipple.stability import modes
from whipple.stability.polynomial import state_matrices_at

#: Speeds on the path along which a real crossing eigenvalue is followed.
PATH_POINTS = 24


def _is_real(values: NDArray[np.complex128]) -> NDArray[np.bool_]:
    return np.abs(values.imag) <= modes.REAL_TOLERANCE * (1.0 + np.abs(values))


def _joins_weave(coefficients: NDArray[np.float64], speed: NDArray[np.float64],
                 eigenvalues: NDArray[np.complex128], branch: NDArray[np.intp]
                 ) -> tuple[NDArray[np.bool_], NDArray[np.intp]]:
    """Follow eigenvalue `branch` forward in speed: whether it becomes complex, and with whom.

    `coefficients` (R, T, n, n) are those of each root's model; every eigenvalue is real at the
    root. Real eigenvalues of a real matrix family keep their order until two of them merge
    into a complex pair, so no tracking is needed: at the first path speed with fewer real
    eigenvalues, the two real ones of the previous speed that have no counterpart left are
    the merged pair, and ranks at the root identify them. Returns, per root, whether the
    branch is one of them and the index (at the root) of the other.
    """
    count, n = eigenvalues.shape
    rows = np.arange(count)
    top = np.maximum(3.0 * np.abs(speed), np.abs(speed) + 10.0) * np.where(speed < 0, -1.0, 1.0)
    fractions = np.linspace(0.0, 1.0, PATH_POINTS + 1)[1:] ** 2
    path = speed[:, None] + (top - speed)[:, None] * fractions
    A = state_matrices_at(coefficients, np.repeat(rows, fractions.size), path.ravel())
    walk = np.concatenate([eigenvalues[:, None],
                           np.linalg.eigvals(A).reshape(count, fractions.size, n)], axis=1)
    real = _is_real(walk)
    fewer = np.sum(real, axis=-1) < n
    becomes = np.any(fewer, axis=-1)
    after = np.where(becomes, np.argmax(fewer, axis=-1), 1)
    before = np.sort(walk[rows, after - 1].real, axis=-1)
    left = np.where(real[rows, after], walk[rows, after].real, np.nan)
    with np.errstate(invalid="ignore"):
        distance = np.nanmin(np.abs(before[:, :, None] - left[:, None, :]), axis=-1,
                             initial=np.inf)
    merged = np.argsort(-np.where(np.isfinite(distance), distance, np.inf), axis=-1)[:, :2]
    rank = np.argsort(np.argsort(eigenvalues.real, axis=-1), axis=-1)
    own = rank[rows, branch]
    joins = becomes & np.any(merged == own[:, None], axis=-1)
    other_rank = np.where(merged[:, 0] == own, merged[:, 1], merged[:, 0])
    partner = np.argmax(rank == other_rank[:, None], axis=-1)
    return joins, partner


def crossing_modes(kind: str, coefficients: NDArray[np.float64], model: NDArray[np.intp],
                   speed: NDArray[np.float64], eigenvalues: NDArray[np.complex128],
                   share: NDArray[np.float64], branch: NDArray[np.intp]) -> NDArray[np.str_]:
    """Label of the crossing eigenvalue at each root (see the module docstring).

    Parameters
    ----------
    kind : {'hopf', 'real'}
        The condition whose roots these are.
    coefficients : ndarray, shape (B, T, n, n)
        Polynomial coefficients of the state matrices of the models.
    model : ndarray of int, shape (R,)
        Model of each root.
    speed : ndarray, shape (R,)
        The roots [m/s].
    eigenvalues : ndarray, shape (R, n), complex
        Eigenvalues [1/s] of A at each root.
    share : ndarray, shape (R, n)
        ``|roll| / (|roll| + |steer|)`` of each eigenvector (angles in rad).
    branch : ndarray of int, shape (R,)
        Index of the crossing eigenvalue in `eigenvalues`.

    Returns
    -------
    ndarray of str, shape (R,)
    """
    count, n = eigenvalues.shape
    labels = np.empty(count, dtype="<U20")
    if count == 0:
        return labels
    rows = np.arange(count)
    real = _is_real(eigenvalues)
    value = eigenvalues[rows, branch]
    n_real = np.sum(real, axis=-1)
    fixed_columns = 2 + np.minimum(n_real, 2)
    if kind == "hopf":
        frequency = np.where(real | (eigenvalues.imag <= 0), np.inf, eigenvalues.imag)
        rank = np.sum(frequency < np.abs(value.imag)[:, None] * (1.0 - 1e-12), axis=-1)
        labels[:] = np.where(rank == 0, modes.WEAVE,
                             np.char.add("mode_", (fixed_columns + 2 * rank - 1).astype(str)))
        return labels
    has_pair = np.any(~real, axis=-1)
    in_weave = np.zeros(count, dtype=bool)
    partner = np.zeros(count, dtype=np.intp)
    scan = np.nonzero(~has_pair)[0]
    if scan.size:
        in_weave[scan], partner[scan] = _joins_weave(
            coefficients[model[scan]], speed[scan], eigenvalues[scan], branch[scan])
    upper = value.real >= eigenvalues[rows, partner].real
    labels[in_weave] = np.where(upper, modes.WEAVE_UPPER, modes.WEAVE_LOWER)[in_weave]
    # Real modes outside the weave group.
    outside = real.copy()
    outside[in_weave, branch[in_weave]] = False
    outside[in_weave, partner[in_weave]] = False
    rolling = outside & (share >= 0.5)
    candidates = np.where(np.any(rolling, axis=-1)[:, None], rolling, outside)
    capsize = np.argmax(np.where(candidates, eigenvalues.real, -np.inf), axis=-1)
    remaining = outside.copy()
    remaining[rows, capsize] = False
    castering = np.argmax(np.where(remaining, 1.0 - share, -np.inf), axis=-1)
    is_capsize = ~in_weave & (capsize == branch)
    is_castering = ~in_weave & ~is_capsize & (castering == branch) & np.any(remaining, axis=-1)
    labels[is_capsize] = modes.CAPSIZE
    labels[is_castering] = modes.CASTERING
    other = ~in_weave & ~is_capsize & ~is_castering
    ranked = np.sum(np.where(remaining, eigenvalues.real, -np.inf) > value.real[:, None], axis=-1)
    labels[other] = np.char.add("mode_", (fixed_columns + ranked + 1).astype(str))[other]
    return labels
