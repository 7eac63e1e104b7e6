"""Per speed, how many pushes of a trial bicycle give a usable window, and how far those windows sit from the model.

For a bicycle of the hidden-effect trials (tests/hidden_effects.py) with no effect hidden:
simulate runs at each trial speed (three pushes each, the trials' sensors and noise), fit their
windows as the trials do (``baseline="auto"``, the controlled bicycles' 0.3 s settle) and
compare each window's eigenvalue with what the bicycle's own model predicts for it (its weave
plus the fitting function's bias on its own response, as the diagnosis compares every model).
Printed per speed: usable windows per push, and the misfit of the real and imaginary part in
standard deviations of the window's fit (with the diagnosis' 0.5% floor): median and RMS.
Where the true model is compared, a median far from 0 is an error the windows make by
themselves, which a diagnosis can only read as a cause. Also the median frequency error and
the median frequency part of the fitting bias [1/s], and how many windows hold fewer than
``MIN_CYCLES`` (0.75) weave cycles *above the noise* (``WeaveFit.cycles_above_noise``). The
package leaves those out by default (``FitOptions.min_cycles_above_noise``); ``--cycles-above-noise 0``
shows the windows as they were before that check. Windows whose eigenvalue no mode of the model
matches within 30% are left out, as in ``bench_fit_bias.py``. ``--bundled``: the cycles above the
noise of the bundled treadmill runs' windows (fitted as ``whipple diagnose --bundled`` does, but
without that check, to count the windows it leaves out).

The last columns: the median standard deviation of the windows' real and imaginary part [1/s]
(with the floor), to compare how sharp the windows are with ``--signals roll_rate,steer_angle``
(both signals fitted jointly, as ``whipple diagnose --signals``) and without.

Run: ``python benchmarks/bench_window_speeds.py BICYCLE [BICYCLE ...] [--runs 20] [--bundled]
[--cycles-above-noise C] [--signals roll_rate,steer_angle]`` (``--runs``: runs per speed, each with its own noise).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from bench_fit_bias import floored_std  # noqa: E402
from hidden_effects import PUSHES, trial_bicycle, trial_options, trial_speeds  # noqa: E402

from whipple.cli.measurement_arguments import signal_names  # noqa: E402
from whipple.diagnosis.fit_bias import fitting_bias  # noqa: E402
from whipple.diagnosis.observations import observations, predicted_weave  # noqa: E402
from whipple.measurement.bundled import bundled_runs  # noqa: E402
from whipple.measurement.experiment import MIN_CYCLES, MIN_CYCLES_ABOVE_NOISE, FitOptions, measure_run  # noqa: E402
from whipple.measurement.runs import read_run, run_from_simulation  # noqa: E402
from whipple.model.parameters import Bicycle  # noqa: E402
from whipple.simulation.scenario import RunScenario  # noqa: E402
from whipple.simulation.simulator import simulate_run  # noqa: E402
from whipple.stability.nearest_modes import SHAPE_MATCH  # noqa: E402

#: Seeds of the runs start here, away from the trials' own.
FIRST_SEED = 1000


def misfits(bicycle: Bicycle, speed: float, runs: int, min_cycles_above_noise: float,
            signals: tuple[str, ...] = ("roll_rate",)) -> dict[str, np.ndarray]:
    """The usable windows of ``runs`` runs at ``speed`` [m/s]: whitened misfits (n, 2), frequency
    errors and biases [1/s] and standard deviations (n, 2) [1/s] (of the windows a mode matches)
    and every window's cycles above the noise; ``signals`` fitted jointly."""
    options = trial_options(bicycle, min_cycles_above_noise, signals)
    measurements = []
    for k in range(runs):
        scenario = RunScenario(speed=speed, seed=FIRST_SEED + k, n_pushes=PUSHES)
        run = run_from_simulation(simulate_run(bicycle, scenario, name=f"run{k}"))
        measurements += [m for m in measure_run(run, None, options) if m.skipped is None]
    found = observations(measurements)
    cycles = np.array([m.fit.cycles_above_noise for m in measurements if m.fit is not None])
    if not found:
        return {"z": np.zeros((0, 2)), "error": np.zeros(0), "bias": np.zeros(0), "std": np.zeros((0, 2)),
                "cycles": cycles}
    measured = np.array([o.eigenvalue for o in found])
    bias = fitting_bias(bicycle, found)
    predicted = predicted_weave(bicycle, found) + bias
    keep = np.abs(measured - predicted) < SHAPE_MATCH * np.abs(predicted)
    std = floored_std(found)
    difference = measured - predicted
    return {"z": (np.column_stack([difference.real, difference.imag]) / std)[keep],
            "error": difference.imag[keep], "bias": bias.imag[keep], "std": std[keep], "cycles": cycles}


def bundled_cycles() -> np.ndarray:
    """Cycles above the noise of the bundled treadmill runs' usable windows (before that check)."""
    options = FitOptions(baseline="auto", min_cycles_above_noise=0.0)
    measurements = [m for source in bundled_runs() for m in measure_run(read_run(source), None, options)]
    return np.array([m.fit.cycles_above_noise for m in measurements if m.skipped is None and m.fit is not None])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bicycles", nargs="+", metavar="BICYCLE")
    parser.add_argument("--runs", type=int, default=20, help="runs per speed")
    parser.add_argument("--bundled", action="store_true", help="also the bundled treadmill runs' windows")
    parser.add_argument("--cycles-above-noise", type=float, default=MIN_CYCLES_ABOVE_NOISE,
                        help="leave out the trials' windows holding fewer weave cycles above the noise "
                             "(FitOptions.min_cycles_above_noise; default the package's, 0: off)")
    parser.add_argument("--signals", type=signal_names, default=("roll_rate",),
                        help="signals fitted jointly in every window (whipple diagnose --signals; default roll_rate)")
    args = parser.parse_args()
    print(f"{'bicycle':<20}{'speed':>6}{'windows/pushes':>16}  misfit [std]: real median, rms; imag median, rms;"
          f"  frequency error, bias [1/s] (medians);  windows < {MIN_CYCLES} cycles above the noise;"
          "  std real, imag [1/s] (medians)")
    for name in args.bicycles:
        try:
            bicycle = trial_bicycle(name)
        except (OSError, ValueError) as error:
            parser.error(f"{name}: {error}")
        for speed in trial_speeds(bicycle):
            found = misfits(bicycle, speed, args.runs, args.cycles_above_noise, args.signals)
            usable = f"{found['cycles'].size}/{args.runs * PUSHES}"
            short = int(np.sum(found["cycles"] < MIN_CYCLES))
            z = found["z"]
            if len(z) == 0:
                print(f"{name:<20}{speed:>6.1f}{usable:>16}")
                continue
            median, rms = np.median(z, axis=0), np.sqrt(np.mean(z**2, axis=0))
            print(f"{name:<20}{speed:>6.1f}{usable:>16}  {median[0]:+6.2f} {rms[0]:5.2f}; {median[1]:+6.2f} "
                  f"{rms[1]:5.2f};  {np.median(found['error']):+6.3f} {np.median(found['bias']):+6.3f};  {short};  "
                  f"{np.median(found['std'][:, 0]):.3f} {np.median(found['std'][:, 1]):.3f}")
    if args.bundled:
        cycles = bundled_cycles()
        print(f"bundled treadmill runs: {cycles.size} windows; fewer than {MIN_CYCLES} cycles above the noise: "
              f"{np.sum(cycles < MIN_CYCLES)}, fewer than 1: {np.sum(cycles < 1.0)}")


if __name__ == "__main__":
    main()
