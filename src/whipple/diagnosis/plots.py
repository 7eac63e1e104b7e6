"""Figures of the diagnosis report: plain matplotlib Figures (no pyplot state), never saved here."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from whipple.diagnosis.report import DiagnosisReport
from whipple.measurement.weavefit import response_with_eigenvalue
from whipple.model.assembly import linear_model
from whipple.model.fleet import Model
from whipple.model.parameters import Bicycle
from whipple.stability.eigen import weave_eigenvalue
from whipple.stability.nearest_modes import nearest_modes

#: Units of the signals a mode shape compares (for the axis label of their amplitude ratio).
SIGNAL_UNITS = {"roll_rate": "rad/s", "steer_angle": "rad", "steer_rate": "rad/s", "yaw_rate": "rad/s",
                "roll_angle": "rad"}


def _weave_curve(bicycle: Bicycle, speeds: np.ndarray) -> np.ndarray:
    """Return the weave eigenvalue against measured speed (speed_scale applied)."""
    return weave_eigenvalue(linear_model(bicycle), bicycle.model_speed(speeds))


def _curves(name: str, model: Model, colour: str) -> list[tuple[str, Bicycle, str, str]]:
    """Return the curves to draw of a model: label, bicycle, colour, line style (a line per group of a fleet)."""
    if isinstance(model, Bicycle):
        return [(name, model, colour, "-")]
    styles = ("-", "--", ":", "-.")
    return [(f"{name}, {group}", member, colour, styles[k % len(styles)])
            for k, (group, member) in enumerate(model.members)]


def plot_eigenvalues(report: DiagnosisReport) -> Figure:
    """Measured weave eigenvalues (bars over their speed range) against both models' weave."""
    observations = report.diagnosis.observations
    speeds = np.array([o.speed for o in observations])
    grid = np.linspace(max(0.0, speeds.min() - 0.5), speeds.max() + 0.5, 300)
    figure = Figure(figsize=(7.5, 6.5))
    axes = figure.subplots(2, 1, sharex=True)
    models = _curves("base model", report.bicycle, "C0")
    if report.diagnosis.best is not None:
        models += _curves(f"extended model ({report.diagnosis.cause})", report.extended, "C3")
    for axis, part, label in ((axes[0], np.real, "real part d [1/s]"), (axes[1], np.imag, "imaginary part w [rad/s]")):
        for name, bicycle, colour, style in models:
            axis.plot(grid, part(_weave_curve(bicycle, grid)), color=colour, ls=style, label=name)
        for o in observations:
            value = part(o.eigenvalue)
            std = np.sqrt(o.covariance[0, 0] if part is np.real else o.covariance[1, 1])
            low, high = sorted(o.speed_range)
            axis.plot([low, high], [value, value], color="k", lw=2)
            axis.errorbar(o.speed, value, yerr=std, color="k", lw=0.8, capsize=2)
        axis.set_ylabel(label)
        axis.grid(alpha=0.3)
    axes[0].axhline(0.0, color="0.5", lw=0.8)
    axes[0].plot([], [], color="k", lw=2, label="measured (speed range, 1 std)")
    axes[0].legend(fontsize=8)
    axes[1].set_xlabel("measured speed [m/s]")
    figure.suptitle("Weave eigenvalue: measurements and models")
    figure.tight_layout()
    return figure


def plot_residuals(report: DiagnosisReport) -> Figure:
    """Measured minus model weave eigenvalue against speed, base and extended."""
    observations = report.diagnosis.observations
    speeds = np.array([o.speed for o in observations])
    measured = np.array([o.eigenvalue for o in observations])
    std = np.array([np.sqrt(np.diag(o.covariance)) for o in observations])
    figure = Figure(figsize=(10, 3.8))
    axes = figure.subplots(1, 2)
    models = [("base model", report.base_prediction, "C0", -0.03)]
    if report.diagnosis.best is not None:
        models.append((f"extended model ({report.diagnosis.cause})", report.extended_prediction, "C3", 0.03))
    for name, prediction, colour, shift in models:
        residual = measured - prediction.eigenvalues
        axes[0].errorbar(speeds + shift, residual.real, yerr=std[:, 0], fmt="o", ms=3, color=colour, label=name)
        axes[1].errorbar(speeds + shift, residual.imag, yerr=std[:, 1], fmt="o", ms=3, color=colour, label=name)
    for axis, title, unit in zip(axes, ("real part (damping)", "imaginary part (frequency)"), ("d [1/s]", "w [rad/s]"),
                                 strict=True):
        axis.axhline(0.0, color="0.5", lw=0.8)
        axis.set_xlabel("measured speed [m/s]")
        axis.set_ylabel(f"measured - model {unit}")
        axis.set_title(title, fontsize=10)
        axis.grid(alpha=0.3)
    axes[0].legend(fontsize=8, title="each window (bars: 1 std of the fit)", title_fontsize=7)
    figure.suptitle("Weave eigenvalue residuals: measured minus model, per window")
    figure.tight_layout()
    return figure


