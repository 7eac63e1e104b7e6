"""From measured runs to weave eigenvalues, one way for ``whipple fit``, ``whipple diagnose`` and the library.

:func:`measure_runs` is the measurement pipeline. For a set of runs it

1. chooses the signals fitted jointly in every window (``signals="auto"``: the roll rate and the
   steer angle where every run measures both, :func:`~whipple.measurement.signal_choice.diagnosis_signals`);
2. finds the free-coasting windows (or takes those of a windows file) and fits each one
   (:func:`~whipple.measurement.experiment.measure_run`: the weave eigenvalue, its speed, its
   mode shape; a window running past a hand's catch is cut before it);
3. sets aside the windows that no free motion of a linear model follows nearly as well as the
   data set's others (:func:`~whipple.measurement.free_motion.set_aside_outlying`);
4. uses windows of half a weave cycle where fewer than two pass the checks
   (:func:`~whipple.measurement.experiment.with_short_windows`);
5. given a bicycle, checks the steer signal's sign against the model's mode shape and, where it
   is opposite, fits the roll rate alone (:mod:`whipple.measurement.steer_sign`).

A window measured here has one eigenvalue whichever command reports it. The seed paper's plain
fit (the roll rate alone with a constant baseline, nothing set aside) is an explicit choice:
:meth:`MeasurementOptions.seed_paper`.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace
from typing import overload

import numpy as np

from whipple.errors import InputError
from whipple.measurement.experiment import (
    CATCH_PASSES,
    MIN_CYCLES_ABOVE_NOISE,
    SHORT_WINDOW_NOTE,
    FitOptions,
    RunMeasurement,
    WindowMeasurement,
    measure_run,
    with_short_windows,
)
from whipple.measurement.free_motion import set_aside_outlying
from whipple.measurement.roll_units import roll_unit_problem
from whipple.measurement.runs import Run, check_distinct_names
from whipple.measurement.signal_choice import diagnosis_signals, steer_constant
from whipple.measurement.speed_units import speed_unit_problem
from whipple.measurement.steer_sign import steer_signal_check
from whipple.measurement.windows import Window
from whipple.model.fleet import Model
from whipple.model.parameters import Bicycle
from whipple.stability.nearest_modes import nearest_oscillations

__all__ = ["Progress", "METHODS", "MeasurementOptions", "MeasuredRuns", "model_modes", "measure_runs", "unusable_text"]

#: A progress report: ``progress(stage, done, total)``, e.g. ``("runs", 3, 40)``; total may be None.
Progress = Callable[[str, int, "int | None"], None]

#: Names of the fits a measurement can make (:attr:`MeasurementOptions.method`).
METHODS = ("whipple", "seed-paper")


@dataclass(frozen=True)
class MeasurementOptions:
    """How measured runs become weave eigenvalues (:func:`measure_runs`).

    The defaults are what ``whipple fit`` and ``whipple diagnose`` do; each field says why.

    Attributes
    ----------
    signals : "auto" or tuple of str
        Signals fitted jointly in every window, sharing one eigenvalue (run-file names; the
        first is the mode shape's reference). ``"auto"`` (default): the roll rate and the steer
        angle where every run measures the steer angle wherever it measures the roll rate, else
        the roll rate alone. The steer angle's weave sharpens the shared eigenvalue: on the
        hidden-effect trials it gave more right names and fewer wrong ones than the roll rate
        alone (docs/diagnosis.md).
    baseline : str
        The fitted function's non-oscillating part: ``"auto"`` (default) takes the seed paper's
        constant, and a quadratic that follows the slow capsize mode in windows of two weave
        cycles or more, where there are enough data to tell the two apart; or ``"constant"``,
        ``"linear"``, ``"quadratic"`` everywhere.
    noise : {"auto", "white", "correlated"}
        Covariance of each eigenvalue: Newey-West where the residual's lag-1 autocorrelation is
        significant (``"auto"``, default), else white.
    settle : float
        Seconds [s] left out at the start of every window (default 0, as in the seed paper); a
        bicycle whose castering mode is slow at the measured speeds may need 0.3 s.
    min_cycles_above_noise : float
        Windows holding fewer weave cycles than this while the oscillation stands above the
        noise are not used (default 0.75: past that a strongly damped window holds mostly noise,
        which biases its frequency); 0: no such check, as in the seed paper.
    set_aside : bool
        Set aside windows that no free motion of a 4-state linear model follows nearly as well
        as the data set's other windows (default True: a catch, a hold and a push read as one
        slow swing otherwise decide a diagnosis; simulated free windows are never set aside).
    short_windows : bool
        Where fewer than two windows pass the checks, use those of at least half a weave cycle,
        with a note (default True: a bicycle that falls within a second of every push leaves
        nothing else).
    check_steer_sign : bool
        Given a bicycle, fit the roll rate alone where the steer signal's sign is opposite to
        the model's convention or its units differ (default True; with ``signals="auto"`` only:
        named signals are fitted as named).
    catch_passes : int
        Fits of a window whose end may hold a hand's catch, each cutting it where the fit's
        residual leaves the noise (default 3); 0: windows are fitted as found.
    """

    signals: str | tuple[str, ...] = "auto"
    baseline: str = "auto"
    noise: str = "auto"
    settle: float = 0.0
    min_cycles_above_noise: float = MIN_CYCLES_ABOVE_NOISE
    set_aside: bool = True
    short_windows: bool = True
    check_steer_sign: bool = True
    catch_passes: int = CATCH_PASSES

    def __post_init__(self) -> None:
        if isinstance(self.signals, str):
            if self.signals != "auto":
                raise InputError(f"signals must be 'auto' or a tuple of signal names, got {self.signals!r}")
        elif not self.signals or not all(isinstance(name, str) and name for name in self.signals):
            raise InputError(f"signals names no signal: {self.signals!r}")
        if self.noise not in ("auto", "white", "correlated"):
            raise InputError(f"unknown noise model {self.noise!r} (auto, white or correlated)")
        # The per-window fit's own checks (baseline, settle, cycles, catch passes), once, here.
        self.fit_options(("roll_rate",))

    @classmethod
    def seed_paper(cls) -> MeasurementOptions:
        """Return the seed paper's plain fit: the roll rate alone, a constant baseline, nothing set aside.

        Returns
        -------
        MeasurementOptions
            ``c1 + e^{dt} (c2 cos wt + c3 sin wt)`` fitted to the roll rate of every window
            found (cut before a catch, checked for cycles above the noise), as Kooijman and
            Schwab fit their windows; no window is set aside and no short window used.
        """
        return cls(signals=("roll_rate",), baseline="constant", set_aside=False, short_windows=False,
                   check_steer_sign=False)

    @property
    def method(self) -> str:
        """Return ``"seed-paper"`` for the seed paper's fit (roll rate alone, constant baseline), else ``"whipple"``."""
        return "seed-paper" if self.signals == ("roll_rate",) and self.baseline == "constant" else "whipple"

    def fit_options(self, signals: tuple[str, ...]) -> FitOptions:
        """Return the per-window fit options with the chosen ``signals``."""
        return FitOptions(signals=signals, baseline=self.baseline, noise=self.noise, settle=self.settle,
                          min_cycles_above_noise=self.min_cycles_above_noise, catch_passes=self.catch_passes)

    def to_dict(self) -> dict[str, object]:
        """Return the options as JSON-ready data, with the method's name."""
        return {"method": self.method, "signals": self.signals if isinstance(self.signals, str) else list(self.signals),
                "baseline": self.baseline, "noise": self.noise, "settle": self.settle,
                "min_cycles_above_noise": self.min_cycles_above_noise, "set_aside": self.set_aside,
                "short_windows": self.short_windows, "check_steer_sign": self.check_steer_sign,
                "catch_passes": self.catch_passes}


