"""Catches inside windows: how often the window finder's windows run past the catch, and what the cut does.

Simulated trial runs know where each free coasting ends (``true_windows``). For the trials of
the given families, seeds and bicycles, each window is measured twice, as the window finder
gives it (no cut, ``FitOptions(catch_passes=0)``) and as ``measure_run`` fits it (cut before a
catch in the fit's residual), and compared with its free segment. Printed: windows running
past their catch before and after, windows cut (rightly, or without running past it), where
the cuts end relative to the catch, and how far the true model leaves the windows off (its
chi-square per sample with its modal amplitudes fitted, each signal weighed by its noise from
the second differences), before and after.

Run: ``python benchmarks/bench_catches.py [--families F ...] [--seeds N] [--bicycles B ...]``
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from hidden_effects import BICYCLES, hidden_bicycle, trial_options, trial_rng, trial_runs  # noqa: E402

import whipple.measurement.experiment as experiment  # noqa: E402
from whipple.diagnosis.observations import observation  # noqa: E402
from whipple.diagnosis.samples import SampleComparison  # noqa: E402
from whipple.model.assembly import linear_model  # noqa: E402

#: Seconds [s] a window may run past its free segment and still count as ending in it (a sample).
TOLERANCE = 0.005


def measured(run, options, passes):
    return list(experiment.measure_run(run, None, replace(options, catch_passes=passes)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--families", nargs="+", default=["none", "steer_damping", "basket", "rack"])
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--bicycles", nargs="+", default=list(BICYCLES))
    args = parser.parse_args()
    rows = []
    for bicycle in args.bicycles:
        for family in args.families:
            for seed in range(args.seeds):
                base, _, runs = trial_runs(family, seed, bicycle)
                truth, _, model = hidden_bicycle(base, family, trial_rng(family, seed))
                model = linear_model(truth) if model is None else model
                options = trial_options(base, signals=experiment.diagnosis_signals(runs))
                for run in runs:
                    segments = [tuple(map(float, part.split(":"))) for part in run.metadata["true_windows"].split(";")]
                    for before, after in zip(measured(run, options, 0), measured(run, options, 3), strict=True):
                        if before.fit is None or after.fit is None or not before.usable:
                            continue
                        start = before.fit.start
                        segment = next((s for s in segments if s[0] - 0.05 <= start <= s[1]), None)
                        if segment is None:
                            continue
                        cut = any(note.startswith("cut before a catch") for note in after.window.notes)
                        misfit = [_per_sample(model, truth, m) for m in (before, after)]
                        rows.append((before.fit.stop - segment[1], after.fit.stop - segment[1], cut, *misfit))
    past_before, past_after, cut, misfit_before, misfit_after = (np.array(column) for column in zip(*rows, strict=True))
    ran_past = past_before > TOLERANCE
    print(f"{len(rows)} usable windows of {len(args.bicycles)} bicycles x {len(args.families)} families x "
          f"{args.seeds} seeds")
    print(f"  running past the catch: {ran_past.sum()} as found, {(past_after > TOLERANCE).sum()} after the cut")
    print(f"  cut: {cut.sum()} ({(cut & ran_past).sum()} ran past the catch, {(cut & ~ran_past).sum()} did not)")
    if (cut & ran_past).any():
        print(f"  the cut windows that ran past end {np.median(-past_after[cut & ran_past]):.3f} s before the catch "
              "(median)")
    print(f"  true model's chi-square per sample, windows running past the catch: median "
          f"{np.median(misfit_before[ran_past]):.2f} as found, {np.median(misfit_after[ran_past]):.2f} after the cut")
    clean = ~ran_past
    print(f"  the other windows: median {np.median(misfit_before[clean]):.2f}, 99th percentile "
          f"{np.quantile(misfit_before[clean], 0.99):.2f}")


def _per_sample(model, truth, measurement) -> float:
    comparison = SampleComparison.of([observation(measurement)])
    return float(comparison.chi2_per_sample(truth, model))


if __name__ == "__main__":
    main()
