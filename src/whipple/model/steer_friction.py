"""Coulomb steer friction: its smooth torque law and its describing-function equivalent damping.

Dry friction in the headset bearings (their seals above all), cables and a steer motor's
brushes or gears acts between the front and the rear frame about the steer axis as a torque of
fixed size ``F`` [N m] against the steer rate. Its sign flips with the steer rate's; the
simulated runs take it smooth,

    T = -F tanh(delta_dot / w),

with a smoothing rate ``w`` [rad/s] (:data:`SMOOTHING_RATE`) far below a weave's steer rates,
so that the law is dry friction wherever the steer moves and a steep viscous torque ``F / w``
where it stands nearly still (no switching logic, no sticking state to integrate).

The torque is nonlinear, so the linear model (:func:`whipple.model.assembly.linear_model`)
leaves it out. A weave of steer-angle amplitude ``A`` [rad] and angular frequency ``omega``
[rad/s] loses per cycle to it what a viscous steer damping of

    c_eq = 4 F / (pi omega A)    [N m s/rad]

loses (the first harmonic of a square wave of height F: the describing function): the linear
model of a window is the model with that damping added (:func:`describing_gain`). The damping
grows as the weave decays, so that windows of different amplitudes tell Coulomb friction
from viscous damping, which is the same at every amplitude.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Smoothing rate w [rad/s] of the friction law's tanh. A weave's steer rate is about
#: omega A: 0.1-1 rad/s for steer amplitudes of 0.02-0.1 rad at 5 rad/s, 5-50 times w, where
#: the tanh's first harmonic is within 1-5% of the sign function's (4/pi).
SMOOTHING_RATE = 0.02


def friction_torque(friction: float, steer_rate: ArrayLike, smoothing: float = SMOOTHING_RATE
                    ) -> NDArray[np.float64]:
    """Return the smooth Coulomb friction torque about the steer axis [N m] (on the front frame).

    Parameters
    ----------
    friction : float
        The friction torque's size F [N m] (>= 0).
    steer_rate : array_like
        Steer rate [rad/s].
    smoothing : float
        Smoothing rate w [rad/s] (:data:`SMOOTHING_RATE`).

    Returns
    -------
    ndarray
        ``-F tanh(steer_rate / w)`` [N m], the shape of ``steer_rate``.
    """
    return -float(friction) * np.tanh(np.asarray(steer_rate, dtype=float) / smoothing)


def describing_gain(frequency: ArrayLike, steer_amplitude: ArrayLike) -> NDArray[np.float64]:
    """Return the equivalent viscous steer damping of a unit Coulomb friction, ``4 / (pi omega A)`` [s/rad].

    Times the friction torque F [N m] it is the viscous damping [N m s/rad] that dissipates as
    much per cycle of a steer oscillation of angular frequency ``frequency`` [rad/s] and
    amplitude ``steer_amplitude`` [rad]. Zero where the amplitude or frequency is not a
    positive finite number (a window whose steer amplitude is unknown: the friction does not
    enter its model).
    """
    omega = np.asarray(frequency, dtype=float)
    amplitude = np.asarray(steer_amplitude, dtype=float)
    valid = np.isfinite(omega) & np.isfinite(amplitude) & (omega > 0) & (amplitude > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        gain = 4.0 / (np.pi * omega * amplitude)
    return np.where(valid, gain, 0.0)


def representative_amplitude(start_amplitude: ArrayLike, damping: ArrayLike, duration: ArrayLike
                             ) -> NDArray[np.float64]:
    """Return a window's amplitude-weighted mean amplitude, ``int A^2 dt / int A dt``, of an envelope ``A0 e^{d t}``.

    A window's weave fit reports one decay rate for an envelope whose equivalent damping changes
    with the amplitude; the fit's samples weigh the large amplitudes most, so each instant's
    equivalent damping (1 / A) is weighed by the amplitude squared: ``int A^2 (1/A) / int A^2``,
    which is 1 / (this amplitude). For an exponential envelope it is the mean of the window's
    first and last amplitude, ``A0 (1 + e^{d T}) / 2``.

    Parameters
    ----------
    start_amplitude : array_like
        Envelope at the window's start A0 [signal unit].
    damping : array_like
        The fitted decay rate d [1/s] (negative: decaying).
    duration : array_like
        The window's length T [s].

    Returns
    -------
    ndarray
        The representative amplitude [signal unit].
    """
    a0 = np.asarray(start_amplitude, dtype=float)
    end = np.exp(np.asarray(damping, dtype=float) * np.asarray(duration, dtype=float))
    return np.asarray(a0 * (1.0 + end) / 2.0, dtype=float)
