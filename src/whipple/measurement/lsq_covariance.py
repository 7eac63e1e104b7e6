"""Covariance of nonlinear least-squares estimates, for white or autocorrelated residuals.

From the Jacobian J of the model at the optimum and the residual r:

* white residuals: ``s^2 (J^T J)^-1`` with ``s^2 = |r|^2 / (N - p)``;
* autocorrelated residuals (unmodelled dynamics, sensor filters): the Newey-West estimate
  ``(J^T J)^-1 S (J^T J)^-1``, with S the Bartlett-weighted sum of the autocovariances of the
  score series ``J_t r_t`` up to L lags; L is Andrews' (1991) AR(1) plug-in bandwidth.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.errors import AnalysisError, InputError

NOISE_MODELS = ("auto", "white", "correlated")


class SingularFitError(AnalysisError):
    """The data do not determine all parameters (singular information matrix)."""


@dataclass(frozen=True)
class LsqCovariance:
    """Covariance of the parameters of a least-squares fit.

    Attributes
    ----------
    covariance : ndarray, shape (p, p)
        The chosen estimate.
    white : ndarray, shape (p, p)
        The estimate for white residuals.
    model : str
        ``"white"`` or ``"newey-west(L)"``.
    lag1 : float
        Lag-1 autocorrelation of the residual.
    """

    covariance: NDArray[np.float64]
    white: NDArray[np.float64]
    model: str
    lag1: float


def lsq_covariance(
    jacobian: NDArray[np.float64], residual: NDArray[np.float64], noise: str = "auto"
) -> LsqCovariance:
    """Covariance of least-squares parameters.

    Parameters
    ----------
    jacobian : ndarray, shape (k, n, p)
        Derivatives of the (weighted) model values of k signals at n times with respect to the
        p parameters.
    residual : ndarray, shape (k, n)
        Weighted residuals at the optimum.
    noise : {"auto", "white", "correlated"}
        White, Newey-West, or Newey-West only when the residual's lag-1 autocorrelation
        exceeds 3 / sqrt(n) (three standard errors of white noise).

    Raises
    ------
    SingularFitError
        If the information matrix is singular or there are no degrees of freedom left.
    InputError
        For an unknown noise model.
    """
    if noise not in NOISE_MODELS:
        raise InputError(f"unknown noise model '{noise}' (one of {', '.join(NOISE_MODELS)})")
    k, n, p = jacobian.shape
    information = np.einsum("kni,knj->ij", jacobian, jacobian)
    # Column scaling makes the conditioning test independent of the parameters' units.
    scale = np.sqrt(np.diag(information))
    if n * k <= p or not (scale > 0).all():
        raise SingularFitError("the data do not determine all parameters")
    normalised = information / np.outer(scale, scale)
    if np.linalg.cond(normalised) > 1e12:
        raise SingularFitError("the data do not determine all parameters")
    inverse = np.linalg.inv(normalised) / np.outer(scale, scale)
    white = float(np.sum(residual**2)) / (n * k - p) * inverse
    rho = _lag1(residual)
    if noise == "white" or (noise == "auto" and rho * np.sqrt(n) <= 3.0):
        return LsqCovariance(white, white, "white", rho)
    # The signals share the time axis: their scores add up to one series in time.
    scores = np.einsum("kni,kn->ni", jacobian, residual)
    # Prewhitening (Andrews & Monahan 1992): take out an AR(1) part, estimate the long-run
    # covariance of what is left with the Bartlett kernel, and put the AR(1) part back.
    phi = min(max(rho, 0.0), 0.97)
    whitened = scores[1:] - phi * scores[:-1]
    lags = _bandwidth(_lag1(whitened.T), n)
    meat = whitened.T @ whitened
    for lag in range(1, lags + 1):
        gamma = whitened[lag:].T @ whitened[:-lag]
        meat += (1 - lag / (lags + 1)) * (gamma + gamma.T)
    meat *= n / ((n - 1) * (1 - phi) ** 2)
    # The degrees-of-freedom correction of the white estimate, per time sample.
    covariance = inverse @ meat @ inverse * n * k / (n * k - p)
    return LsqCovariance(covariance, white, f"newey-west({lags}, prewhitened {phi:.2f})", rho)


def _lag1(residual: NDArray[np.float64]) -> float:
    centred = residual - residual.mean(axis=1, keepdims=True)
    denominator = float(np.sum(centred**2))
    if denominator == 0:
        return 0.0
    return float(np.sum(centred[:, 1:] * centred[:, :-1]) / denominator)


def _bandwidth(rho: float, n: int) -> int:
    """Andrews (1991) AR(1) plug-in bandwidth of the Bartlett kernel, at most n / 4 lags."""
    rho = min(max(rho, -0.99), 0.99)
    alpha = 4 * rho**2 / ((1 - rho) ** 2 * (1 + rho) ** 2)
    return int(min(max(1, np.ceil(1.1447 * (alpha * n) ** (1 / 3))), n // 4))
