"""The diagnosis report: what the model gets wrong, the cause, the extended model, the gain.

Assembles the pieces (measurements, diagnosis, held-out gain, critical speeds) into plain data,
the JSON of the shared spec ``diagnosis-report.md`` and a Markdown report.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from whipple.causes import Cause, candidate_causes, with_cause
from whipple.critical import CriticalSpeeds, critical_speeds
from whipple.diagnosis import (
    EIGENVALUE_FLOOR,
    MARGIN,
    NAMED_THRESHOLD,
    ROBUST_SCALE,
    Diagnosis,
    Gain,
    Observation,
    compared_shapes,
    diagnose_observations,
    held_out_gain,
    predicted_modes,
    predicted_weave,
    speed_groups,
)
from whipple.errors import AnalysisError, InputError
from whipple.experiment import WindowMeasurement, observation
from whipple.model import extended_matrices, linear_model
from whipple.parameters import Bicycle

EVIDENCE_DEFINITION = (
    "approximate natural-log Bayes factor of the cause against the base model: "
    "(chi2_base - chi2_cause) / 2 - (k/2) ln(n) + ln(prior), with chi2 a soft-L1 sum (scale "
    f"{ROBUST_SCALE}) of squared whitened residuals of the weave eigenvalue (its covariance with a floor of "
    f"{100 * EIGENVALUE_FLOOR:g}% of |eigenvalue| for the fitting function's bias) and, where a steer signal was "
    "measured, of the weave mode shape (steer per roll rate), each kind divided by its own s^2 >= 1, "
    "the best model's reduced chi2 on that kind; n residuals, k fitted values, "
    "prior 1 per named cause (shared by its forms) and "
    f"1/(number of parameters) per parameter:<key>; 'named' needs evidence >= {NAMED_THRESHOLD} "
    f"and a lead of {MARGIN} over the runner-up")


@dataclass(frozen=True)
class DiagnosisReport:
    """Everything the report shows."""

    bicycle: Bicycle
    measurements: tuple[WindowMeasurement, ...]
    used: tuple[WindowMeasurement, ...]
    diagnosis: Diagnosis
    extended: Bicycle
    cause: Cause | None
    gain: Gain | None
    gain_note: str
    base_critical: CriticalSpeeds
    extended_critical: CriticalSpeeds
    residual_summary: tuple[str, ...]
    baseline: str


def describe_residuals(observations: Sequence[Observation], predicted: np.ndarray) -> tuple[str, ...]:
    """Sentences on how measured weave eigenvalues differ from a model's, over speed."""
    lines = []
    frequency_errors, damping_errors, damping_noise = [], [], []
    for group in speed_groups(observations):
        measured = np.array([observations[i].eigenvalue for i in group])
        model = predicted[group]
        std = np.array([np.sqrt(np.diag(observations[i].covariance)) for i in group])
        # Where the model has no oscillation near the measured one, the frequency is compared
        # with the eigenvalue's magnitude instead.
        relative = (measured.imag - model.imag) / np.maximum(np.abs(model.imag), np.abs(model))
        damping = measured.real - model.real
        # Standard error of the group mean from the scatter (at least the stated uncertainty).
        se_d = max(np.std(damping, ddof=1) / np.sqrt(len(group)) if len(group) > 1 else 0.0,
                   float(np.sqrt(np.mean(std[:, 0] ** 2) / len(group))))
        speeds = [observations[i].speed for i in group]
        frequency_errors.append(float(np.mean(relative)))
        damping_errors.append(float(np.mean(damping)))
        damping_noise.append(se_d)
        lines.append(f"at {np.mean(speeds):.2f} m/s ({len(group)} windows): frequency "
                     f"{100 * np.mean(relative):+.0f}%, real part {np.mean(damping):+.2f} +/- {se_d:.2f} 1/s "
                     "(measured minus model)")
    f = np.array(frequency_errors)
    summary = []
    if np.all(np.abs(f) < 0.03):
        summary.append("frequency within 3% of the model at all speeds")
    elif np.all(f < 0) or np.all(f > 0):
        side = "low" if f[0] < 0 else "high"
        summary.append(f"frequency {100 * np.min(np.abs(f)):.0f}-{100 * np.max(np.abs(f)):.0f}% {side} at all speeds")
    else:
        summary.append(f"frequency off by {100 * np.min(f):+.0f}% to {100 * np.max(f):+.0f}% depending on speed")
    d, noise = np.array(damping_errors), np.array(damping_noise)
    if np.all(np.abs(d) <= 2 * noise):
        summary.append("damping within noise")
    else:
        more = d < -2 * noise
        less = d > 2 * noise
        parts = []
        if more.any():
            parts.append(f"more damped than the model at {int(more.sum())} of {len(d)} speeds")
        if less.any():
            parts.append(f"less damped at {int(less.sum())} of {len(d)} speeds")
        summary.append("measured weave " + " and ".join(parts)
                       + f" (real part differences {np.min(d):+.2f} to {np.max(d):+.2f} 1/s)")
    return tuple(["; ".join(summary)] + lines)


