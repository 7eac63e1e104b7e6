"""Windows that are no one free motion: how the free-response misfit separates them, and what the rule sets aside.

For the hidden-effect trials of the given bicycles, families and seeds, every usable window is
judged twice: by the true model (its chi-square per sample compared with the window's samples,
``SampleComparison``; a window is *spoilt* when the truth leaves it more than ``--spoilt``
times its noise off, as a window spanning a catch is), and by the package's rule, which knows
no model (``free_motion.free_response_misfit`` relative to the trial's median, and
``free_motion.outlying``). Printed: the clean windows' largest misfit relative to their trial's
median, each spoilt window's, and how many windows the rule sets aside rightly and wrongly. Then
the same misfits on the bundled treadmill runs: their spread, and the windows set aside.

Run: ``python benchmarks/bench_free_motion.py [--bicycles B ...] [--families F ...] [--seeds N]``
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from hidden_effects import BICYCLES, hidden_bicycle, trial_options, trial_rng, trial_runs  # noqa: E402

from whipple.diagnosis.observations import observations  # noqa: E402
from whipple.diagnosis.samples import SampleComparison  # noqa: E402
from whipple.measurement.bundled import bundled_runs  # noqa: E402
from whipple.measurement.experiment import FitOptions, diagnosis_signals, measure_run  # noqa: E402
from whipple.measurement.free_motion import free_response_misfit, outlying  # noqa: E402
from whipple.measurement.runs import read_run  # noqa: E402


def trial_windows(bicycle: str, family: str, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Each usable window's chi-square per sample under the true model, and its free-response misfit."""
    base, _, runs = trial_runs(family, seed, bicycle)
    truth, _, model = hidden_bicycle(base, family, trial_rng(family, seed))
    options = trial_options(base, signals=diagnosis_signals(runs))
    usable = [m for run in runs for m in measure_run(run, None, options) if m.usable]
    if not usable:
        return np.zeros(0), np.zeros(0)
    comparison = SampleComparison.of(observations(usable))
    residual = comparison.residuals([truth], [model])[0]
    window = comparison.window_of_residuals()
    true_chi2 = np.array([np.mean(residual[window == k] ** 2) for k in range(len(usable))])
    return true_chi2, np.array([free_response_misfit(m.fit) for m in usable])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bicycles", nargs="+", default=list(BICYCLES))
    parser.add_argument("--families", nargs="+",
                        default=["none", "steer_damping", "rack", "basket", "tyre_compliance", "motor", "payload"])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--spoilt", type=float, default=5.0,
                        help="a window the true model leaves more than this chi-square per sample off is spoilt")
    args = parser.parse_args()
    clean, counts = [], {"right": 0, "wrong": 0, "missed": 0}
    trials = windows = 0
    for bicycle in args.bicycles:
        for family in args.families:
            for seed in range(args.seeds):
                true_chi2, misfit = trial_windows(bicycle, family, seed)
                if misfit.size == 0:
                    continue
                trials, windows = trials + 1, windows + misfit.size
                relative = misfit / np.median(misfit)
                aside = outlying(misfit)
                for chi2, ratio, out in zip(true_chi2, relative, aside, strict=True):
                    spoilt = chi2 > args.spoilt
                    if not spoilt:
                        clean.append(ratio)
                    else:
                        print(f"spoilt: {bicycle} {family} {seed}: truth {chi2:.1f}, misfit {ratio:.2f} x median, "
                              f"{'set aside' if out else 'kept'}")
                    if spoilt or out:
                        counts["right" if spoilt and out else "wrong" if out else "missed"] += 1
    print(f"{windows} usable windows of {trials} trials ({len(args.bicycles)} bicycles x {len(args.families)} "
          f"families x {args.seeds} seeds)")
    print(f"  clean windows (truth <= {args.spoilt:g}): {len(clean)}; misfit relative to the trial's median: "
          f"median {np.median(clean):.2f}, 99th percentile {np.percentile(clean, 99):.2f}, largest {np.max(clean):.2f}")
    print(f"  set aside: {counts['right']} spoilt windows rightly, {counts['wrong']} clean windows wrongly; "
          f"spoilt windows kept: {counts['missed']}")
    runs = [read_run(source) for source in bundled_runs()]
    options = FitOptions(signals=diagnosis_signals(runs), baseline="auto")
    real = np.array([free_response_misfit(m.fit) for run in runs for m in measure_run(run, None, options)
                     if m.usable])
    print(f"bundled treadmill runs: {real.size} usable windows; misfit median {np.median(real):.3g}, 10th-90th "
          f"percentile {np.percentile(real, 10):.3g}-{np.percentile(real, 90):.3g}; set aside "
          f"{int(outlying(real).sum())} (misfits {', '.join(f'{v:.3g}' for v in np.sort(real[outlying(real)]))})")


if __name__ == "__main__":
    main()