@dataclass(frozen=True)
class MeasuredRuns(Sequence[RunMeasurement]):
    """Every window of a set of runs, measured one way (:func:`measure_runs`).

    Iterating (or indexing) gives each run's :class:`~whipple.measurement.experiment.RunMeasurement`.

    Attributes
    ----------
    runs : tuple of RunMeasurement
        Per run, every window by start time, with the set-aside and short-window rules applied.
    signals : tuple of str
        The signals fitted jointly in every window.
    options : MeasurementOptions
        The options measured with.
    steer_sign : str
        What the steer signal's check found: ``"as the model's"``, ``"opposite to the model's"``
        or ``"<factor> times the model's (...)"`` (other units; in both the roll rate was then
        fitted alone: :func:`~whipple.measurement.steer_sign.steer_signal_check`), ``"not
        checked"`` (no bicycle, or the signals were named), ``"no steer signal"`` or ``"constant in
        <runs>"`` (a steer angle column whose values never change: the roll rate fitted alone).
    speed_units : str or None
        Given a bicycle, why the windows' speeds seem to be in other units than the model's
        (:func:`~whipple.measurement.speed_units.speed_unit_problem`); None when they do not
        (or no bicycle was given).
    roll_units : str or None
        Why the roll rate seems to be in other units than rad/s: its weave implies leans beyond
        lying flat (:func:`~whipple.measurement.roll_units.roll_unit_problem`); None when not.
    """

    runs: tuple[RunMeasurement, ...]
    signals: tuple[str, ...]
    options: MeasurementOptions
    steer_sign: str = "not checked"
    speed_units: str | None = None
    roll_units: str | None = None

    @overload
    def __getitem__(self, index: int) -> RunMeasurement: ...

    @overload
    def __getitem__(self, index: slice) -> Sequence[RunMeasurement]: ...

    def __getitem__(self, index: int | slice) -> RunMeasurement | Sequence[RunMeasurement]:
        return self.runs[index]

    def __len__(self) -> int:
        return len(self.runs)

    def __iter__(self) -> Iterator[RunMeasurement]:
        return iter(self.runs)

    @property
    def windows(self) -> tuple[WindowMeasurement, ...]:
        """Every window of every run, run by run."""
        return tuple(m for run in self.runs for m in run)

    @property
    def usable(self) -> tuple[WindowMeasurement, ...]:
        """The windows usable as observations."""
        return tuple(m for m in self.windows if m.usable)

    @property
    def run_notes(self) -> dict[str, tuple[str, ...]]:
        """Return what reading each run noted (gaps filled, units converted, ...), by run; runs without any left out."""
        return {run.run.name: run.run.warnings for run in self.runs if run.run.warnings}

    @property
    def short(self) -> int:
        """Return how many usable windows are used though short (:func:`.experiment.with_short_windows`)."""
        return sum(any(note.startswith(SHORT_WINDOW_NOTE) for note in m.window.notes) for m in self.usable)

    def describe(self) -> str:
        """Say in words how the windows were fitted."""
        signals = " and ".join(self.signals) + (" jointly" if len(self.signals) > 1 else "")
        name = " (the seed paper's fit)" if self.options.method == "seed-paper" else ""
        sign = ""
        if self.steer_sign == "opposite to the model's":
            sign = ("; the steer signal's sign is opposite to the model's (or the roll rate's is), so the roll rate "
                    "was fitted alone")
        elif self.steer_sign.startswith("constant in "):
            sign = (f"; the steer angle does not change in {self.steer_sign.removeprefix('constant in ')} (a sensor "
                    "not connected?), so the roll rate was fitted alone")
        elif "times the model's" in self.steer_sign:
            sign = f"; the weave's steer per roll rate is {self.steer_sign}, so the roll rate was fitted alone"
        if self.speed_units is not None:
            sign += f"; {self.speed_units}"
        if self.roll_units is not None:
            sign += f"; {self.roll_units}"
        return f"fitted {signals}, baseline {self.options.baseline}{name}{sign}"


