"""Following eigenvalues across speed and naming the bicycle's modes.

Tracking
    Eigenvalues come out of ``numpy.linalg.eig`` in no particular order. Between neighbouring
    speeds of a fine grid each eigenvalue is matched to the nearest one at the next speed; where
    nearest neighbours do not form a one-to-one matching (near a double root, say), the optimal
    assignment on squared distance is solved (Hungarian method, :func:`assignment`; a few lines
    here rather than importing ``scipy.optimize``, which would double the start-up time of
    ``whipple sweep``). The
    few steps that reorder eigenvalues are then composed with a segmented parallel prefix scan,
    so there is no Python loop over speeds or parameter sets (only over the rare ambiguous steps).

Labelling
    A tracked *branch* keeps its identity over the whole grid; the labels below are properties
    of branches, decided once per branch, so they cannot swap between neighbouring speeds:

    * branches that are complex conjugates of each other at some non-negative speed form an
      oscillatory group (all rules look at non-negative speeds only, where there are any);
    * ``weave``: the oscillatory group that is complex on at least half the (non-negative)
      speeds with the lowest median frequency, else the one complex on most speeds. Where
      its branches are real (below the speed where weave forms from two real modes, the
      double root) they are ``weave_real_upper`` and ``weave_real_lower`` by real part. At
      most one pair is weave at a speed: where the oscillation passes from one pair of
      branches to another (the group then has more than two branches), the members outside
      the pair are ``mode_<column>``;
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

import math

import numpy as np
from numpy.typing import NDArray

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


def reorder(array: NDArray, order: NDArray[np.intp]) -> NDArray:
    """Permute the last axis of `array` by `order`, separately for every leading index.

    The same as ``numpy.take_along_axis(array, order, axis=-1)`` for an `order` that broadcasts
    to ``array.shape`` (one index per element), but a single flat gather: several times faster
    on the large arrays of eigenvectors.
    """
    n = array.shape[-1]
    offsets = np.arange(0, array.size, n).reshape(array.shape[:-1] + (1,))
    return np.take(array.reshape(-1), np.broadcast_to(order, array.shape) + offsets)


def assignment(cost: NDArray[np.float64]) -> NDArray[np.intp]:
    """Optimal assignment: the permutation p minimising ``sum(cost[i, p[i]])``.

    Shortest augmenting paths with dual potentials (Crouse 2016, IEEE Trans. Aerosp. Electron.
    Syst. 52(4), 1679-1696), with the tie rules of ``scipy.optimize.linear_sum_assignment``
    (SciPy 1.17: columns scanned from the last; among equally short paths, one ending at a
    free column), so that ties, such as two equal eigenvalues at a double root, are broken the
    same way.

    Parameters
    ----------
    cost : ndarray, shape (n, n)
        Finite costs (here squared distances between eigenvalues [1/s^2]).

    Returns
    -------
    ndarray of int, shape (n,)
        ``p[i]``: the column assigned to row i.
    """
    n = cost.shape[0]
    cost = cost.tolist()
    u, v = [0.0] * n, [0.0] * n
    row_of, column_of = [-1] * n, [-1] * n
    for first in range(n):
        distance, previous = [math.inf] * n, [-1] * n
        rows_seen, columns_seen = {first}, []
        pending = list(range(n - 1, -1, -1))  # columns not yet reached, in scan order
        row, reached, sink = first, 0.0, -1
        while sink < 0:
            rows_seen.add(row)
            best, pick = math.inf, -1
            for position, column in enumerate(pending):
                length = reached + cost[row][column] - u[row] - v[column]
                if length < distance[column]:
                    distance[column], previous[column] = length, row
                if distance[column] < best or (distance[column] == best and row_of[column] < 0):
                    best, pick = distance[column], position
            reached, column = best, pending[pick]
            pending[pick] = pending[-1]
            pending.pop()
            columns_seen.append(column)
            if row_of[column] < 0:
                sink = column
            else:
                row = row_of[column]
        u[first] += reached
        for other in rows_seen - {first}:
            u[other] += reached - distance[column_of[other]]
        for column in columns_seen:
            v[column] -= reached - distance[column]
        column = sink
        while True:  # flip the matching along the path
            row = previous[column]
            row_of[column] = row
            column_of[row], column = column, column_of[row]
            if row == first:
                break
    return np.array(column_of, dtype=np.intp)


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
    # step[b, s, i]: position at s+1 of position i at s (the nearest; the first of equals). One
    # position at a time: no (B, S, n, n) temporaries, whose allocation costs more than the work.
    now, after = eigenvalues[:, :-1], eigenvalues[:, 1:]
    step = np.zeros(now.shape, dtype=np.intp)
    nearest = np.abs(now - after[..., :1])
    for position in range(1, n):
        distance = np.abs(now - after[..., position:position + 1])
        np.copyto(step, position, where=distance < nearest)
        np.minimum(nearest, distance, out=nearest)
    # Most steps keep every eigenvalue in place; only the others need checking and composing.
    model, moved = np.nonzero(np.any(step != np.arange(n), axis=-1))
    maps = step[model, moved]
    ambiguous = np.flatnonzero(np.any(np.sort(maps, axis=-1) != np.arange(n), axis=-1))
    for k in ambiguous.tolist():
        b, speed = model[k], moved[k]
        distance = np.abs(eigenvalues[b, speed, :, None] - eigenvalues[b, speed + 1, None, :])
        # Squares of distances beyond 1e154 overflow, and infinite costs never end the assignment's
        # search: such distances (eigenvalues of absurd models) are scaled down first.
        largest = float(distance.max())
        maps[k] = assignment((distance / largest if largest > 1e150 else distance) ** 2)
    # Segmented inclusive prefix scan of the moving steps of each model (composition is
    # associative): after it, maps[k] sends a position at speed 0 to that of the same branch
    # just after step k.
    shift = 1
    while shift < maps.shape[0]:
        same = model[shift:] == model[:-shift]
        composed = np.take_along_axis(maps[shift:], maps[:-shift], axis=-1)
        maps[shift:] = np.where(same[:, None], composed, maps[shift:])
        shift *= 2
    if maps.shape[0] == 0:
        return np.broadcast_to(start[:, None, :], (batch, speeds, n)).copy()
    # At each speed, the map of the last moving step before it in the same model (identity if none).
    after = np.zeros((batch, speeds), dtype=bool)
    after[model, moved + 1] = True
    latest = np.cumsum(after.ravel()).reshape(batch, speeds) - 1
    clipped = np.maximum(latest, 0)
    own = (latest >= 0) & (model[clipped] == np.arange(batch)[:, None])
    positions = np.where(own[..., None], maps[clipped], np.arange(n))
    return reorder(positions, start[:, None, :])


def _groups(eigenvalues: NDArray[np.complex128], complex_: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """``same[b, j, k]``: branches j and k are linked by being complex conjugates somewhere."""
    batch, n = eigenvalues.shape[0], eigenvalues.shape[-1]
    # partner[b, s, j]: the branch nearest to the conjugate of branch j (the first of equals),
    # one branch at a time to avoid (B, S, n, n) temporaries.
    partner = np.zeros(eigenvalues.shape, dtype=np.intp)
    nearest = np.full(eigenvalues.shape, np.inf)
    conjugate = np.conj(eigenvalues)
    for other in range(n):
        gap = np.abs(eigenvalues - conjugate[..., other:other + 1])
        gap[..., other] = np.inf
        np.copyto(partner, other, where=gap < nearest)
        np.minimum(nearest, gap, out=nearest)
    model, speed, branch = np.nonzero(complex_)
    linked = np.zeros((batch, n, n), dtype=bool)
    linked[model, branch, partner[model, speed, branch]] = True
    same = (linked | np.swapaxes(linked, -1, -2) | np.eye(n, dtype=bool)).astype(np.int64)
    for _ in range(int(np.ceil(np.log2(max(n, 2))))):
        same = np.minimum(same @ same, 1)
    return same.astype(bool)


def _median_frequency(eigenvalues: NDArray[np.complex128], complex_: NDArray[np.bool_]) -> NDArray[np.float64]:
    """Median |imaginary part| [1/s] of each branch over the speeds where it is complex; inf if never.

    As ``numpy.nanmedian`` computes it (the middle value, or the mean of the two middle ones),
    batched: one sort over speed for all branches.
    """
    frequency = np.sort(np.where(complex_, np.abs(eigenvalues.imag), np.nan), axis=1)  # NaN last
    count = complex_.sum(axis=1)
    low = np.take_along_axis(frequency, np.maximum(count - 1, 0)[:, None, :] // 2, axis=1)[:, 0]
    high = np.take_along_axis(frequency, (count // 2)[:, None, :], axis=1)[:, 0]
    return np.where(count > 0, (low + high) / 2, np.inf)


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
    if np.all(forward):  # the usual case: no copies
        forward_values, forward_complex = eigenvalues, complex_
    else:
        forward_values, forward_complex = eigenvalues[:, forward], complex_[:, forward]
    same = _groups(forward_values, forward_complex)
    oscillatory = same.sum(axis=-1) >= 2
    share_complex = forward_complex.mean(axis=1)
    median_frequency = _median_frequency(forward_values, forward_complex)
    persistent = oscillatory & (share_complex >= 0.5)
    rows = np.arange(batch)
    seed = np.where(
        np.any(persistent, axis=-1),
        np.argmin(np.where(persistent, median_frequency, np.inf), axis=-1),
        np.argmax(np.where(oscillatory, share_complex, -1.0), axis=-1),
    )
    weave = same[rows, seed] & np.any(oscillatory, axis=-1)[:, None]

    single = ~oscillatory
    mean_real = forward_values.real.mean(axis=1)
    # NaN shares (not computed) count as 0.5: neither roll nor steer.
    mean_roll = np.where(np.isfinite(roll_share), roll_share, 0.5)[:, forward].mean(axis=1)
    rolling = single & (mean_roll >= 0.5)
    candidates = np.where(np.any(rolling, axis=-1)[:, None], rolling, single)
    capsize_index = np.argmax(np.where(candidates, mean_real, -np.inf), axis=-1)
    capsize = (np.arange(n) == capsize_index[:, None]) & np.any(single, axis=-1)[:, None]
    remaining = single & ~capsize
    castering_index = np.argmax(np.where(remaining, 1.0 - mean_roll, -np.inf), axis=-1)
    castering = (np.arange(n) == castering_index[:, None]) & np.any(remaining, axis=-1)[:, None]

    rank = np.select([weave, capsize, castering], [0, 1, 2], default=3)
    mean_imag = forward_values.imag.mean(axis=1)
    columns = np.lexsort((-mean_imag, -mean_real, rank), axis=-1)

    eig = reorder(eigenvalues, columns[:, None, :])
    weave, capsize, castering = (reorder(part, columns) for part in (weave, capsize, castering))
    is_complex = reorder(complex_, columns[:, None, :])
    codes = np.broadcast_to(len(NAMES) + np.arange(n), eig.shape).copy()
    real_weave = weave[:, None, :] & ~is_complex
    # Count the weave-group eigenvalues ranked above each one; ties (the double root itself)
    # go to the lower column so that the two members still get different labels. Only speeds
    # where the weave group has real members need it.
    where = np.nonzero(np.any(real_weave, axis=-1))
    higher = np.where(real_weave[where], eig.real[where], -np.inf)
    column = np.arange(n)
    above = np.sum((higher[..., None, :] > higher[..., :, None])
                   | ((higher[..., None, :] == higher[..., :, None])
                      & (column[None, :] < column[:, None])), axis=-1)
    codes[where] = np.where(real_weave[where], np.where(above == 0, 1, 2), codes[where])
    codes[weave[:, None, :] & is_complex] = 0
    codes[np.broadcast_to(capsize[:, None, :], eig.shape)] = 3
    codes[np.broadcast_to(castering[:, None, :], eig.shape)] = 4
    for b in np.flatnonzero(weave.sum(axis=-1) > 2).tolist():
        codes[b] = _one_weave_pair(codes[b], weave[b], is_complex[b], eig[b].real)
    return columns, codes


def _one_weave_pair(codes: NDArray[np.intp], weave: NDArray[np.bool_], is_complex: NDArray[np.bool_],
                    real: NDArray[np.float64]) -> NDArray[np.intp]:
    """Relabel a weave group of more than two branches so that at most one pair is weave at a speed.

    Where the group has a complex pair, that pair is the weave and its other (real) members
    are ``mode_<column>``; elsewhere the two real members that form the nearest complex pair
    are ``weave_real_upper`` and ``weave_real_lower`` and the others ``mode_<column>``. (Such a
    group arises when the oscillation passes from one pair of branches to another over speed,
    as in a bicycle with a nearly massless rear frame.)

    Parameters
    ----------
    codes : ndarray of int, shape (S, n)
        Labels of one model (see :func:`label`), columns in display order.
    weave, is_complex : ndarray of bool, shapes (n,) and (S, n)
        The weave group's columns; which eigenvalues are complex.
    real : ndarray, shape (S, n)
        Real parts [1/s].
    """
    codes = codes.copy()
    speeds, n = codes.shape
    other = len(NAMES) + np.arange(n)
    pairs = weave[None, :] & is_complex
    has_pair = pairs.sum(axis=-1) >= 2
    with_pair = np.flatnonzero(has_pair)
    for s in range(speeds):
        members = np.flatnonzero(weave & ~pairs[s])
        codes[s, members] = other[members]
        if has_pair[s] or not with_pair.size:
            continue
        nearest = with_pair[np.argmin(np.abs(with_pair - s))]
        pair = np.flatnonzero(pairs[nearest])[:2]
        if np.all(~is_complex[s, pair]):
            upper, lower = (pair[0], pair[1]) if real[s, pair[0]] >= real[s, pair[1]] else (pair[1], pair[0])
            codes[s, upper], codes[s, lower] = 1, 2
    return codes


def names(codes: NDArray[np.intp]) -> NDArray[np.str_]:
    """Label strings of the integer codes returned by :func:`label`."""
    n_max = int(np.max(codes, initial=len(NAMES))) - len(NAMES) + 1
    table = np.array(list(NAMES) + [f"mode_{k}" for k in range(1, n_max + 1)])
    return table[codes]
