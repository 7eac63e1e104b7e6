"""The diagnosis report in Markdown, for people.

What the model gets wrong, the cause, the extended model and the gain, with the figures
beside it.
"""

from __future__ import annotations

from whipple.diagnosis.amplitude import amplitude_markdown
from whipple.diagnosis.estimate_text import bounds_text
from whipple.diagnosis.evidence import Diagnosis
from whipple.diagnosis.gain import Gain
from whipple.diagnosis.gain_text import cause_gain_sentences, gain_sentences
from whipple.diagnosis.report import DiagnosisReport, evidence_definition, report_json
from whipple.stability.critical import CriticalSpeeds


def _speeds(critical: CriticalSpeeds) -> str:
    """Return the critical speeds' summary in one line."""
    return "; ".join(" ".join(line.split()) for line in critical.summary())


#: How the models were compared with the windows, by ``Diagnosis.comparison``.
_COMPARISON = {"samples": "Each model was compared with the windows' samples: its free response at each window's "
                          "speed, with its modal amplitudes and each signal's offset fitted, each signal weighed by "
                          "its noise (from its second differences).",
               "fitting-function": "Each model was compared with the windows through the fitting function: its "
                                   "weave eigenvalue plus the bias the window's fit shows on the model's own "
                                   "response.",
               "eigenvalues": "Each model's weave eigenvalue was compared with the windows' fitted eigenvalues "
                              "directly."}


def _dispersions(diagnosis: Diagnosis, typical: bool) -> str:
    """Return the dispersions in words: of the typical window of the best single cause, or the best model's."""
    first, second = diagnosis.single_scales if typical else (diagnosis.dispersion, diagnosis.shape_scale)
    digits = 1 if typical else 2
    if diagnosis.comparison == "samples":
        correlated = "" if typical or diagnosis.correlation == 1.0 else (
            f", times {diagnosis.correlation:.2f} for the residual's correlation in time")
        return f"{first:.{digits}f} for the samples{correlated}"
    shapes = "" if typical else f" ({diagnosis.n_shapes} windows with a shape)"
    return f"{first:.{digits}f} for eigenvalues, {second:.{digits}f} for mode shapes{shapes}"


def _fitted_to(report: DiagnosisReport) -> str:
    """Return the signals the first used window was fitted to, as a clause ("" without one)."""
    fit = next((m.fit for m in report.used if m.fit is not None), None)
    if fit is None:
        return ""
    listed = " and ".join(name.replace("_", " ") for name in fit.signal_names)
    return f"; each window's eigenvalue fitted to the {listed}" + (" jointly" if len(fit.signal_names) > 1 else "")


