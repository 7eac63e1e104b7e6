"""Do the roll rate and the steer angle of a window give the same weave eigenvalue?

Each window is fitted twice, to the roll rate alone and to the steer angle alone (automatic
baseline), and the two eigenvalues are compared through their combined standard deviations:
``sqrt(((dd / s_d)^2 + (dw / s_w)^2) / 2)`` for the difference ``dd + i dw``. Printed for the
bundled treadmill runs and, as the yardstick, for effect-free simulated runs of the
hidden-effect trials' bicycles (``tests/hidden_effects.py``, family ``none``): the model's own
response holds other modes besides the weave, so that even there the two fits differ by more
than their stated noise. Quoted in benchmarks/results/diagnosis-log.md ("The real data").

Run: ``python docs/figures/signal_agreement.py [--seeds 3]`` (about two minutes on one core).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))
from hidden_effects import BICYCLES, CONTROLLED, trial_runs, trial_settle  # noqa: E402

from whipple.measurement.bundled import bundled_runs  # noqa: E402
from whipple.measurement.experiment import FitOptions, measure_run  # noqa: E402
from whipple.measurement.runs import Run, read_run  # noqa: E402


def disagreement(runs: Sequence[Run], settle: float = 0.0) -> np.ndarray:
    """Return, per window that both single-signal fits use, their eigenvalues' difference in
    combined standard deviations (root mean square over the real and imaginary part)."""
    fitted = []
    for signal in ("roll_rate", "steer_angle"):
        options = FitOptions(signals=(signal,), baseline="auto", settle=settle)
        fitted.append({(m.run.name, m.window.start_index): m for run in runs for m in measure_run(run, None, options)
                       if m.usable and m.fit is not None})
    roll, steer = fitted
    values = []
    for key in roll.keys() & steer.keys():
        a, b = roll[key].fit, steer[key].fit
        difference = a.eigenvalue - b.eigenvalue
        std = np.sqrt(np.diag(a.covariance) + np.diag(b.covariance))
        values.append(np.hypot(difference.real / std[0], difference.imag / std[1]) / np.sqrt(2))
    return np.array(values)


def _line(label: str, values: np.ndarray) -> str:
    return (f"{label:<34}{values.size:>8}{np.median(values):>8.2f}{np.percentile(values, 90):>8.2f}"
            f"{np.mean(values > 3):>12.0%}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3, help="simulated trials (seeds) per bicycle")
    args = parser.parse_args()
    print(f"{'runs':<34}{'windows':>8}{'median':>8}{'p90':>8}{'over 3 std':>12}")
    print(_line("bundled treadmill runs", disagreement([read_run(source) for source in bundled_runs()])))
    for bicycle in (*BICYCLES, CONTROLLED):
        values = []
        for seed in range(args.seeds):
            base, _, runs = trial_runs("none", seed, bicycle)
            values.append(disagreement(runs, trial_settle(base)))
        print(_line(f"{bicycle}, simulated, no effect", np.concatenate(values)))


if __name__ == "__main__":
    main()
