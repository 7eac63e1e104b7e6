"""From measured runs to weave eigenvalues: windows, fits and speeds, window by window.

This is the one measurement loop behind ``whipple fit`` and ``whipple diagnose``: every window
of a run (found automatically, or read from a windows file) either yields a fitted eigenvalue
at a speed range, or is rejected with a reason; stretches the window finder turned down are
listed too. A fitted window that is too poor to use as an observation (low R^2, under a weave
cycle, or under 0.75 of one while the oscillation stands above the noise) keeps its fit and
says why in ``quality``.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Any, overload

import numpy as np

from whipple.errors import InputError
from whipple.measurement import catches
from whipple.measurement.mode_shape import SETTLE, AmplitudeRatio, amplitude_ratio
from whipple.measurement.runs import Run
from whipple.measurement.signal_choice import JOINT_SIGNALS, constant_signal, diagnosis_signals
from whipple.measurement.speedometer import SpeedRange, speed_regression
from whipple.measurement.weavefit import BASELINES, NoOscillationError, WeaveFit, fit_window
from whipple.measurement.windows import Window, WindowSearch, find_windows

__all__ = ["MIN_R_SQUARED", "MIN_CYCLES", "MIN_CYCLES_ABOVE_NOISE", "CATCH_PASSES", "AUTO_QUADRATIC_CYCLES",
           "CSV_COLUMNS", "FitOptions", "WindowMeasurement", "RunMeasurement", "JOINT_SIGNALS", "diagnosis_signals",
           "measure_run", "measure_window", "MIN_WINDOWS", "SHORT_WINDOW_CYCLES", "SHORT_WINDOW_NOTE",
           "with_short_windows"]

#: Fits explaining less of the window's variance than this are not used as observations.
MIN_R_SQUARED = 0.5
#: Nor fits covering less of a weave period than this (cycles = w * length / 2 pi).
MIN_CYCLES = 0.75
#: Nor, by default (:attr:`FitOptions.min_cycles_above_noise`), fits holding fewer periods than
#: this while the oscillation stays above the noise (:attr:`WeaveFit.cycles_above_noise`): past
#: that a strongly damped window holds mostly noise, which stretches it and biases its frequency.
MIN_CYCLES_ABOVE_NOISE = 0.75
#: Fits of a window whose end holds a catch (:attr:`FitOptions.catch_passes`): the first locates
#: the catch roughly (the fit across it bends towards the hand), the second, judged over the
#: whole window, places it where the free fit's curve and the samples part, the third confirms
#: that nothing more stands out.
CATCH_PASSES = 3
#: With baseline "auto", windows of at least this many weave cycles get a quadratic baseline
#: (enough data to separate the slow capsize mode from the weave); shorter ones the constant.
AUTO_QUADRATIC_CYCLES = 2.0

#: Columns of :meth:`WindowMeasurement.csv_row`.
CSV_COLUMNS = ("run", "window", "start", "stop", "speed_low", "speed_high", "speed_mean",
               "damping", "damping_std", "frequency", "frequency_std", "r_squared", "samples",
               "skipped", "notes")


@dataclass(frozen=True)
class FitOptions:
    """How the windows of a run are fitted.

    Attributes
    ----------
    signals : tuple of str
        Signals fitted jointly, sharing one eigenvalue (the first one is the reference of the
        mode shape).
    baseline : str
        The fitted function's non-oscillating part (see :func:`whipple.measurement.weavefit.fit_weave`):
        the seed paper's constant, a polynomial that follows the slow capsize mode, or
        ``"auto"``: the constant, and the quadratic when the window holds at least
        :data:`AUTO_QUADRATIC_CYCLES` weave cycles (in shorter windows the extra terms would
        trade off against the weave itself).
    noise : str
        Covariance estimate of the eigenvalue (``auto``, ``white`` or ``correlated``).
    shape_signal : str or None
        Where the run holds this signal (and it is not the first of ``signals``), each usable
        window also gets the weave's mode shape: that signal's amplitude relative to the first
        of ``signals`` (:func:`whipple.measurement.mode_shape.amplitude_ratio`). It may be one
        of the jointly fitted ``signals``: the ratio is then fitted at their shared eigenvalue.
    settle : float
        Seconds [s] left out at the start of each window: a window starts at the end of a
        push, while the fast castering mode still moves the bicycle, which the fitting
        function does not hold. The seed paper fits from the push's end (0).
    min_cycles_above_noise : float
        A fit holding fewer weave periods than this while its decaying envelope stays above the
        residual's RMS (:attr:`~whipple.measurement.weavefit.WeaveFit.cycles_above_noise`) is not
        used as an observation; 0 turns the check off (as the seed paper, which has none).
    catch_passes : int
        Fits of a window whose end may hold a hand's catch (default :data:`CATCH_PASSES`; 0: the
        window is fitted as found, never cut).
    """

    signals: tuple[str, ...] = ("roll_rate",)
    baseline: str = "constant"
    noise: str = "auto"
    shape_signal: str | None = "steer_angle"
    settle: float = 0.0
    min_cycles_above_noise: float = MIN_CYCLES_ABOVE_NOISE
    catch_passes: int = CATCH_PASSES

    def __post_init__(self) -> None:
        if self.baseline != "auto" and self.baseline not in BASELINES:
            raise InputError(f"unknown baseline '{self.baseline}' (auto or one of {', '.join(BASELINES)})")
        if not self.signals:
            raise InputError("no signal to fit")
        if not 0.0 <= self.settle < 10.0:  # also rejects NaN
            raise InputError(f"settle time must be between 0 and 10 s, got {self.settle}")
        if not 0.0 <= self.min_cycles_above_noise <= 100.0:  # also rejects NaN
            raise InputError("the least number of weave cycles above the noise must be between 0 and 100, "
                             f"got {self.min_cycles_above_noise}")
        if not 0 <= self.catch_passes <= 10:
            raise InputError(f"the number of catch passes must be between 0 and 10, got {self.catch_passes}")


@dataclass(frozen=True)
class WindowMeasurement:
    """One window of a run: its fit and speed, or why there is none.

    Attributes
    ----------
    run : Run
        The run.
    window : Window
        The window (for a rejected stretch, its reason starts with ``rejected:``).
    fit : WeaveFit or None
        The fitted weave, None when rejected.
    speed : SpeedRange or None
        Linear regression of the speed over the window [m/s].
    rejected : str or None
        Why there is no fit: turned down by the window finder, outside the run, no
        oscillation, ...
    quality : str or None
        Why a fit is not used as an observation (low R^2, too short, covariance not finite).
    shape : AmplitudeRatio or None
        The weave's mode shape, where measured.
    number : int
        1-based position of the window in its run, by start time.
    group : str
        The group of an experiment the run belongs to ("" outside experiments of several groups).
    """

    run: Run
    window: Window
    fit: WeaveFit | None
    speed: SpeedRange | None
    rejected: str | None = None
    quality: str | None = None
    shape: AmplitudeRatio | None = None
    number: int = 0
    group: str = ""

    @property
    def skipped(self) -> str | None:
        """Why the window is not an observation (rejected, or too poor a fit); None if usable."""
        return self.rejected or self.quality

    @property
    def usable(self) -> bool:
        """Whether the window is an observation: fitted, and good enough."""
        return self.fit is not None and self.skipped is None

    @property
    def notes(self) -> str:
        """The window's reason and quality notes, in one line."""
        return "; ".join((self.window.reason, *self.window.notes))

    def to_dict(self) -> dict[str, Any]:
        """Return the window as JSON-ready data.

        Run, times [s], speed range [m/s], eigenvalue [1/s] with its std and covariance, R^2,
        why skipped, and where the window came from.
        """
        fit, speed = self.fit, self.speed
        return {
            "run": self.run.name,
            "start": self.window.start,
            "stop": self.window.stop,
            "speed": None if speed is None else [speed.low, speed.high],
            "speed_mean": None if speed is None else speed.mean,
            "eigenvalue": None if fit is None else [fit.damping, fit.frequency],
            "eigenvalue_std": None if fit is None else list(fit.eigenvalue_std),
            "r_squared": None if fit is None else fit.r_squared,
            "skipped": self.rejected,
            "quality": self.quality,
            "eigenvalue_covariance": None if fit is None else fit.covariance.tolist(),
            "samples": None if fit is None else fit.n_samples,
            "signals": None if fit is None else list(fit.signal_names),
            "noise_model": None if fit is None else fit.noise_model,
            "baseline": None if fit is None else fit.baseline,
            "notes": self.notes,
            "window": self.number,
            "source": self.run.source,
            **({"group": self.group} if self.group else {}),
        }

    def csv_row(self) -> list[object]:
        """One row of :data:`CSV_COLUMNS` (numbers to 6 significant digits, blanks for none)."""
        fit, speed = self.fit, self.speed
        values: list[object] = [self.run.name, self.number, self.window.start, self.window.stop]
        values += [speed.low, speed.high, speed.mean] if speed else [None] * 3
        values += ([fit.damping, fit.eigenvalue_std[0], fit.frequency, fit.eigenvalue_std[1],
                    fit.r_squared, fit.n_samples] if fit else [None] * 6)
        values += [self.rejected, self.notes]
        return [("" if v is None else f"{v:.6g}" if isinstance(v, float) else v) for v in values]