def _shape_curve(bicycle: Bicycle, speeds: np.ndarray, signals: tuple[str, str]) -> np.ndarray:
    """Return the weave's eigenvector ratio of two signals against measured speed (NaN with no weave)."""
    weave = _weave_curve(bicycle, speeds)
    ratio = nearest_modes(bicycle, speeds, weave, [signals] * len(speeds))[1]
    return np.where(weave.imag > 0, ratio, np.nan)


def _phase(ratio: complex | np.ndarray) -> np.ndarray:
    # Steer lags the roll rate by 90-270 degrees over the usual speeds; (-360, 0] keeps that
    # range in one piece where (-180, 180] would cut it.
    return np.asarray(np.degrees(np.angle(ratio)) % 360.0 - 360.0)


def plot_mode_shapes(report: DiagnosisReport) -> Figure:
    """Measured weave mode shapes (magnitude and phase of the amplitude ratio) against both models'."""
    observations = report.diagnosis.observations
    compared = [o for o, used in zip(observations, report.shapes.compared, strict=True)
                if used and o.shape is not None and o.shape_covariance is not None]
    figure = Figure(figsize=(7.5, 6.0))
    axes = figure.subplots(2, 1, sharex=True)
    if not compared:
        axes[0].set_title("no mode shapes compared")
        return figure
    signals = compared[0].shape_signals
    speeds = np.array([o.speed for o in compared])
    grid = np.linspace(max(0.0, speeds.min() - 0.5), speeds.max() + 0.5, 300)
    models = _curves("base model", report.bicycle, "C0")
    if report.diagnosis.best is not None:
        models += _curves(f"extended model ({report.diagnosis.cause})", report.extended, "C3")
    for name, bicycle, colour, style in models:
        curve = _shape_curve(bicycle, grid, signals)
        axes[0].plot(grid, np.abs(curve), color=colour, ls=style, label=name)
        axes[1].plot(grid, _phase(curve), color=colour, ls=style, label=name)
    for o in compared:
        ratio = complex(o.shape or 0.0)
        covariance = np.asarray(o.shape_covariance)
        # Standard deviations along and across the ratio: of its magnitude and (over |ratio|) its phase.
        along = np.array([ratio.real, ratio.imag]) / abs(ratio)
        across = np.array([-along[1], along[0]])
        axes[0].errorbar(o.speed, abs(ratio), yerr=np.sqrt(along @ covariance @ along), fmt="o", ms=3, color="k",
                         lw=0.8, capsize=2)
        axes[1].errorbar(o.speed, _phase(ratio),
                         yerr=np.degrees(np.sqrt(across @ covariance @ across) / abs(ratio)), fmt="o", ms=3,
                         color="k", lw=0.8, capsize=2)
    axes[0].plot([], [], "o", color="k", ms=3, label="measured (1 std)")
    units = [SIGNAL_UNITS.get(signal, "?") for signal in signals]
    axes[0].set_ylabel(f"|{signals[0]} / {signals[1]}| [{units[0]} per {units[1]}]")
    axes[1].set_ylabel("phase [deg], in (-360, 0]")
    axes[1].set_xlabel("measured speed [m/s]")
    for axis in axes:
        axis.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    figure.suptitle("Weave mode shape: measurements and models")
    figure.tight_layout()
    return figure


