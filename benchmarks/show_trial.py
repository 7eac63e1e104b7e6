"""Diagnose hidden-effect trials one by one and print what the diagnosis says of each.

For each trial given as ``BICYCLE:FAMILY:SEED`` (as in the rates' logs, e.g.
``browser:rack:3``): the true values, the verdict, the leading cause's values and standard
deviations, the reasons for a verdict that is not a confident name, and the values the data
leave open (:func:`whipple.diagnosis.identifiability.open_values`). Used to attribute the
trials whose outcome changes between two versions (run it with each version on the path).

Run: ``python benchmarks/show_trial.py BICYCLE:FAMILY:SEED [...] [--size-scale S] [--twin]
[--signals roll_rate] [--conditions ground+faults] [--sample-rate 500]``
(``S``: as in ``bench_diagnosis.py``, the hidden effect's size multiplied
by S; ``--twin``: also the verdict on the same windows without noise,
:func:`hidden_effects.noise_free_twin`; ``--signals``: as in ``bench_diagnosis.py``, by default
what ``whipple diagnose`` chooses, the roll rate with the steer angle, and ``roll_rate`` for the
logs of the roll rate alone; ``--conditions``: as in ``bench_diagnosis.py``, where the runs are
made and the sensors' faults; ``--sample-rate``: every run's, in Hz).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from hidden_effects import CONDITIONS, field_conditions, measurement_options, run_trial  # noqa: E402

from whipple.cli.measurement_arguments import signal_names  # noqa: E402
from whipple.diagnosis.identifiability import open_values  # noqa: E402
from whipple.diagnosis.options import DiagnosisOptions  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trials", nargs="+", metavar="BICYCLE:FAMILY:SEED")
    parser.add_argument("--size-scale", type=float, default=1.0, help="multiply the hidden effect's size by this")
    parser.add_argument("--twin", action="store_true",
                        help="also diagnose the same windows without noise (hidden_effects.noise_free_twin)")
    parser.add_argument("--signals", type=signal_names, default=None,
                        help="signals fitted jointly in every window (whipple diagnose --signals; default: as whipple "
                             "diagnose chooses, roll_rate,steer_angle for the trials' runs)")
    parser.add_argument("--conditions", choices=sorted(CONDITIONS), default="treadmill",
                        help="where the trials' runs are made and the sensors' faults (default treadmill)")
    parser.add_argument("--sample-rate", type=float, default=None,
                        help="every run's sample rate [Hz] (default: the simulator's, 100 Hz)")
    args = parser.parse_args()
    conditions = replace(field_conditions(args.conditions), sample_rate=args.sample_rate)
    for trial_name in args.trials:
        try:
            bicycle, family, seed = trial_name.split(":")
            options = DiagnosisOptions(measurement=measurement_options(args.signals or "auto"))
            trial = run_trial(family, int(seed), bicycle, scale=args.size_scale, twin=args.twin, options=options,
                              conditions=conditions)
        except ValueError as error:
            parser.error(f"{trial_name}: {error}")
        diagnosis = trial.diagnosis
        print(f"{trial_name}: truth {trial.truth}; verdict {diagnosis.verdict} ({diagnosis.cause}); "
              f"outcome {trial.outcome}")
        best = diagnosis.best
        if best is not None:
            print("  " + ", ".join(f"{name} = {value:.4g} +/- {std:.2g}"
                                   for name, value, std in zip(best.parameters, best.values, best.std, strict=True)))
        for reason in diagnosis.reasons:
            print(f"  why not named: {reason}")
        family_left = open_values(diagnosis.chosen, best) if diagnosis.chosen is not None and best else None
        if family_left is not None:
            print(f"  the data leave open: {family_left.sentence()}")
        if trial.twin is not None:
            twin = trial.twin
            print(f"  without noise: verdict {twin.verdict} ({twin.cause}); outcome {trial.twin_outcome}")
            for reason in twin.reasons:
                print(f"    why not named: {reason}")


if __name__ == "__main__":
    main()
