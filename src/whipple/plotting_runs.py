"""Figures of measured runs in the style of the seed paper (Kooijman & Schwab 2009, Figs 4-5).

Functions return :class:`matplotlib.figure.Figure` objects built without pyplot (Agg canvas),
so nothing is shown and no global state is touched; saving is the caller's business (the CLI
writes them atomically).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from whipple.runs import Run
from whipple.speedometer import SpeedRange
from whipple.weavefit import WeaveFit
from whipple.windows import Window

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
) -> Figure:
    """Raw signals of a run stacked over time, with windows shaded (seed Figure 4).

    Parameters
    ----------
    run : Run
        The run.
    windows : sequence of Window
        Free-coasting windows to shade (green).
    signals : sequence of str, optional
        Signals to show; by default those of RUN_SIGNALS the run has.
    rejected : sequence of Window
        Rejected stretches to shade (grey).
    """
    names = [name for name in (signals or RUN_SIGNALS) if name in run.signals]
    figure = Figure(figsize=(10, 1.6 * len(names) + 0.8), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
    for axis, name in zip(axes, names, strict=True):
        axis.plot(run.time, run.signals[name], color="k", linewidth=0.6)
        axis.set_ylabel(RUN_SIGNALS.get(name, name))
        for window in windows:
            axis.axvspan(window.start, window.stop, color="tab:green", alpha=0.2, linewidth=0)
        for window in rejected:
            axis.axvspan(window.start, window.stop, color="0.6", alpha=0.2, linewidth=0)
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title(f"{run.name}: {len(windows)} free-coasting window(s)")
    return figure


def plot_weave_fit(
    fit: WeaveFit,
    run: Run | None = None,
    speed_range: SpeedRange | None = None,
    margin: float = 0.5,
) -> Figure:
    """Measured and fitted signal over the window, with the speed (seed Figure 5).

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
    """
    figure = Figure(figsize=(8, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    axis = figure.subplots()
    name = fit.signal_names[0]
    if run is not None and name in run.signals:
        around = (run.time >= fit.start - margin) & (run.time <= fit.stop + margin)
        axis.plot(run.time[around], run.signals[name][around], color="0.6", linewidth=0.6)
    axis.plot(fit.time, fit.measured[0], color="k", linewidth=0.8, label="measured")
    axis.plot(fit.time, fit.fitted[0], color="tab:red", linewidth=1.6, label="fit")
    axis.set_xlabel("time [s]")
    axis.set_ylabel(RUN_SIGNALS.get(name, name))
    d_std, w_std = fit.eigenvalue_std
    axis.set_title(
        f"λ = {fit.damping:.2f} ± {d_std:.2f} {'+' if fit.frequency >= 0 else '-'} "
        f"({abs(fit.frequency):.2f} ± {w_std:.2f})i 1/s over {fit.start:.2f}-{fit.stop:.2f} s, "
        f"R² = {fit.r_squared:.3f}"
    )
    if run is not None:
        twin = axis.twinx()
        around = (run.time >= fit.start - margin) & (run.time <= fit.stop + margin)
        twin.step(run.time[around], run.speed()[around], where="post", color="tab:blue",
                  linewidth=0.8, label="speed")
        if speed_range is not None:
            twin.plot([speed_range.start, speed_range.stop],
                      [speed_range.start_speed, speed_range.stop_speed],
                      "--", color="tab:blue", label="speed regression")
        twin.set_ylabel("speed [m/s]", color="tab:blue")
        lower, upper = twin.get_ylim()
        centre = 0.5 * (lower + upper)
        # A speed axis spanning at least 0.5 m/s keeps a flat speed from looking like noise.
        half = max(0.5 * (upper - lower), 0.25)
        twin.set_ylim(centre - 3 * half, centre + half)
    axis.legend(loc="upper right")
    axis.set_xlim(fit.start - (margin if run else 0), fit.stop + (margin if run else 0))
    return figure


def plot_eigenvalues(
    speeds: Sequence[SpeedRange], fits: Sequence[WeaveFit], model: tuple | None = None
) -> Figure:
    """Measured weave eigenvalues against speed, as bars over each speed range (seed Fig. 6).

    Parameters
    ----------
    speeds : sequence of SpeedRange
        Speed range of each fit.
    fits : sequence of WeaveFit
        The fits, in the same order.
    model : tuple of (ndarray, ndarray), optional
        Speeds [m/s] and model weave eigenvalues [1/s] to draw as lines.
    """
    figure = Figure(figsize=(7, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    axis = figure.subplots()
    for speed, fit in zip(speeds, fits, strict=True):
        low, high = speed.low, speed.high
        for value, std, colour in ((fit.damping, fit.eigenvalue_std[0], "tab:red"),
                                   (fit.frequency, fit.eigenvalue_std[1], "tab:blue")):
            axis.plot([low, high], [value, value], color=colour, linewidth=2)
            axis.errorbar([0.5 * (low + high)], [value], yerr=[std], color=colour, capsize=2)
    if model is not None:
        model_speeds, eigenvalues = (np.asarray(v) for v in model)
        axis.plot(model_speeds, eigenvalues.real, color="tab:red", label="model Re λ")
        axis.plot(model_speeds, np.abs(eigenvalues.imag), "--", color="tab:blue",
                  label="model Im λ")
        axis.legend()
    axis.axhline(0, color="0.5", linewidth=0.5)
    axis.set_xlabel("speed [m/s]")
    axis.set_ylabel("eigenvalue [1/s] (red: real, blue: imaginary)")
    return figure