def shape_ratios(bicycle: Bicycle, observations: Sequence[Observation]) -> tuple[np.ndarray, tuple[str, str]]:
    """Measured over model mode shape, for the windows whose shapes are compared, and the
    shape's two signals (those of the first such window)."""
    shapes = predicted_modes(bicycle, observations)[1]
    index = [int(n) for n in np.flatnonzero(compared_shapes(bicycle, observations)) if np.isfinite(shapes[n])]
    signals = observations[index[0]].shape_signals if index else observations[0].shape_signals
    return np.array([complex(observations[n].shape or 0.0) / shapes[n] for n in index], dtype=complex), signals


def describe_mode_shapes(ratios: np.ndarray, signals: tuple[str, str]) -> str | None:
    """A sentence on how the measured mode shapes differ from a model's (``ratios``: measured
    over model, see :func:`shape_ratios`); None without shapes."""
    if ratios.size == 0:
        return None
    magnitude, phase = 100 * (np.abs(ratios) - 1), np.degrees(np.angle(ratios))
    # Standard error of the median-ish summary from the scatter between windows.
    se_magnitude = 1.2533 * np.std(magnitude, ddof=1) / np.sqrt(ratios.size) if ratios.size > 1 else np.inf
    se_phase = 1.2533 * np.std(phase, ddof=1) / np.sqrt(ratios.size) if ratios.size > 1 else np.inf
    size, angle = float(np.median(magnitude)), float(np.median(phase))
    within = abs(size) <= 2 * se_magnitude and abs(angle) <= 2 * se_phase
    verdict = "within noise" if within else "off"
    return (f"weave mode shape ({signals[0]} per {signals[1]}, {ratios.size} windows) {verdict}: magnitude "
            f"{size:+.0f}% +/- {se_magnitude:.0f}%, phase {angle:+.1f} +/- {se_phase:.1f} deg (median, measured "
            "relative to model)")


def assemble(bicycle: Bicycle, measurements: Sequence[WindowMeasurement], baseline: str = "auto",
             include_parameters: bool = True, speed_range: tuple[float, float] = (0.0, 10.0)) -> DiagnosisReport:
    """Diagnose the usable windows of ``measurements`` against ``bicycle`` and measure the gain."""
    used = tuple(m for m in measurements if m.usable)
    if len(used) < 2:
        raise InputError(f"only {len(used)} usable window(s) with a fitted weave eigenvalue; need at least 2")
    observations = [observation(m) for m in used]
    causes = candidate_causes(bicycle, include_parameters)
    diagnosis = diagnose_observations(bicycle, observations, causes)
    chosen = None
    if diagnosis.best is not None:
        forms = [c for c in causes if c.name == diagnosis.best.cause]
        chosen = max(forms, key=lambda c: len(c.parameters))
    extended = with_cause(bicycle, chosen, diagnosis.best.values) if chosen and diagnosis.best else bicycle
    gain, note = None, ""
    if chosen is not None:
        series = [(m.fit.time, m.fit.measured, m.fit.baseline) for m in used if m.fit is not None]
        try:
            gain = held_out_gain(bicycle, chosen, observations, series)
        except AnalysisError as error:
            note = str(error)
    else:
        note = "no cause named: nothing to extend"
    summary = describe_residuals(observations, predicted_weave(bicycle, observations))
    shape_summary = describe_mode_shapes(*shape_ratios(bicycle, observations))
    if shape_summary is not None:
        summary += (shape_summary,)
    return DiagnosisReport(
        bicycle, tuple(measurements), used, diagnosis, extended, chosen, gain, note,
        critical_speeds(linear_model(bicycle), *speed_range), critical_speeds(linear_model(extended), *speed_range),
        summary, baseline)


