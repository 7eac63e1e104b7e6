"""The speed a window's model is evaluated at when the speed changes inside the window.

Coasting on the ground, the speed falls through a window (``v(t) = v + v' (t - t_c)``, the
measured mean ``v`` and slope ``v'`` [m/s^2] of the speed's regression): the bicycle is a linear
time-varying system along v(t), with the term ``v' Ka q`` a changing speed adds
(:func:`whipple.model.speed_change.acceleration_stiffness`). A fitted window's eigenvalue is not
the model's at the mean speed: the fit weighs each instant by the oscillation's squared
amplitude ``e^{2 d t}``, so a decaying weave is fitted mostly at the window's start (higher
speed) and a growing one at its end. Fitting a constant ``d + i w`` to a log-amplitude and a
phase whose slopes drift linearly in time gives the slopes at the weighted regression time

    t_eff = Cov_w(t^2 / 2, t) / Var_w(t),   w(t) = e^{2 d t} on [0, T],

(the window's centre for ``d = 0``). The model's eigenvalue for the window is that of the frozen
model at ``v(t_eff)`` with ``v' Ka q`` added; against the weave fit of simulated free responses
along v(t) this leaves 0.005-0.05 1/s where the mean speed left up to 0.16 1/s
(tests/test_window_speed.py). Windows at constant speed (``v' = 0``: treadmill runs) keep their
mean speed exactly.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Points of the quadrature of the weighted moments over a window (the integrands are smooth).
_QUADRATURE_POINTS = 257


class _Window(Protocol):
    @property
    def start(self) -> float: ...
    @property
    def stop(self) -> float: ...
    @property
    def speed(self) -> float: ...
    @property
    def eigenvalue(self) -> complex: ...
    @property
    def acceleration(self) -> float: ...


def fit_weighted_offset(damping: ArrayLike, duration: ArrayLike) -> NDArray[np.float64]:
    """Return ``t_eff - T / 2`` [s]: where in a window a fit of a drifting eigenvalue reads it.

    Parameters
    ----------
    damping : array_like
        The fitted real part ``d`` of each window's eigenvalue [1/s].
    duration : array_like
        Each window's length ``T`` [s], same shape.

    Returns
    -------
    ndarray
        ``t_eff - T / 2`` [s], with ``t_eff`` the squared-amplitude-weighted regression time of
        ``t^2 / 2`` on ``t`` (module docstring): negative for a decaying oscillation.
    """
    d = np.atleast_1d(np.asarray(damping, dtype=float))
    T = np.atleast_1d(np.asarray(duration, dtype=float))
    s = np.linspace(0.0, 1.0, _QUADRATURE_POINTS)
    t = T[..., None] * s
    # Weights relative to their largest value: no overflow for any d T.
    exponent = 2.0 * d[..., None] * t
    weight = np.exp(exponent - exponent.max(axis=-1, keepdims=True))
    weight /= weight.sum(axis=-1, keepdims=True)
    mean = (weight * t).sum(axis=-1)
    centred = t - mean[..., None]
    variance = (weight * centred**2).sum(axis=-1)
    covariance = (weight * centred * (0.5 * t**2)).sum(axis=-1)
    return np.asarray(np.where(variance > 0, covariance / np.where(variance > 0, variance, 1.0), 0.5 * T) - 0.5 * T,
                      dtype=float)


def window_speeds(windows: Sequence[_Window]) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Return the measured speed [m/s] each window's model is evaluated at, and the accelerations.

    The speed is the mean where the window's speed is constant, else the speed at ``t_eff``
    (:func:`fit_weighted_offset` of the window's fitted damping); the accelerations [m/s^2]
    are the measured slopes, None where every window's speed is constant (then nothing
    changes from constant-speed windows, to the last bit).
    """
    speeds = np.array([w.speed for w in windows], dtype=float)
    accelerations = np.array([w.acceleration for w in windows], dtype=float)
    if not np.any(accelerations != 0):
        return speeds, None
    offset = fit_weighted_offset([complex(w.eigenvalue).real for w in windows], [w.stop - w.start for w in windows])
    return np.where(accelerations != 0, speeds + accelerations * offset, speeds), accelerations
