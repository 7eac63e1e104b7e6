"""Standard deviation of a critical speed from uncertain parameters, to first order.

A critical speed v* solves a scalar condition ``g(v, p) = 0`` (the Hopf condition for the
weave speed, ``det A`` for the capsize speed; :mod:`whipple.stability.characteristic`). By the implicit
function theorem its sensitivity to the parameters p is ``dv*/dp = -(dg/dp) / (dg/dv)``, and
for parameters with covariance ``Sigma`` the first-order variance is
``dv*/dp Sigma (dv*/dp)^T``. CasADi gives both derivatives exactly from any function
``A(v, p)``. The approximation is valid while the speed is close to linear in p over a few
standard deviations; it fails at a tangential root (``dg/dv = 0``), which raises.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi
import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import AnalysisError, InputError
from whipple.stability.characteristic import NEWTON_OPTIONS, casadi_conditions

__all__ = ["GUESS_TOLERANCE", "KINDS", "SpeedUncertainty", "critical_speed_uncertainty"]

#: Largest relative distance between the given speed and the root Newton's method finds;
#: farther means the guess belonged to no crossing of this kind (or to another one).
GUESS_TOLERANCE = 0.01
#: Names accepted for the condition of a crossing, by kind of crossing.
KINDS = {"weave": "hopf", "hopf": "hopf", "capsize": "real", "real": "real"}


@dataclass(frozen=True)
class SpeedUncertainty:
    """A critical speed with its first-order standard deviation.

    Attributes
    ----------
    speed : float
        Critical speed [m/s] at the nominal parameters (re-solved with CasADi).
    std : float
        Standard deviation [m/s] propagated from the parameter covariance.
    sensitivity : ndarray, shape (m,)
        ``dv*/dp_i`` [m/s per unit of parameter i].
    kind : str
        ``hopf`` (weave-type crossing) or ``real`` (capsize-type crossing).
    """

    speed: float
    std: float
    sensitivity: NDArray[np.float64]
    kind: str


def _covariance(std_or_cov: ArrayLike, size: int) -> NDArray[np.float64]:
    spread = np.asarray(std_or_cov, dtype=float)
    if spread.ndim == 1 and spread.shape == (size,):
        if np.any(spread < 0) or not np.all(np.isfinite(spread)):
            raise InputError("standard deviations must be finite and non-negative")
        return np.diag(spread**2)
    if spread.shape == (size, size):
        if not np.all(np.isfinite(spread)) or not np.allclose(spread, spread.T):
            raise InputError("covariance must be a finite symmetric matrix")
        return spread
    raise InputError(f"expected {size} standard deviations or a {size}x{size} covariance, "
                     f"got shape {spread.shape}")


def critical_speed_uncertainty(
    state_function: casadi.Function,
    p0: ArrayLike,
    std_or_cov: ArrayLike,
    speed: float,
    kind: str,
) -> SpeedUncertainty:
    """First-order standard deviation of a critical speed.

    Parameters
    ----------
    state_function : casadi.Function
        ``A(v, p)``: forward speed v [m/s] and parameter vector p to the dense n x n state
        matrix [1/s] (SX or MX based), e.g. from ``whipple.model.casadi_model.casadi_state_function``.
    p0 : array_like, shape (m,)
        Nominal parameters.
    std_or_cov : array_like, shape (m,) or (m, m)
        Standard deviations of the parameters (independent), or their covariance; same
        units as p.
    speed : float
        The critical speed at p0 [m/s], or a guess within 1 % of it: it is re-solved by
        Newton's method.
    kind : {'weave', 'capsize', 'hopf', 'real'}
        Which condition the speed solves: a complex pair (weave) or a real eigenvalue
        (capsize) on the imaginary axis.

    Returns
    -------
    SpeedUncertainty

    Raises
    ------
    InputError
        For a bad kind, non-finite p0 or a malformed spread.
    AnalysisError
        If Newton's method does not converge or the root is tangential (dg/dv = 0).
    """
    if kind not in KINDS:
        raise InputError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    condition_kind = KINDS[kind]
    nominal = np.atleast_1d(np.asarray(p0, dtype=float))
    if nominal.ndim != 1 or not np.all(np.isfinite(nominal)):
        raise InputError("nominal parameters must be a finite 1-D vector")
    covariance = _covariance(std_or_cov, nominal.size)
    if not np.isfinite(speed):
        raise InputError(f"speed must be finite, got {speed}")

    v: Any
    p: Any
    try:
        v, p = casadi.SX.sym("v"), casadi.SX.sym("p", nominal.size)
        A = state_function(v, p)
    except RuntimeError:
        # Functions with operations that have no SX form (e.g. a linear solve) stay MX.
        v, p = casadi.MX.sym("v"), casadi.MX.sym("p", nominal.size)
        A = state_function(v, p)
    if A.shape[0] != A.shape[1]:
        raise InputError(f"state function must return a square matrix, got {A.shape}")
    hopf, real = casadi_conditions(A)
    g = hopf if condition_kind == "hopf" else real
    derivative = casadi.Function("dg", [v, p], [g, casadi.jacobian(g, v), casadi.jacobian(g, p)])
    _, slope, _ = derivative(speed, nominal)
    scale = abs(float(slope)) if float(slope) != 0 else 1.0
    residual = casadi.Function("residual", [v, p], [g / scale])
    solver = casadi.rootfinder("critical_speed", "newton", residual, NEWTON_OPTIONS)
    root = float(solver(speed, nominal))
    value, slope, gradient = (np.asarray(x, dtype=float) for x in derivative(root, nominal))
    dg_dv = float(slope.ravel()[0])
    converged = np.isfinite(root) and abs(float(value.ravel()[0])) <= 1e-8 * abs(dg_dv)
    if not converged or abs(root - speed) > GUESS_TOLERANCE * (1.0 + abs(speed)):
        raise AnalysisError(f"no critical speed of kind {kind!r} found near {speed} m/s")
    if dg_dv == 0:
        raise AnalysisError(f"critical speed {root} m/s is a tangential root: "
                            "no first-order uncertainty")
    sensitivity = -gradient.ravel() / dg_dv
    variance = float(sensitivity @ covariance @ sensitivity)
    std = float(np.sqrt(max(variance, 0.0)))
    return SpeedUncertainty(root, std, sensitivity, condition_kind)