#: Reduced chi-square of the best model above which the report warns that no candidate
#: explains the data within the stated uncertainty.
DISPERSION_WARNING = 2.0
#: Causes within this much evidence of the named one are listed as close alternatives.
CLOSE_EVIDENCE = 5.0


#: Median phase difference between measured and model mode shapes beyond which the report
#: suspects a steer signal of the opposite sign [deg].
FLIPPED_PHASE = 120.0


def caveats(report: DiagnosisReport) -> list[str]:
    """What the verdict does not say: residual misfit, close alternatives, a suspect steer sign."""
    diagnosis = report.diagnosis
    notes = []
    ratios, signals = shape_ratios(report.bicycle, diagnosis.observations)
    # Median phase of measured over model shape [deg].
    offset = np.degrees(np.angle(np.median(ratios.real) + 1j * np.median(ratios.imag))) if ratios.size else 0.0
    if abs(offset) > FLIPPED_PHASE:
        notes.append(f"the measured {signals[0]} is {abs(offset):.0f} degrees out of phase with the model's mode "
                     f"shape: its sign is probably opposite to the convention of Meijaard et al. (2007) (check the "
                     "layout's scale factor); the mode shapes then carry little weight in the evidence")
    if diagnosis.scale > DISPERSION_WARNING:
        notes.append(f"even the best-fitting model leaves eigenvalue residuals {np.sqrt(diagnosis.scale):.1f} times "
                     f"the stated uncertainties (reduced chi2 {diagnosis.scale:.1f}): the verdict ranks the "
                     "candidates, but none explains all of the disagreement")
    if diagnosis.shape_scale > DISPERSION_WARNING:
        notes.append(f"the best-fitting model leaves mode-shape residuals {np.sqrt(diagnosis.shape_scale):.1f} "
                     f"times their stated uncertainties (reduced chi2 {diagnosis.shape_scale:.1f}); they count "
                     "correspondingly less in the evidence")
    if diagnosis.best is not None:
        close = [f"{fit.cause} ({fit.evidence:.1f})" for fit in diagnosis.fits[1:]
                 if fit.evidence > diagnosis.best.evidence - CLOSE_EVIDENCE]
        if close:
            notes.append(f"close alternatives to {diagnosis.best.cause} ({diagnosis.best.evidence:.1f}): "
                         + ", ".join(close))
    return notes


def _pair(value: complex) -> list[float]:
    return [float(value.real), float(value.imag)]


def _critical(critical: CriticalSpeeds) -> dict[str, Any]:
    return {"weave_speed": critical.weave_speed, "capsize_speed": critical.capsize_speed,
            "stable_speed_ranges": [list(r) for r in critical.stable_speed_ranges]}