def model_modes(windows: Sequence[WindowMeasurement], bicycle: Bicycle
                ) -> list[tuple[complex | None, bool] | None]:
    """Return, per window, the model's oscillating mode nearest its fitted eigenvalue at its speed.

    Parameters
    ----------
    windows : sequence of WindowMeasurement
        The windows.
    bicycle : Bicycle
        The model.

    Returns
    -------
    list
        Per window: None where it has no fit; else ``(eigenvalue, near)``, the model's oscillating
        mode nearest the measured eigenvalue [1/s] (None where the model has none at that speed)
        and whether it lies near enough to describe the measured oscillation
        (:func:`~whipple.stability.nearest_modes.nearest_oscillations`).
    """
    fitted = [k for k, m in enumerate(windows) if m.fit is not None and m.speed is not None]
    result: list[tuple[complex | None, bool] | None] = [None] * len(windows)
    if not fitted:
        return result
    targets = [windows[k].fit.eigenvalue for k in fitted]  # type: ignore[union-attr]
    speeds = [windows[k].speed.mean for k in fitted]  # type: ignore[union-attr]
    values, near = nearest_oscillations(bicycle, speeds, targets)
    for k, value, ok in zip(fitted, values, near, strict=True):
        result[k] = (None if np.isnan(value) else complex(value), bool(ok))
    return result


