"""The two scalar conditions for a change of stability of ``x' = A(v) x``.

A linear model changes stability only where an eigenvalue crosses the imaginary axis. For a
real matrix that happens in one of two generic ways, each the zero of a scalar function of the
speed v [m/s]:

* a complex pair crosses at ``+/- i w`` (a Hopf point; for the bicycle, the weave speed).
  By Orlando's formula the Hurwitz determinant of the characteristic polynomial
  ``det(lambda I - A) = lambda^n + a_1 lambda^(n-1) + ... + a_n`` satisfies
  ``Delta_(n-1) = (-1)^(n(n-1)/2) prod_(i<j) (lambda_i + lambda_j)``, so the *Hopf condition*
  ``hopf = prod_(i<j) (lambda_i + lambda_j)`` vanishes, with a sign change, when a pair's real
  part ``(lambda + conj(lambda)) / 2`` does. It also vanishes when two *real* eigenvalues of
  opposite sign have a zero sum, which is not a change of stability: callers must check the
  eigenvalues at each root.
* a real eigenvalue crosses zero (for the bicycle, the capsize speed): the *real condition*
  ``det A = prod_i lambda_i`` vanishes. For the Whipple model ``det A = det(K0 + v^2 K2) /
  det M``.

Both conditions are computed here twice. In NumPy, batched, from eigenvalues (the products
above): as accurate as the eigenvalues themselves, for figures and tests. And as CasADi
expressions, exact and differentiable in v and in any parameters, from the characteristic
coefficients and the Hurwitz determinant, for the sensitivities of
:mod:`whipple.stability.uncertainty`. The critical-speed solver uses the same conditions as
exact polynomials in v (:mod:`whipple.stability.polynomial`). The
coefficients are sums of principal minors expanded without division; the Faddeev-LeVerrier
recursion was tried and rejected: its rounding error grows like ``||A||^k`` and it moved the
weave speed of a random bicycle with a stiff castering mode (eigenvalue -563 1/s) by
7e-11 m/s.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import casadi
import numpy as np
from numpy.typing import NDArray

#: Options of the CasADi Newton solver (used by the uncertainty analysis): iterate until the
#: step is at round-off level.
NEWTON_OPTIONS: dict[str, Any] = {
    "abstol": 1e-15,
    "abstolStep": 1e-14,
    "max_iter": 40,
    "error_on_fail": False,
    # Failures are detected by the callers; CasADi must not print them.
    "show_eval_warnings": False,
}


def hopf_condition(eigenvalues: NDArray[Any]) -> NDArray[np.float64]:
    """``prod_(i<j) (lambda_i + lambda_j)`` from eigenvalues.

    Parameters
    ----------
    eigenvalues : ndarray, shape (..., n), complex
        Eigenvalues [1/s] of each matrix.

    Returns
    -------
    ndarray, shape (...)
        The Hopf condition [1/s^(n(n-1)/2)] (real: the factors come in conjugate pairs).
    """
    first, second = np.triu_indices(eigenvalues.shape[-1], 1)
    return np.prod(eigenvalues[..., first] + eigenvalues[..., second], axis=-1).real


def real_condition(eigenvalues: NDArray[Any]) -> NDArray[np.float64]:
    """``det A = prod_i lambda_i`` [1/s^n] from eigenvalues [1/s], shape (..., n)."""
    return np.prod(eigenvalues, axis=-1).real


def hurwitz_indices(n: int) -> list[tuple[int, int, int]]:
    """Nonzero entries ``(row, column, k)`` of the Hurwitz matrix of order n-1: entry ``a_k``."""
    entries = []
    for row in range(n - 1):
        for column in range(n - 1):
            k = 2 * (column + 1) - (row + 1)
            if 0 <= k <= n:
                entries.append((row, column, k))
    return entries


def _orlando_sign(n: int) -> float:
    return -1.0 if (n * (n - 1) // 2) % 2 else 1.0


def _is_zero(entry: Any) -> bool:
    """Return True for a structural zero (a CasADi constant 0 or a Python 0)."""
    if isinstance(entry, casadi.SX | casadi.MX | casadi.DM):
        return bool(entry.is_zero())
    return bool(entry == 0)


def casadi_characteristic_coefficients(A: Any) -> list[Any]:
    """``[1, a_1, ..., a_n]`` of ``det(lambda I - A)`` for a CasADi (SX or MX) n x n matrix.

    ``a_k`` is ``(-1)^k`` times the sum of the k x k principal minors, each expanded along
    rows with shared sub-minors (at most 3^n minors in all, no division).
    """
    n = A.shape[0]
    entries = [[A[i, j] for j in range(n)] for i in range(n)]
    memo: dict[tuple[int, int], Any] = {}

    def minor(rows: int, columns: int) -> Any:
        if rows == 0:
            return 1.0
        if (rows, columns) in memo:
            return memo[(rows, columns)]
        row = (rows & -rows).bit_length() - 1
        total: Any = 0
        sign = 1.0
        for column in range(n):
            if columns >> column & 1:
                entry = entries[row][column]
                if not _is_zero(entry):
                    total = total + sign * entry * minor(
                        rows & ~(1 << row), columns & ~(1 << column))
                sign = -sign
        memo[(rows, columns)] = total
        return total

    sums: list[Any] = [0] * (n + 1)
    for subset in range(1, 1 << n):
        size = bin(subset).count("1")
        sums[size] = sums[size] + minor(subset, subset)
    return [1.0] + [(-1) ** k * sums[k] for k in range(1, n + 1)]


def casadi_determinant(entries: list[list[Any]]) -> Any:
    """Division-free determinant of a square matrix given as rows of CasADi scalars.

    Laplace expansion along rows with the minors memoised by their column set (O(m 2^m)
    operations, no pivoting, so no division by an entry that may vanish at some speed).
    ``None`` marks a structural zero.
    """
    size = len(entries)
    memo: dict[int, Any] = {}

    def minor(columns: int) -> Any:
        # `columns` is the bit set of columns still free; the row is fixed by their number.
        if columns in memo:
            return memo[columns]
        row = size - bin(columns).count("1")
        if row == size:
            return 1.0
        total: Any = 0
        sign = 1.0
        for column in range(size):
            if not columns >> column & 1:
                continue
            entry = entries[row][column]
            if entry is not None and not _is_zero(entry):
                rest = minor(columns & ~(1 << column))
                if not (isinstance(rest, int) and rest == 0):
                    total = total + sign * entry * rest
            sign = -sign
        memo[columns] = total
        return total

    return minor((1 << size) - 1)


def casadi_conditions(A: Any) -> tuple[Any, Any]:
    """Hopf and real conditions of a CasADi n x n matrix expression (see module docstring)."""
    n = A.shape[0]
    real = casadi_determinant([[A[i, j] for j in range(n)] for i in range(n)])
    if n < 2:
        return casadi.SX(1.0) if isinstance(A, casadi.SX) else casadi.MX(1.0), real
    a = casadi_characteristic_coefficients(A)
    entries: list[list[Any]] = [[None] * (n - 1) for _ in range(n - 1)]
    for row, column, k in hurwitz_indices(n):
        entries[row][column] = a[k]
    return _orlando_sign(n) * casadi_determinant(entries), real


def casadi_polynomial_matrix(coefficients: Any, speed: Any, pattern: Pattern) -> Any:
    """``sum_k speed^k A_k`` from a flat CasADi vector of C-ordered n x n coefficient blocks.

    Entries that `pattern` marks as zero in every block are structural zeros, which keeps the
    expressions built from the matrix small.
    """
    mask = np.array(pattern, dtype=bool)
    terms, n = mask.shape[0], mask.shape[1]
    rows = []
    for i in range(n):
        row = []
        for j in range(n):
            entry: Any = 0
            for power in range(terms - 1, -1, -1):
                entry = entry * speed
                if mask[power, i, j]:
                    entry = entry + coefficients[(power * n + i) * n + j]
            row.append(entry)
        rows.append(casadi.horzcat(*row))
    return casadi.vertcat(*rows)


#: Which entries of the polynomial coefficients of A may be nonzero, shape (T, n, n), as
#: nested tuples of bool (hashable, for caching the CasADi functions).
Pattern = tuple[tuple[tuple[bool, ...], ...], ...]


def sparsity_pattern(coefficients: NDArray[np.float64]) -> Pattern:
    """Return the :data:`Pattern` of coefficients (..., T, n, n): entries nonzero in any model."""
    mask = np.any(coefficients.reshape((-1,) + coefficients.shape[-3:]) != 0, axis=0)
    return tuple(tuple(tuple(bool(x) for x in row) for row in block) for block in mask)


@lru_cache(maxsize=32)
def condition_functions(pattern: Pattern) -> casadi.Function:
    """CasADi function ``(v, c) -> (hopf, real)`` for ``A(v) = sum_k v^k A_k``.

    ``c`` holds the T coefficient matrices, each n x n in row-major order, flattened. One
    function serves every model with the same sparsity `pattern`, so batches need no
    per-model code.
    """
    terms, n = len(pattern), len(pattern[0])
    speed = casadi.SX.sym("v")
    coefficients = casadi.SX.sym("c", terms * n * n)
    hopf, real = casadi_conditions(casadi_polynomial_matrix(coefficients, speed, pattern))
    return casadi.Function("conditions", [speed, coefficients], [hopf, real],
                           ["v", "c"], ["hopf", "real"])