@dataclass(frozen=True)
class RunMeasurement(Sequence[WindowMeasurement]):
    """Every window of one run, by start time, and the run's noise figures.

    Iterating (or indexing) gives the :class:`WindowMeasurement` of each window.

    Attributes
    ----------
    run : Run
        The run.
    windows : tuple of WindowMeasurement
        Fitted, failed and rejected windows, by start time.
    search : WindowSearch
        What the window finder found in the run (its windows, rejected stretches and noise
        figures), whether or not its windows were the ones fitted.
    from_file : bool
        Whether the windows came from a windows file rather than the window finder.
    """

    run: Run
    windows: tuple[WindowMeasurement, ...]
    search: WindowSearch
    from_file: bool = False

    @property
    def noise(self) -> float:
        """Standard deviation of the roll rate's noise [rad/s]."""
        return self.search.noise

    @property
    def frequency(self) -> float:
        """Dominant frequency of the roll rate [Hz]."""
        return self.search.frequency

    @overload
    def __getitem__(self, index: int) -> WindowMeasurement: ...

    @overload
    def __getitem__(self, index: slice) -> Sequence[WindowMeasurement]: ...

    def __getitem__(self, index: int | slice) -> WindowMeasurement | Sequence[WindowMeasurement]:
        return self.windows[index]

    def __len__(self) -> int:
        return len(self.windows)

    def __iter__(self) -> Iterator[WindowMeasurement]:
        return iter(self.windows)

    @property
    def fitted(self) -> tuple[WindowMeasurement, ...]:
        """The windows with a fit."""
        return tuple(m for m in self.windows if m.fit is not None)


