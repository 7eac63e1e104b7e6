"""Variable projection of the weave function, for one window or many at once.

For a given eigenvalue ``d + i w`` the fitted function's coefficients (the baseline's
polynomial and the oscillation's c2, c3, per signal) enter linearly: they are a least-squares
solution, and only the projected residual remains to be minimised over (d, w), with Kaufman's
Jacobian (Golub & Pereyra). :mod:`whipple.measurement.weavefit` minimises it for one window;
:mod:`whipple.measurement.refit` for many windows at once, where per-window NumPy calls on
matrices of a few hundred rows would cost more in overhead than in arithmetic.

The windows' samples lie end to end in one array, and every inner product is a sum over a
window's own samples (``numpy.add.reduceat``). The projection is built by classical
Gram-Schmidt with one reorthogonalisation ("twice is enough"), which keeps the basis as
orthonormal as Householder's: the baseline's polynomial columns once per window (they do not
depend on the eigenvalue), then the decaying cosine and sine at each eigenvalue.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray


class Projection:
    """The projected residual of the weave function for a set of windows.

    Parameters
    ----------
    taus : sequence of ndarray, shape (n_i,)
        Each window's sample times from its first sample [s].
    values : sequence of ndarray, shape (n_i, k)
        Each window's k signals (the same k for every window), as they are to be weighted.
    degree : int
        Degree of the baseline polynomial (:data:`~whipple.measurement.weavefit.BASELINES`).
    """

    def __init__(self, taus: Sequence[NDArray[np.float64]], values: Sequence[NDArray[np.float64]],
                 degree: int = 0) -> None:
        self.sizes = np.array([tau.size for tau in taus])
        self.tau = np.concatenate(taus)
        every = _Segments(self.sizes)
        # Polynomials in the window's time scaled to [-1, 1]: the same column space as powers
        # of tau, better conditioned.
        span = every.expand(np.array([tau[-1] for tau in taus]))
        scaled = 2.0 * self.tau / np.where(span > 0, span, 1.0) - 1.0
        basis = np.empty((self.tau.size, 0))
        for power in range(degree + 1):
            basis = np.column_stack([basis, every.orthonormal(basis, scaled**power)[0]])
        self.polynomials = basis
        self.data_left = np.concatenate(values)
        for _ in range(2):
            self.data_left = self.data_left - _project(every, basis, self.data_left)

    def parts(self, theta: NDArray[np.float64], rows: NDArray[np.intp]
              ) -> tuple[NDArray[np.float64], NDArray[np.float64], _Segments]:
        """Return the projected residuals (s, k) and Jacobians (s, k, 2) of windows `rows` at `theta` (m, 2).

        ``rows`` are in increasing order and ``theta`` holds their (d, w) [1/s]. The samples of
        the windows lie end to end (s in all); the returned segments say where each begins.
        """
        segments = _Segments(self.sizes[rows])
        samples = np.repeat(np.isin(np.arange(self.sizes.size), rows), self.sizes)
        tau, polynomials, data_left = self.tau[samples], self.polynomials[samples], self.data_left[samples]
        d, w = segments.expand(theta[:, 0]), segments.expand(theta[:, 1])
        decay = np.exp(d * tau)
        cos, sin = decay * np.cos(w * tau), decay * np.sin(w * tau)
        cos_unit, cos_norm = segments.orthonormal(polynomials, cos)
        sin_unit, sin_norm, along = segments.orthonormal(np.column_stack([polynomials, cos_unit]), sin,
                                                         with_coefficients=True)
        cos_share, sin_share = segments.dot(cos_unit, data_left), segments.dot(sin_unit, data_left)
        residual = (data_left - segments.expand(cos_share) * cos_unit[:, None]
                    - segments.expand(sin_share) * sin_unit[:, None])
        # The coefficients of the cosine and sine themselves (per signal): back-substitution
        # through their 2 x 2 triangular factor.
        c3 = sin_share / sin_norm[:, None]
        c2 = (cos_share - along[:, -1:] * c3) / cos_norm[:, None]
        c2, c3 = segments.expand(c2), segments.expand(c3)
        basis = np.column_stack([polynomials, cos_unit, sin_unit])
        columns = []
        for derivative in (
            tau[:, None] * (cos[:, None] * c2 + sin[:, None] * c3),  # d/dd of the model, per signal
            tau[:, None] * (cos[:, None] * c3 - sin[:, None] * c2),  # d/dw
        ):
            columns.append(-(derivative - _project(segments, basis, derivative)))
        return residual, np.stack(columns, axis=2), segments

    def costs_and_steps(self, theta: NDArray[np.float64], rows: NDArray[np.intp]
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return each window's sum of squared residuals and Gauss-Newton step (m, 2) at `theta` (m, 2).

        The step solves the 2 x 2 normal equations of the window's Jacobian; where they are
        singular (or not finite), the step is NaN.
        """
        residual, jacobian, segments = self.parts(theta, rows)
        costs = segments.sum(np.sum(residual**2, axis=1))
        normal = segments.sum(np.einsum("ska,skb->sab", jacobian, jacobian))
        gradient = segments.sum(np.einsum("ska,sk->sa", jacobian, residual))
        determinant = normal[:, 0, 0] * normal[:, 1, 1] - normal[:, 0, 1] * normal[:, 1, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            steps = -np.column_stack([normal[:, 1, 1] * gradient[:, 0] - normal[:, 0, 1] * gradient[:, 1],
                                      normal[:, 0, 0] * gradient[:, 1] - normal[:, 1, 0] * gradient[:, 0]]
                                     ) / determinant[:, None]
        return costs, np.where(np.isfinite(steps), steps, np.nan)


class _Segments:
    """Windows whose samples lie end to end: sums over each, and values spread over each."""

    def __init__(self, sizes: NDArray[np.intp]) -> None:
        self.sizes = sizes
        self.starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)

    def sum(self, values: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return each window's sum of `values` (first axis: samples)."""
        return np.asarray(np.add.reduceat(values, self.starts, axis=0), dtype=float)

    def expand(self, values: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return each window's value repeated over its samples."""
        return np.repeat(values, self.sizes, axis=0)

    def dot(self, column: NDArray[np.float64], values: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return each window's inner products of `column` (s,) with each column of `values` (s, k)."""
        return self.sum(column[:, None] * values)

    def orthonormal(self, basis: NDArray[np.float64], column: NDArray[np.float64], with_coefficients: bool = False
                    ) -> tuple[NDArray[np.float64], ...]:
        """Return `column` orthogonalised against the orthonormal `basis` (s, j), normalised per window; and its norm.

        With ``with_coefficients`` also its components along the basis (m, j), the
        triangular factor's column above the norm.
        """
        coefficients = np.zeros((self.sizes.size, basis.shape[1]))
        left = column
        for _ in range(2):
            along = self.sum(basis * left[:, None])
            coefficients = coefficients + along
            left = left - np.sum(basis * self.expand(along), axis=1)
        norm = np.sqrt(self.sum(left**2))
        with np.errstate(divide="ignore", invalid="ignore"):
            unit = left / self.expand(norm)
        return (unit, norm, coefficients) if with_coefficients else (unit, norm)


def _project(segments: _Segments, basis: NDArray[np.float64], values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the projection of `values` (s, k) on each window's orthonormal `basis` (s, j)."""
    along = segments.sum(basis[:, :, None] * values[:, None, :])  # (m, j, k)
    return np.einsum("sj,sjk->sk", basis, segments.expand(along))