def measure_runs(runs: Sequence[Run], options: MeasurementOptions | None = None, *,
                 windows: Sequence[Window] | None = None, bicycle: Model | None = None,
                 groups: Sequence[str] | None = None, progress: Progress | None = None) -> MeasuredRuns:
    """Measure every window of `runs`: the pipeline of ``whipple fit`` and ``whipple diagnose``.

    Parameters
    ----------
    runs : sequence of Run
        The runs, measured together (their windows share one choice of signals, and the
        set-aside rule judges them against each other). Names must be distinct.
    options : MeasurementOptions, optional
        How to measure (default :class:`MeasurementOptions`).
    windows : sequence of Window, optional
        Windows to fit instead of the window finder's (e.g. from a windows file).
    bicycle : Bicycle or Fleet, optional
        The model whose mode shape the steer signal's sign is checked against; without one the
        sign is not checked. A fleet (the groups of an experiment) checks each group's windows
        against its group's bicycle.
    groups : sequence of str, optional
        The group of each run (an experiment of several groups), given to each of its windows.
    progress : callable, optional
        Called as ``progress("runs", done, total)`` after each run is measured.

    Returns
    -------
    MeasuredRuns
        Every window of every run, with the signals fitted and the sign check's finding.
    """
    options = options or MeasurementOptions()
    runs = list(runs)
    if not runs:
        raise InputError("no runs to measure")
    check_distinct_names(runs)
    if groups is not None and len(groups) != len(runs):
        raise InputError(f"{len(groups)} groups given for {len(runs)} runs")
    auto = options.signals == "auto"
    signals = diagnosis_signals(runs) if auto else tuple(options.signals)
    measured = _measured(runs, windows, options, signals, progress, groups)
    steer_sign = "not checked"
    if len(signals) > 1 and auto and options.check_steer_sign and bicycle is not None:
        steer_sign = steer_signal_check(bicycle, measured.windows)
        if steer_sign != "as the model's":
            # A flipped steer angle, or one in other units, would mislead every comparison with a
            # model: the roll rate alone.
            signals = signals[:1]
            measured = _measured(runs, windows, options, signals, progress, groups)
    elif auto and len(signals) == 1:
        constant = [run.name for run in runs if steer_constant(run)]
        steer_sign = f"constant in {', '.join(constant)}" if constant else "no steer signal"
    speed_units = speed_unit_problem(bicycle, measured.windows) if bicycle is not None else None
    return replace(measured, steer_sign=steer_sign, speed_units=speed_units,
                   roll_units=roll_unit_problem(measured.windows))


def _measured(runs: Sequence[Run], windows: Sequence[Window] | None, options: MeasurementOptions,
              signals: tuple[str, ...], progress: Progress | None, groups: Sequence[str] | None) -> MeasuredRuns:
    """Fit every window of every run with `signals`, then apply the data set's rules."""
    fit_options = options.fit_options(signals)
    per_run = []
    for done, run in enumerate(runs, 1):
        measurement = measure_run(run, windows, fit_options)
        if groups is not None:
            group = groups[done - 1]
            measurement = replace(measurement, windows=tuple(replace(m, group=group) for m in measurement))
        per_run.append(measurement)
        if progress is not None:
            progress("runs", done, len(runs))
    flat = [m for run in per_run for m in run]
    if options.set_aside:
        flat = set_aside_outlying(flat)
    if options.short_windows:
        flat = with_short_windows(flat)
    regrouped, start = [], 0
    for measurement in per_run:
        regrouped.append(replace(measurement, windows=tuple(flat[start:start + len(measurement)])))
        start += len(measurement)
    return MeasuredRuns(tuple(regrouped), signals, options)


def unusable_text(measurements: Sequence[WindowMeasurement]) -> tuple[str, str]:
    """Return where windows without a usable fit come from, and why: ``(" in a.csv", " (most often ...)")``.

    For the message of a command that needs usable windows and got none or too few: the run
    files (three at most) and the commonest reason a window was skipped; empty strings where
    there are none.
    """
    reasons = Counter(m.skipped.split(" (")[0] for m in measurements if m.skipped)
    why = f" (most often skipped: {reasons.most_common(1)[0][0]})" if reasons else ""
    files = sorted({str(m.run.source) for m in measurements})
    where = f" in {', '.join(files[:3])}{' ...' if len(files) > 3 else ''}" if files else ""
    return where, why
