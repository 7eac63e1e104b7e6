"""Following eigenvalues across speed and naming the bicycle's modes.

Tracking
    Eigenvalues come out of ``numpy.linalg.eig`` in no particular order. Between neighbouring
    speeds of a fine grid each eigenvalue is matched to the nearest one at the next speed; where
    nearest neighbours do not form a one-to-one matching (near a double root, say), the optimal
    assignment on squared distance is solved with ``scipy.optimize.linear_sum_assignment``. The
    step permutations are then composed with a parallel prefix scan, so there is no Python
    loop over speeds or parameter sets (only over the rare ambiguous steps).

Labelling
    A tracked *branch* keeps its identity over the whole grid; the labels below are properties
    of branches, decided once per branch, so they cannot swap between neighbouring speeds:

    * branches that are complex conjugates of each other at some non-negative speed form an
      oscillatory group (all rules look at non-negative speeds only, where there are any);
    * ``weave``: the oscillatory group that is complex on at least half the (non-negative)
      speeds with the lowest median frequency, else the one complex on most speeds. Where
      its branches are real (below the speed where weave forms from two real modes, the
      double root) they are ``weave_real_upper`` and ``weave_real_lower`` by real part;
    * ``capsize``: of the branches that are always real, the one with the largest mean real
      part among those dominated by roll (roll/steer amplitude of the eigenvector, both in
      rad), or among all if none is;
    * ``castering``: of the remaining always-real branches, the most steer-dominated one;
    * anything else (extra states of extended models, a second oscillatory group such as
      wobble) is ``mode_<column>``, by its column after ordering.

    Columns are ordered weave group, capsize, castering, then the rest by decreasing mean
    real part.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

#: Relative size of an imaginary part below which an eigenvalue is treated as real (eig
#: resolves a double root only to about the square root of machine precision).
REAL_TOLERANCE = 1e-6

WEAVE = "weave"
WEAVE_UPPER = "weave_real_upper"
WEAVE_LOWER = "weave_real_lower"
CAPSIZE = "capsize"
CASTERING = "castering"
#: Labels by integer code; code ``len(NAMES) + k`` is ``mode_<k + 1>``.
NAMES = (WEAVE, WEAVE_UPPER, WEAVE_LOWER, CAPSIZE, CASTERING)


def track(eigenvalues: NDArray[np.complex128]) -> NDArray[np.intp]:
    """Column permutations that follow each eigenvalue continuously along the speed axis.

    Parameters
    ----------
    eigenvalues : ndarray, shape (B, S, n)
        Eigenvalues [1/s] of B models at S increasing speeds, in any order per speed.

    Returns
    -------
    ndarray of int, shape (B, S, n)
        ``order``: ``eigenvalues[b, s, order[b, s, k]]`` is branch k at speed s. Branches
        start sorted by real part, then imaginary part, at the first speed.
    """
    batch, speeds, n = eigenvalues.shape
    start = np.lexsort((eigenvalues[:, 0].imag, eigenvalues[:, 0].real), axis=-1)
    if speeds == 1:
        return start[:, None, :]
    distance = np.abs(eigenvalues[:, :-1, :, None] - eigenvalues[:, 1:, None, :])
    step = np.argmin(distance, axis=-1)  # step[b, s, i]: position at s+1 of position i at s
    ambiguous = np.any(np.sort(step, axis=-1) != np.arange(n), axis=-1)
    for b, s in zip(*np.nonzero(ambiguous), strict=True):
        rows, columns = linear_sum_assignment(distance[b, s] ** 2)
        step[b, s, rows] = columns
    # Inclusive prefix scan of the step maps (composition is associative): after it,
    # maps[b, s] sends a position at speed 0 to the position of the same branch at speed s.
    maps = np.concatenate([np.broadcast_to(np.arange(n), (batch, 1, n)), step], axis=1)
    shift = 1
    while shift < speeds:
        composed = np.take_along_axis(maps[:, shift:], maps[:, :-shift], axis=-1)
        maps = np.concatenate([maps[:, :shift], composed], axis=1)
        shift *= 2
    return np.take_along_axis(maps, np.broadcast_to(start[:, None, :], maps.shape), axis=-1)


def _groups(eigenvalues: NDArray[np.complex128], complex_: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """``same[b, j, k]``: branches j and k are linked by being complex conjugates somewhere."""
    n = eigenvalues.shape[-1]
    gap = np.abs(eigenvalues[..., :, None] - np.conj(eigenvalues[..., None, :]))
    gap[..., np.arange(n), np.arange(n)] = np.inf
    partner = np.argmin(gap, axis=-1)
    linked = np.any((partner[..., None] == np.arange(n)) & complex_[..., None], axis=1)
    same = (linked | np.swapaxes(linked, -1, -2) | np.eye(n, dtype=bool)).astype(np.int64)
    for _ in range(int(np.ceil(np.log2(max(n, 2))))):
        same = np.minimum(same @ same, 1)
    return same.astype(bool)


def label(
    eigenvalues: NDArray[np.complex128],
    roll_share: NDArray[np.float64],
    speeds: NDArray[np.float64],
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Name the tracked branches of B models (see the module docstring for the rules).

    Parameters
    ----------
    eigenvalues : ndarray, shape (B, S, n)
        Tracked eigenvalues [1/s] (column k is branch k at every speed).
    roll_share : ndarray, shape (B, S, n)
        ``|roll| / (|roll| + |steer|)`` of each branch's eigenvector (angles in rad); NaN
        where not computed (ignored in the means).
    speeds : ndarray, shape (S,)
        The increasing speeds [m/s].

    Returns
    -------
    columns : ndarray of int, shape (B, n)
        Display order of the branches: ``eigenvalues[b, :, columns[b]]``.
    codes : ndarray of int, shape (B, S, n)
        Label of each eigenvalue after reordering by ``columns``, as an index into
        :data:`NAMES` (see :func:`names`).
    """
    batch, _, n = eigenvalues.shape
    magnitude = 1.0 + np.abs(eigenvalues)
    complex_ = np.abs(eigenvalues.imag) > REAL_TOLERANCE * magnitude
    # Modes are characterised by forward motion: at negative speeds the spectrum is mirrored
    # (for the Whipple model lambda(-v) = -lambda(v)) and other branches pair up.
    forward = speeds >= 0 if np.any(speeds >= 0) else np.ones(speeds.shape, dtype=bool)
    same = _groups(eigenvalues[:, forward], complex_[:, forward])
    oscillatory = same.sum(axis=-1) >= 2
    share_complex = complex_[:, forward].mean(axis=1)
    frequency = np.where(complex_, np.abs(eigenvalues.imag), np.nan)[:, forward]
    has_complex = np.any(np.isfinite(frequency), axis=1)
    median_frequency = np.full((batch, n), np.inf)
    if np.any(has_complex):
        median_frequency[has_complex] = np.nanmedian(
            np.moveaxis(frequency, 1, -1)[has_complex], axis=-1)
    persistent = oscillatory & (share_complex >= 0.5)
    rows = np.arange(batch)
    seed = np.where(
        np.any(persistent, axis=-1),
        np.argmin(np.where(persistent, median_frequency, np.inf), axis=-1),
        np.argmax(np.where(oscillatory, share_complex, -1.0), axis=-1),
    )
    weave = same[rows, seed] & np.any(oscillatory, axis=-1)[:, None]

    single = ~oscillatory
    mean_real = eigenvalues.real[:, forward].mean(axis=1)
    mean_roll = np.nanmean(np.where(np.isfinite(roll_share), roll_share, 0.5)[:, forward], axis=1)
    rolling = single & (mean_roll >= 0.5)
    candidates = np.where(np.any(rolling, axis=-1)[:, None], rolling, single)
    capsize_index = np.argmax(np.where(candidates, mean_real, -np.inf), axis=-1)
    capsize = (np.arange(n) == capsize_index[:, None]) & np.any(single, axis=-1)[:, None]
    remaining = single & ~capsize
    castering_index = np.argmax(np.where(remaining, 1.0 - mean_roll, -np.inf), axis=-1)
    castering = (np.arange(n) == castering_index[:, None]) & np.any(remaining, axis=-1)[:, None]

    rank = np.select([weave, capsize, castering], [0, 1, 2], default=3)
    mean_imag = eigenvalues.imag[:, forward].mean(axis=1)
    columns = np.lexsort((-mean_imag, -mean_real, rank), axis=-1)

    def ordered(array: NDArray) -> NDArray:
        return np.take_along_axis(array, columns, axis=-1)

    eig = np.take_along_axis(eigenvalues, columns[:, None, :], axis=-1)
    weave, capsize, castering = ordered(weave), ordered(capsize), ordered(castering)
    is_complex = np.take_along_axis(complex_, columns[:, None, :], axis=-1)
    codes = np.broadcast_to(len(NAMES) + np.arange(n), eig.shape).copy()
    real_weave = weave[:, None, :] & ~is_complex
    higher = np.where(real_weave, eig.real, -np.inf)
    # Count the weave-group eigenvalues ranked above each one; ties (the double root itself)
    # go to the lower column so that the two members still get different labels.
    column = np.arange(n)
    above = np.sum((higher[..., None, :] > higher[..., :, None])
                   | ((higher[..., None, :] == higher[..., :, None])
                      & (column[None, :] < column[:, None])), axis=-1)
    codes[real_weave] = np.where(above == 0, 1, 2)[real_weave]
    codes[weave[:, None, :] & is_complex] = 0
    codes[np.broadcast_to(capsize[:, None, :], eig.shape)] = 3
    codes[np.broadcast_to(castering[:, None, :], eig.shape)] = 4
    return columns, codes


def names(codes: NDArray[np.intp]) -> NDArray[np.str_]:
    """Label strings of the integer codes returned by :func:`label`."""
    n_max = int(np.max(codes, initial=len(NAMES))) - len(NAMES) + 1
    table = np.array(list(NAMES) + [f"mode_{k}" for k in range(1, n_max + 1)])
    return table[codes]