def measure_run(run: Run, windows: Sequence[Window] | None = None, options: FitOptions | None = None,
                **settings: Any) -> RunMeasurement:
    """Fit the weave in each window of a run (found automatically unless given).

    Parameters
    ----------
    run : Run
        The run.
    windows : sequence of Window, optional
        Windows to fit (those of other runs are ignored), e.g. from a windows file. By default
        the window finder's (:func:`whipple.measurement.windows.find_windows`), whose rejected
        stretches are listed as rejected windows.
    options : FitOptions, optional
        How to fit; keyword ``settings`` (``signals``, ``baseline``, ``noise``,
        ``shape_signal``, ``settle``, ``min_cycles_above_noise``) override its fields.

    Returns
    -------
    RunMeasurement
        Every window, by start time; a run with no window at all gets one rejected window
        spanning it.
    """
    options = replace(options or FitOptions(), **settings)
    missing = [name for name in options.signals if name not in run.signals]
    if missing:
        raise InputError(f"no {', '.join(missing)} signal to fit", run.source)
    constant = [name for name in options.signals if constant_signal(run.signals[name])]
    if constant:
        raise InputError(f"{', '.join(constant)} never changes (a sensor not connected?): nothing to fit", run.source)
    speed = run.speed()
    # Windows never span a gap in what a fit reads: the fitted signals and the speed.
    valid = np.isfinite(speed) & np.logical_and.reduce([np.isfinite(run.signals[name]) for name in options.signals])
    search = find_windows(run, valid=valid)
    from_file = windows is not None
    chosen = [w for w in windows if w.run == run.name] if windows is not None else list(search.windows)
    measured = [measure_window(run, window, options, speed, search.stills) for window in chosen]
    if not from_file:
        measured += [_rejected(run, window, window.reason.removeprefix("rejected: "), speed)
                     for window in search.rejected]
    if not measured:
        whole = Window(run.name, float(run.time[0]), float(run.time[-1]), 0, run.time.size, "the whole run")
        none = "no window of this run in the windows file" if from_file else "no free-coasting window found"
        measured.append(_rejected(run, whole, none, speed))
    measured.sort(key=lambda m: m.window.start)
    numbered = tuple(replace(m, number=number) for number, m in enumerate(measured, 1))
    return RunMeasurement(run, numbered, search, from_file)


