"""How much of the true model's misfit to a trial's windows is the fitting function's bias.

For each hidden-effect trial given as ``BICYCLE:FAMILY:SEED`` (tests/hidden_effects.py): the
windows' fitted weave eigenvalues against the *true* model (the base bicycle with the hidden
effect), as the dispersion chi2/n of the whitened differences (each part's standard deviation
from the window's fit with the diagnosis' 0.5% floor), and its median over windows, three ways:

- raw: measured minus the true model's eigenvalue (how the seed paper compares);
- own bias: less the fitting function's bias on the true model's own response
  (:func:`whipple.diagnosis.fit_bias.fitting_bias`), as the diagnosis compares every model;
- base bias: less the bias computed for the base model instead (what one correction for all
  models would give);
- at the truth: less the true model's bias with the modal amplitudes fitted at its own weave
  (``fitting_bias(..., amplitudes="model")``): what the bias is when the model is right. The
  diagnosis cannot use it (for a wrong model the other modes would absorb its error); the gap
  between "own bias" and this column is what the diagnosis' fixed point misses.

Near 1 the truth fits its windows to their noise; the diagnosis' verdicts depend on it (a true
cause that leaves chi2/n of 9 is flagged as "values that change with speed" or "no candidate
explains the data"). Windows whose eigenvalue no mode of the true model matches within 30% are
left out (a catch, noise), as the diagnosis leaves their shapes out. A truth given as feedback
(steer_spring, roll_damping) is the base bicycle with the same torque as a model term.

Run: ``python benchmarks/bench_fit_bias.py BICYCLE:FAMILY:SEED [...] [--windows]`` (``--windows``: each
window's measured and true eigenvalue and both biases too; ``--fixed-point-start model``: an
experiment, ``fitting_bias(start="model")``; ``--signals roll_rate``: the roll rate alone,
as the docs' figures before 2026-11-29, latest, were measured).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from hidden_effects import hidden_bicycle, trial_options, trial_rng, trial_runs  # noqa: E402

from whipple.cli.measurement_arguments import signal_names  # noqa: E402
from whipple.diagnosis.fit_bias import fitting_bias  # noqa: E402
from whipple.diagnosis.fitting import EIGENVALUE_FLOOR  # noqa: E402
from whipple.diagnosis.observations import Observation, observations, predicted_weave  # noqa: E402
from whipple.measurement.experiment import JOINT_SIGNALS, measure_run  # noqa: E402
from whipple.model.linear_terms import LinearTerms  # noqa: E402
from whipple.stability.nearest_modes import SHAPE_MATCH  # noqa: E402

#: Trial families whose truth is a feedback torque, and the model term that is the same torque.
FEEDBACK_TERMS = {"steer_spring": "K0_steer_steer", "roll_damping": "D_roll_roll"}


def floored_std(found: list[Observation]) -> np.ndarray:
    """Standard deviations [1/s] of each window's real and imaginary part, shape (n, 2), with the
    diagnosis' floor (a share of |eigenvalue|) added in quadrature."""
    return np.array([np.hypot(np.sqrt(np.diag(o.covariance)), EIGENVALUE_FLOOR * abs(o.eigenvalue)) for o in found])


def dispersions(bicycle: str, family: str, seed: int, windows: bool = False,
                signals: tuple[str, ...] = JOINT_SIGNALS, start: str = "measured"
                ) -> dict[str, tuple[float, float, int]]:
    """Return chi2/n and median whitened misfit of the true model's windows: raw, own bias, base
    bias, at the truth's weave. ``windows``: also print each window's numbers [1/s]; ``signals``:
    fitted jointly in every window."""
    base, _, runs = trial_runs(family, seed, bicycle)
    truth, values, model = hidden_bicycle(base, family, trial_rng(family, seed))
    if model is not None:
        # The feedback -k x as the model term +k: the same model (tests/test_linear_terms.py).
        truth = base.with_extensions(linear_terms=LinearTerms.from_mapping({FEEDBACK_TERMS[family]: values[family]}))
    found = observations([m for run in runs for m in measure_run(run, None, trial_options(base, signals=signals))])
    measured = np.array([o.eigenvalue for o in found])
    predicted = predicted_weave(truth, found)
    keep = np.abs(measured - predicted) < SHAPE_MATCH * np.abs(predicted)
    std = floored_std(found)

    def whitened(difference: np.ndarray) -> np.ndarray:
        return ((difference.real / std[:, 0]) ** 2 + (difference.imag / std[:, 1]) ** 2)[keep] / 2.0

    results = {}
    biases = {"raw": 0.0, "own bias": fitting_bias(truth, found, start=start),
              "base bias": fitting_bias(base, found, start=start),
              "at the truth": fitting_bias(truth, found, amplitudes="model", start=start)}
    if windows:
        for n in np.flatnonzero(keep):
            print(f"  {found[n].speed:5.2f} m/s: measured {measured[n]:.3f}, true weave {predicted[n]:.3f}, bias: own "
                  f"{biases['own bias'][n]:.3f}, at the truth's weave {biases['at the truth'][n]:.3f}")
    for name, bias in biases.items():
        values = whitened(measured - predicted - bias)
        results[name] = (float(values.mean()), float(np.median(values)), int(keep.sum()))
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trials", nargs="+", metavar="BICYCLE:FAMILY:SEED")
    parser.add_argument("--windows", action="store_true", help="also each window's eigenvalue and biases")
    parser.add_argument("--fixed-point-start", choices=("measured", "model"), default="measured",
                        help="experiment: where the fixed point of the own bias starts "
                             "(fitting_bias(start=...), DiagnosisOptions.fixed_point_start)")
    parser.add_argument("--signals", type=signal_names, default=JOINT_SIGNALS,
                        help="signals fitted jointly in every window (default roll_rate,steer_angle, as whipple "
                             "diagnose fits the trials' runs; docs' figures before 2026-11-29, latest: roll_rate)")
    args = parser.parse_args()
    columns = ("raw", "own bias", "base bias", "at the truth")
    print(f"{'trial':<34}{'windows':>8}  chi2/n {' / '.join(columns)}   (median)")
    for name in args.trials:
        try:
            bicycle, family, seed = name.split(":")
            results = dispersions(bicycle, family, int(seed), args.windows, args.signals, args.fixed_point_start)
        except ValueError as error:
            parser.error(f"{name}: {error}")
        count = results["raw"][2]
        means = " / ".join(f"{results[key][0]:.2f}" for key in columns)
        medians = " / ".join(f"{results[key][1]:.2f}" for key in columns)
        print(f"{name:<34}{count:>8}  {means:<40}({medians})")


if __name__ == "__main__":
    main()
