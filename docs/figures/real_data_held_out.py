"""Print the held-out numbers of docs/explanation/real-data.md (research log: benchmarks/results/diagnosis-log.md).

Run from anywhere:  python docs/figures/real_data_held_out.py [--no-parameters] [--cycles-above-noise C]
[--fixed-point-start model] [--signals roll_rate]

On the bundled treadmill runs (sbw2024 with its controller):

1. each speed left out in turn, the cause chosen again and fitted on the other speeds only
   (``whipple.diagnosis.gain.held_out_gain``, what the report shows);
2. the earlier figure for comparison: the cause chosen once on all speeds and only refitted
   per fold, summarised by the median over all left-out windows pooled;
3. whole speeds never seen: the diagnosis on alternate speeds (the lowest, middle and highest)
   predicts the two speeds in between, like the three speeds the bundled files leave out of
   the same experiment;
4. for a controlled bicycle, each controller cause fitted on all speeds (to the windows'
   eigenvalues, and to their samples as ``whipple diagnose`` compares them): how much of the
   disagreement at each speed it can explain at best;
5. why the evidence and the held-out prediction disagree: the evidence's leading pair and the
   best predictors of ``--gain-by-cause`` (a payload with a controller delay), each fitted to all
   windows, by kind of residual (robust chi-square at unit dispersion).

``--no-parameters`` restricts the candidates to the physical causes (no ``parameter:<key>``);
``--cycles-above-noise C`` leaves out the windows holding fewer than C weave cycles above the
noise (``FitOptions.min_cycles_above_noise``; default the package's 0.75, 0: the windows before
that check). ``--fixed-point-start model`` is an experiment: the fitting bias' fixed point starts
from each model's weave (``DiagnosisOptions.fixed_point_start``); ``--signals`` the
signals fitted jointly in every window (``whipple diagnose --signals``; by default as ``whipple
diagnose`` chooses: the roll rate with the steer angle, which the bundled runs measure).
Every number is an RMS or median of |measured - predicted| weave eigenvalue [1/s].
"""

from __future__ import annotations

import argparse

import numpy as np

from whipple.cli.measurement_arguments import signal_names
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.families import combined_cause, general_forms
from whipple.diagnosis.fitting import fit_cause, window_whitening
from whipple.diagnosis.gain import held_out_gain
from whipple.diagnosis.observations import observations, predicted_weave, speed_groups
from whipple.diagnosis.options import DiagnosisOptions
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment import MIN_CYCLES_ABOVE_NOISE
from whipple.measurement.measure import MeasurementOptions, measure_runs
from whipple.measurement.runs import read_run
from whipple.model.parameters import load_bicycle