def measure_window(run: Run, window: Window, options: FitOptions | None = None,
                   speed: np.ndarray | None = None, stills: Sequence[int] = ()) -> WindowMeasurement:
    """Fit the weave in one window of a run; a failure is a rejected window with the reason.

    Parameters
    ----------
    run : Run
        The run.
    window : Window
        The window.
    options : FitOptions, optional
        How to fit (default :class:`FitOptions`).
    speed : ndarray, optional
        The run's speed at every sample [m/s] (default ``run.speed()``), to save recomputing it.
    stills : sequence of int
        Sample indices where the roll rate comes to rest
        (:attr:`~whipple.measurement.window_search.WindowSearch.stills`). A window that runs on past
        the first of them inside it is cut there when the bicycle is held still from there
        (:func:`~whipple.measurement.catches.hold_evidence`), or rejected when too little free
        motion comes before it; none given: no such test.
    """
    options = options or FitOptions()
    first, last = float(run.time[0]), float(run.time[-1])
    if window.start >= last or window.stop <= first:
        return WindowMeasurement(run, window, None, None, f"window outside the run ({first:.2f}-{last:.2f} s)")
    step = 1.0 / run.sample_rate
    if window.start < first - step or window.stop > last + step:
        # A hand-picked window reaching past the record is a typing error more likely than a
        # window meant to be cut to it.
        return WindowMeasurement(run, window, None, None,
                                 f"window {window.start:.6g}-{window.stop:.6g} s reaches beyond the run "
                                 f"({first:.2f}-{last:.2f} s)")
    speed = run.speed() if speed is None else speed
    gap = _gap_in(run, window, (*options.signals, "speed"), speed)
    if gap:
        return WindowMeasurement(run, window, None, None, gap)
    try:
        speeds = speed_regression(run.time, speed, window.start, window.stop)
    except InputError as error:
        return WindowMeasurement(run, window, None, None, error.problem)
    if speeds.low <= 0:
        # The model's speed is forward; a fit here would describe another bicycle (at rest, no weave).
        return WindowMeasurement(run, window, None, speeds, f"{'negative' if speeds.low < 0 else 'zero'} speed "
                                 f"({speeds.low:.3g} m/s): the model needs forward speed")
    try:
        fitted = _settled(run, window, options.settle)
        fit = _fit(run, fitted, options)
        held = _before_hold(run, window, fitted, fit, options, stills)
        window, fit = held if held is not None else _before_catch(run, window, fitted, fit, options)
    except InputError as error:
        return WindowMeasurement(run, window, None, speeds, error.problem)
    if window.stop < speeds.stop:
        speeds = speed_regression(run.time, speed, window.start, window.stop)
    quality = _quality(fit, options.min_cycles_above_noise)
    shape = None
    signal = options.shape_signal
    if quality is None and signal is not None and signal in run.signals and signal != options.signals[0]:
        shape = _mode_shape(run, fit, signal, max(SETTLE - (fit.start - window.start), 0.0))
    return WindowMeasurement(run, window, fit, speeds, None, quality, shape)


