"""Figures of measured runs in the style of the seed paper (Kooijman & Schwab 2009, Figs 4-6).

* :func:`plot_run` (Figure 4): the raw signals of a run, stacked over time, with the free
  coasting windows shaded and numbered, rejected stretches and skipped windows marked.
* :func:`plot_weave_fit` (Figure 5): the fitted damped sinusoid over the measured signal, the
  speed (staircase from a speedometer, or the speed column) with its linear regression over
  the window, and the residual.
* :func:`plot_measured_eigenvalues` (Figure 6): measured weave eigenvalues as horizontal bars
  over their speed ranges, with error bars, over the model's eigenvalues against speed.
* :func:`fit_figures`: all of these for measured runs, by file name (what ``whipple fit
  --plot`` writes).

Functions return :class:`matplotlib.figure.Figure` objects built without pyplot (Agg canvas),
so nothing is shown and no global state is touched; saving is the caller's business (the CLI
writes them atomically).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator, Sequence

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from whipple.errors import InputError
from whipple.measurement.experiment import RunMeasurement
from whipple.measurement.runs import Run
from whipple.measurement.speedometer import SpeedRange, speedometer_speed
from whipple.measurement.weavefit import WeaveFit
from whipple.measurement.windows import Window
from whipple.model.assembly import linear_model
from whipple.model.parameters import Bicycle
from whipple.stability.critical import CriticalSpeeds, critical_speeds
from whipple.stability.eigen import EigenResult, eigen_analysis
from whipple.stability.plots import plot_eigenvalues

#: Signals shown by :func:`plot_run`, top to bottom, with axis labels.
RUN_SIGNALS = {
    "battery": "battery [V]",
    "steer_angle": "steer angle [rad]",
    "roll_rate": "roll rate [rad/s]",
    "yaw_rate": "yaw rate [rad/s]",
    "steer_torque": "steer torque [N m]",
    "lateral_acceleration": "lateral acc. [m/s²]",
    "speedometer": "speedometer [V]",
    "speed": "speed [m/s]",
}


def plot_run(
    run: Run,
    windows: Sequence[Window] = (),
    signals: Sequence[str] | None = None,
    rejected: Sequence[Window] = (),
    skipped: Sequence[Window] = (),
    numbers: Sequence[int] | None = None,
    span: tuple[float, float] | None = None,
) -> Figure:
    """Raw signals of a run stacked over time, with the regimes marked (seed Figure 4).

    Parameters
    ----------
    run : Run
        The run.
    windows : sequence of Window
        Free-coasting windows that were fitted, shaded green and numbered.
    signals : sequence of str, optional
        Signals to show; by default those of RUN_SIGNALS the run has (and the speed from the
        speedometer signal when the run has no speed column).
    rejected : sequence of Window
        Stretches after a perturbation that the window finder rejected (no oscillation),
        shaded grey.
    skipped : sequence of Window
        Windows whose fit failed, shaded red.
    numbers : sequence of int, optional
        Label of each of `windows` (default 1, 2, ...).
    span : (float, float), optional
        Time range to show [s] (default: the whole run).
    """
    names = [name for name in (signals or RUN_SIGNALS) if name in run.signals]
    if not names:
        raise InputError("none of the signals to plot is in the run", run.source)
    traces = {name: run.signals[name] for name in names}
    if signals is None and "speedometer" in names and "speed" not in names:
        # The raw magnet-ring signal is a solid band at this scale: show its speed as well.
        names.append("speed")
        traces["speed"] = run.speed()
    labels = list(numbers) if numbers is not None else list(range(1, len(windows) + 1))
    if len(labels) != len(windows):
        raise ValueError("plot_run: one number per window needed")
    shown = np.ones(run.time.shape, dtype=bool)
    if span is not None:
        shown = (run.time >= span[0]) & (run.time <= span[1])
    figure = Figure(figsize=(10, 1.5 * len(names) + 1.0), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
    shading = ((windows, "tab:green", 0.25), (rejected, "0.5", 0.25), (skipped, "tab:red", 0.2))
    for axis, name in zip(axes, names, strict=True):
        axis.plot(run.time[shown], traces[name][shown], color="k", linewidth=0.6)
        axis.set_ylabel(RUN_SIGNALS.get(name, name), fontsize=8)
        for group, colour, alpha in shading:
            for window in group:
                axis.axvspan(window.start, window.stop, color=colour, alpha=alpha, linewidth=0)
    for window, label in zip(windows, labels, strict=True):
        if span is None or span[0] <= window.start <= span[1]:
            axes[0].annotate(str(label), xy=(window.start, 1.0), xycoords=("data", "axes fraction"),
                             xytext=(1, 2), textcoords="offset points", fontsize=7,
                             color="tab:green", va="bottom")
    axes[-1].set_xlabel("time [s]")
    axes[-1].set_xlim(run.time[shown][0], run.time[shown][-1])
    legend = [Patch(color="tab:green", alpha=0.4, label="free coasting (fitted)")]
    if rejected:
        legend.append(Patch(color="0.5", alpha=0.4, label="perturbation without oscillation"))
    if skipped:
        legend.append(Patch(color="tab:red", alpha=0.3, label="window not fitted"))
    figure.legend(handles=legend, loc="outside lower center", ncols=len(legend), fontsize=8)
    figure.suptitle(f"{run.name}: {len(windows)} free-coasting window(s); unshaded: launch, "
                    "perturbation, catch and hold", fontsize=10)
    return figure


def _speed_trace(run: Run, low: float, high: float) -> tuple[np.ndarray, np.ndarray, str]:
    """Speed [m/s] to draw over [low, high] s: the speedometer staircase, or the speed."""
    if "speed" not in run.signals and "speedometer" in run.signals:
        try:
            radius = float(run.metadata["wheel_radius"])
            pulses = float(run.metadata["pulses_per_revolution"])
            stairs = speedometer_speed(run.time, run.signals["speedometer"], radius, pulses,
                                       source=run.source)
        except (KeyError, ValueError):
            pass
        else:
            inside = (stairs.crossing_times[:-1] <= high) & (stairs.crossing_times[1:] >= low)
            edges = stairs.crossing_times[:-1][inside]
            return edges, stairs.speeds[inside], "speedometer staircase"
    around = (run.time >= low) & (run.time <= high)
    return run.time[around], run.speed()[around], "speed"


def plot_weave_fit(
    fit: WeaveFit,
    run: Run | None = None,
    speed_range: SpeedRange | None = None,
    margin: float = 0.5,
    title: str | None = None,
) -> Figure:
    """Measured and fitted signal over a window, with the speed and residual (seed Figure 5).

    Parameters
    ----------
    fit : WeaveFit
        The fit; its first signal is drawn.
    run : Run, optional
        The run, to show the signal `margin` seconds around the window and the speed.
    speed_range : SpeedRange, optional
        The speed regression over the window, drawn dashed on the speed axis.
    margin : float
        Time shown before and after the window [s].
    title : str, optional
        First title line (default: the run's name, if given).
    """
    # Fixed margins and title positions: the CLI draws one of these per window, and automatic
    # placement triples the time to save it.
    figure = Figure(figsize=(8, 5.2))
    FigureCanvasAgg(figure)
    axis, lower = figure.subplots(2, 1, sharex=True, height_ratios=(3, 1),
                                  gridspec_kw=dict(left=0.1, right=0.9, top=0.89, bottom=0.09,
                                                   hspace=0.28))
    name = fit.signal_names[0]
    low, high = fit.start - (margin if run else 0.0), fit.stop + (margin if run else 0.0)
    if run is not None and name in run.signals:
        around = (run.time >= low) & (run.time <= high)
        axis.plot(run.time[around], run.signals[name][around], color="0.65", linewidth=0.6,
                  label="measured, outside the window")
    axis.plot(fit.time, fit.measured[0], color="k", linewidth=0.8, label="measured")
    axis.plot(fit.time, fit.fitted[0], color="tab:red", linewidth=1.6,
              label="fit c1 + exp(dt)[c2 cos wt + c3 sin wt]")
    axis.set_ylabel(RUN_SIGNALS.get(name, name))
    d_std, w_std = fit.eigenvalue_std
    heading = title or (run.name if run is not None else "")
    axis.set_title(
        (f"{heading}\n" if heading else "")
        + f"λ = {fit.damping:.2f} ± {d_std:.2f} {'+' if fit.frequency >= 0 else '-'} "
        f"({abs(fit.frequency):.2f} ± {w_std:.2f})i 1/s over {fit.start:.2f}-{fit.stop:.2f} s, "
        f"R² = {fit.r_squared:.3f}", fontsize=10, y=1.0)
    handles, texts = axis.get_legend_handles_labels()
    if run is not None:
        twin = axis.twinx()
        times, speeds, what = _speed_trace(run, low, high)
        twin.step(times, speeds, where="post", color="tab:blue", linewidth=0.8)
        handles.append(Line2D([], [], color="tab:blue", linewidth=0.8))
        texts.append(what)
        if speed_range is not None:
            twin.plot([speed_range.start, speed_range.stop],
                      [speed_range.start_speed, speed_range.stop_speed],
                      "--", color="tab:blue", linewidth=1.4)
            handles.append(Line2D([], [], color="tab:blue", linestyle="--", linewidth=1.4))
            texts.append(f"speed regression {speed_range.start_speed:.2f} → "
                         f"{speed_range.stop_speed:.2f} m/s")
        twin.set_ylabel("speed [m/s]", color="tab:blue")
        bottom, top = twin.get_ylim()
        centre = 0.5 * (bottom + top)
        # A speed axis spanning at least 0.5 m/s keeps a flat speed from looking like noise;
        # the speed sits in the upper quarter, clear of the oscillation.
        half = max(0.5 * (top - bottom), 0.25)
        twin.set_ylim(centre - 3 * half, centre + half)
    axis.legend(handles, texts, loc="lower right", fontsize=7)
    residual = fit.measured[0] - fit.fitted[0]
    lower.plot(fit.time, residual, color="k", linewidth=0.6)
    lower.axhline(0.0, color="tab:red", linewidth=0.8)
    lower.set_ylabel(f"residual, {RUN_SIGNALS.get(name, name)}", fontsize=8)
    lower.set_xlabel("time [s]")
    lower.set_title(f"residual: RMS {fit.rms_residual[0]:.3g}, lag-1 autocorrelation "
                    f"{fit.residual_correlation:.2f}, covariance {fit.noise_model}", fontsize=8, y=1.0)
    axis.set_xlim(low, high)
    return figure


def _scaled_critical(critical: CriticalSpeeds, scale: float) -> CriticalSpeeds:
    """Critical speeds with every speed multiplied by `scale` (true -> measured speed)."""

    def times(value: float | None) -> float | None:
        return None if value is None else value * scale

    return dataclasses.replace(
        critical,
        low=critical.low * scale,
        high=critical.high * scale,
        crossings=tuple(dataclasses.replace(c, speed=c.speed * scale) for c in critical.crossings),
        weave_speeds=tuple(v * scale for v in critical.weave_speeds),
        capsize_speeds=tuple(v * scale for v in critical.capsize_speeds),
        stable_speed_ranges=tuple((a * scale, b * scale) for a, b in critical.stable_speed_ranges),
        weave_speed=times(critical.weave_speed),
        capsize_speed=times(critical.capsize_speed),
    )


def plot_measured_eigenvalues(
    speeds: Sequence[SpeedRange],
    fits: Sequence[WeaveFit],
    model: EigenResult | None = None,
    critical: CriticalSpeeds | None = None,
    speed_scale: float = 1.0,
    title: str | None = None,
) -> Figure:
    """Measured weave eigenvalues as bars over their speed ranges, on the model's (seed Fig. 6).

    Each measured eigenvalue is a horizontal bar over the speed range of its window (the speed
    regression's ends) at its real part (solid) and imaginary part (dotted), with a vertical
    error bar of one standard deviation at the mean speed.

    Parameters
    ----------
    speeds : sequence of SpeedRange
        Measured speed range of each fit [m/s].
    fits : sequence of WeaveFit
        The fits, in the same order.
    model : EigenResult, optional
        The model's eigenvalues against true speed (:func:`whipple.stability.eigen.eigen_analysis`
        of one bicycle on an increasing grid); drawn with
        :func:`whipple.stability.plots.plot_eigenvalues`.
    critical : CriticalSpeeds, optional
        The model's critical speeds (true speeds), marked on the figure.
    speed_scale : float
        Measured speed / true speed of the bicycle: the model is drawn against
        ``speed_scale * true speed``, the speed a measurement would report.
    title : str, optional
        Axes title.
    """
    if len(speeds) != len(fits):
        raise ValueError("plot_measured_eigenvalues: one speed range per fit needed")
    if not (np.isfinite(speed_scale) and speed_scale > 0):
        raise InputError(f"speed_scale must be positive, got {speed_scale}")
    values = np.array([fit.eigenvalue for fit in fits], dtype=complex)
    stds = np.array([fit.eigenvalue_std for fit in fits], dtype=float).reshape(-1, 2)
    reach = float(np.max(np.abs(np.concatenate([values.real, values.imag])) + 0.5, initial=10.0))
    if model is not None:
        shown = dataclasses.replace(model, speeds=model.speeds * speed_scale)
        marks = None if critical is None else _scaled_critical(critical, speed_scale)
        measured = [(s.low, s.high, complex(v)) for s, v in zip(speeds, values, strict=True)]
        ylim = (-1.1 * reach, 1.1 * reach)
        figure = plot_eigenvalues(shown, marks, title=title, ylim=ylim, measured=measured)
        axis = figure.axes[0]
        if speed_scale != 1.0:
            axis.set_xlabel(f"measured forward speed [m/s] (= {speed_scale:g} × model speed)")
    else:
        figure = Figure(figsize=(9.0, 4.8), layout="constrained")
        FigureCanvasAgg(figure)
        axis = figure.add_subplot()
        for speed, value in zip(speeds, values, strict=True):
            axis.plot([speed.low, speed.high], [value.real] * 2, color="black", linewidth=2.5)
            axis.plot([speed.low, speed.high], [abs(value.imag)] * 2, color="black",
                      linewidth=2.5, linestyle=":")
        axis.axhline(0, color="black", linewidth=0.6)
        axis.set_xlabel("forward speed v [m/s]")
        axis.set_ylabel("eigenvalue λ [1/s]")
        axis.grid(alpha=0.3)
        axis.legend(handles=[Line2D([], [], color="black", linewidth=2.5, label="measured real part"),
                             Line2D([], [], color="black", linewidth=2.5, linestyle=":",
                                    label="measured imaginary part")], fontsize=8)
        axis.set_title(title or "Measured weave eigenvalues against forward speed")
    means = np.array([s.mean for s in speeds])
    if means.size:
        axis.errorbar(means, values.real, yerr=stds[:, 0], fmt="none", ecolor="black",
                      elinewidth=0.8, capsize=2)
        axis.errorbar(means, np.abs(values.imag), yerr=stds[:, 1], fmt="none", ecolor="black",
                      elinewidth=0.8, capsize=2)
    return figure


def fit_figures(measured: Sequence[RunMeasurement], bicycle: Bicycle | None = None
                ) -> Iterator[tuple[str, Figure]]:
    """Return the figures of measured runs, one at a time, with their file names.

    For each run its signals with the windows marked (``<run>_run.png``) and each fitted
    window (``<run>_window<NN>_<start>s.png``); then all measured eigenvalues against speed
    (``eigenvalues.png``), over the model of `bicycle` when given.
    """
    for run_ in measured:
        run = run_.run
        fitted = run_.fitted
        unfitted = [m.window for m in run_ if m.fit is None]
        rejected = [w for w in unfitted if w.reason.startswith("rejected")]
        failed = [w for w in unfitted if not w.reason.startswith("rejected") and w.reason != "the whole run"]
        yield f"{run.name}_run.png", plot_run(run, [m.window for m in fitted], rejected=rejected, skipped=failed,
                                              numbers=[m.number for m in fitted])
        for m in fitted:
            assert m.fit is not None
            yield (f"{run.name}_window{m.number:02d}_{m.window.start:.2f}s.png",
                   plot_weave_fit(m.fit, run, m.speed, title=f"{run.name}, window {m.number}"))
    timed = [m for run_ in measured for m in run_.fitted if m.speed is not None]
    if not timed:
        return
    model = critical = None
    scale = 1.0
    title = "measured weave eigenvalues"
    if bicycle is not None:
        scale = float(bicycle.extensions.speed_scale)
        top = max([10.0, *(1.1 * float(bicycle.model_speed(m.speed.high)) for m in timed if m.speed is not None)])
        linear = linear_model(bicycle)
        model = eigen_analysis(linear, np.linspace(0.0, top, 1001), vectors=False)
        critical = critical_speeds(linear, 0.0, top)
        title = f"measured weave eigenvalues and the model of {bicycle.name or 'the bicycle'}"
    yield "eigenvalues.png", plot_measured_eigenvalues(
        [m.speed for m in timed if m.speed is not None], [m.fit for m in timed if m.fit is not None],
        model, critical, scale, title)
