"""Whether a window holds one free motion: a window that no linear free response follows.

The window finder reads the roll rate swing by swing, and a slowly oscillating, barely damped
run can hide a catch, the hand's hold and the next push inside what looks like one more swing
(the low-passed roll rate goes from the catch through the hold into the push without an
extreme). Such a window holds two free motions with a forced stretch between them. The
fitting function bends across it and its eigenvalue is biased; compared with its samples, the
true model leaves it tens of times its noise off and outweighs every clean window of the data
set, so that one window sets the diagnosis (hidden-effect trials, docs/diagnosis.md).

A free motion of the linear model at one speed is a sum of its modes. :func:`free_response_misfit`
fits the most general such sum a Whipple bicycle gives, an oscillating pair and two real modes
with free eigenvalues and each signal's own amplitudes (and the weave fit's baseline), to the
window's samples and returns its chi-square per sample, each signal weighed by its white noise
(:func:`whipple.measurement.noise.second_difference_noise`). Free windows sit near 1 on
simulated runs, whatever the bicycle; a window spanning a catch does not. Real records add what
no low-order model holds (vibration, friction, a rider-free bicycle's small nonlinearities), so
the level is judged against the data set's own windows: :func:`outlying` sets aside a window
far above the median of all windows (:func:`set_aside_outlying`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from whipple.measurement.experiment import WindowMeasurement
from whipple.measurement.noise import robust_scale, second_difference_noise
from whipple.measurement.weavefit import WeaveFit

#: A window is set aside when its misfit is at least this many times the data set's median.
#: Free windows of simulated runs stay within 1.64 times it (756 windows of 63 trials, 3
#: bicycles, 7 hidden effects; benchmarks/bench_free_motion.py); windows spanning a catch
#: reach 3.7 to 141 times (one, which the true model leaves 10 times its noise off, 1.6).
OUTLIER_RATIO = 2.0
#: ... and beyond this many robust standard deviations of the misfits' logarithm above their
#: median: real records spread over a decade or more (the bundled runs: 3.3 to 59 times the
#: noise between their 10th and 90th percentiles), and a window is an outlier only beyond that spread.
OUTLIER_SPREAD = 3.0
#: Fewer windows than this give no median to judge by: none is set aside.
MIN_WINDOWS = 3
#: Starting rates of the two real modes, as multiples of the weave's angular frequency: a fast
#: castering-like mode with a slow capsize-like one, then two slow ones.
_REAL_STARTS = ((-3.0, -0.1), (-0.5, 0.05))


def free_response_misfit(fit: WeaveFit) -> float:
    """Return the chi-square per sample of the best free response of a 4-state linear model.

    Parameters
    ----------
    fit : WeaveFit
        A window's weave fit: its samples, its eigenvalue (the start of the oscillating pair)
        and its baseline (kept: a drifting sensor offset is not a mode).

    Returns
    -------
    float
        Mean squared residual of the samples, each signal in units of its white noise
        (dimensionless; 1 where the window is one free motion of such a model and white noise).
    """
    tau = fit.time - fit.time[0]
    noise = second_difference_noise(fit.measured)
    targets = (fit.measured / noise[:, None]).T  # (n, k)
    degree = fit.coefficients.shape[1] - 3
    powers = np.column_stack([tau**k for k in range(degree + 1)])
    step = float(np.median(np.diff(tau))) if tau.size > 1 else 1.0
    length = max(float(tau[-1]), step)
    frequency = abs(fit.eigenvalue.imag)

    def residual(theta: NDArray[np.float64]) -> NDArray[np.float64]:
        d, w, fast, slow = theta
        decay = np.exp(d * tau)
        basis = np.column_stack([powers, decay * np.cos(w * tau), decay * np.sin(w * tau),
                                 np.exp(fast * tau), np.exp(slow * tau)])
        coefficients = np.linalg.lstsq(basis, targets, rcond=None)[0]
        return np.asarray((targets - basis @ coefficients).ravel(), dtype=float)

    # Rates beyond a quarter of the sample rate are gone within a sample or two; growth beyond
    # 10 e-folds over the window is no bicycle's free motion.
    fastest, growth = 0.25 / step, 10.0 / length
    lower = [-fastest, 0.3 * frequency, -fastest, -fastest]
    upper = [growth, 3.0 * frequency, growth, growth]
    best = float(np.mean(residual(np.array([fit.eigenvalue.real, frequency, -fastest, -fastest])) ** 2))
    for fast, slow in _REAL_STARTS:
        start = np.clip([fit.eigenvalue.real, frequency, fast * frequency, slow * frequency],
                        np.array(lower) + 1e-9, np.array(upper) - 1e-9)
        solution = least_squares(residual, start, bounds=(lower, upper), x_scale=max(frequency, 1e-3))
        best = min(best, float(np.mean(solution.fun**2)))
    return best


def outlying(misfits: Sequence[float] | NDArray[np.float64]) -> NDArray[np.bool_]:
    """Return which misfits stand out from the rest: an outlying window each.

    A misfit stands out when it is above the median by more than ``OUTLIER_RATIO`` and by more
    than ``OUTLIER_SPREAD`` robust standard deviations of the logarithms (the median absolute
    deviation). With fewer than ``MIN_WINDOWS`` finite misfits, none does; a misfit that is not
    finite is never an outlier (nor counted in the median).
    """
    values = np.asarray(misfits, dtype=float)
    finite = np.isfinite(values)
    if np.count_nonzero(finite) < MIN_WINDOWS:
        return np.zeros(values.shape, dtype=bool)
    logs = np.log(np.maximum(np.where(finite, values, 1.0), np.finfo(float).tiny))
    centre = float(np.median(logs[finite]))
    spread = float(robust_scale(logs[finite]))
    return np.asarray(finite & (logs - centre > max(np.log(OUTLIER_RATIO), OUTLIER_SPREAD * spread)), dtype=bool)


def set_aside_outlying(measurements: Sequence[WindowMeasurement]) -> list[WindowMeasurement]:
    """Return the measurements with each usable window that is no free motion set aside.

    The usable windows of all runs are judged together (:func:`free_response_misfit`,
    :func:`outlying`); an outlier keeps its fit but gets a ``quality`` saying why it is not
    used. The others are returned unchanged, in the same order.
    """
    usable = [k for k, m in enumerate(measurements) if m.usable]
    result = list(measurements)
    if not usable:
        return result
    misfits = np.array([free_response_misfit(measurements[k].fit) for k in usable])  # type: ignore[arg-type]
    median = float(np.median(misfits))
    for k, misfit, out in zip(usable, misfits, outlying(misfits), strict=True):
        if out:
            result[k] = replace(result[k], quality=(
                f"not one free motion: the best free response of a 4-state linear model leaves it "
                f"{misfit:.3g} times its noise off (chi-square per sample), {misfit / median:.3g} times "
                f"the windows' median (a catch, a hand or a push inside?)"))
    return result