def plot_time_overlay(report: DiagnosisReport, count: int = 4) -> Figure:
    """Measured roll rate of a few windows across speed, explained by each model's eigenvalue."""
    used = [m for m in report.used if m.fit is not None]
    order = np.argsort([m.speed.mean if m.speed else 0.0 for m in used])
    picks = [used[i] for i in order[np.linspace(0, len(order) - 1, min(count, len(order))).astype(int)]]
    figure = Figure(figsize=(7.5, 2.0 * len(picks) + 0.5))
    axes = figure.subplots(len(picks), 1, squeeze=False)
    for axis, m in zip(axes[:, 0], picks, strict=True):
        fit = m.fit
        assert fit is not None
        index = report.used.index(m)
        o = report.observations[index]
        axis.plot(fit.time, fit.measured[0], color="k", lw=1, label="measured")
        for name, prediction, colour in (("base", report.base_prediction, "C0"),
                                         ("extended", report.extended_prediction, "C3")):
            if name == "extended" and report.diagnosis.best is None:
                continue
            eigenvalue = complex(prediction.eigenvalues[index])
            curve = response_with_eigenvalue(fit.time, fit.measured, eigenvalue, fit.baseline)[0]
            axis.plot(fit.time, curve, color=colour, lw=1.2, label=f"{name} model ({eigenvalue.real:.2f}"
                      f"{eigenvalue.imag:+.2f}i)")
        axis.set_title(f"{m.run.name}, {o.speed:.2f} m/s", fontsize=9)
        axis.set_ylabel("roll rate [rad/s]")
        axis.legend(fontsize=7, loc="upper right")
    axes[-1, 0].set_xlabel("time [s]")
    figure.suptitle("Roll rate of windows across speed, explained by each model's weave eigenvalue [1/s]",
                    fontsize=10)
    figure.tight_layout()
    return figure


def plot_ranking(report: DiagnosisReport, count: int = 10) -> Figure:
    """Evidence of the best-supported causes (and none at 0)."""
    ranking = report.diagnosis.ranking()[:count]
    width = max([len(cause) for cause, _ in ranking] + [20])
    figure = Figure(figsize=(5 + 0.07 * width, 0.35 * len(ranking) + 1.7))
    axis = figure.subplots()
    names = [cause for cause, _ in ranking][::-1]
    values = [evidence for _, evidence in ranking][::-1]
    leading = report.diagnosis.cause
    axis.barh(names, values, color=["C3" if n == leading else "0.6" for n in names])
    axis.axvline(0.0, color="k", lw=0.8)
    axis.set_xlabel("evidence (natural-log Bayes factor against the base model)")
    figure.legend(handles=[Patch(color="C3", label=f"leading cause (verdict: {report.diagnosis.verdict})"),
                           Patch(color="0.6", label="other candidates; none: the base model, at 0")],
                  loc="lower center", ncols=2, fontsize=7, frameon=False)
    axis.set_title("Candidate causes ranked by evidence", fontsize=10)
    figure.tight_layout(rect=(0.0, 0.3 / figure.get_figheight(), 1.0, 1.0))
    return figure


def plot_gain(report: DiagnosisReport) -> Figure:
    """RMS and median weave-eigenvalue error on each held-out speed, base and extended model."""
    gain = report.gain
    figure = Figure(figsize=(7, 3.2))
    axes = figure.subplots(1, 2, sharey=True)
    if gain is None:
        return figure
    positions = np.arange(len(gain.speeds))
    labels = [f"{s.speed:.2f}" for s in gain.speeds]
    for axis, (title, base, extended) in zip(axes, (
            ("RMS", [s.base_rms for s in gain.speeds], [s.extended_rms for s in gain.speeds]),
            ("median", [s.base_median for s in gain.speeds], [s.extended_median for s in gain.speeds])),
            strict=True):
        axis.bar(positions - 0.2, base, 0.4, color="0.6", label="base model")
        axis.bar(positions + 0.2, extended, 0.4, color="C3", label="extended without this speed")
        axis.set_xticks(positions, labels)
        axis.set_xlabel("held-out speed [m/s]")
        axis.set_title(f"{title} |measured - predicted|", fontsize=9)
    axes[0].set_ylabel("weave eigenvalue error [1/s]")
    axes[0].legend(fontsize=7)
    figure.suptitle("Held-out gain: each speed predicted by a model fitted without it", fontsize=10)
    figure.tight_layout()
    return figure


def report_figures(report: DiagnosisReport) -> dict[str, Figure]:
    """Return every figure of the report by key.

    The keys are eigenvalues, residuals, time and ranking, where mode shapes were compared
    shapes, and with a held-out gain, gain.
    """
    makers = {"eigenvalues": plot_eigenvalues, "residuals": plot_residuals, "time": plot_time_overlay,
              "ranking": plot_ranking}
    if report.diagnosis.n_shapes:
        makers["shapes"] = plot_mode_shapes
    if report.gain is not None and report.gain.speeds:
        makers["gain"] = plot_gain
    return {key: make(report) for key, make in makers.items()}
