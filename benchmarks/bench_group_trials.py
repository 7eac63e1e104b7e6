"""Rates of the diagnosis on experiments of two groups: one bicycle under two controller gains.

For each family (mechanical effects in both groups; a controller's error in the second group
only; tests/group_trials.py) and seed: simulate both groups' runs, diagnose them as one
experiment, and count right names, ambiguous verdicts with the truth among the contenders,
wrong confident names, and mechanical effects blamed on a controller.

Run: ``python benchmarks/bench_group_trials.py [--seeds 5] [--first-seed 0] [--bicycles sbw2024 ...]
[--families ...] [--workers 2] [--log FILE]``
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from group_trials import MECHANICAL, run_group_trial  # noqa: E402
from hidden_effects import CONTROLLED_BICYCLES, CONTROLLER  # noqa: E402

from whipple.distributed import map_ordered  # noqa: E402
from whipple.errors import InputError  # noqa: E402


def _trial(task: tuple[str, str, int]) -> tuple:
    bicycle, family, seed = task
    try:
        trial = run_group_trial(family, seed, bicycle)
    except InputError as error:
        return (bicycle, family, seed, "error", error.problem, "error", False)
    return (bicycle, family, seed, trial.diagnosis.verdict, trial.diagnosis.cause, trial.outcome,
            trial.blamed_controller)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--bicycles", nargs="+", default=list(CONTROLLED_BICYCLES))
    parser.add_argument("--families", nargs="+", default=[*MECHANICAL, *CONTROLLER])
    parser.add_argument("--workers", type=int, default=None, help="local Dask worker processes")
    parser.add_argument("--log", type=Path, help="append each trial's result to this JSON-lines file")
    args = parser.parse_args()
    tasks = [(bicycle, family, seed) for seed in range(args.first_seed, args.first_seed + args.seeds)
             for bicycle in args.bicycles for family in args.families]
    started, rows = time.perf_counter(), []
    with map_ordered(_trial, tasks, workers=args.workers) as results:
        for row in results:
            rows.append(row)
            if args.log is not None:
                with args.log.open("a") as log:
                    log.write(json.dumps(row) + "\n")
            print(f"\r{len(rows)}/{len(tasks)} trials", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    print(f"{len(rows)} trials in {time.perf_counter() - started:.0f} s")
    print(f"{'family':<20}{'trials':>7}{'right':>7}{'amb(T)':>8}{'wrong':>7}{'controller blamed':>19}")
    for family in args.families:
        mine = [r for r in rows if r[1] == family]
        count = Counter(r[5] for r in mine)
        print(f"{family:<20}{len(mine):>7}{count['right']:>7}{count['ambiguous_truth']:>8}{count['wrong']:>7}"
              f"{sum(r[6] for r in mine):>19}")
    for r in rows:
        if r[5] in ("wrong", "error"):
            print(f"  {r[5]}: {r[0]} {r[1]} seed {r[2]}: {r[3]} {r[4]}")


if __name__ == "__main__":
    main()