def _fit(run: Run, window: Window, options: FitOptions) -> WeaveFit:
    """Fit the weave over the window with the options' baseline (``auto``: by its cycles)."""
    baseline = "constant" if options.baseline == "auto" else options.baseline
    fit = fit_window(run, window, options.signals, options.noise, baseline)
    if options.baseline == "auto" and fit.cycles >= AUTO_QUADRATIC_CYCLES:
        fit = fit_window(run, window, options.signals, options.noise, "quadratic")
    return fit


def _before_hold(run: Run, window: Window, fitted: Window, fit: WeaveFit, options: FitOptions,
                 stills: Sequence[int]) -> tuple[Window, WeaveFit] | None:
    """Return the window and its fit cut before a hand that holds the bicycle still; None if none does.

    ``window`` is the window as found, ``fitted`` the part of it that ``fit`` fitted. Where the
    roll rate comes to rest inside ``fitted`` (the first of `stills`, still for ``LOOK_PAST`` of
    a fitted period at least), the free motion is fitted again to the samples before it. It is
    a hold when (1) that free motion and a constant after it beat one free motion throughout by
    ``HOLD_EVIDENCE`` (:func:`~whipple.measurement.catches.hold_evidence`), (2) the catch test,
    the still samples past the end, finds the catch inside (:func:`_before_catch`), and (3) the
    free motion fitted up to the catch leaves the held samples after it (``LOOK_PAST`` of a
    period) ``HOLD_MARK`` times its residual's RMS off or more (first signal): it would have
    swung on. Then the window is cut at the catch; one the catch leaves too short to fit is
    rejected (:class:`NoOscillationError`, naming the hold). (1) alone is not enough: where the
    fitted function lacks some of the bicycle's modes, two pieces beat one curve by more than
    chance in a free decay into the noise too. Under half a period of motion before the
    stillness: nothing is done.
    """
    first = fitted.start_index if fitted.start_index >= 0 else int(np.searchsorted(run.time, fitted.start))
    n = fit.time.size
    # The stillness must last a quarter of a fitted period, in which a held bicycle and the free
    # motion it stopped part by the free motion's amplitude.
    held_for = catches.look_past_samples(fit.frequency, run.sample_rate)
    inside = [int(s) - first for s in stills if first < s <= first + n - held_for]
    if not inside:
        return None
    kept = inside[0]
    head_window = replace(fitted, stop=float(run.time[first + kept - 1]), stop_index=first + kept)
    try:
        head_fit = _fit(run, head_window, options)
    except NoOscillationError:
        # Under half a period before the stillness: no free motion to tell a hold by.
        return None
    evidence = catches.hold_evidence(fit.measured - fit.fitted, head_fit.measured - head_fit.fitted,
                                     fit.measured[:, kept:])
    if evidence < catches.HOLD_EVIDENCE:
        return None
    held = float(run.time[first + kept])
    # The hand takes hold before the roll rate is seen still (stillness is read over half a
    # period): the catch test finds where the free motion and the samples part.
    note = (f"held still from {held:.2f} s (one free motion throughout misfits it: log-likelihood "
            f"ratio {min(evidence, 1e6):.0f})")
    cut = replace(window, stop=head_window.stop, stop_index=head_window.stop_index, notes=(*window.notes, note))
    try:
        caught = _before_catch(run, cut, head_window, head_fit, options)
    except NoOscillationError as error:
        raise NoOscillationError(f"held still from {held:.2f} s, caught before it with too little free motion "
                                 f"to fit ({error.problem})") from error
    window, fit = caught
    if window.stop_index >= cut.stop_index:
        return None
    past_time, past = _past_end(run, window.stop_index, fit, options.signals[:1])
    if past_time.size == 0:
        return None
    mark = float(np.sqrt(np.mean((fit.curve(past_time)[0] - past[0])**2))) / fit.rms_residual[0]
    return (window, fit) if mark >= catches.HOLD_MARK else None


