"""The weave's mode shape in a window: a second signal's complex amplitude relative to the first.

In a free decay every measured state oscillates as ``Re[a_k exp(lambda tau)]`` with its own
complex amplitude ``a_k = c2_k - i c3_k``. The ratio of two amplitudes (steer angle per roll
rate, say) does not depend on how the decay was started: the linear model predicts it as the
ratio of the weave eigenvector's components. Eigenvalues alone leave some model errors nearly
interchangeable; the mode shape tells several of them apart.

The weave's eigenvalue is the window's fit (:mod:`whipple.measurement.weavefit`). Two things the weave fit
tolerates would bias a ratio, and are handled here (the eigenvalue is refined with them):

* the slow capsize mode moves the steer far more than the roll rate, and over a long window no
  low polynomial follows its exponential: both signals get a constant plus ``exp(s tau)``, with
  the rate s shared and fitted;
* a window starts soon after a push, while the fast castering mode still moves the steer: the
  first ``settle`` seconds are left out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares, minimize_scalar

from whipple.errors import InputError
from whipple.measurement.lsq_covariance import SingularFitError, lsq_covariance
from whipple.measurement.weavefit import MIN_SAMPLES, NoOscillationError, WeaveFit

#: Time after the window's start left out of the amplitude fit [s]: three time constants of the
#: castering mode at weave speeds for the benchmark and the bundled bicycles (0.05-0.1 s). On
#: noise-free simulated benchmark runs at 4-8 m/s the ratio (about 0.2-0.3 s) was off by up to
#: 8e-3 s without it, 3e-4 s with 0.2 s and 1e-4 s with 0.3 s.
SETTLE = 0.3
#: Largest |s| times the window length: beyond it the exponential is a step at one end.
MAX_SLOW_EXPONENT = 20.0


@dataclass(frozen=True)
class AmplitudeRatio:
    """A second signal's oscillation relative to the fitted one.

    Attributes
    ----------
    signal, reference : str
        Names of the two signals (e.g. ``"steer_angle"`` relative to ``"roll_rate"``).
    ratio : complex
        ``a_signal / a_reference`` (signal unit per reference unit, e.g. rad per rad/s = s).
    covariance : ndarray, shape (2, 2)
        Covariance of the (real, imaginary) part of the ratio, including the uncertainty of
        the shared eigenvalue and slow rate.
    slow_rate : float
        The fitted rate s of the non-oscillating part [1/s].
    eigenvalue : complex
        The weave eigenvalue d + i w refined jointly from both signals, with the slow mode as
        an exponential [1/s].
    eigenvalue_covariance : ndarray, shape (2, 2)
        Covariance of (d, w) [1/s^2].
    """

    signal: str
    reference: str
    ratio: complex
    covariance: NDArray[np.float64]
    slow_rate: float
    eigenvalue: complex
    eigenvalue_covariance: NDArray[np.float64]


def _basis(tau: NDArray[np.float64], slow: float, d: float, w: float) -> NDArray[np.float64]:
    decay = np.exp(d * tau)
    return np.column_stack([np.ones_like(tau), np.exp(slow * tau), decay * np.cos(w * tau), decay * np.sin(w * tau)])


def _jacobian(tau: NDArray[np.float64], coefficients: NDArray[np.float64], slow: float, d: float,
              w: float) -> NDArray[np.float64]:
    """Return the derivatives (k, n, 4 k + 3) of the model values w.r.t. (4 c's per signal, s, d, w)."""
    k = coefficients.shape[0]
    basis = _basis(tau, slow, d, w)
    jacobian = np.zeros((k, tau.size, 4 * k + 3))
    for signal, (_, c4, c2, c3) in enumerate(coefficients):
        jacobian[signal, :, 4 * signal: 4 * signal + 4] = basis
        jacobian[signal, :, -3] = tau * c4 * basis[:, 1]
        jacobian[signal, :, -2] = tau * (basis[:, 2] * c2 + basis[:, 3] * c3)
        jacobian[signal, :, -1] = tau * (basis[:, 2] * c3 - basis[:, 3] * c2)
    return jacobian


def amplitude_ratio(fit: WeaveFit, values: ArrayLike, signal: str, noise: str = "auto",
                    settle: float = SETTLE) -> AmplitudeRatio:
    """Return the complex amplitude of ``values`` relative to the fit's first signal.

    Parameters
    ----------
    fit : WeaveFit
        A fit of the window; its eigenvalue is used for the second signal too.
    values : array_like, shape (n,)
        The second signal at the fit's sample times (signal unit).
    signal : str
        Its name.
    noise : {"auto", "white", "correlated"}
        Covariance estimate, as in :func:`whipple.measurement.weavefit.fit_weave`.
    settle : float
        Time after the window's start left out of the amplitude fit [s].

    Raises
    ------
    NoOscillationError
        If under half a weave period remains after ``settle``, the reference signal does not
        oscillate, or the data do not determine the ratio.
    InputError
        If ``values`` do not match the fit's samples or are not finite.
    """
    y = np.asarray(values, dtype=float)
    if y.shape != fit.time.shape or not np.isfinite(y).all():
        raise InputError(f"amplitude_ratio: {signal} must be {fit.time.size} finite samples of the fitted window")
    keep = fit.time >= fit.start + settle
    if fit.frequency * (fit.stop - fit.start - settle) < np.pi or np.count_nonzero(keep) < MIN_SAMPLES:
        raise NoOscillationError(f"under half a weave period left for the {signal} amplitude after {settle:g} s")
    tau = fit.time[keep] - fit.start
    measured = np.vstack([fit.measured[0][keep], y[keep]])
    if not np.all(np.ptp(measured, axis=1) > 0):
        raise NoOscillationError(f"{signal} does not change in the window")
    # Each signal counts by the inverse of its spread until its residual is known.
    weights = 1.0 / np.maximum(measured.std(axis=1), 1e-300)

    def solve(theta: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        basis = _basis(tau, *theta)
        coefficients = np.linalg.lstsq(basis, measured.T, rcond=None)[0]
        curves = (basis @ coefficients).T
        return ((measured - curves) * weights[:, None]).ravel(), coefficients.T, curves

    limit = MAX_SLOW_EXPONENT / float(tau[-1])
    d, w = fit.damping, fit.frequency
    start = minimize_scalar(lambda slow: float(np.sum(solve(np.array([slow, d, w]))[0] ** 2)),
                            bounds=(-limit, limit), method="bounded", options={"xatol": 1e-6 * limit}).x
    # The eigenvalue is refined with the slow mode in the model: the window's weave fit uses a
    # polynomial for it, which leaves a small bias that the ratio would inherit.
    span = float(tau[-1])
    lower, upper = [-limit, d - 5.0 / span, 0.5 * w], [limit, d + 5.0 / span, 1.5 * w]
    theta = least_squares(lambda th: solve(th)[0], np.clip([start, d, w], lower, upper), bounds=(lower, upper),
                          x_scale=np.array([1.0, 1.0, 1.0]) / span).x
    slow, d, w = (float(v) for v in theta)
    _, coefficients, curves = solve(theta)
    rms = np.sqrt(np.mean((measured - curves) ** 2, axis=1))
    weights = 1.0 / np.maximum(rms, 1e-12 * np.maximum(measured.std(axis=1), 1e-300))
    jacobian = _jacobian(tau, coefficients, slow, d, w) * weights[:, None, None]
    try:
        covariance = lsq_covariance(jacobian, (measured - curves) * weights[:, None], noise).covariance
    except SingularFitError:
        raise NoOscillationError(f"degenerate fit: the window does not determine the {signal} amplitude") from None
    reference_amplitude = complex(coefficients[0, 2], -coefficients[0, 3])
    if abs(reference_amplitude) == 0.0:
        raise NoOscillationError(f"{fit.signal_names[0]} does not oscillate in the window")
    ratio = complex(coefficients[1, 2], -coefficients[1, 3]) / reference_amplitude
    # d ratio / d (c2, c3) of the reference and of the signal (a = c2 - i c3).
    derivative = np.array([-ratio, 1j * ratio, 1.0, -1j]) / reference_amplitude
    gradient = np.zeros((2, covariance.shape[0]))
    gradient[:, [2, 3, 6, 7]] = np.vstack([derivative.real, derivative.imag])
    return AmplitudeRatio(signal, fit.signal_names[0], ratio, gradient @ covariance @ gradient.T, slow,
                          complex(d, w), covariance[-2:, -2:])
