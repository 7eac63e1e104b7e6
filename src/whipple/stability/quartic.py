"""Eigenvalues and eigenvectors of second-order bicycle models from their characteristic quartic.

A model ``M q'' + C q' + K q = 0`` with q = [roll, steer] (the Whipple model, its extensions
of the mass and steer terms, a state-feedback controller; C and K at one speed) has the
eigenvalues of its first-order form ``x = [q, q']`` at the roots of the quartic
``det(M s^2 + C s + K)``, and each eigenvector is ``[u, s u]`` with u in the null space of
that 2 x 2 matrix. For the few dozen models of one residual evaluation of a diagnosis fit this
closed form costs a fraction of ``numpy.linalg.eig`` on the 4 x 4 state matrices, whose
per-matrix overhead dominates at this size. Rows the closed form does not resolve to rounding
go to eig (see :func:`second_order_eigenvalues`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from whipple.model.linear import second_order_model
from whipple.stability.cubic import real_cubic_root
from whipple.stability.polynomial import det_2x2, mixed_2x2

#: Largest mismatch, relative to the size of the terms that make up each coefficient, between
#: the quartic built back from the computed roots and the characteristic quartic; rows above
#: it are solved by eig.
VIETA_TOLERANCE = 1e-12
#: Relative imaginary part below which a root is real: rounding of the complex arithmetic
#: (eig gives the real eigenvalues of a real matrix an imaginary part of exactly zero).
REAL_ROUNDING = 1e-12
#: Newton steps on each root of the quartic after Ferrari's formula, which may lose digits
#: when the roots differ greatly in size; each step about doubles a simple root's digits.
NEWTON_STEPS = 1
#: Newton steps on the resolvent cubic's root after Cardano's formula.
RESOLVENT_STEPS = 1


def matrix_quartic(M: NDArray[np.float64], C: NDArray[np.float64], K: NDArray[np.float64]
                   ) -> NDArray[np.float64]:
    """Monic coefficients ``[1, a1, a2, a3, a4]`` of ``det(M s^2 + C s + K) / det M``.

    M, C, K: 2 x 2 matrices (..., 2, 2) broadcast against each other; result (..., 5).
    """
    lead = det_2x2(M)
    terms = (mixed_2x2(M, C), det_2x2(C) + mixed_2x2(M, K), mixed_2x2(C, K), det_2x2(K))
    shape = np.broadcast_shapes(*(term.shape for term in terms), lead.shape)
    a = np.empty(shape + (5,))
    a[..., 0] = 1.0
    for k, term in enumerate(terms, start=1):
        a[..., k] = term / lead
    return a


def _largest_resolvent_root(p: NDArray[np.float64], q: NDArray[np.float64], r: NDArray[np.float64]
                            ) -> NDArray[np.float64]:
    """Largest real root of Ferrari's resolvent ``m^3 + p m^2 + (p^2/4 - r) m - q^2/8``.

    The resolvent is -q^2 <= 0 at m = 0 and grows without bound, so this root is >= 0.
    """
    return np.maximum(real_cubic_root(p, p * p / 4.0 - r, -q * q / 8.0, RESOLVENT_STEPS), 0.0)


def quartic_roots(a: NDArray[np.float64]) -> NDArray[np.complex128]:
    """All four roots of monic quartics ``s^4 + a1 s^3 + a2 s^2 + a3 s + a4`` (rows ``a`` (..., 5)).

    Ferrari: with ``s = y - a1/4`` the depressed quartic ``y^4 + p y^2 + q y + r`` splits
    into ``(y^2 + w y + p/2 + m - q/(2w)) (y^2 - w y + p/2 + m + q/(2w))`` with
    ``w = sqrt(2m)`` and m the resolvent's largest root; then Newton steps on the quartic.
    Check the result with :func:`vieta_mismatch`: close or multiple roots lose digits.
    """
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return _ferrari(a)


def _ferrari(a: NDArray[np.float64]) -> NDArray[np.complex128]:
    a1, a2, a3, a4 = a[..., 1], a[..., 2], a[..., 3], a[..., 4]
    shift = a1 / 4.0
    shift2 = shift * shift
    p = a2 - 6.0 * shift2
    q = a3 - 2.0 * a2 * shift + 8.0 * shift2 * shift
    r = a4 - a3 * shift + a2 * shift2 - 3.0 * shift2 * shift2
    w = np.sqrt(2.0 * _largest_resolvent_root(p, q, r))
    ratio = q / w  # w = 0 only where q = 0 (NaN here: such rows go to eig)
    plus = np.sqrt(-2.0 * p - w * w - 2.0 * ratio + 0j)
    minus = np.sqrt(-2.0 * p - w * w + 2.0 * ratio + 0j)
    # Roots along the first axis while they are refined: the arithmetic is on contiguous rows.
    roots = np.stack([w + plus, w - plus, -w + minus, -w - minus]) / 2.0 - shift
    # A step divided by a zero slope (a multiple root) gives NaN: the caller's check sends
    # that row to eig.
    for _ in range(NEWTON_STEPS):
        roots = roots - ((((roots + a1) * roots + a2) * roots + a3) * roots + a4) \
            / (((4.0 * roots + 3.0 * a1) * roots + 2.0 * a2) * roots + a3)
    real = np.abs(roots.imag) <= REAL_ROUNDING * (1.0 + np.abs(roots))
    return np.moveaxis(np.where(real, roots.real + 0j, roots), 0, -1)


def vieta_mismatch(a: NDArray[np.float64], roots: NDArray[np.complex128]) -> NDArray[np.float64]:
    """Return the largest relative difference between quartics ``a`` (..., 5) and ``roots``' (..., 4).

    Each coefficient's difference is measured against the elementary symmetric function of the
    roots' magnitudes (the size of the terms that make it up), so well-conditioned roots pass
    at rounding level whatever their spread.
    """
    def symmetric(x: NDArray) -> tuple[NDArray, ...]:
        s1, p1 = x[0] + x[1], x[0] * x[1]
        s2, p2 = x[2] + x[3], x[2] * x[3]
        return -(s1 + s2), p1 + p2 + s1 * s2, -(s1 * p2 + s2 * p1), p1 * p2

    by_root = np.moveaxis(roots, -1, 0)
    built, sizes = symmetric(by_root), symmetric(np.abs(by_root))
    worst = np.zeros(roots.shape[:-1])
    for k in range(4):
        coefficient = a[..., k + 1]
        with np.errstate(divide="ignore", invalid="ignore"):  # 0/0 where both are exactly zero: a match
            error = np.abs(built[k] - coefficient) / np.maximum(np.abs(sizes[k]), np.abs(coefficient))
        worst = np.fmax(worst, error)
    # A NaN root or a non-finite coefficient (a singular M) must fail the check; fmax would hide it.
    broken = np.isnan(roots).any(axis=-1) | ~np.isfinite(a[..., 1:]).all(axis=-1)
    return np.where(broken, np.inf, worst)


def second_order_eigenvalues(M: NDArray[np.float64], C: NDArray[np.float64], K: NDArray[np.float64]
                             ) -> NDArray[np.complex128]:
    """Eigenvalues [1/s] of ``M q'' + C q' + K q = 0`` (2 x 2 matrices (..., 2, 2)); shape (..., 4).

    From the characteristic quartic; rows whose roots do not reproduce it to
    ``VIETA_TOLERANCE`` (a root lost to cancellation, a singular M) come from
    ``numpy.linalg.eigvals`` of the first-order form instead.
    """
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # a singular M: to eig
        a = matrix_quartic(M, C, K)
    roots = quartic_roots(a)
    doubtful = ~(vieta_mismatch(a, roots) <= VIETA_TOLERANCE)
    if np.any(doubtful):
        shape = roots.shape[:-1]
        M, C, K = (np.broadcast_to(X, shape + (2, 2)) for X in (M, C, K))
        zero = np.zeros_like(K[doubtful])
        first_order = second_order_model(M[doubtful], zero, K[doubtful], zero, damping=C[doubtful])
        roots[doubtful] = np.linalg.eigvals(first_order.state_matrix(0.0))
    return roots


def second_order_eigenvectors(M: NDArray[np.float64], C: NDArray[np.float64], K: NDArray[np.float64],
                              values: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """Return the eigenvector ``[u, s u]`` (..., 4) of each model for its eigenvalue s (...,) [1/s].

    u spans the null space of ``N = M s^2 + C s + K``, read from the row of N with the larger
    entries (both rows give it when s is an eigenvalue). Unit length, as eig's.
    """
    s = np.asarray(values, dtype=complex)[..., None, None]
    N = M * (s * s) + C * s + K
    first = np.stack([-N[..., 0, 1], N[..., 0, 0]], axis=-1)
    second = np.stack([N[..., 1, 1], -N[..., 1, 0]], axis=-1)
    size_first = np.abs(first[..., 0]) ** 2 + np.abs(first[..., 1]) ** 2
    size_second = np.abs(second[..., 0]) ** 2 + np.abs(second[..., 1]) ** 2
    u = np.where((size_first >= size_second)[..., None], first, second)
    vector = np.concatenate([u, s[..., 0] * u], axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return vector / np.sqrt(np.sum(np.abs(vector) ** 2, axis=-1, keepdims=True))
