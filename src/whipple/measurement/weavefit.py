"""Weave eigenvalue of a free-coasting window: a damped sinusoid fitted by variable projection.

The model of the seed paper (Kooijman & Schwab 2009, eq. 4), for one or more signals sharing
the eigenvalue ``d + i w``::

    y_k(t) = c1_k + exp(d tau) [c2_k cos(w tau) + c3_k sin(w tau)],    tau = t - t_start

The c's enter linearly: for each (d, w) they are the least-squares solution, and only the
two-parameter projected residual is minimised (Golub & Pereyra's variable projection, with
Kaufman's Jacobian). Starting values come from a matrix-pencil estimate and from the zero
crossings and peaks of the window; several starts are tried and the best optimum kept.

The covariance of (d, w) comes from the Jacobian of the full model at the optimum. Residuals
of real runs are rarely white (unmodelled modes, sensor filters): when the lag-1
autocorrelation of the residual is significant, a Newey-West (Bartlett kernel) estimate
replaces the white-noise one, with Andrews' AR(1) plug-in bandwidth.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares

from whipple.errors import AnalysisError, InputError, RunFileError
from whipple.measurement.lsq_covariance import NOISE_MODELS, SingularFitError, lsq_covariance
from whipple.measurement.projection import Projection
from whipple.measurement.runs import Run
from whipple.measurement.weave_starts import starting_values
from whipple.measurement.windows import Window

__all__ = ["MIN_SAMPLES", "BASELINES", "NoOscillationError", "WeaveFit", "fit_weave", "fit_window", "window_bounds",
           "response_with_eigenvalue"]

#: Fewer samples than this cannot constrain five parameters with any honesty.
MIN_SAMPLES = 12


#: Non-oscillating parts of the fitted function, by name: the degree of a polynomial in time.
BASELINES = {"constant": 0, "linear": 1, "quadratic": 2}


class NoOscillationError(InputError, AnalysisError):
    """The window holds no usable oscillation (under half a period, or a degenerate fit)."""


@dataclass(frozen=True)
class WeaveFit:
    """A damped sinusoid fitted to a window.

    Attributes
    ----------
    eigenvalue : complex
        ``d + i w`` [1/s]: damping d (negative is stable) and angular frequency w [rad/s].
    eigenvalue_std : tuple of float
        Standard deviations of the real and imaginary part [1/s].
    covariance : ndarray, shape (2, 2)
        Covariance of (d, w) [1/s^2], the one `eigenvalue_std` is taken from.
    covariance_white : ndarray, shape (2, 2)
        Covariance assuming white residuals (equal to `covariance` when `noise_model` is
        ``"white"``).
    noise_model : str
        ``"white"`` or ``"newey-west(L)"`` with L lags.
    coefficients : ndarray, shape (k, 3)
        ``c1, c2, c3`` of each signal (signal units), time origin at `start`.
    signal_names : tuple of str
        Names of the k signals.
    start, stop : float
        First and last sample time of the window [s].
    time : ndarray, shape (n,)
        Sample times [s].
    measured, fitted : ndarray, shape (k, n)
        The data and the fitted curves.
    r_squared : float
        Coefficient of determination of the (noise-weighted) joint fit.
    signal_r_squared, rms_residual : tuple of float
        R^2 and RMS residual (signal units) of each signal.
    residual_correlation : float
        Lag-1 autocorrelation of the residual (0 for white noise).
    n_samples : int
        Samples per signal.
    signal_weights : tuple of float
        The weight of each signal in the fit [1/signal unit]: the inverse of its spread over
        the window, for several signals the inverse of its residual RMS (what a refit of the
        same samples must use to reach the same optimum, :mod:`whipple.measurement.refit`).
    """

    eigenvalue: complex
    eigenvalue_std: tuple[float, float]
    covariance: NDArray[np.float64]
    covariance_white: NDArray[np.float64]
    noise_model: str
    coefficients: NDArray[np.float64]
    signal_names: tuple[str, ...]
    start: float
    stop: float
    time: NDArray[np.float64]
    measured: NDArray[np.float64]
    fitted: NDArray[np.float64]
    r_squared: float
    signal_r_squared: tuple[float, ...]
    rms_residual: tuple[float, ...]
    residual_correlation: float
    n_samples: int
    signal_weights: tuple[float, ...] = ()

    @property
    def damping(self) -> float:
        """Real part d of the eigenvalue [1/s]."""
        return float(self.eigenvalue.real)

    @property
    def frequency(self) -> float:
        """Imaginary part w of the eigenvalue [rad/s]."""
        return float(self.eigenvalue.imag)

    @property
    def baseline(self) -> str:
        """Name of the fitted non-oscillating part (see :data:`BASELINES`)."""
        degree = self.coefficients.shape[1] - 3
        return next(name for name, value in BASELINES.items() if value == degree)

    @property
    def cycles(self) -> float:
        """Number of oscillation periods in the window."""
        return self.frequency * (self.stop - self.start) / (2 * np.pi)

    def amplitude(self, signal: str) -> float:
        """Return the amplitude of `signal`'s oscillation at the window's start (signal units): ``hypot(c2, c3)``."""
        cosine, sine = self.coefficients[self.signal_names.index(signal), -2:]
        return float(np.hypot(cosine, sine))

    @property
    def cycles_above_noise(self) -> float:
        """Oscillation periods while the fitted envelope of the first signal exceeds its residual's RMS.

        A decaying envelope of amplitude A meets the noise after ln(A / RMS) / |d|; past that the
        window holds mostly noise, which can stretch a strongly damped window and bias its frequency
        (docs/diagnosis.md, "The controller's causes on three controlled bicycles").
        """
        length = self.stop - self.start
        amplitude, noise = self.amplitude(self.signal_names[0]), float(self.rms_residual[0])
        if self.damping < 0.0 and noise > 0.0:
            length = min(length, float(np.log(max(amplitude / noise, 1.0))) / -self.damping)
        return self.frequency * length / (2 * np.pi)

    def curve(self, time: ArrayLike) -> NDArray[np.float64]:
        """Return the fitted curves at `time` [s], shape ``(k,) + shape(time)``."""
        tau = np.asarray(time, dtype=float) - self.start
        basis = _basis(tau.ravel(), self.damping, self.frequency, self.coefficients.shape[1] - 3)
        return (basis @ self.coefficients.T).T.reshape((-1,) + tau.shape)

    def terms(self, time: ArrayLike, degree: int | None = None) -> NDArray[np.float64]:
        """Return the fitted function's terms at `time` [s] (its eigenvalue fixed), shape (n, degree + 3).

        The powers of the time from `start` up to `degree` (default: the fit's baseline), then
        the damped cosine and sine; the fitted curves are these terms times `coefficients`
        (for the fit's own degree). Other coefficients of the same terms are other free
        motions of the same eigenvalue, with another baseline for a larger `degree`.
        """
        degree = self.coefficients.shape[1] - 3 if degree is None else degree
        tau = np.asarray(time, dtype=float).ravel() - self.start
        return _basis(tau, self.damping, self.frequency, degree)


def fit_weave(
    time: ArrayLike,
    values: ArrayLike,
    names: Sequence[str] = ("roll_rate",),
    noise: str = "auto",
    baseline: str = "constant",
) -> WeaveFit:
    """Fit ``c1 + exp(d t) [c2 cos(w t) + c3 sin(w t)]`` to one or more signals.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times of the window [s], increasing.
    values : array_like, shape (n,) or (k, n)
        The signal(s) (e.g. roll rate [rad/s]); several signals share (d, w) and have their own
        c's, each weighted by the inverse of its residual RMS.
    names : sequence of str
        Names of the k signals.
    noise : {"auto", "white", "correlated"}
        Covariance estimate: white residuals, Newey-West, or Newey-West only when the
        residual's lag-1 autocorrelation is significant (above 3 / sqrt(n)).
    baseline : {"constant", "linear", "quadratic"}
        The non-oscillating part: the seed paper's constant c1, or a polynomial in time that
        also follows the slow capsize mode's exponential (it would otherwise bias d and w).

    Returns
    -------
    WeaveFit
        The eigenvalue ``d + i w`` [1/s] with its covariance, the coefficients, the fitted curve
        and the residual's statistics.

    Raises
    ------
    NoOscillationError
        Fewer than MIN_SAMPLES samples, under half a period of oscillation, or a degenerate fit.
    InputError
        Non-finite values or mismatched shapes.
    """
    if baseline not in BASELINES:
        raise InputError(f"fit_weave: unknown baseline '{baseline}' (one of {', '.join(BASELINES)})")
    degree = BASELINES[baseline]
    if noise not in NOISE_MODELS:
        raise InputError(f"fit_weave: unknown noise model '{noise}' (one of "
                         f"{', '.join(NOISE_MODELS)})")
    t = np.asarray(time, dtype=float)
    y = np.atleast_2d(np.asarray(values, dtype=float))
    if y.shape[1] != t.size or len(names) != y.shape[0]:
        raise InputError(f"fit_weave: {y.shape[0]} signal(s) of {y.shape[1]} samples, "
                         f"{t.size} times and {len(names)} names do not match")
    if not (np.isfinite(t).all() and np.isfinite(y).all()):
        raise InputError("fit_weave: non-finite values in the window")
    if t.size < MIN_SAMPLES:
        raise NoOscillationError(f"window of {t.size} samples is too short to fit (needs "
                                 f"{MIN_SAMPLES})")
    tau = t - t[0]
    span = float(tau[-1])
    spread = y.std(axis=1)
    if not (spread > 0).all():
        raise NoOscillationError("a signal is constant over the window")
    weights = 1.0 / spread
    theta = _best_optimum(tau, y * weights[:, None], span, degree)
    # One reweighting by the residual RMS puts signals of different noise on an equal footing.
    if y.shape[0] > 1:
        residual = y - _linear_fit(tau, y.T, theta, degree)[1].T
        weights = 1.0 / np.maximum(residual.std(axis=1), 1e-12 * spread)
        theta = _polish(tau, y * weights[:, None], theta, span, degree)
    d, w = theta
    if w * span < np.pi:
        raise NoOscillationError(
            f"under half a period of oscillation in the window (w = {w:.3g} rad/s over "
            f"{span:.3g} s)"
        )
    coefficients, fitted = _linear_fit(tau, y.T, theta, degree)
    coefficients, fitted = coefficients.T, fitted.T
    return _result(t, y, names, fitted, coefficients, weights, theta, noise)


def fit_window(
    run: Run, window: Window, signals: Sequence[str] = ("roll_rate",), noise: str = "auto",
    baseline: str = "constant",
) -> WeaveFit:
    """Fit the weave eigenvalue over a window of a run (see :func:`fit_weave`).

    Parameters
    ----------
    run : Run
        The run.
    window : Window
        The window (its sample indices, or its times when the indices are unknown).
    signals : sequence of str
        Signals to fit jointly (e.g. ``("roll_rate", "yaw_rate")``).
    noise, baseline : str
        Covariance estimate and non-oscillating part, as in :func:`fit_weave`.

    Returns
    -------
    WeaveFit
        As :func:`fit_weave`.

    Raises
    ------
    RunFileError
        If the run lacks one of the signals.
    NoOscillationError
        If the window holds no usable oscillation.
    """
    missing = [name for name in signals if name not in run.signals]
    if missing:
        raise RunFileError(f"no {', '.join(missing)} signal to fit", run.source)
    first, stop = window.start_index, window.stop_index
    if first < 0 or stop <= first:
        first = int(np.searchsorted(run.time, window.start))
        stop = int(np.searchsorted(run.time, window.stop, side="right"))
    values = np.array([run.signals[name][first:stop] for name in signals])
    return fit_weave(run.time[first:stop], values, tuple(signals), noise, baseline)


def _basis(tau: NDArray[np.float64], d: float, w: float, degree: int = 0) -> NDArray[np.float64]:
    decay = np.exp(d * tau)
    powers = [tau**k for k in range(degree + 1)]
    return np.column_stack(powers + [decay * np.cos(w * tau), decay * np.sin(w * tau)])


def _linear_fit(
    tau: NDArray[np.float64], Y: NDArray[np.float64], theta: NDArray[np.float64], degree: int = 0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the c's (degree + 3, k) for given (d, w) and the fitted curves (n, k)."""
    basis = _basis(tau, float(theta[0]), float(theta[1]), degree)
    coefficients = np.asarray(np.linalg.lstsq(basis, Y, rcond=None)[0], dtype=float)
    return coefficients, np.asarray(basis @ coefficients, dtype=float)


_Projection = Callable[[NDArray[np.float64]], tuple[NDArray[np.float64], NDArray[np.float64]]]


def _projected(tau: NDArray[np.float64], Y: NDArray[np.float64], degree: int = 0) -> _Projection:
    """Residual and Kaufman Jacobian of one window's variable-projection problem, for least_squares."""
    projection, rows = Projection([tau], [Y], degree), np.zeros(1, dtype=np.intp)

    def parts(theta: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        residual, jacobian, _ = projection.parts(theta[None, :], rows)
        return residual.ravel(), jacobian.reshape(-1, 2)

    return parts


def window_bounds(tau: NDArray[np.float64]) -> tuple[list[float], list[float]]:
    """Return the lower and upper bounds of (d, w) [1/s] for a window with sample times `tau` from its start."""
    # w from (almost) nothing to the Nyquist frequency; the damping bound only keeps exp()
    # finite over the window.
    span = float(tau[-1])
    return [-60.0 / span, 1e-3 / span], [60.0 / span, np.pi * (tau.size - 1) / span]


def _best_optimum(tau: NDArray[np.float64], Y: NDArray[np.float64], span: float,
                  degree: int = 0) -> NDArray[np.float64]:
    parts = _projected(tau, Y.T, degree)
    lower, upper = window_bounds(tau)
    starts = [np.clip(start, lower, upper) for start in starting_values(tau, Y.T[:, 0])]
    # Polishing every start is wasteful: the two most promising ones are polished.
    ranked = sorted(starts, key=lambda start: float(np.sum(parts(start)[0] ** 2)))
    best: tuple[float, NDArray[np.float64]] | None = None
    for start in ranked[:2]:
        theta = _polish(tau, Y, start, span, degree)
        cost = float(np.sum(parts(theta)[0] ** 2))
        if best is None or cost < best[0]:
            best = (cost, theta)
    assert best is not None
    return best[1]


def _polish(
    tau: NDArray[np.float64], Y: NDArray[np.float64], start: NDArray[np.float64], span: float,
    degree: int = 0,
) -> NDArray[np.float64]:
    lower, upper = window_bounds(tau)
    x0 = np.clip(start, np.array(lower) + 1e-9, np.array(upper) - 1e-9)
    parts = _projected(tau, Y.T, degree)
    cache: dict[bytes, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}

    def evaluate(theta: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        key = theta.tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = parts(theta)
        return cache[key]

    solution = least_squares(
        lambda th: evaluate(th)[0], x0, jac=lambda th: evaluate(th)[1],
        bounds=(lower, upper), x_scale=np.array([1.0, 1.0]) / span, method="trf",
    )
    return np.asarray(solution.x, dtype=float)


def _result(
    t: NDArray[np.float64],
    y: NDArray[np.float64],
    names: Sequence[str],
    fitted: NDArray[np.float64],
    coefficients: NDArray[np.float64],
    weights: NDArray[np.float64],
    theta: NDArray[np.float64],
    noise: str,
) -> WeaveFit:
    tau = t - t[0]
    n = y.shape[1]
    d, w = float(theta[0]), float(theta[1])
    residual = (y - fitted) * weights[:, None]
    jacobian = _full_jacobian(tau, coefficients, d, w) * weights[:, None, None]
    try:
        estimate = lsq_covariance(jacobian, residual, noise)
    except SingularFitError:
        raise NoOscillationError(
            "degenerate fit: the window does not constrain the eigenvalue"
        ) from None
    covariance, white, model, rho = (estimate.covariance, estimate.white, estimate.model,
                                     estimate.lag1)
    block = covariance[-2:, -2:]
    centred = y - y.mean(axis=1, keepdims=True)
    signal_r2 = 1 - np.sum((y - fitted) ** 2, axis=1) / np.sum(centred**2, axis=1)
    total_r2 = 1 - np.sum(residual**2) / np.sum((centred * weights[:, None]) ** 2)
    return WeaveFit(
        eigenvalue=complex(d, w),
        eigenvalue_std=(float(np.sqrt(block[0, 0])), float(np.sqrt(block[1, 1]))),
        covariance=block,
        covariance_white=white[-2:, -2:],
        noise_model=model,
        coefficients=coefficients,
        signal_names=tuple(names),
        start=float(t[0]),
        stop=float(t[-1]),
        time=t,
        measured=y,
        fitted=fitted,
        r_squared=float(total_r2),
        signal_r_squared=tuple(float(v) for v in signal_r2),
        rms_residual=tuple(float(v) for v in np.sqrt(np.mean((y - fitted) ** 2, axis=1))),
        residual_correlation=float(rho),
        n_samples=int(n),
        signal_weights=tuple(float(v) for v in weights),
    )


def _full_jacobian(
    tau: NDArray[np.float64], coefficients: NDArray[np.float64], d: float, w: float
) -> NDArray[np.float64]:
    """Jacobian (k, n, m k + 2) of all model values w.r.t. (m c's of each signal, d, w)."""
    k, m = coefficients.shape
    basis = _basis(tau, d, w, m - 3)
    decay = basis[:, -2:]
    jacobian = np.zeros((k, tau.size, m * k + 2))
    for signal in range(k):
        c2, c3 = coefficients[signal, -2:]
        jacobian[signal, :, m * signal: m * signal + m] = basis
        jacobian[signal, :, -2] = tau * (decay[:, 0] * c2 + decay[:, 1] * c3)
        jacobian[signal, :, -1] = tau * (decay[:, 0] * c3 - decay[:, 1] * c2)
    return jacobian


def response_with_eigenvalue(
    time: ArrayLike, values: ArrayLike, eigenvalue: complex, baseline: str = "constant"
) -> NDArray[np.float64]:
    """Return the best fit of a window with the eigenvalue held fixed (amplitude, phase, baseline free).

    This is how a model's weave eigenvalue explains a measured window in the time domain:
    the model fixes d and w, the window's initial state fixes the linear coefficients.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times [s].
    values : array_like, shape (n,) or (k, n)
        Measured signal(s).
    eigenvalue : complex
        d + i w [1/s].
    baseline : str
        As in :func:`fit_weave`.

    Returns
    -------
    ndarray, shape (k, n)
        The fitted curves.
    """
    if baseline not in BASELINES:
        raise InputError(f"unknown baseline '{baseline}' (one of {', '.join(BASELINES)})")
    t = np.asarray(time, dtype=float)
    y = np.atleast_2d(np.asarray(values, dtype=float))
    fitted = _linear_fit(t - t[0], y.T, np.array([eigenvalue.real, abs(eigenvalue.imag)]), BASELINES[baseline])[1]
    return np.asarray(fitted.T, dtype=float)
