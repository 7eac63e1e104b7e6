"""Hidden mass-and-delay trials for the choice by prediction (``whipple diagnose --gain-by-cause pairs``).

Run:  python benchmarks/bench_prediction_choice.py [--seeds N] [--first-seed K] [--workers N]
[--choose evidence|prediction]

The bundled treadmill data are predicted best by a payload together with a controller delay.
Would the choice by prediction find such a pair if it were the truth? Per seed, the controlled
sbw2024 bicycle gets a hidden rear payload (5-15 kg, x and z uniform within the payload
cause's bounds restricted to the wheelbase and 0.1-0.6 m above the ground) and a controller
delay (20-80 ms); synthetic windows (``tests/synthetic_windows.py``: the true model's weave
eigenvalues and mode shapes with noise, 4 windows at each of 1.5, 2.5, 3.5, 4.5 and 5.5 m/s)
are diagnosed against the plain sbw2024 by:

- the evidence (the diagnosis itself): its verdict and leading cause, and its held-out gain;
- the choice by prediction among the 78 candidates of ``--gain-by-cause pairs``: per
  left-out speed the cause chosen and its values, and the held-out gain.

Printed per seed, then how often each choice held the true pair (payload + controller_delay)
in every fold. No window fits: this tests the choices, not the window finder.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from synthetic_windows import synthetic_observations  # noqa: E402

from whipple.diagnosis.causes import candidate_causes, payload_bounds  # noqa: E402
from whipple.diagnosis.families import combined_cause, components, general_forms  # noqa: E402
from whipple.diagnosis.gain import held_out_candidates, held_out_gain  # noqa: E402
from whipple.model.parameters import load_bicycle  # noqa: E402

TRUE_PAIR = "payload + controller_delay"
SPEEDS = np.repeat([1.5, 2.5, 3.5, 4.5, 5.5], 4)


def hidden_truth(bicycle, seed: int) -> tuple[list[float], object]:
    """Draw the hidden payload [kg, m, m] and delay [s]; return the values and the pair cause."""
    rng = np.random.default_rng(1000 + seed)
    forms = {cause.name: cause for cause in general_forms(candidate_causes(bicycle))}
    pair = combined_cause(forms["payload"], forms["controller_delay"])
    bounds = payload_bounds(bicycle, "payload")
    x_low, x_high = max(bounds["x"][0], 0.0), min(bounds["x"][1], bicycle.parameters["w"])
    values = [rng.uniform(5.0, 15.0), rng.uniform(x_low, x_high), -rng.uniform(0.1, 0.6), rng.uniform(0.02, 0.08)]
    return values, pair


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=None, help="local Dask workers for the folds")
    parser.add_argument("--choose", choices=("evidence", "prediction"), action="append",
                        help="only this choice (repeatable; default both)")
    args = parser.parse_args()
    bicycle = load_bicycle("sbw2024")
    causes = candidate_causes(bicycle)
    candidates = held_out_candidates(causes, pairs=True)
    choices = args.choose or ["evidence", "prediction"]
    pools = {"evidence": causes, "prediction": candidates}
    found, folds, total = dict.fromkeys(choices, 0), dict.fromkeys(choices, 0), 0
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        values, pair = hidden_truth(bicycle, seed)
        observations = synthetic_observations(pair.apply(bicycle, values), seed, SPEEDS)
        total += len(np.unique(SPEEDS))
        print(f"seed {seed}: truth {TRUE_PAIR} = {', '.join(f'{v:.3g}' for v in values)}", flush=True)
        for choice in choices:
            pool = pools[choice]
            start = time.perf_counter()
            gain = held_out_gain(bicycle, observations, pool, choose=choice, workers=args.workers)
            chosen = [s.cause for s in gain.speeds]
            true = [set(components(name)) == set(components(TRUE_PAIR)) for name in chosen]
            found[choice] += all(true)
            folds[choice] += sum(true)
            print(f"  by {choice}: held-out RMS {gain.base_rms:.3f} -> {gain.extended_rms:.3f} 1/s "
                  f"({100 * gain.cut:+.0f}%), {time.perf_counter() - start:.0f} s", flush=True)
            for speed in gain.speeds:
                print(f"    {speed.speed:.1f} m/s: {speed.cause} ({', '.join(f'{v:.3g}' for v in speed.values)})")
    for choice, count in found.items():
        print(f"true pair chosen by {choice}: in every fold in {count} of {args.seeds} seeds, "
              f"in {folds[choice]} of {total} folds")


if __name__ == "__main__":
    main()
