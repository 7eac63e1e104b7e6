"""Refits of the weave function from a start near its optimum, for one window or many at once.

For a response whose weave is known (a model's own response over a window,
:mod:`whipple.diagnosis.fit_bias`), the fitted function's optimum nearest the true eigenvalue
is reached in two or three Gauss-Newton steps on the variable-projection problem, where the
setup of SciPy's trust-region solver alone costs more than those steps. A diagnosis makes such
refits for every window of every candidate model, so they are made for all windows at once
(:class:`~whipple.measurement.projection.Projection`), each window with its own steps, step
halvings and stop.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import InputError
from whipple.measurement.projection import Projection
from whipple.measurement.weavefit import BASELINES, NoOscillationError, window_bounds

#: Relative size of the last Gauss-Newton step at which a refit stops: far below any window's
#: stated uncertainty (a few percent of the eigenvalue).
REFIT_TOLERANCE = 1e-7
#: Most Gauss-Newton steps of a refit (a start near the optimum needs 2-4).
REFIT_STEPS = 20
#: Halvings of a step that raises the cost before the point is taken as the optimum.
HALVINGS = 30


def refit_weave(time: ArrayLike, values: ArrayLike, start: complex, baseline: str = "constant",
                weights: ArrayLike | None = None) -> complex:
    """Return the eigenvalue ``fit_weave`` reaches from a start near it, without its search for starts.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times [s].
    values : array_like, shape (n,) or (k, n)
        The signal(s).
    start : complex
        Starting eigenvalue d + i w [1/s].
    baseline : str
        As in :func:`~whipple.measurement.weavefit.fit_weave`.
    weights : array_like, shape (k,), optional
        Each signal's weight [1/signal unit], e.g. a fit's
        :attr:`~whipple.measurement.weavefit.WeaveFit.signal_weights`; by default the inverse
        of its spread (what ``fit_weave`` uses for one signal; for several it reweights them
        by their residuals, so a refit of its samples needs its weights to reach its optimum).

    Raises
    ------
    NoOscillationError
        If a signal is constant or the optimum holds under half a period of oscillation.
    """
    eigenvalues, failures = refit_weaves([np.asarray(time, dtype=float)], [np.asarray(values, dtype=float)],
                                         np.array([start]), [baseline],
                                         None if weights is None else [np.asarray(weights, dtype=float)])
    if failures[0] is not None:
        raise NoOscillationError(failures[0])
    return complex(eigenvalues[0])


def refit_weaves(times: Sequence[NDArray[np.float64]], values: Sequence[NDArray[np.float64]],
                 starts: NDArray[np.complex128], baselines: Sequence[str],
                 weights: Sequence[NDArray[np.float64] | None] | None = None
                 ) -> tuple[NDArray[np.complex128], list[str | None]]:
    """Refit many windows at once: :func:`refit_weave` for each, without raising.

    Parameters
    ----------
    times : sequence of ndarray, shape (n_i,)
        Each window's sample times [s].
    values : sequence of ndarray, shape (n_i,) or (k_i, n_i)
        Each window's signal(s).
    starts : ndarray of complex, shape (N,)
        Each window's starting eigenvalue [1/s].
    baselines : sequence of str
        Each window's baseline.
    weights : sequence of (ndarray, shape (k_i,), or None), optional
        Each window's signal weights, as :func:`refit_weave` takes them (None: the inverse spreads).

    Returns
    -------
    eigenvalues : ndarray of complex, shape (N,)
        The refitted eigenvalues [1/s]; NaN where a refit failed.
    failures : list of str or None
        Why a window's refit failed, or None.
    """
    unknown = sorted(set(baselines) - set(BASELINES))
    if unknown:
        raise InputError(f"unknown baseline '{unknown[0]}' (one of {', '.join(BASELINES)})")
    eigenvalues = np.full(len(times), np.nan, dtype=complex)
    failures: list[str | None] = [None] * len(times)
    signals = [np.atleast_2d(np.asarray(v, dtype=float)) for v in values]
    spreads = [y.std(axis=1) for y in signals]
    given = [None] * len(signals) if weights is None else list(weights)
    if len(given) != len(signals):
        raise ValueError(f"{len(given)} weights for {len(signals)} windows")
    with np.errstate(divide="ignore"):
        scales = [1.0 / spread if weight is None else np.asarray(weight, dtype=float)
                  for spread, weight in zip(spreads, given, strict=True)]
    groups: dict[tuple[int, int], list[int]] = {}
    for n, (y, spread, baseline) in enumerate(zip(signals, spreads, baselines, strict=True)):
        if not (spread > 0).all():
            failures[n] = "a signal is constant over the window"
        else:
            groups.setdefault((BASELINES[baseline], y.shape[0]), []).append(n)
    for (degree, _), members in groups.items():
        taus = [np.asarray(times[n], dtype=float) - float(times[n][0]) for n in members]
        weighted = [(signals[n] * scales[n][:, None]).T for n in members]
        bounds = np.array([window_bounds(tau) for tau in taus])
        start = np.array([[starts[n].real, abs(starts[n].imag)] for n in members])
        with np.errstate(over="ignore", invalid="ignore"):
            theta = _gauss_newton(Projection(taus, weighted, degree), start, bounds[:, 0], bounds[:, 1])
        for n, tau, (d, w) in zip(members, taus, theta, strict=True):
            if not (np.isfinite(d) and np.isfinite(w)):
                failures[n] = "the refit left the window's arithmetic (a mode grows beyond it)"
            elif w * tau[-1] < np.pi:
                failures[n] = f"under half a period of oscillation in the window (w = {w:.3g} rad/s)"
            else:
                eigenvalues[n] = complex(d, w)
    return eigenvalues, failures


def _gauss_newton(projection: Projection, theta: NDArray[np.float64], lower: NDArray[np.float64],
                  upper: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return each window's least-squares optimum near its `theta` (N, 2).

    By Gauss-Newton steps, each halved while it raises the window's cost; every window stops
    on its own.
    """
    theta = theta.copy()
    active = np.arange(len(theta))
    cost, step = projection.costs_and_steps(theta, active)
    optimum = theta.copy()
    for _ in range(REFIT_STEPS):
        if active.size == 0:
            break
        proposed = step[active]
        converged = np.all(np.abs(proposed) <= REFIT_TOLERANCE * np.abs(theta[active]).max(axis=1, keepdims=True),
                           axis=1)
        done = active[converged]
        # Converged: the last step needs no check.
        optimum[done] = np.clip(theta[done] + proposed[converged], lower[done], upper[done])
        movable = ~converged & np.isfinite(proposed).all(axis=1)
        pending, proposed = active[movable], proposed[movable]
        moved = []
        for _ in range(HALVINGS):
            if pending.size == 0:
                break
            trial = np.clip(theta[pending] + proposed, lower[pending], upper[pending])
            trial_cost, trial_step = projection.costs_and_steps(trial, pending)
            lower_cost = trial_cost <= cost[pending]
            accepted = pending[lower_cost]
            theta[accepted], cost[accepted], step[accepted] = trial[lower_cost], trial_cost[lower_cost], trial_step[
                lower_cost]
            moved.append(accepted)
            pending, proposed = pending[~lower_cost], proposed[~lower_cost] / 2
        # Still pending (no step lowers the cost), or no step at all (a singular Jacobian):
        # theta is the optimum to rounding.
        stuck = np.concatenate([pending, active[~converged & ~movable]]).astype(np.intp)
        optimum[stuck] = theta[stuck]
        active = np.sort(np.concatenate(moved)).astype(np.intp) if moved else np.array([], dtype=np.intp)
    optimum[active] = theta[active]
    return optimum
