"""The speed of a bicycle coasting on the ground: rolling resistance and air drag.

While it coasts, the speed obeys ``v' = -(a + k v^2)``: ``a`` [m/s^2] the rolling resistance
(and any slope), nearly independent of speed, and ``k v^2`` the air drag, ``k = rho CdA / (2 m)``
[1/m]. Its closed form, with ``r = sqrt(a k)`` and ``T(x) = tan(x) / x``,

    v(t) = (v0 - a t T(r t)) / (1 + v0 k t T(r t)),

is ``v0 - a t`` without drag and ``v0 / (1 + v0 k t)`` without rolling resistance; the distance
rolled, ``x(t) = ln(cos(r t) + v0 sqrt(k / a) sin(r t)) / k``, is written with ``log1p`` and
``sinc`` so that it tends to ``v0 t - a t^2 / 2`` as k tends to 0 without cancellation.

Down a slope steeper than the rolling resistance, ``a`` is negative (gravity's pull along the
road exceeds it) and the bicycle speeds up: ``r`` is then imaginary, and the same forms hold with
``tanh`` and ``sinh`` for ``tan`` and ``sin``; with drag the speed tends to ``sqrt(-a / k)``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray


def stopping_time(speed: float, deceleration: float, drag: float) -> float:
    """Time [s] at which the coasting bicycle comes to rest (inf: never, without rolling resistance).

    Parameters
    ----------
    speed : float
        Speed at t = 0 [m/s], positive.
    deceleration : float
        Rolling resistance ``a`` [m/s^2] (negative down a slope that speeds the bicycle up).
    drag : float
        Air drag coefficient ``k`` [1/m], >= 0.
    """
    if deceleration <= 0:
        return math.inf
    if drag <= 0:
        return speed / deceleration
    return math.atan(speed * math.sqrt(drag / deceleration)) / math.sqrt(deceleration * drag)


def coasting_speed(speed: float, deceleration: float, drag: float, t: ArrayLike) -> NDArray[np.float64]:
    """Speed [m/s] at times ``t`` [s] (before :func:`stopping_time`) of ``v' = -(a + k v^2)``.

    ``speed`` [m/s] at t = 0, ``deceleration`` a [m/s^2], ``drag`` k [1/m]; without drag exactly
    ``speed - deceleration * t``.
    """
    t = np.asarray(t, dtype=float)
    if drag == 0:
        return speed - deceleration * t
    ratio = _tan_ratio(deceleration * drag, t)
    return (speed - deceleration * t * ratio) / (1.0 + speed * drag * t * ratio)


def coasting_distance(speed: float, deceleration: float, drag: float, t: ArrayLike) -> NDArray[np.float64]:
    """Distance rolled [m] from t = 0 to times ``t`` [s]: the exact integral of :func:`coasting_speed`."""
    t = np.asarray(t, dtype=float)
    if drag == 0:
        return speed * t - 0.5 * deceleration * t**2
    # cos(rt) - 1 + v0 sqrt(k/a) sin(rt), divided by k, written without 0/0 at a = 0 or k -> 0.
    inner = speed * t * _sin_ratio(deceleration * drag, t) - 0.5 * deceleration * t**2 * _sin_ratio(
        deceleration * drag, t / 2)**2
    return np.log1p(drag * inner) / drag


def coasting_deceleration(speed: float, deceleration: float, drag: float, t: ArrayLike) -> NDArray[np.float64]:
    """Deceleration ``a + k v(t)^2`` [m/s^2] at times ``t`` [s] (positive while slowing down)."""
    return deceleration + drag * coasting_speed(speed, deceleration, drag, t) ** 2


def _tan_ratio(rate_squared: float, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """``tan(r t) / (r t)`` with ``r**2 = rate_squared`` [1/s^2] (``tanh`` for a negative one), 1 at r t = 0."""
    x = math.sqrt(abs(rate_squared)) * np.asarray(t, dtype=float)
    safe = np.where(x == 0, 1.0, x)
    tangent = np.tan(safe) if rate_squared >= 0 else np.tanh(safe)
    return np.where(x == 0, 1.0, tangent / safe)


def _sin_ratio(rate_squared: float, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """``sin(r t) / (r t)`` with ``r**2 = rate_squared`` [1/s^2] (``sinh`` for a negative one), 1 at r t = 0."""
    x = math.sqrt(abs(rate_squared)) * np.asarray(t, dtype=float)
    if rate_squared >= 0:
        return np.sinc(x / np.pi)
    safe = np.where(x == 0, 1.0, x)
    return np.where(x == 0, 1.0, np.sinh(safe) / safe)
