"""The characteristic polynomial of ``A(v)`` and the stability conditions as exact polynomials in v.

Every model of the package has ``A(v) = sum_k v^k A_k`` (:class:`~whipple.model.linear.LinearModel`;
controller gains are polynomials in v and the tyre model's ``1/v`` terms are cleared in its
derivation). So each coefficient of ``det(s I - A(v)) = s^n + a_1 s^(n-1) + ... + a_n`` is a
polynomial in v, and so are

* the *Hopf condition*, the Hurwitz determinant ``Delta_(n-1)`` of the ``a_k`` (zero where a
  complex pair crosses the imaginary axis; see :mod:`whipple.stability.characteristic`), and
* the *real condition* ``a_n = det(-A(v))`` (zero where a real eigenvalue crosses zero).

They are formed here by exact polynomial arithmetic (sums and products of coefficient arrays,
no division, no interpolation), batched over models: a batch of polynomials is an array of shape
``(N, L)``, coefficient of ``v^j`` in column j. Two paths give the same polynomials:

* **second order** (4 states with ``x = [q, q']``: the Whipple model, steer damping, any
  controller): ``det(s I - A) = det(s^2 I + C(v) s + K(v))`` with ``[-K, -C]`` the lower rows of A,
  expanded with the 2 x 2 identities ``det(X + Y) = det X + m(X, Y) + det Y``;
* **general** (any n, e.g. the 8-state tyre model): ``a_k = (-1)^k`` times the sum of the k x k
  principal minors, each expanded along rows with shared sub-minors (division-free Laplace
  expansion; structural zeros skipped).

:func:`hurwitz_stable` is the Routh-Hurwitz test at given speeds (all leading Hurwitz minors
positive), used between critical speeds instead of eigenvalues.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Poly = NDArray[np.float64]


def multiply(p: Poly, q: Poly, length: int | None = None) -> Poly:
    """Product of batched polynomials ``(N, Lp) x (N, Lq)``, truncated to `length` coefficients.

    Truncation is exact whenever the degrees are known to stay below `length`.
    """
    length = p.shape[-1] + q.shape[-1] - 1 if length is None else length
    out = np.zeros(p.shape[:-1] + (length,))
    if q.shape[-1] > p.shape[-1]:
        p, q = q, p
    for j in range(min(q.shape[-1], length)):
        width = min(p.shape[-1], length - j)
        out[..., j:j + width] += q[..., j:j + 1] * p[..., :width]
    return out


def pad(p: Poly, length: int) -> Poly:
    """Batched polynomials padded with zero coefficients (or cut) to `length` coefficients."""
    if p.shape[-1] >= length:
        return p[..., :length]
    return np.concatenate([p, np.zeros(p.shape[:-1] + (length - p.shape[-1],))], axis=-1)


def add(*terms: Poly) -> Poly:
    """Sum of batched polynomials of any lengths."""
    length = max(term.shape[-1] for term in terms)
    total = pad(terms[0], length).copy()
    for term in terms[1:]:
        total += pad(term, length)
    return total


def evaluate(p: Poly, speeds: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Value and derivative of batched polynomials ``(N, L)`` at speeds ``(N,)`` [m/s] (Horner)."""
    value = np.zeros(p.shape[:-1])
    slope = np.zeros(p.shape[:-1])
    for j in range(p.shape[-1] - 1, -1, -1):
        slope = slope * speeds + value
        value = value * speeds + p[..., j]
    return value, slope


@dataclass(frozen=True)
class Conditions:
    """Characteristic polynomial and stability conditions of N models, as polynomials in v.

    Attributes
    ----------
    characteristic : ndarray, shape (N, n + 1, L)
        ``a_k(v)`` of ``det(s I - A(v)) = sum_k a_k s^(n-k)``, ``a_0 = 1``; row k holds the
        coefficients of v^0, v^1, ... [1/s^k per (m/s)^j].
    hopf : ndarray, shape (N, H)
        The Hurwitz determinant ``Delta_(n-1)(v)`` (for n = 1: the constant 1).
    real : ndarray, shape (N, L)
        ``a_n(v) = det(-A(v))``.
    """

    characteristic: NDArray[np.float64]
    hopf: Poly
    real: Poly


def is_second_order(coefficients: NDArray[np.float64]) -> bool:
    """Return True if A (N, T, 4, 4) is ``[[0, I], [-K(v), -C(v)]]`` for every model."""
    if coefficients.shape[-1] != 4:
        return False
    upper = coefficients[:, :, :2, :]
    kinematics = np.zeros(upper.shape[1:])
    kinematics[0, :, 2:] = np.eye(2)
    return bool(np.all(upper == kinematics))