def report_markdown(report: DiagnosisReport, figures: dict[str, str], command: str = "") -> str:
    """Return the human-readable report; ``figures`` maps figure keys to file names beside it."""
    data = report_json(report)
    diagnosis = report.diagnosis
    lines = [f"# Diagnosis of {report.bicycle.name or 'the bicycle'}", ""]
    if command:
        lines += [f"Produced by `{command}`.", ""]
    lines += [f"{len(report.used)} windows with a fitted weave eigenvalue were used "
              f"({len(report.measurements) - len(report.used)} skipped, listed at the end), from "
              f"{len({m.run.name for m in report.measurements})} runs{_fitted_to(report)}.", "",
              "## 1. What the model gets wrong", "", f"**{report.residual_summary[0]}.**", ""]
    lines += [f"- {line}" for line in report.residual_summary[1:]]
    lines += ["", f"![eigenvalues]({figures['eigenvalues']})", "", f"![residuals]({figures['residuals']})", ""]
    if "shapes" in figures:
        lines += ["Mode shape: the steer angle's amplitude and phase relative to the roll rate in each window "
                  "whose eigenvalue a weave of the base model matches:", "", f"![mode shapes]({figures['shapes']})", ""]
    lines += ["Time domain: each window explained by the model's weave eigenvalue (amplitude, phase and "
              "baseline fitted):", "", f"![time domain]({figures['time']})", "", "## 2. The cause", ""]
    verdict = {"named": f"The cause is **{diagnosis.cause}**: it clearly beats the base model and the runner-up, "
                        "and its predictions are distinguishable from theirs.",
               "ambiguous": f"**Ambiguous**: what the data support is **{diagnosis.family}**; {diagnosis.cause} "
                            "fits best, but the evidence does not single it out:",
               "none": "**None**: no cause explains the data clearly better than the base model."}[diagnosis.verdict]
    lines += [verdict, ""]
    lines += [f"- {reason}." for reason in diagnosis.reasons]
    if diagnosis.combinations:
        typical = _dispersions(diagnosis, True)
        lines += [f"- No single cause explained the typical window (median dispersion {typical}): pairs were fitted "
                  f"jointly, charged for their extra values: {', '.join(diagnosis.combinations)}."]
    lines += [f"- Caveat: {note}." for note in data["caveats"]]
    lines += ["", "| cause | evidence |", "|---|---|"]
    lines += [f"| {cause} | {evidence:.1f} |" for cause, evidence in diagnosis.ranking()[:12]]
    definition = evidence_definition(diagnosis.comparison, report.options)
    lines += ["", f"Evidence: {definition}. Dispersion (reduced chi2 of the best "
              f"model): {_dispersions(diagnosis, False)}. {_COMPARISON[diagnosis.comparison]}", "",
              f"![ranking]({figures['ranking']})", "",
              "## 3. The extended model", ""]
    if diagnosis.best is not None:
        offered = data["offered"]
        if offered is not None and offered["cause"] != diagnosis.best.cause:
            how = ("the simplest consistent candidate that predicts the speeds left out in turn within "
                   f"{report.options.prediction_standard_errors:g} standard error(s) of the best predictor"
                   if offered["chosen_by"] == "prediction" else "the best-supported physically consistent candidate")
            lines += [f"The model offered is **{offered['cause']}**, {how} (see the caveats above):", "",
                      "| parameter | value | unit |", "|---|---|---|"]
            lines += [f"| {name} | {e['value']:.6g} | {e['unit']} |" for name, e in offered["values"].items()]
            if report.open_values is not None:
                lines += ["", f"The data leave open: {report.open_values.sentence()}."]
            lines += ["", f"The leading cause, {diagnosis.best.cause}, not offered:", ""]
        elif offered is None:
            lines += ["No model is offered (the base model stands; see the caveats above). The leading cause:", ""]
        lines += ["| parameter | value | std | unit |", "|---|---|---|---|"]
        lines += [f"| {name} | {e['value']:.6g} | {_std_text(e)} | {e['unit']} |"
                  for name, e in data["estimate"].items()]
        if report.open_values is not None and (offered is None or offered["cause"] == diagnosis.best.cause):
            lines += ["", f"The data leave open: {report.open_values.sentence()}."]
        lines += _prediction_table(data["offer_predictions"], report.options.prediction_standard_errors,
                                   offered["cause"] if offered is not None else "none")
        lines += ["", f"- base model: {_speeds(report.base_critical)}",
                  f"- extended model: {_speeds(report.extended_critical)}"]
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
        lines += ["No extension: the base model stands.", f"- base model: {_speeds(report.base_critical)}"]
    lines += ["", "## 4. The gain", ""]
    if report.gain is not None:
        g = report.gain
        how = ("the cause is chosen again among all candidates and fitted on the other speeds only"
               if g.reselected else "the cause is refitted on the other speeds only")
        lines += [f"Each speed is left out in turn ({g.folds} folds): {how}, and the model so extended predicts "
                  "the left-out speed. Error |measured - predicted| weave eigenvalue [1/s]:", "", *_gain_table(g), ""]
        lines += [f"- {sentence[0].upper() + sentence[1:]}." for sentence in gain_sentences(g)]
        if "gain" in figures:
            lines += ["", f"![held-out gain]({figures['gain']})", ""]
        if g.time_base is not None and g.time_extended is not None:
            lines.append(f"- Time domain (median rms roll-rate residual / window rms, held out): base "
                         f"{g.time_base:.3f}, extended {g.time_extended:.3f}.")
    else:
        lines.append(report.gain_note or "No gain computed.")
    lines += _cause_gains_markdown(report)
    if report.amplitude is not None:
        lines += ["", *amplitude_markdown(report.amplitude)]
    notes = (data["measurement"] or {}).get("run_notes", {})
    if notes:
        lines += ["", "## How the run files were read", ""]
        lines += [f"- {name}: {note}" for name, run_notes in notes.items() for note in run_notes]
    skipped = data["skipped_windows"]
    if skipped:
        lines += ["", "## Skipped windows", "", "| run | start [s] | stop [s] | reason |", "|---|---|---|---|"]
        lines += [f"| {s['run']} | {s['start']:.2f} | {s['stop']:.2f} | {s['reason']} |" for s in skipped]
    return "\n".join(lines) + "\n"