def _before_catch(run: Run, window: Window, fitted: Window, fit: WeaveFit,
                  options: FitOptions) -> tuple[Window, WeaveFit]:
    """Return the window and its fit, both cut before a catch at the window's end, if any.

    ``window`` is the window as found, ``fitted`` the part of it that ``fit`` fitted (after the
    settle time). Each fit's curve is compared with every sample of ``fitted``, so that a fit
    that no longer holds the catch finds where it begins (:func:`~whipple.measurement.catches.catch_onset`).
    """
    time, measured = fit.time, fit.measured
    first = fitted.start_index if fitted.start_index >= 0 else int(np.searchsorted(run.time, fitted.start))
    kept = time.size
    # The samples right after the window, where a hand that caught the bicycle just before its
    # end holds it still while the fit's continuation swings on.
    past_time, past = _past_end(run, first + time.size, fit, options.signals)
    time, measured = np.r_[time, past_time], np.hstack([measured, past])
    for _ in range(options.catch_passes):
        degree = max(catches.DRIFT_DEGREE, BASELINES[fit.baseline])
        onset = catches.catch_onset(time, measured - fit.curve(time), after=past_time.size,
                                    terms=fit.terms(time, degree))
        if onset is None or onset == kept:
            break
        kept = onset
        fit = _fit(run, replace(fitted, stop=float(time[kept - 1]), stop_index=first + kept), options)
    if kept == time.size - past_time.size:
        return window, fit
    note = f"cut before a catch at {time[kept]:.2f} s (the fit's residual leaves the noise)"
    return replace(window, stop=float(time[kept - 1]), stop_index=first + kept, notes=(*window.notes, note)), fit