def det_2x2(X: NDArray[np.float64]) -> NDArray[np.float64]:
    """``det`` of 2 x 2 matrices X (..., 2, 2)."""
    return X[..., 0, 0] * X[..., 1, 1] - X[..., 0, 1] * X[..., 1, 0]


def mixed_2x2(X: NDArray[np.float64], Y: NDArray[np.float64]) -> NDArray[np.float64]:
    """``m(X, Y) = det(X + Y) - det X - det Y`` of 2 x 2 matrices (..., 2, 2)."""
    return (X[..., 0, 0] * Y[..., 1, 1] + X[..., 1, 1] * Y[..., 0, 0]
            - X[..., 0, 1] * Y[..., 1, 0] - X[..., 1, 0] * Y[..., 0, 1])


def _det2(X: NDArray[np.float64], length: int) -> Poly:
    """``det`` of 2 x 2 matrices of polynomials ``(N, 2, 2, L)``."""
    return (multiply(X[:, 0, 0], X[:, 1, 1], length) - multiply(X[:, 0, 1], X[:, 1, 0], length))


def _mixed2(X: NDArray[np.float64], Y: NDArray[np.float64], length: int) -> Poly:
    """``m(X, Y) = det(X + Y) - det X - det Y`` of 2 x 2 matrices of polynomials."""
    return (multiply(X[:, 0, 0], Y[:, 1, 1], length) + multiply(X[:, 1, 1], Y[:, 0, 0], length)
            - multiply(X[:, 0, 1], Y[:, 1, 0], length) - multiply(X[:, 1, 0], Y[:, 0, 1], length))


def _second_order_characteristic(coefficients: NDArray[np.float64]) -> NDArray[np.float64]:
    terms = coefficients.shape[1]
    length = 4 * (terms - 1) + 1
    # Matrices of polynomials, shape (N, 2, 2, T): C(v) and K(v).
    C = -np.moveaxis(coefficients[:, :, 2:, 2:], 1, -1)
    K = -np.moveaxis(coefficients[:, :, 2:, :2], 1, -1)
    one = np.zeros((coefficients.shape[0], length))
    one[:, 0] = 1.0
    a1 = C[:, 0, 0] + C[:, 1, 1]
    a2 = add(K[:, 0, 0], K[:, 1, 1], _det2(C, length))
    a3 = _mixed2(C, K, length)
    a4 = _det2(K, length)
    return np.stack([pad(a, length) for a in (one, a1, a2, a3, a4)], axis=1)


def _general_characteristic(coefficients: NDArray[np.float64]) -> NDArray[np.float64]:
    count, terms, n, _ = coefficients.shape
    length = n * (terms - 1) + 1
    entries = np.moveaxis(coefficients, 1, -1)  # (N, n, n, T)
    nonzero = np.any(entries != 0, axis=(0, 3))
    memo: dict[tuple[int, int], Poly] = {}

    def minor(rows: int, columns: int) -> Poly:
        if rows == 0:
            unit = np.zeros((count, length))
            unit[:, 0] = 1.0
            return unit
        if (rows, columns) in memo:
            return memo[(rows, columns)]
        row = (rows & -rows).bit_length() - 1
        total = np.zeros((count, length))
        sign = 1.0
        for column in range(n):
            if columns >> column & 1:
                if nonzero[row, column]:
                    rest = minor(rows & ~(1 << row), columns & ~(1 << column))
                    total += sign * multiply(rest, entries[:, row, column], length)
                sign = -sign
        memo[(rows, columns)] = total
        return total

    sums = np.zeros((count, n + 1, length))
    sums[:, 0, 0] = 1.0
    for subset in range(1, 1 << n):
        size = bin(subset).count("1")
        sums[:, size] += minor(subset, subset)
    signs = (-1.0) ** np.arange(n + 1)
    return sums * signs[None, :, None]


def hurwitz_entries(n: int) -> dict[tuple[int, int], int]:
    """Entries ``(row, column) -> k`` (``a_k``) of the n x n Hurwitz matrix, zero ones left out."""
    return {(row, column): 2 * (column + 1) - (row + 1)
            for row in range(n) for column in range(n) if 0 <= 2 * (column + 1) - (row + 1) <= n}


