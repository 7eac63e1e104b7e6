"""From measured runs to weave eigenvalues: windows, fits and speeds, window by window.

This is the measurement side shared by ``whipple fit`` and ``whipple diagnose``: every window
of every run either yields a fitted eigenvalue at a speed range, or is skipped with a reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from whipple.diagnosis import Observation
from whipple.errors import InputError
from whipple.mode_shape import SETTLE, AmplitudeRatio, amplitude_ratio
from whipple.runs import Run
from whipple.speedometer import SpeedRange, speed_regression
from whipple.weavefit import NoOscillationError, WeaveFit, fit_window
from whipple.windows import Window, find_windows

#: Fits explaining less of the window's variance than this are not used as observations.
MIN_R_SQUARED = 0.5
#: Nor fits covering less of a weave period than this (cycles = w * length / 2 pi).
MIN_CYCLES = 0.75
#: With baseline "auto", windows of at least this many weave cycles get a quadratic baseline
#: (enough data to separate the slow capsize mode from the weave); shorter ones the constant.
AUTO_QUADRATIC_CYCLES = 2.0


@dataclass(frozen=True)
class WindowMeasurement:
    """One window: its fit and speed, or why it was skipped."""

    run: Run
    window: Window
    fit: WeaveFit | None
    speed: SpeedRange | None
    skipped: str | None = None
    shape: AmplitudeRatio | None = None

    @property
    def usable(self) -> bool:
        return self.fit is not None and self.skipped is None


def measure_run(run: Run, windows: Sequence[Window] | None = None,
                signals: Sequence[str] = ("roll_rate",), baseline: str = "constant",
                shape_signal: str | None = "steer_angle", settle: float = 0.0) -> list[WindowMeasurement]:
    """Fit the weave in each window of a run (found automatically unless given).

    ``settle`` [s] leaves the start of each window out of the fits: a window starts at the end
    of a push, while the fast castering mode still moves the bicycle, which the fitting
    function does not hold (see :data:`whipple.mode_shape.SETTLE`). The seed paper fits from
    the push's end (0, the default; also ``whipple diagnose --settle``'s default).

    Where the run also holds ``shape_signal`` (and it is not among ``signals``), each window
    also gets the weave's mode shape: that signal's amplitude relative to the first of
    ``signals`` (:func:`whipple.mode_shape.amplitude_ratio`); a window too short for it keeps its
    eigenvalue and has no shape.

    ``baseline`` is the fitted function's non-oscillating part (see
    :func:`whipple.weavefit.fit_weave`): the seed paper's constant, a polynomial that follows
    the slow capsize mode, or "auto": the constant, and the quadratic when the window holds at
    least AUTO_QUADRATIC_CYCLES weave cycles (in shorter windows the extra terms would trade
    off against the weave itself).
    """
    if windows is None:
        windows = find_windows(run).windows
    else:
        windows = [w for w in windows if w.run == run.name]
    speed = run.speed()
    measurements = []
    for window in windows:
        try:
            speeds = speed_regression(run.time, speed, window.start, window.stop)
            fitted = _settled(run, window, settle)
            fit = fit_window(run, fitted, signals, baseline="constant" if baseline == "auto" else baseline)
            if baseline == "auto" and fit.cycles >= AUTO_QUADRATIC_CYCLES:
                fit = fit_window(run, fitted, signals, baseline="quadratic")
        except InputError as error:
            measurements.append(WindowMeasurement(run, window, None, None, error.problem))
            continue
        reason = None
        if fit.r_squared < MIN_R_SQUARED:
            reason = f"poor fit (R^2 = {fit.r_squared:.2f} < {MIN_R_SQUARED})"
        elif fit.cycles < MIN_CYCLES:
            reason = f"too short ({fit.cycles:.2f} weave cycles < {MIN_CYCLES})"
        elif not np.all(np.isfinite(fit.covariance)):
            reason = "eigenvalue covariance not finite"
        shape = None
        if reason is None and shape_signal in run.signals and shape_signal not in signals:
            shape = _mode_shape(run, fit, shape_signal, max(SETTLE - (fit.start - window.start), 0.0))
        measurements.append(WindowMeasurement(run, window, fit, speeds, reason, shape))
    return measurements


def _settled(run: Run, window: Window, settle: float) -> Window:
    """The window without its first ``settle`` seconds (unchanged for 0)."""
    if settle <= 0.0:
        return window
    first = int(np.searchsorted(run.time, window.start + settle))
    if first >= len(run.time) or run.time[first] >= window.stop:
        raise NoOscillationError(f"window shorter than the {settle:g} s settle time")
    stop = window.stop_index if window.stop_index > 0 else int(np.searchsorted(run.time, window.stop, side="right"))
    return replace(window, start=float(run.time[first]), start_index=first, stop_index=stop)


def _mode_shape(run: Run, fit: WeaveFit, signal: str, settle: float) -> AmplitudeRatio | None:
    first = int(np.searchsorted(run.time, fit.start))
    values = run.signals[signal][first:first + fit.n_samples]
    try:
        shape = amplitude_ratio(fit, values, signal, settle=settle)
    except NoOscillationError:
        return None
    return shape if np.all(np.isfinite(shape.covariance)) and np.isfinite(shape.ratio) else None


def observation(measurement: WindowMeasurement) -> Observation:
    """The diagnosis' view of a usable window."""
    if measurement.fit is None or measurement.speed is None:
        raise ValueError("window has no fit")
    speed, shape = measurement.speed, measurement.shape
    return Observation(measurement.run.name, measurement.window.start, measurement.window.stop, float(speed.mean),
                       (float(speed.start_speed), float(speed.stop_speed)), complex(measurement.fit.eigenvalue),
                       np.asarray(measurement.fit.covariance, dtype=float),
                       None if shape is None else complex(shape.ratio),
                       None if shape is None else np.asarray(shape.covariance, dtype=float),
                       ("steer_angle", "roll_rate") if shape is None else (shape.signal, shape.reference))


def observations(measurements: Sequence[WindowMeasurement]) -> list[Observation]:
    """Observations of all usable windows."""
    return [observation(m) for m in measurements if m.usable]