def report_json(report: DiagnosisReport) -> dict[str, Any]:
    """The JSON object of the shared spec diagnosis-report.md (and more)."""
    diagnosis = report.diagnosis
    best = diagnosis.best
    estimate = {}
    if best is not None:
        estimate = {name: {"value": value, "std": std, "unit": unit}
                    for name, value, std, unit in zip(best.parameters, best.values, best.std, best.units, strict=True)}
    observations = diagnosis.observations
    base, base_shapes = predicted_modes(report.bicycle, observations)
    extended, extended_shapes = predicted_modes(report.extended, observations)
    compared = compared_shapes(report.bicycle, observations)
    windows = []
    for n, (m, o) in enumerate(zip(report.used, observations, strict=True)):
        window = {"run": o.run, "start": o.start, "stop": o.stop, "speed": list(o.speed_range),
                  "speed_mean": o.speed, "eigenvalue": _pair(o.eigenvalue),
                  "eigenvalue_std": [float(np.sqrt(o.covariance[0, 0])), float(np.sqrt(o.covariance[1, 1]))],
                  "model_eigenvalue": _pair(base[n]), "extended_eigenvalue": _pair(extended[n]),
                  "r_squared": m.fit.r_squared if m.fit else None}
        if o.shape is not None and o.shape_covariance is not None and np.isfinite(base_shapes[n]):
            window["mode_shape"] = {
                "signals": list(o.shape_signals), "value": _pair(o.shape),
                "std": [float(np.sqrt(o.shape_covariance[0, 0])), float(np.sqrt(o.shape_covariance[1, 1]))],
                "model": _pair(base_shapes[n]), "extended": _pair(extended_shapes[n]),
                "compared": bool(compared[n])}
        windows.append(window)
    skipped = [{"run": m.run.name, "start": m.window.start, "stop": m.window.stop, "reason": m.skipped}
               for m in report.measurements if not m.usable]
    gain: dict[str, Any] | None = None
    if report.gain is not None:
        g = report.gain
        gain = {"metric": g.metric, "base": g.base, "extended": g.extended, "held_out": g.held_out,
                "folds": g.folds,
                "time_domain": {"metric": "median over held-out windows of rms roll-rate residual / window rms",
                                "base": g.time_base, "extended": g.time_extended}}
    result: dict[str, Any] = {
        "cause": diagnosis.cause,
        "verdict": diagnosis.verdict,
        "estimate": estimate,
        "ranking": [{"cause": cause, "evidence": evidence} for cause, evidence in diagnosis.ranking()],
        "gain": gain,
        "gain_note": report.gain_note,
        "windows": windows,
        "skipped_windows": skipped,
        "summary": list(report.residual_summary),
        "caveats": caveats(report),
        "evidence_definition": EVIDENCE_DEFINITION,
        "dispersion": diagnosis.scale,
        "dispersion_mode_shape": diagnosis.shape_scale,
        "mode_shape_windows": diagnosis.n_shapes,
        "bicycle": report.bicycle.name,
        "base_model": _critical(report.base_critical),
        "extended_model": _critical(report.extended_critical),
        "fit_baseline": report.baseline,
    }
    if report.bicycle.extensions.tyre_compliance is None and report.extended.extensions.tyre_compliance is None:
        matrices = extended_matrices(report.extended.parameters, report.extended.extensions)
        result["extended_model"]["matrices"] = {name: getattr(matrices, name).tolist()
                                                for name in ("M", "C1", "D", "K0", "K2")}
    return result


def _speeds_text(critical: CriticalSpeeds) -> str:
    ranges = ", ".join(f"{low:.3f}-{high:.3f}" for low, high in critical.stable_speed_ranges) or "none"
    weave = "none" if critical.weave_speed is None else f"{critical.weave_speed:.3f} m/s"
    capsize = "none" if critical.capsize_speed is None else f"{critical.capsize_speed:.3f} m/s"
    return f"weave speed {weave}, capsize speed {capsize}, stable speed ranges (m/s): {ranges}"