def _hurwitz_determinant(a: NDArray[np.float64], order: int) -> Poly:
    """Leading ``order`` x ``order`` Hurwitz minor of polynomial coefficients a (N, n + 1, L)."""
    count, _, length = a.shape
    if order == 0:
        unit = np.zeros((count, 1))
        unit[:, 0] = 1.0
        return unit
    n = a.shape[1] - 1
    size = order * (length - 1) + 1
    entries = {key: k for key, k in hurwitz_entries(n).items() if key[0] < order and key[1] < order}
    memo: dict[int, Poly] = {}

    def minor(columns: int) -> Poly:
        row = order - bin(columns).count("1")
        if row == order:
            unit = np.zeros((count, size))
            unit[:, 0] = 1.0
            return unit
        if columns in memo:
            return memo[columns]
        total = np.zeros((count, size))
        sign = 1.0
        for column in range(order):
            if not columns >> column & 1:
                continue
            k = entries.get((row, column))
            if k is not None:
                total += sign * multiply(minor(columns & ~(1 << column)), a[:, k], size)
            sign = -sign
        memo[columns] = total
        return total

    return minor((1 << order) - 1)


def conditions(coefficients: NDArray[np.float64]) -> Conditions:
    """Characteristic polynomial, Hopf and real conditions of models as exact polynomials in v.

    Parameters
    ----------
    coefficients : ndarray, shape (N, T, n, n)
        Polynomial coefficients ``A_k`` of the state matrices [1/s per (m/s)^k], constant first.

    Returns
    -------
    Conditions
    """
    n = coefficients.shape[-1]
    if is_second_order(coefficients):
        a = _second_order_characteristic(coefficients)
        a1, a2, a3, a4 = (_trim(a[:, k]) for k in range(1, 5))
        hopf = add(multiply(multiply(a1, a2), a3), -multiply(a3, a3), -multiply(multiply(a1, a1), a4))
    else:
        a = _general_characteristic(coefficients)
        hopf = _hurwitz_determinant(a, n - 1)
    return Conditions(_trim(a), _trim(hopf), _trim(a[:, n]))


def _trim(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Drop trailing coefficient columns that are zero in every polynomial of the batch."""
    used = np.nonzero(np.any(p.reshape(-1, p.shape[-1]) != 0, axis=0))[0]
    return p[..., :used[-1] + 1] if used.size else p[..., :1]


def characteristic_at(characteristic: NDArray[np.float64], speeds: NDArray[np.float64]
                      ) -> NDArray[np.float64]:
    """``a_k`` at one speed per model: characteristic (N, n + 1, L), speeds (N,) -> (N, n + 1)."""
    value = np.zeros(characteristic.shape[:2])
    for j in range(characteristic.shape[-1] - 1, -1, -1):
        value = value * speeds[:, None] + characteristic[:, :, j]
    return value


def hurwitz_stable(a: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Routh-Hurwitz test: all roots of ``sum_k a_k s^(n-k)`` (rows of a, ``a_0 = 1``) in Re s < 0.

    The polynomial is first rescaled (``s = sigma z``, sigma a power of two, so exactly) to
    keep the Hurwitz minors of order one; then every leading principal minor of the Hurwitz
    matrix must be positive.
    """
    count, width = a.shape
    n = width - 1
    if n == 0:
        return np.ones(count, dtype=bool)
    k = np.arange(1, n + 1)
    with np.errstate(divide="ignore"):
        size = np.max(np.log2(np.maximum(np.abs(a[:, 1:]), 1e-300)) / k, axis=-1)
    sigma = 2.0 ** np.round(size)
    scaled = a * sigma[:, None] ** -np.arange(width)
    if n == 4:
        # The bicycle's quartic: the Hurwitz minors written out (monic, so Delta_1 = a_1).
        a1, a2, a3, a4 = scaled[:, 1], scaled[:, 2], scaled[:, 3], scaled[:, 4]
        delta2 = a1 * a2 - a3
        delta3 = delta2 * a3 - a1 * a1 * a4
        return (a1 > 0) & (a4 > 0) & (delta2 > 0) & (delta3 > 0)
    matrix = np.zeros((count, n, n))
    for (row, column), index in hurwitz_entries(n).items():
        matrix[:, row, column] = scaled[:, index]
    stable = np.all(scaled[:, 1:] > 0, axis=-1)
    for order in range(2, n + 1):
        stable &= np.linalg.det(matrix[:, :order, :order]) > 0
    return stable


def state_matrices_at(coefficients: NDArray[np.float64], model: NDArray[np.intp],
                      speed: NDArray[np.float64]) -> NDArray[np.float64]:
    """State matrices ``A(v) = sum_k v^k A_k`` [1/s] of models ``model`` at speeds ``speed`` [m/s].

    Parameters
    ----------
    coefficients : ndarray, shape (N, T, n, n)
        ``A_k`` of N models.
    model, speed : ndarray, shape (P,)
        Which model, at which speed, for each of P points.

    Returns
    -------
    ndarray, shape (P, n, n)
    """
    total = np.zeros((speed.size,) + coefficients.shape[2:])
    for power in range(coefficients.shape[1] - 1, -1, -1):
        total = total * speed[:, None, None] + coefficients[model, power]
    return total