#: Rows of the every-candidate table in the report (the JSON has all).
CAUSE_GAIN_ROWS = 12


def _std_text(estimate: dict) -> str:
    return f"{estimate['std']:.3g}" if estimate["determined"] else f"not determined ({bounds_text(estimate)})"


def _cause_gains_markdown(report: DiagnosisReport) -> list[str]:
    """Return the lines of every candidate's held-out gain without a choice (when computed), best first."""
    gains = report.cause_gains
    if not gains:
        return []
    speeds = [s.speed for s in gains[0].gain.speeds]
    lines = ["", "### Every candidate on the held-out speeds", "",
             "Each candidate (cause, or pair of causes) refitted on the other speeds of every fold, no choice "
             f"made; RMS cut of |measured - predicted| weave eigenvalue per held-out speed and overall (the best "
             f"{min(CAUSE_GAIN_ROWS, len(gains))} of {len(gains)}; all in the JSON, `cause_gains`):", "",
             "| candidate | " + " | ".join(f"{v:.2f} m/s" for v in speeds) + " | all: RMS | cut | folds at a bound |",
             "|---|" + "---|" * len(speeds) + "---|---|---|"]
    for g in gains[:CAUSE_GAIN_ROWS]:
        lines.append(f"| {g.cause} | " + " | ".join(f"{100 * s.cut:+.0f}%" for s in g.gain.speeds)
                     + f" | {g.gain.base_rms:.2f} -> {g.gain.extended_rms:.2f} | {100 * g.gain.cut:+.0f}% | "
                     f"{g.at_bound} |")
    sentences = cause_gain_sentences(gains, report.gain, report.prediction_gain, report.prediction_fit)
    lines += ["", *(f"- {sentence[0].upper() + sentence[1:]}." for sentence in sentences)]
    if report.prediction_gain is not None:
        lines += ["", "Chosen by prediction, per held-out speed (each fold's choice made on its training speeds "
                  "alone, each left out in turn):", "", *_gain_table(report.prediction_gain)]
    return lines


def _gain_table(gain: Gain) -> list[str]:
    """Return a Markdown table of a held-out gain: per held-out speed and over all."""
    lines = ["| held-out speed [m/s] | windows | cause chosen without it | base RMS | extended RMS | "
             "RMS cut | base median | extended median |", "|---|---|---|---|---|---|---|---|"]
    lines += [f"| {s.speed:.2f} | {s.windows} | {s.cause} | {s.base_rms:.2f} | {s.extended_rms:.2f} | "
              f"{100 * s.cut:+.0f}% | {s.base_median:.2f} | {s.extended_median:.2f} |" for s in gain.speeds]
    lines.append(f"| all | {sum(s.windows for s in gain.speeds)} | | {gain.base_rms:.2f} | {gain.extended_rms:.2f} | "
                 f"{100 * gain.cut:+.0f}% | {gain.base:.2f} | {gain.extended:.2f} |")
    return lines


def _prediction_table(predictions: dict[str, dict[str, float]] | None, standard_errors: float,
                      offered: str) -> list[str]:
    """Return the choice by prediction as a table: each model's error on the speeds left out in turn."""
    if not predictions:
        return []
    lines = ["", f"Chosen by prediction: the simplest model (fewest fitted values) whose mean squared error on the "
             f"speeds left out in turn is within {standard_errors:g} standard error(s) of the best predictor's "
             "(the standard error of the excess over the speeds):", "",
             "| model | fitted values | RMS [1/s] | mean squared error above the best [1/s^2] |", "|---|---|---|---|"]
    for name, p in predictions.items():
        # The best predictor's excess over itself is 0 by definition: say what it is instead.
        excess = ("the best predictor" if p["mse_above_best"] == 0.0 and p["standard_error"] == 0.0
                  else f"{p['mse_above_best']:.3g} +/- {p['standard_error']:.2g}")
        label = f"**{name}** (chosen)" if name == offered else name
        lines.append(f"| {label} | {p['values']} | {p['rms']:.3g} | {excess} |")
    return lines
