"""The speed of a bicycle coasting on the ground: rolling resistance and air drag.

While it coasts, the speed obeys ``v' = -(a + k v^2)``: ``a`` [m/s^2] the rolling resistance
(and any slope), nearly independent of speed, and ``k v^2`` the air drag, ``k = rho CdA / (2 m)``
[1/m]. Its closed form, with ``r = sqrt(a k)`` and ``T(x) = tan(x) / x``,

    v(t) = (v0 - a t T(r t)) / (1 + v0 k t T(r t)),

is ``v0 - a t`` without drag and ``v0 / (1 + v0 k t)`` without rolling resistance; the distance
rolled, ``x(t) = ln(cos(r t) + v0 sqrt(k / a) sin(r t)) / k``, is written with ``log1p`` and
``sinc`` so that it tends to ``v0 t - a t^2 / 2`` as k tends to 0 without cancellation.
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
        Rolling resistance ``a`` [m/s^2], >= 0.
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
    rt = math.sqrt(deceleration * drag) * t
    ratio = _tan_ratio(rt)
    return (speed - deceleration * t * ratio) / (1.0 + speed * drag * t * ratio)


def coasting_distance(speed: float, deceleration: float, drag: float, t: ArrayLike) -> NDArray[np.float64]:
    """Distance rolled [m] from t = 0 to times ``t`` [s]: the exact integral of :func:`coasting_speed`."""
    t = np.asarray(t, dtype=float)
    if drag == 0:
        return speed * t - 0.5 * deceleration * t**2
    rt = math.sqrt(deceleration * drag) * t
    # cos(rt) - 1 + v0 sqrt(k/a) sin(rt), divided by k, written without 0/0 at a = 0 or k -> 0.
    inner = speed * t * np.sinc(rt / np.pi) - 0.5 * deceleration * t**2 * np.sinc(rt / (2 * np.pi))**2
    return np.log1p(drag * inner) / drag


def coasting_deceleration(speed: float, deceleration: float, drag: float, t: ArrayLike) -> NDArray[np.float64]:
    """Deceleration ``a + k v(t)^2`` [m/s^2] at times ``t`` [s] (positive while slowing down)."""
    return deceleration + drag * coasting_speed(speed, deceleration, drag, t) ** 2


def _tan_ratio(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``tan(x) / x``, 1 at x = 0."""
    x = np.asarray(x, dtype=float)
    safe = np.where(x == 0, 1.0, x)
    return np.where(x == 0, 1.0, np.tan(safe) / safe)
