"""The held-out gain in words and as JSON: what the report and the command line say of it."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from whipple.diagnosis.fitting import CauseFit
from whipple.diagnosis.gain import HELPS, CauseGain, Gain


def gain_json(gain: Gain) -> dict[str, Any]:
    """Return the held-out gain as JSON: overall and per held-out speed."""
    return {
        "metric": "median " + gain.metric, "base": gain.base, "extended": gain.extended,
        "rms": {"metric": "rms " + gain.metric, "base": gain.base_rms, "extended": gain.extended_rms,
                "cut": gain.cut},
        "held_out": gain.held_out, "held_out_by": gain.held_out_by, "folds": gain.folds,
        "cause_chosen_per_fold": gain.reselected,
        "per_speed": [{"speed": s.speed, "windows": s.windows, "cause": s.cause, "verdict": s.verdict,
                       "values": list(s.values), "base_rms": s.base_rms, "extended_rms": s.extended_rms,
                       "base_median": s.base_median, "extended_median": s.extended_median, "rms_cut": s.cut,
                       "helps": s.helps} for s in gain.speeds],
        "not_helped": [s.speed for s in gain.not_helped()],
        "time_domain": {"metric": "median over held-out windows of rms roll-rate residual / window rms",
                        "base": gain.time_base, "extended": gain.time_extended}}


def cause_gains_json(gains: Sequence[CauseGain]) -> list[dict[str, Any]]:
    """Return every candidate's held-out gain as JSON, best first."""
    return [{"cause": g.cause, "parameters": list(g.parameters), "units": list(g.units),
             "rms": {"base": g.gain.base_rms, "extended": g.gain.extended_rms, "cut": g.gain.cut},
             "median": {"base": g.gain.base, "extended": g.gain.extended}, "folds_at_bound": g.at_bound,
             "per_speed": [{"speed": s.speed, "values": list(s.values), "extended_rms": s.extended_rms,
                            "rms_cut": s.cut} for s in g.gain.speeds]} for g in gains]


def cause_gain_sentences(gains: Sequence[CauseGain], chosen: Gain | None, predicted: Gain | None = None,
                         fit: CauseFit | None = None) -> list[str]:
    """Say what the best candidates gain on held-out speeds, against the choices made per fold."""
    if not gains:
        return []
    best = gains[0]
    bound = f"; values at a bound in {best.at_bound} of {best.gain.folds} folds" if best.at_bound else ""
    lines = [f"the best of {len(gains)} candidate models, each refitted on every fold without a choice, is "
             f"{best.cause}: RMS {best.gain.base_rms:.2f} -> {best.gain.extended_rms:.2f} 1/s "
             f"({100 * best.gain.cut:+.0f}% cut; per speed " + ", ".join(
                 f"{100 * s.cut:+.0f}%" for s in best.gain.speeds) + f"){bound}"]
    if chosen is not None:
        lines.append(f"the diagnosis' own choice, made again on each fold: RMS cut {100 * chosen.cut:+.0f}%; "
                     "picking the best candidate by these figures has seen every speed, so its cut is an upper "
                     "bound, not a held-out gain")
    if predicted is not None:
        lines.append(f"chosen by prediction instead (each fold picks the candidate whose refits best predict its own "
                     f"training speeds left out in turn, a choice that never sees the held-out speed), RMS "
                     f"{predicted.base_rms:.2f} -> {predicted.extended_rms:.2f} 1/s ({100 * predicted.cut:+.0f}% cut; "
                     "per speed " + ", ".join(f"{s.speed:.2f} m/s {s.cause} {100 * s.cut:+.0f}%"
                                             for s in predicted.speeds) + ")")
    if fit is not None:
        lines.append(f"fitted to all speeds, {fit.cause} takes " + ", ".join(
            f"{name} = {value:.4g}{' ' + unit if unit else ''}"
            for name, value, unit in zip(fit.parameters, fit.values, fit.units, strict=True)))
    return lines


def gain_sentences(gain: Gain) -> list[str]:
    """Say per held-out speed whether the extended model helps, and overall, in plain words."""
    if gain.held_out_by == "window":
        return [f"one speed only: the gain is over {gain.folds} windows left out in turn, not over speeds (it says "
                f"how well the model fits this speed's other windows, not how it predicts another speed): RMS "
                f"{gain.base_rms:.2f} -> {gain.extended_rms:.2f} 1/s ({100 * gain.cut:+.0f}% cut), median "
                f"{gain.base:.2f} -> {gain.extended:.2f} 1/s"]
    lines = [f"overall on {gain.folds} held-out speeds: RMS {gain.base_rms:.2f} -> {gain.extended_rms:.2f} 1/s "
             f"({100 * gain.cut:+.0f}% cut), median {gain.base:.2f} -> {gain.extended:.2f} 1/s"]
    worse = [s for s in gain.speeds if s.cut < 0]
    flat = [s for s in gain.not_helped() if s.cut >= 0]
    if worse:
        lines.append("the extended model is worse than the base model at " + ", ".join(
            f"{s.speed:.2f} m/s (RMS {s.base_rms:.2f} -> {s.extended_rms:.2f} 1/s)" for s in worse))
    if flat:
        lines.append(f"it does not help (RMS cut below {100 * HELPS:.0f}%) at " + ", ".join(
            f"{s.speed:.2f} m/s ({100 * s.cut:.0f}%)" for s in flat))
    if not worse and not flat:
        lines.append(f"it cuts the RMS error by at least {100 * HELPS:.0f}% at every held-out speed")
    return lines
