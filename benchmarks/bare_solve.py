"""Bare batched NumPy solve of the Whipple model's critical-speed conditions: the baseline.

This is the floor against which the library's critical-speed solver and ``whipple sweep`` are
measured (``benchmarks/bench_critical.py``): exactly the polynomial conditions, their real roots
from batched companion-matrix eigenvalues, nothing else (no polishing, no verification, no
labels, no stable ranges).

For ``M q'' + v C1 q' + (K0 + v^2 K2) q = 0`` the characteristic polynomial is
``det(M s^2 + v C1 s + K0 + v^2 K2) = a4 s^4 + a3 s^3 + a2 s^2 + a1 s + a0`` with, writing
``m(X, Y) = X00 Y11 + X11 Y00 - X01 Y10 - X10 Y01`` (so ``det(X + Y) = det X + m(X, Y) + det Y``)
and ``u = v^2``::

    a4 = det M
    a3 = v m(M, C1)
    a2 = m(M, K0) + u (m(M, K2) + det C1)
    a1 = v (m(C1, K0) + u m(C1, K2))
    a0 = det K0 + u m(K0, K2) + u^2 det K2

* Hopf condition: the Hurwitz determinant ``Delta_3 = a3 a2 a1 - a4 a1^2 - a3^2 a0`` equals
  ``u`` times a quadratic in u.
* Real condition: ``a0 = det(K0 + u K2)``, a quadratic in u (linear when ``det K2 = 0``, as for
  the benchmark bicycle).

Each quadratic is solved for ``w = 1 / u`` (its reversed coefficients), so that a vanishing
leading coefficient (``det K2 = 0``) gives ``w = 0``, i.e. no finite root, instead of a
division by zero; the 2 x 2 companion matrices of all bicycles and both conditions go through
one ``numpy.linalg.eigvals`` call. Speeds are ``v = 1 / sqrt(w)`` for real ``w > 0``.

The sweep benchmark imports this file too: keep :func:`bare_critical_roots`' interface stable.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def _det(X: NDArray[np.float64]) -> NDArray[np.float64]:
    return X[..., 0, 0] * X[..., 1, 1] - X[..., 0, 1] * X[..., 1, 0]


def _mixed(X: NDArray[np.float64], Y: NDArray[np.float64]) -> NDArray[np.float64]:
    return (X[..., 0, 0] * Y[..., 1, 1] + X[..., 1, 1] * Y[..., 0, 0]
            - X[..., 0, 1] * Y[..., 1, 0] - X[..., 1, 0] * Y[..., 0, 1])


def bare_critical_roots(M: NDArray[np.float64], C1: NDArray[np.float64], K0: NDArray[np.float64],
                        K2: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Positive real roots [m/s] of the Hopf and real conditions of N Whipple models.

    Parameters
    ----------
    M, C1, K0, K2 : ndarray, shape (N, 2, 2)
        Mass [kg m^2], velocity damping [kg m], stiffness with gravity [N m/rad] and
        speed-squared stiffness [kg] matrices.

    Returns
    -------
    hopf_speeds, real_speeds : ndarray, shape (N, 2)
        Positive speeds [m/s] where the Hopf (Hurwitz determinant) and the real (``det(K0 +
        v^2 K2)``) conditions vanish, ascending, padded with NaN. Not verified: a Hopf root
        may be a pair of opposite real eigenvalues rather than an axis crossing.
    """
    det_m = _det(M)
    c3 = _mixed(M, C1)
    e0, e2 = _mixed(M, K0), _mixed(M, K2) + _det(C1)
    d1, d3 = _mixed(C1, K0), _mixed(C1, K2)
    f0, f2, f4 = _det(K0), _mixed(K0, K2), _det(K2)
    # Delta_3 / u = c3 (e0 + e2 u)(d1 + d3 u) - det M (d1 + d3 u)^2 - c3^2 (f0 + f2 u + f4 u^2).
    h0 = c3 * e0 * d1 - det_m * d1**2 - c3**2 * f0
    h1 = c3 * (e0 * d3 + e2 * d1) - 2.0 * det_m * d1 * d3 - c3**2 * f2
    h2 = c3 * e2 * d3 - det_m * d3**2 - c3**2 * f4
    # Reversed quadratics in w = 1/u, monic after division by the constant term:
    # w^2 + (p1/p0) w + p2/p0, companion [[-p1/p0, -p2/p0], [1, 0]].
    constant = np.stack([h0, f0], axis=-1)
    middle = np.stack([h1, f2], axis=-1) / constant
    last = np.stack([h2, f4], axis=-1) / constant
    companion = np.zeros(constant.shape + (2, 2))
    companion[..., 0, 0] = -middle
    companion[..., 0, 1] = -last
    companion[..., 1, 0] = 1.0
    w = np.linalg.eigvals(companion)
    real = np.abs(w.imag) <= 1e-12 * np.abs(w)
    with np.errstate(divide="ignore", invalid="ignore"):
        speeds = np.where(real & (w.real > 0), 1.0 / np.sqrt(w.real), np.nan)
    speeds = np.sort(speeds, axis=-1)
    return speeds[:, 0], speeds[:, 1]


if __name__ == "__main__":
    import time

    G = 9.81
    benchmark = (np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]]),
                 np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]]),
                 np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]) * G,
                 np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]]))
    count = 100_000
    rng = np.random.default_rng(1)
    batch = [X * (1.0 + 0.05 * rng.uniform(-1.0, 1.0, (count, 2, 2))) for X in benchmark]
    for X in (batch[0], batch[2]):
        X[:, 1, 0] = X[:, 0, 1]
    start = time.perf_counter()
    hopf, real = bare_critical_roots(*batch)
    elapsed = time.perf_counter() - start
    single = bare_critical_roots(*(X[None] for X in benchmark))
    print(f"benchmark bicycle: hopf roots {single[0][0]}, real roots {single[1][0]} m/s")
    print(f"{count} bicycles: {elapsed / count * 1e6:.2f} us per bicycle")
