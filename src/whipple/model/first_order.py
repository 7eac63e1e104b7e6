"""The first-order form ``x' = A(v) x + B f`` of the derived equations, for NumPy and CasADi alike.

The derived models come in two forms, each with an optional state feedback
``f -> f + F(v) x``, ``F(v) = sum_k v^k F_k`` (a controller whose gains are polynomials in v)
acting on the first four states (roll, steer and their rates):

* second order, ``M q'' + (v C1 + D) q' + (K0 + v^2 K2) q = f`` with ``q = [roll, steer]``:
  ``x = [q, q']`` and ``A(v) = [[0, I], [M^-1 R(v)]]`` with the rows
  ``R(v) = [-(K0 + v^2 K2), -(v C1 + D)] + F(v)``;
* descriptor, ``E x' = (sum_k v^k A_k) x + B f`` (the tyre model): ``A(v) = E^-1 (sum_k v^k A_k
  + B F(v) [I 0])``.

Both are assembled here once, as the list of polynomial coefficients ``A_k`` of ``A(v)`` and
``E^-1 B``, by code that only adds, multiplies, joins blocks and solves; an :class:`ArrayOps`
supplies those operations. :data:`NUMPY_OPS` works on batches of parameter sets (leading axes);
``whipple.model.casadi_model`` supplies the CasADi ones, so that the exact, differentiable
expressions used for root finding and sensitivities are the same assembly.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class ArrayOps:
    """The operations the assembly needs, for one kind of array.

    Attributes
    ----------
    join_columns, join_rows : callable
        Join a sequence of blocks side by side, or one above the other.
    split_columns : callable
        ``split_columns(X, width)``: X cut into blocks of `width` columns, left to right.
    solve : callable
        ``solve(M, X)``: ``M^-1 X``.
    zeros : callable
        ``zeros(like, rows, columns)``: a zero block with the batch of `like`.
    identity : callable
        ``identity(like, size)``: an identity block with the batch of `like`.
    """

    join_columns: Callable[[Sequence[Any]], Any]
    join_rows: Callable[[Sequence[Any]], Any]
    split_columns: Callable[[Any, int], list[Any]]
    solve: Callable[[Any, Any], Any]
    zeros: Callable[[Any, int, int], Any]
    identity: Callable[[Any, int], Any]


def _numpy_zeros(like: Any, rows: int, columns: int) -> Any:
    return np.zeros(np.shape(like)[:-2] + (rows, columns))


def _numpy_identity(like: Any, size: int) -> Any:
    return np.broadcast_to(np.eye(size), np.shape(like)[:-2] + (size, size))


def _numpy_join(axis: int) -> Callable[[Sequence[Any]], Any]:
    def join(blocks: Sequence[Any]) -> Any:
        arrays = [np.asarray(block, dtype=float) for block in blocks]
        batches = {array.shape[:-2] for array in arrays}
        if len(batches) == 1:  # one bicycle, or a batch alike in every block: nothing to broadcast
            return np.concatenate(arrays, axis=axis)
        batch = np.broadcast_shapes(*batches)
        return np.concatenate([np.broadcast_to(a, batch + a.shape[-2:]) for a in arrays], axis=axis)

    return join


def _numpy_solve(M: Any, X: Any) -> Any:
    """Return ``M^-1 X``; a 2 x 2 M (a bicycle's mass matrix) by its adjugate.

    For batches of 2 x 2 matrices that is several times faster than ``numpy.linalg.solve``.
    """
    if np.shape(M)[-2:] != (2, 2):
        return np.linalg.solve(M, X)
    M, X = np.asarray(M, dtype=float), np.asarray(X, dtype=float)
    m00, m01, m10, m11 = M[..., 0, 0, None], M[..., 0, 1, None], M[..., 1, 0, None], M[..., 1, 1, None]
    with np.errstate(all="ignore"):
        det = m00 * m11 - m01 * m10
        singular = not np.all(np.isfinite(1.0 / det))
    if singular:
        return np.linalg.solve(M, X)  # NumPy decides: LinAlgError for a singular M
    x0, x1 = X[..., 0, :], X[..., 1, :]
    return np.stack([(m11 * x0 - m01 * x1) / det, (m00 * x1 - m10 * x0) / det], axis=-2)


def _numpy_split(array: Any, width: int) -> list[Any]:
    return list(np.split(array, array.shape[-1] // width, axis=-1))


#: NumPy arrays, with any leading batch axes (broadcast against each other).
NUMPY_OPS = ArrayOps(_numpy_join(-1), _numpy_join(-2), _numpy_split, _numpy_solve, _numpy_zeros,
                     _numpy_identity)


def _with_feedback(rows: list[Any], gains: Sequence[Any], input_matrix: Any, states: int, ops: ArrayOps
                   ) -> list[Any]:
    """Add ``input_matrix F_k [I 0]`` to the row coefficients of each power k (extending them)."""
    rows = list(rows)
    for power, gain in enumerate(gains):
        feedback = input_matrix @ gain
        if states > feedback.shape[-1]:
            feedback = ops.join_columns([feedback, ops.zeros(feedback, feedback.shape[-2],
                                                             states - feedback.shape[-1])])
        if power < len(rows):
            rows[power] = rows[power] + feedback
        else:
            rows += [ops.zeros(rows[0], rows[0].shape[-2], states)] * (power - len(rows)) + [feedback]
    return rows


def second_order_coefficients(M: Any, C1: Any, D: Any, K0: Any, K2: Any, gains: Sequence[Any] = (),
                              ops: ArrayOps = NUMPY_OPS) -> tuple[list[Any], Any]:
    """Polynomial coefficients of A(v) and the input matrix of a second-order model.

    Parameters
    ----------
    M, C1, D, K0, K2 : array, each (..., 2, 2)
        Mass [kg m^2], velocity-damping [kg m], speed-independent damping [N m s/rad],
        stiffness with gravity [N m/rad] and speed-squared stiffness [kg] matrices.
    gains : sequence of array, each (..., 2, 4)
        Feedback coefficients ``F_k`` [N m per state unit], ``f = sum_k v^k F_k x``.
    ops : ArrayOps
        The array operations (NumPy by default).

    Returns
    -------
    coefficients : list of array, each (..., 4, 4)
        ``A_k`` [1/s per (m/s)^k], k = 0 .. max(2, len(gains) - 1).
    input_matrix : array (..., 4, 2)
        ``B = [[0], [M^-1]]`` [1/(kg m^2)].
    """
    zero = ops.zeros(K0, 2, 2)
    rows = [ops.join_columns([-K0, -D]), ops.join_columns([zero, -C1]), ops.join_columns([-K2, zero])]
    rows = _with_feedback(rows, gains, ops.identity(K0, 2), 4, ops)
    # One solve with M for every block: the rows of each power and the inputs' identity.
    *lower, inputs = ops.split_columns(ops.solve(M, ops.join_columns([*rows, ops.identity(K0, 2)])), 2)
    kinematics = [ops.join_columns([zero, ops.identity(K0, 2)])] + [ops.join_columns([zero, zero])] * (len(rows) - 1)
    coefficients = [ops.join_rows([upper, ops.join_columns(lower[2 * k:2 * k + 2])])
                    for k, upper in enumerate(kinematics)]
    return coefficients, ops.join_rows([zero, inputs])


def descriptor_coefficients(E: Any, A: Sequence[Any], B: Any, gains: Sequence[Any] = (),
                            ops: ArrayOps = NUMPY_OPS) -> tuple[list[Any], Any]:
    """Polynomial coefficients of A(v) and the input matrix of a descriptor model.

    Parameters
    ----------
    E : array (..., n, n)
        The descriptor (mass-like) matrix.
    A : sequence of array, each (..., n, n)
        ``A_k`` of ``E x' = (sum_k v^k A_k) x + B f``.
    B : array (..., n, 2)
        Input matrix of the roll and steer torques.
    gains : sequence of array, each (..., 2, 4)
        Feedback coefficients on the first four states, as in :func:`second_order_coefficients`.
    ops : ArrayOps
        The array operations (NumPy by default).

    Returns
    -------
    coefficients : list of array, each (..., n, n)
        The ``E^-1 A_k`` with the feedback added.
    input_matrix : array (..., n, 2)
        ``E^-1 B``.
    """
    rows = _with_feedback(list(A), gains, B, A[0].shape[-1], ops)
    return [ops.solve(E, row) for row in rows], ops.solve(E, B)


def actuator_coefficients(coefficients: Sequence[Any], input_matrix: Any, gains: Sequence[Any],
                          rows: Sequence[int], actuator: tuple[Any, Any, Any, float],
                          ops: ArrayOps = NUMPY_OPS) -> tuple[list[Any], Any]:
    """Close a feedback loop through an actuator around ``x' = (sum_k v^k P_k) x + Bp f``.

    Each torque row r in `rows` gets its own copy of the single-input actuator
    ``z' = a z + b u``, ``T = c z + d u`` driven by the commanded torque
    ``u = sum_k v^k F_k[r] x`` (on the first four states); the plant receives ``f + T``. The
    actuator's matrices are constant, so ``A(v)`` stays a polynomial in v of the same degree.

    Parameters
    ----------
    coefficients : sequence of array, each (..., n, n)
        ``P_k`` of the plant without feedback.
    input_matrix : array (..., n, 2)
        ``Bp``, the roll and steer torques' input matrix.
    gains : sequence of ndarray, each (2, 4)
        Feedback coefficients ``F_k`` [N m per state unit].
    rows : sequence of int
        Torque rows (0 roll, 1 steer) that pass through an actuator; the others get no torque.
    actuator : tuple
        ``(a, b, c, d)``: NumPy arrays (m, m) [1/s], (m, 1) [1/s], (1, m) and a float.
    ops : ArrayOps
        The array operations (NumPy by default).

    Returns
    -------
    coefficients : list of array, each (..., n + m len(rows), n + m len(rows))
        The loop's ``A_k``: the plant's states first, then each row's actuator states.
    input_matrix : array (..., n + m len(rows), 2)
        ``[Bp; 0]``: external torques act on the plant directly.
    """
    a, b, c, d = actuator
    like = coefficients[0]
    n, m = like.shape[-1], a.shape[0]
    extra = m * len(rows)
    columns = ops.split_columns(input_matrix, 1)

    def constant(array: Any) -> Any:
        array = np.asarray(array, dtype=float)
        return ops.zeros(like, *array.shape) + array

    def padded(gain: Any, row: int) -> Any:
        line = np.zeros((1, n))
        line[0, :4] = np.asarray(gain, dtype=float)[row]
        return line

    actuator_block = np.kron(np.eye(len(rows)), a)
    result = []
    for k in range(max(len(coefficients), len(gains))):
        top = coefficients[k] if k < len(coefficients) else ops.zeros(like, n, n)
        lower = []
        for row in rows:
            line = padded(gains[k], row) if k < len(gains) else np.zeros((1, n))
            if d != 0.0 and np.any(line):
                top = top + columns[row] @ constant(d * line)
            lower.append(constant(b @ line))
        if k == 0:
            right = ops.join_columns([columns[row] @ constant(c) for row in rows])
            corner = constant(actuator_block)
        else:
            right, corner = ops.zeros(like, n, extra), ops.zeros(like, extra, extra)
        result.append(ops.join_rows([ops.join_columns([top, right]),
                                     ops.join_columns([ops.join_rows(lower), corner])]))
    return result, ops.join_rows([input_matrix, ops.zeros(like, extra, input_matrix.shape[-1])])
