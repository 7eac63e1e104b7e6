"""Hidden-effect rates of the diagnosis, and its speed.

For every cause (and ``none``), over many seeds: simulate runs of the benchmark bicycle with
that effect hidden at a random realistic size (tests/hidden_effects.py), diagnose them blind,
and count how often the cause is named correctly, how often ``none`` is said, and how often
the named cause's interval (value +/- 2 std) covers the true values. Also times
``diagnose_observations`` on the observations of 40 simulated runs.

Run: ``python benchmarks/bench_diagnosis.py [--seeds 50] [--workers 2 | --scheduler ADDRESS]``: the trials
run on a local Dask cluster of N worker processes, or on an existing Dask cluster
(:func:`whipple.distributed.map_ordered`; the workers of an existing cluster need this repository's
``tests`` folder on their path, for ``hidden_effects``).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from hidden_effects import CAUSES, run_trial  # noqa: E402

from whipple.distributed import map_ordered  # noqa: E402
from whipple.errors import InputError  # noqa: E402


def _trial(arguments: tuple[str, int]) -> tuple[str, int, str, str, bool, bool, bool]:
    cause, seed = arguments
    try:
        trial = run_trial(cause, seed)
    except InputError as error:  # e.g. an effect so large that too few windows were usable
        return (cause, seed, "error", error.problem, False, False, False)
    return (cause, seed, trial.diagnosis.verdict, trial.diagnosis.cause, trial.named_correctly,
            trial.said_none, trial.covers())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=50)
    cluster = parser.add_mutually_exclusive_group()
    cluster.add_argument("--workers", type=int, default=2, help="local Dask worker processes")
    cluster.add_argument("--scheduler", help="address of an existing Dask scheduler")
    parser.add_argument("--causes", nargs="*", default=list(CAUSES))
    args = parser.parse_args()
    jobs = [(cause, seed) for cause in args.causes for seed in range(args.seeds)]
    started = time.perf_counter()
    workers = None if args.scheduler else args.workers
    results = []
    with map_ordered(_trial, jobs, scheduler=args.scheduler, workers=workers) as trials:
        for result in trials:
            results.append(result)
            print(f"\r{len(results)}/{len(jobs)} trials", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    elapsed = time.perf_counter() - started
    where = args.scheduler or f"{args.workers} local workers"
    print(f"{len(jobs)} trials in {elapsed:.0f} s ({where})")
    print(f"{'hidden cause':<18}{'seeds':>6}{'named right':>13}{'said none':>11}{'covered':>9}  wrong verdicts")
    for cause in args.causes:
        rows = [r for r in results if r[0] == cause]
        named = sum(r[4] for r in rows) / len(rows)
        none = sum(r[5] for r in rows) / len(rows)
        covered = sum(r[6] for r in rows) / len(rows)
        wrong: dict[str, int] = {}
        for r in rows:
            expected = ("none", "none") if cause == "none" else ("named", cause)
            if (r[2], r[3]) != expected:
                key = f"{r[2]}:{r[3]}"
                wrong[key] = wrong.get(key, 0) + 1
        shown = ", ".join(f"{k} x{v}" for k, v in sorted(wrong.items(), key=lambda kv: -kv[1]))
        if cause == "none":
            print(f"{cause:<18}{len(rows):>6}{'-':>13}{none:>11.0%}{'-':>9}  {shown}")
        else:
            print(f"{cause:<18}{len(rows):>6}{named:>13.0%}{none:>11.0%}{covered:>9.0%}  {shown}")


if __name__ == "__main__":
    main()