def _past_end(run: Run, stop: int, fit: WeaveFit,
              signals: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """Return the times [s] and values (fitted signals' units) of the samples after a window's end.

    ``stop`` is the index of the first sample after the window; the samples run for
    :data:`~whipple.measurement.catches.LOOK_PAST` of the fitted period, up to the record's end,
    the first sample any fitted signal lacks or a jump in time (a gap: what lies beyond it is
    no continuation).
    """
    last = min(stop + catches.look_past_samples(fit.frequency, run.sample_rate), run.time.size)
    values = np.array([run.signals[name][stop:last] for name in signals], dtype=float).reshape(len(signals), -1)
    time = np.asarray(run.time[max(stop - 1, 0):last], dtype=float)
    usable = np.all(np.isfinite(values), axis=0) & (np.diff(time) <= 1.5 / run.sample_rate)[-values.shape[1]:]
    keep = int(np.argmin(usable)) if not usable.all() else usable.size
    return time[time.size - values.shape[1]:][:keep], values[:, :keep]


def _gap_in(run: Run, window: Window, names: Sequence[str], speed: np.ndarray) -> str | None:
    """Why a window cannot be fitted because it spans a gap (samples without a value), or None."""
    first = int(np.searchsorted(run.time, window.start))
    stop = int(np.searchsorted(run.time, window.stop, side="right"))
    empty = [name for name in names
             if not np.all(np.isfinite((speed if name == "speed" else run.signals[name])[first:stop]))]
    if not empty:
        return None
    return f"window spans a gap in {', '.join(empty)} (samples without a value): not fitted across it"


#: A diagnosis needs at least this many windows (:func:`with_short_windows`).
MIN_WINDOWS = 2
#: Where fewer than ``MIN_WINDOWS`` windows pass the checks, windows of at least this many weave
#: cycles (in all and above the noise) are used instead (:func:`with_short_windows`).
SHORT_WINDOW_CYCLES = 0.5
#: The note that starts each such window's note (:func:`with_short_windows`).
SHORT_WINDOW_NOTE = "used though short"


def with_short_windows(measurements: Sequence[WindowMeasurement]) -> list[WindowMeasurement]:
    """Return the measurements, with shorter windows made usable where too few pass the checks.

    A bicycle that falls within a second of every push (a heavy load high on a light front
    frame, a weave growing fast) can leave no window of ``MIN_CYCLES`` weave cycles, and a
    diagnosis nothing to work on. Where fewer than ``MIN_WINDOWS`` windows are usable, every
    window that fails only the length checks but holds at least ``SHORT_WINDOW_CYCLES`` cycles
    (in all and above the noise) is used, with a note starting ``SHORT_WINDOW_NOTE``; if that still
    gives fewer than ``MIN_WINDOWS``, the measurements are returned unchanged. Otherwise they
    are returned unchanged too, in the same order.
    """
    result = list(measurements)
    if sum(m.usable for m in result) >= MIN_WINDOWS:
        return result
    short = [k for k, m in enumerate(result)
             if m.rejected is None and m.quality is not None and m.fit is not None
             and _quality(m.fit, SHORT_WINDOW_CYCLES, SHORT_WINDOW_CYCLES) is None]
    if sum(m.usable for m in result) + len(short) < MIN_WINDOWS:
        return result
    for k in short:
        m = result[k]
        note = (f"{SHORT_WINDOW_NOTE} ({m.quality}): fewer than {MIN_WINDOWS} windows pass the checks, "
                f"so windows of at least {SHORT_WINDOW_CYCLES:g} weave cycles are used")
        result[k] = replace(m, quality=None, window=replace(m.window, notes=(*m.window.notes, note)))
    return result


def _quality(fit: WeaveFit, min_cycles_above_noise: float, min_cycles: float = MIN_CYCLES) -> str | None:
    """Why a fit is too poor to be an observation, or None."""
    if fit.r_squared < MIN_R_SQUARED:
        return f"poor fit (R^2 = {fit.r_squared:.2f} < {MIN_R_SQUARED})"
    if fit.cycles < min_cycles:
        return f"too short ({fit.cycles:.2f} weave cycles < {min_cycles})"
    if fit.cycles_above_noise < min_cycles_above_noise:
        return f"too short above the noise ({fit.cycles_above_noise:.2f} weave cycles < {min_cycles_above_noise:g})"
    if not np.all(np.isfinite(fit.covariance)):
        return "eigenvalue covariance not finite"
    return None


def _rejected(run: Run, window: Window, reason: str, speed: np.ndarray) -> WindowMeasurement:
    """Return a window with no fit, with its speed range where one can be computed."""
    try:
        speeds: SpeedRange | None = speed_regression(run.time, speed, window.start, window.stop)
    except InputError:
        speeds = None
    return WindowMeasurement(run, window, None, speeds, reason)


def _settled(run: Run, window: Window, settle: float) -> Window:
    """Return the window without its first ``settle`` seconds (unchanged for 0)."""
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
    if not np.all(np.isfinite(values)):
        return None  # a gap in the shape signal: no mode shape from this window
    try:
        shape = amplitude_ratio(fit, values, signal, settle=settle)
    except NoOscillationError:
        return None
    return shape if np.all(np.isfinite(shape.covariance)) and np.isfinite(shape.ratio) else None
