"""Exact discretisation of linear systems over sample intervals, for stacks of matrices.

For ``x' = A x + B u`` with A, B and u constant over an interval of length dt, the state at its
end is ``Phi x + Gamma u`` with ``[[Phi, Gamma], [0, I]] = expm([[A, B], [0, 0]] dt)``: exact
whatever the stiffness of A (no step-size limit from fast modes).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

#: Taylor degree of :func:`expm_batch`; after scaling to a 1-norm <= 1/2 the truncation error
#: is below 0.5^19 / 19! ~ 2e-23.
_DEGREE = 18


def expm_batch(matrices: NDArray[np.float64]) -> NDArray[np.float64]:
    """Matrix exponentials of a stack of matrices, shape (..., n, n), vectorised.

    Scaling and squaring with a Taylor polynomial, the scaling set by the largest 1-norm in
    the stack. ``scipy.linalg.expm`` loops over a stack in Python, about a thousand times
    slower for thousands of small matrices (one per sample interval of a run).
    """
    matrices = np.asarray(matrices, dtype=float)
    norm = float(np.abs(matrices).sum(axis=-2).max(initial=0.0))
    squarings = max(0, math.ceil(math.log2(norm / 0.5))) if norm > 0 else 0
    scaled = matrices / 2.0**squarings
    identity = np.eye(matrices.shape[-1])
    result = identity + scaled / _DEGREE
    for order in range(_DEGREE - 1, 0, -1):
        result = identity + (scaled @ result) / order
    for _ in range(squarings):
        result = result @ result
    return result


def zero_order_hold(
    A: NDArray[np.float64], B: NDArray[np.float64], dt: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Transition and input matrices of intervals with inputs held constant.

    Parameters
    ----------
    A : ndarray, shape (..., n, n)
        State matrices [1/s].
    B : ndarray, shape (..., n, m)
        Input matrices (state unit per second per input unit).
    dt : float
        Interval length [s].

    Returns
    -------
    Phi : ndarray, shape (..., n, n)
    Gamma : ndarray, shape (..., n, m)
        ``x(t + dt) = Phi x(t) + Gamma u`` exactly.
    """
    n, m = A.shape[-1], B.shape[-1]
    batch = np.broadcast_shapes(A.shape[:-2], B.shape[:-2])
    blocks = np.zeros(batch + (n + m, n + m))
    blocks[..., :n, :n] = A * dt
    blocks[..., :n, n:] = B * dt
    result = expm_batch(blocks)
    return result[..., :n, :n], result[..., :n, n:]
