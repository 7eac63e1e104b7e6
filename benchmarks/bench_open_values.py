"""Does the family of values the diagnosis leaves open hold the true load?

Hidden-effect trials of the ``payload`` family (a point mass near the rear frame's mass centre,
exactly the ``payload`` cause's form; tests/hidden_effects.py) on the benchmark, kooijman2008
and BicycleParameters' Browser bicycles. For each trial whose leading cause is ``payload``:
where the diagnosis reports a family (:func:`whipple.diagnosis.identifiability.open_values`),
is its sentence true of the truth, that is, does the true (mass, x, z) lie within the family's
two ends along its line and within the stated reach of every other combination? Where it
reports none, does every value's +/- 2 std interval hold the truth? The baseline, measured on
the same trials, is the per-value +/- 2 std intervals alone (the estimate table). Columns:
trials, trials led by ``payload``, of those with a family reported, and how many the report
holds the truth in, with the family or with the intervals alone.

Run: ``python benchmarks/bench_open_values.py [--seeds 20] [--workers 2]``
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from hidden_effects import BICYCLES, bicycle_source, hidden_bicycle, run_trial, trial_rng  # noqa: E402

from whipple.diagnosis.identifiability import open_values  # noqa: E402
from whipple.distributed import map_ordered  # noqa: E402
from whipple.errors import InputError  # noqa: E402
from whipple.model.parameters import load_bicycle  # noqa: E402

FAMILY = "payload"


def _trial(arguments: tuple[str, int]) -> tuple[str, int, str, bool | None, bool | None, bool]:
    """(bicycle, seed, leading cause, family or intervals hold the truth, intervals alone hold it, family given)."""
    bicycle, seed = arguments
    truth_bicycle = hidden_bicycle(load_bicycle(bicycle_source(bicycle)), FAMILY, trial_rng(FAMILY, seed))[0]
    load = truth_bicycle.extensions.payload
    truth = np.array([load.mass, load.x, load.z])
    try:
        diagnosis = run_trial(FAMILY, seed, bicycle).diagnosis
    except InputError:
        return bicycle, seed, "error", None, None, False
    best, cause = diagnosis.best, diagnosis.chosen
    if best is None or cause is None or best.cause != FAMILY:
        return bicycle, seed, diagnosis.cause, None, None, False
    values, std = np.array(best.values), np.array(best.std)
    intervals = bool(np.all(np.abs(values - truth) <= 2.0 * std))
    family = open_values(cause, best)
    if family is None:
        return bicycle, seed, best.cause, intervals, intervals, False
    lower, upper = cause.limits
    span = upper - lower
    low, high, point = (np.asarray(v, dtype=float) / span for v in (family.low, family.high, truth))
    line = high - low
    along = float(np.dot(point - low, line) / np.dot(line, line))
    off_line = float(np.linalg.norm(point - (low + along * line)))
    return (bicycle, seed, best.cause, bool(0.0 <= along <= 1.0 and off_line <= family.determined), intervals,
            True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20, help="seeds per bicycle")
    parser.add_argument("--workers", type=int, default=2, help="local Dask worker processes")
    args = parser.parse_args()
    tasks = [(bicycle, seed) for bicycle in BICYCLES for seed in range(args.seeds)]
    with map_ordered(_trial, tasks, workers=args.workers) as results:
        rows = list(results)
    print(f"{'bicycle':<14}{'trials':>7}{'led':>6}{'family':>8}{'family or intervals':>21}{'intervals alone':>17}")
    for bicycle in [*BICYCLES, "all"]:
        mine = [r for r in rows if bicycle in ("all", r[0])]
        led = [r for r in mine if r[3] is not None]
        held, alone = sum(r[3] for r in led), sum(r[4] for r in led)
        print(f"{bicycle:<14}{len(mine):>7}{len(led):>6}{sum(r[5] for r in led):>8}"
              f"{held:>14} ({held / max(len(led), 1):.0%})"
              f"{alone:>10} ({alone / max(len(led), 1):.0%})")
    led = [r for r in rows if r[3] is not None]
    alone = sum(r[4] for r in led)
    with_family = [r for r in led if r[5]]
    print(f"trials with a family: {len(with_family)}; the family holds the truth in {sum(r[3] for r in with_family)}, "
          f"the intervals alone in {sum(r[4] for r in with_family)}")
    print(f"ratio of trials whose truth the report holds, family against intervals alone: "
          f"{sum(r[3] for r in led) / max(alone, 1):.2f}")


if __name__ == "__main__":
    main()
