"""Starting values for fitting a damped sinusoid ``c1 + exp(d t)[c2 cos wt + c3 sin wt]``.

Local optimisers need a start near the right (d, w): the projected least-squares cost has
local minima at multiples and fractions of the frequency. Several independent estimates are
offered; :mod:`whipple.measurement.weavefit` polishes the most promising ones.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import eigh


def starting_values(tau: ArrayLike, y: ArrayLike) -> list[tuple[float, float]]:
    """Candidate (d [1/s], w [rad/s]) for a damped sinusoid in `y` sampled at times `tau` [s].

    A matrix-pencil estimate first (when the window is long enough), then the zero-crossing
    frequency with the envelope's decay, at three frequencies, and one period per window.
    """
    t = np.asarray(tau, dtype=float)
    t = t - t[0]
    v = np.asarray(y, dtype=float)
    span = float(t[-1])
    dt = span / (t.size - 1)
    starts = []
    pencil = _matrix_pencil(t, v, dt)
    if pencil is not None:
        starts.append(pencil)
    # Zero crossings of the detrended signal: half a period apart.
    signal = v - np.polyval(np.polyfit(t, v, 1), t)
    crossings = t[np.flatnonzero(np.diff(np.signbit(signal)))]
    if crossings.size >= 2:
        w0 = np.pi * (crossings.size - 1) / (crossings[-1] - crossings[0])
    else:
        w0 = np.pi / span
    envelope = np.abs(signal)
    head, tail = envelope[: t.size // 2].max(), envelope[t.size // 2:].max()
    d0 = float(np.log(max(tail, 1e-12) / max(head, 1e-12)) / (0.5 * span))
    for factor in (1.0, 0.6, 1.6):
        starts.append((d0, w0 * factor))
    starts.append((0.0, 2 * np.pi / span))
    return starts


def _matrix_pencil(tau: NDArray[np.float64], y: NDArray[np.float64], dt: float) -> tuple[float, float] | None:
    """Dominant oscillatory pole of a 3-pole (offset + pair) matrix-pencil model."""
    step = max(1, tau.size // 300)
    x = y[::step]
    n = x.size
    # A modest pencil keeps the matrices small; these are only starting values.
    pencil = min(n // 3, 40)
    if pencil < 3:
        return None
    hankel = np.ascontiguousarray(np.lib.stride_tricks.sliding_window_view(x, pencil + 1))
    # The three dominant right singular vectors of the Hankel matrix, from its Gram matrix.
    vectors = eigh(hankel.T @ hankel, subset_by_index=[pencil - 2, pencil], driver="evr")[1]
    poles = np.linalg.eigvals(np.linalg.pinv(vectors[:-1]) @ vectors[1:])
    poles = poles[np.abs(poles.imag) > 1e-9]
    if poles.size == 0:
        return None
    s = np.log(poles[np.argmax(poles.imag)]) / (dt * step)
    return float(s.real), float(abs(s.imag))