def _line(label: str, base: np.ndarray, extended: np.ndarray) -> str:
    rms_base, rms_extended = np.sqrt(np.mean(base**2)), np.sqrt(np.mean(extended**2))
    return (f"{label}: RMS {rms_base:.2f} -> {rms_extended:.2f} 1/s (cut {100 * (1 - rms_extended / rms_base):+.0f}%), "
            f"median {np.median(base):.2f} -> {np.median(extended):.2f} 1/s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-parameters", action="store_true")
    parser.add_argument("--cycles-above-noise", type=float, default=MIN_CYCLES_ABOVE_NOISE)
    parser.add_argument("--fixed-point-start", choices=("measured", "model"), default="measured")
    parser.add_argument("--signals", type=signal_names, default=None,
                        help="signals fitted jointly (whipple diagnose --signals; default: as it chooses)")
    args = parser.parse_args()
    options = DiagnosisOptions(measurement=MeasurementOptions(signals=args.signals or "auto",
                                                              min_cycles_above_noise=args.cycles_above_noise),
                               parameters=not args.no_parameters, fixed_point_start=args.fixed_point_start)
    bicycle = load_bicycle("sbw2024")
    runs = [read_run(source) for source in bundled_runs()]
    # The windows as whipple diagnose measures them (the one measurement of the package).
    measured = measure_runs(runs, options.measurement, bicycle=bicycle)
    seen = observations(measured.windows)
    causes = options.candidates(bicycle)
    print(f"{len(seen)} windows; {measured.describe()}; "
          f"candidates: {'physical causes only' if args.no_parameters else 'all'}")

    full = diagnose_observations(bicycle, seen, causes, options)
    print(f"all speeds: {full.verdict} ({full.cause}); median dispersion {full.typical_scales[0]:.1f} "
          f"(the comparison's first kind: {full.comparison}), {full.typical_scales[1]:.1f} (mode shapes)")

    print("1. each speed left out, cause chosen again on the others:")
    gain = held_out_gain(bicycle, seen, causes, options=options)
    for s in gain.speeds:
        print(f"   {s.speed:.2f} m/s, {s.windows} windows, {s.cause} chosen: RMS {s.base_rms:.2f} -> "
              f"{s.extended_rms:.2f} (cut {100 * s.cut:+.0f}%), median {s.base_median:.2f} -> {s.extended_median:.2f}")
    print(f"   all: RMS {gain.base_rms:.2f} -> {gain.extended_rms:.2f} (cut {100 * gain.cut:+.0f}%), "
          f"median {gain.base:.2f} -> {gain.extended:.2f}")

    if full.chosen is not None:
        fixed = held_out_gain(bicycle, seen, causes, fixed=full.chosen, options=options)
        print(f"2. earlier figure ({full.cause} chosen on all speeds, refitted per fold): pooled median "
              f"{fixed.base:.2f} -> {fixed.extended:.2f}; RMS {fixed.base_rms:.2f} -> {fixed.extended_rms:.2f} "
              f"(cut {100 * fixed.cut:+.0f}%)")

    groups = speed_groups(seen)
    training = [i for k, group in enumerate(groups) if k % 2 == 0 for i in group]
    held = [i for k, group in enumerate(groups) if k % 2 == 1 for i in group]
    diagnosis = diagnose_observations(bicycle, [seen[i] for i in training], causes, options, estimate_spread=False)
    extended = bicycle
    if diagnosis.chosen is not None and diagnosis.best is not None:
        extended = diagnosis.chosen.apply(bicycle, diagnosis.best.values)
    trained_speeds = ", ".join(f"{np.mean([seen[i].speed for i in g]):.2f}" for k, g in enumerate(groups) if k % 2 == 0)
    print(f"3. diagnosed on {trained_speeds} m/s only: {diagnosis.verdict} ({diagnosis.cause}, values "
          f"{', '.join(f'{v:.4g}' for v in (diagnosis.best.values if diagnosis.best else ()))})")
    measured = np.array([seen[i].eigenvalue for i in held])
    base_error = np.abs(measured - predicted_weave(bicycle, [seen[i] for i in held]))
    extended_error = np.abs(measured - predicted_weave(extended, [seen[i] for i in held]))
    for k, group in enumerate(groups):
        if k % 2 == 1:
            mask = np.isin(held, group)
            print("   " + _line(f"never seen {np.mean([seen[i].speed for i in group]):.2f} m/s ({len(group)} windows)",
                               base_error[mask], extended_error[mask]))
    print("   " + _line(f"all never-seen speeds ({len(held)} windows)", base_error, extended_error))

    controller = [cause for cause in causes if cause.name.startswith("controller_")]
    if controller:
        eigenvalues = np.array([o.eigenvalue for o in seen])
        base_all = np.abs(eigenvalues - predicted_weave(bicycle, seen))
        low = [i for g in groups[:2] for i in g]
        for comparison in ("eigenvalues", "samples"):
            print(f"4. controller causes fitted on all speeds to the windows' {comparison} (in sample: the most "
                  "they can explain), eigenvalue RMS by speed:")
            for cause in controller:
                fit = _controller_fit(bicycle, cause, seen, comparison)
                error = np.abs(eigenvalues - predicted_weave(cause.apply(bicycle, fit.values), seen))
                by_speed = "; ".join(f"{np.mean([seen[i].speed for i in g]):.2f} m/s "
                                     f"{np.sqrt(np.mean(base_all[g] ** 2)):.2f} -> "
                                     f"{np.sqrt(np.mean(error[g] ** 2)):.2f}" for g in groups)
                print(f"   {cause.name} = {fit.values[0]:.4g}: {by_speed}")
            print("   fitted on the two lowest speeds only (in sample), RMS there:")
            for cause in controller:
                lowest = [seen[i] for i in low]
                fit = _controller_fit(bicycle, cause, lowest, comparison)
                error = np.abs(eigenvalues[low] - predicted_weave(cause.apply(bicycle, fit.values), lowest))
                print(f"   {cause.name} = {fit.values[0]:.4g}: RMS {np.sqrt(np.mean(base_all[low] ** 2)):.2f} -> "
                      f"{np.sqrt(np.mean(error ** 2)):.2f}, median {np.median(base_all[low]):.2f} -> "
                      f"{np.median(error):.2f}")

        forms = {cause.name: cause for cause in general_forms(causes)}
        print("5. fitted to all windows, robust chi-square by kind (eigenvalues, mode shapes):")
        for first, second in (("speed_scale", "parameter:mF"), ("payload", "controller_delay"),
                              ("front_payload", "controller_delay")):
            if first in forms and second in forms:
                pair = combined_cause(forms[first], forms[second])
                fit = fit_cause(bicycle, pair, seen)
                print(f"   {pair.name}: values {', '.join(f'{v:.4g}' for v in fit.values)}; chi-square "
                      f"{fit.block_chi2[0]:.1f} (eigenvalues), {fit.block_chi2[1]:.1f} (mode shapes)")


def _controller_fit(bicycle, cause, seen, comparison):
    """Fit a controller cause to the windows' eigenvalues, or to their samples from that fit's value."""
    fit = fit_cause(bicycle, cause, seen)
    if comparison == "samples":
        whitening = window_whitening(seen, bicycle, comparison="samples")
        fit = fit_cause(bicycle, cause, seen, whitening, [fit.values])
    return fit


if __name__ == "__main__":
    main()
