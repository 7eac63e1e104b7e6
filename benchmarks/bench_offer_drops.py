"""Is the offer by prediction stable when one window is left out? Both bundled experiments, a window dropped.

The offer by prediction (:mod:`whipple.diagnosis.offer`) picks, where no candidate explains the
data, the simplest candidate whose held-out error is within ``K`` standard errors of the best
predictor's (the one-standard-error rule, ``K = 1`` by default; ``K = 0``: the best predictor, the
choice before the rule). An offer that flips when one window more or less is measured is no
offer an engineer can trust. This script measures the windows of both bundled experiments once
(``whipple diagnose --experiment bundled``'s windows), then diagnoses them whole and with each
listed window left out (the held-out gain and the amplitude check off: only the offer is
compared), and prints per case the offer under the rule and under ``K = 0``, with every
candidate's held-out RMS [1/s] and its mean squared error above the best's +/- that excess'
standard error [1/s^2]. One JSON line per case.

Run: ``python benchmarks/bench_offer_drops.py [--drop 57 0 84] [--save FILE | --windows FILE]``;
``--drop`` takes indices into the usable windows in the order the JSON of ``whipple diagnose
--experiment bundled`` lists them (``none``: all windows); ``--save FILE`` pickles the measured
fleet and windows, ``--windows FILE`` diagnoses such a file instead of measuring (windows
measured by another version of the code, say). About 2.5 minutes per case on 2 idle cores.
"""

from __future__ import annotations

import argparse
import json
import pickle
from dataclasses import replace

from whipple.diagnosis.offer import simplest_within
from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.pipeline import _measured_experiment
from whipple.diagnosis.report import assemble
from whipple.measurement.bundled import bundled_experiment
from whipple.measurement.experiment_file import read_experiment


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--drop", nargs="+", default=["none"], help="usable windows to leave out, one per case")
    parser.add_argument("--save", help="pickle the measured fleet and usable windows here")
    parser.add_argument("--windows", help="diagnose the fleet and windows of this pickle instead of measuring")
    args = parser.parse_args()
    options = replace(DiagnosisOptions(), held_out_gain=False, amplitude_check=False)
    if args.windows is not None:
        with open(args.windows, "rb") as file:
            fleet, used = pickle.load(file)  # noqa: S301 - a file this script wrote
    else:
        fleet, measured = _measured_experiment(read_experiment(bundled_experiment()), options, None)
        used = [m for m in measured.windows if m.usable]
    if args.save is not None:
        with open(args.save, "wb") as file:
            pickle.dump((fleet, used), file)
    for drop in (None if d == "none" else int(d) for d in args.drop):
        windows = used if drop is None else [m for i, m in enumerate(used) if i != drop]
        report = assemble(fleet, windows, options)
        offer = report.offer
        row: dict[str, object] = {
            "windows": len(windows), "verdict": report.diagnosis.verdict, "leader": report.diagnosis.cause,
            "dropped": None if drop is None else f"{used[drop].run.name} {used[drop].window.start:.2f} s",
            "chosen_by": offer.chosen_by}
        if offer.chosen_by == "prediction":
            sizes = [p.values for p in offer.predictions]
            excess = [p.excess for p in offer.predictions]
            error = [p.standard_error for p in offer.predictions]
            for k in (offer.standard_errors, 0.0):
                row[f"offer_{k:g}_se"] = offer.predictions[simplest_within(sizes, excess, error, k)].name
            row["predictions"] = [(p.name, p.values, round(p.rms, 4), round(p.excess, 4), round(p.standard_error, 4))
                                  for p in offer.predictions]
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