def report_markdown(report: DiagnosisReport, figures: dict[str, str], command: str = "") -> str:
    """The human-readable report; ``figures`` maps figure keys to file names beside it."""
    data = report_json(report)
    diagnosis = report.diagnosis
    lines = [f"# Diagnosis of {report.bicycle.name or 'the bicycle'}", ""]
    if command:
        lines += [f"Produced by `{command}`.", ""]
    lines += [f"{len(report.used)} windows with a fitted weave eigenvalue were used "
              f"({len(report.measurements) - len(report.used)} skipped, listed at the end), from "
              f"{len({m.run.name for m in report.measurements})} runs.", "",
              "## 1. What the model gets wrong", "", f"**{report.residual_summary[0]}.**", ""]
    lines += [f"- {line}" for line in report.residual_summary[1:]]
    lines += ["", f"![eigenvalues]({figures['eigenvalues']})", "", f"![residuals]({figures['residuals']})", ""]
    if "shapes" in figures:
        lines += ["Mode shape: the steer angle's amplitude and phase relative to the roll rate in each window "
                  "whose eigenvalue a weave of the base model matches:", "", f"![mode shapes]({figures['shapes']})", ""]
    lines += ["Time domain: each window explained by the model's weave eigenvalue (amplitude, phase and "
              "baseline fitted):", "", f"![time domain]({figures['time']})", "", "## 2. The cause", ""]
    verdict = {"named": f"The cause is **{diagnosis.cause}**: it clearly beats the base model and the runner-up.",
               "ambiguous": f"**Ambiguous**: {diagnosis.cause} explains the data best, but the runner-up about "
                            "as well; the evidence does not single out one cause.",
               "none": "**None**: no cause explains the data clearly better than the base model."}[diagnosis.verdict]
    lines += [verdict, ""]
    lines += [f"- Caveat: {note}." for note in data["caveats"]]
    lines += ["", "| cause | evidence |", "|---|---|"]
    lines += [f"| {cause} | {evidence:.1f} |" for cause, evidence in diagnosis.ranking()[:12]]
    lines += ["", f"Evidence: {EVIDENCE_DEFINITION}. Dispersion (reduced chi2 of the best model): "
              f"{diagnosis.scale:.2f} for eigenvalues, {diagnosis.shape_scale:.2f} for mode shapes "
              f"({diagnosis.n_shapes} windows with a shape).", "", f"![ranking]({figures['ranking']})", "",
              "## 3. The extended model", ""]
    if diagnosis.best is not None:
        lines += ["| parameter | value | std | unit |", "|---|---|---|---|"]
        lines += [f"| {name} | {e['value']:.6g} | {e['std']:.3g} | {e['unit']} |"
                  for name, e in data["estimate"].items()]
        lines += ["", f"- base model: {_speeds_text(report.base_critical)}",
                  f"- extended model: {_speeds_text(report.extended_critical)}"]
        if "matrices" in data["extended_model"]:
            lines += ["", "Extended equations, M q'' + (v C1 + D) q' + (K0 + v^2 K2) q = f (from the generated "
                      "code of derivation/, model whipple_extended):", ""]
            for name, matrix in data["extended_model"]["matrices"].items():
                lines.append(f"- {name} = [[{matrix[0][0]:.6g}, {matrix[0][1]:.6g}], "
                             f"[{matrix[1][0]:.6g}, {matrix[1][1]:.6g}]]")
        else:
            lines += ["", "Extended equations: the tyre-compliance model of derivation/tyre.py "
                      "(generated/tyre_numpy.py, descriptor form E x' = (A0 + v A1) x + B f)."]
    else:
        lines += ["No extension: the base model stands.", f"- base model: {_speeds_text(report.base_critical)}"]
    lines += ["", "## 4. The gain", ""]
    if report.gain is not None:
        g = report.gain
        lines += [f"Leave-one-speed-out ({g.folds} folds): the cause is refitted without each speed and "
                  "predicts it.", "", "| metric | base | extended |", "|---|---|---|",
                  f"| {g.metric} | {g.base:.3f} | {g.extended:.3f} |"]
        if g.time_base is not None and g.time_extended is not None:
            lines.append("| median rms roll-rate residual / window rms (held out) | "
                         f"{g.time_base:.3f} | {g.time_extended:.3f} |")
    else:
        lines.append(report.gain_note or "No gain computed.")
    skipped = data["skipped_windows"]
    if skipped:
        lines += ["", "## Skipped windows", "", "| run | start [s] | stop [s] | reason |", "|---|---|---|---|"]
        lines += [f"| {s['run']} | {s['start']:.2f} | {s['stop']:.2f} | {s['reason']} |" for s in skipped]
    return "\n".join(lines) + "\n"
