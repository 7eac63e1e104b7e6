"""Benchmark of the critical-speed solver against the bare polynomial solve, measured in one run.

Run:  python benchmarks/bench_critical.py [--bicycles N]

Per bicycle, for a batch of N realistic bicycles (every entry of the benchmark bicycle's M, C1,
K0, K2 scaled by a uniform factor within +/-5 %, M and K0 kept symmetric) and for one bicycle:

* ``bare``: benchmarks/bare_solve.py, the Hopf and real conditions' roots from batched
  companion matrices, nothing else (the baseline: every ratio is time / bare time);
* ``new``: ``whipple.stability.critical.critical_speeds_batch`` (exact polynomial conditions,
  closed form, Newton, verification, directions, labels, Routh-Hurwitz stable ranges, result
  objects), on the LinearModel, and with the model's assembly from M, C1, K0, K2 included;
  ``critical_speed_table`` (the same speeds as arrays) on the LinearModel, and
  ``whipple_speed_table`` from M, C1, K0, K2 (the bare solve's own input; what a sweep runs);
* ``old grid``: the replaced method (tests/grid_critical.py: conditions from eigenvalues on a
  0.01 m/s grid, sign changes, bisection; on a sub-batch);
* ``grid + brentq``: a loop over bicycles, the largest real part on the 0.01 m/s grid and
  ``scipy.optimize.brentq`` in each cell where it changes sign (on a few bicycles).

Also: the distance of the weave and capsize speeds to the published values (Meijaard et al.
2007, Table 2(a), from the published matrices), the agreement of the new solver with the bare
roots over the batch, and the cost of the interval 0:1e6 m/s against 0:10 m/s.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent / "tests")]

from bare_solve import bare_critical_roots  # noqa: E402
from bench_stability import C1, CAPSIZE, K0, K2, WEAVE, M, best_time  # noqa: E402
from grid_critical import grid_brentq_speeds, grid_critical_speeds  # noqa: E402

from whipple.model.linear import second_order_model  # noqa: E402
from whipple.stability.critical import (  # noqa: E402
    critical_speed_table,
    critical_speeds,
    critical_speeds_batch,
    whipple_speed_table,
)


def realistic(count: int, seed: int = 1) -> list[np.ndarray]:
    """M, C1, K0, K2 of `count` bicycles within +/-5 % of the benchmark bicycle, entry by entry."""
    rng = np.random.default_rng(seed)
    batch = [X * (1.0 + 0.05 * rng.uniform(-1.0, 1.0, (count, 2, 2))) for X in (M, C1, K0, K2)]
    for X in (batch[0], batch[2]):
        X[:, 1, 0] = X[:, 0, 1]
    return batch


def main() -> None:
    """Run every case and print times per bicycle, ratios and precision."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bicycles", type=int, default=10_000)
    count = parser.parse_args().bicycles
    batch = realistic(count)
    model = second_order_model(*batch)
    coefficients = model.A
    rows = []

    bare = best_time(lambda: bare_critical_roots(*batch)) / count
    rows.append(("bare polynomial solve (batch)", bare))
    new = best_time(lambda: critical_speeds_batch(model)) / count
    rows.append(("new solver, batch, on the LinearModel", new))
    assembled = best_time(lambda: critical_speeds_batch(second_order_model(*batch))) / count
    rows.append(("new solver, batch, model assembly included", assembled))
    table = best_time(lambda: critical_speed_table(model)) / count
    rows.append(("new solver, batch, arrays (critical_speed_table)", table))
    from_matrices = best_time(lambda: whipple_speed_table(*batch)) / count
    rows.append(("new solver, batch, from the matrices (whipple_speed_table)", from_matrices))
    one = [X[:1] for X in batch]
    bare_one = best_time(lambda: bare_critical_roots(*one), 20)
    rows.append(("bare polynomial solve, one bicycle", bare_one))
    single = second_order_model(M, C1, K0, K2)
    new_one = best_time(lambda: critical_speeds(single), 20)
    rows.append(("new solver, one bicycle", new_one))
    sub = min(count, 200)
    old = best_time(lambda: grid_critical_speeds(coefficients[:sub], 0.0, 10.0), 1) / sub
    rows.append((f"old grid solver (0.01 m/s grid + bisection, {sub} bicycles)", old))
    few = min(count, 5)
    brent = best_time(lambda: grid_brentq_speeds(coefficients[:few], 0.0, 10.0), 1) / few
    rows.append((f"grid + scipy brentq ({few} bicycles)", brent))

    print(f"time per bicycle, {count} realistic bicycles (+/-5 % of the benchmark):")
    for name, seconds in rows:
        baseline = bare_one if "one bicycle" in name else bare
        print(f"  {name:62s} {seconds * 1e6:12.2f} us   {seconds / baseline:9.1f} x bare")

    results = critical_speeds_batch(model)
    hopf, real = bare_critical_roots(*batch)
    worst, unmatched, spurious = 0.0, 0, 0
    for index, result in enumerate(results):
        for kind, bare_roots in (("hopf", hopf[index]), ("real", real[index])):
            ours = np.array([c.speed for c in result.crossings if c.kind == kind])
            theirs = bare_roots[(bare_roots >= 0.0) & (bare_roots <= 10.0)]
            for speed in ours:
                distance = np.min(np.abs(theirs - speed), initial=np.inf)
                worst = max(worst, distance)
                unmatched += int(distance > 1e-9)
            spurious += sum(np.min(np.abs(ours - x), initial=np.inf) > 1e-9 for x in theirs)
    print(f"against the bare roots in 0-10 m/s: largest difference {worst:.1e} m/s, {unmatched}"
          f" crossings without a bare root, {spurious} bare roots rejected (opposite real pairs)")

    benchmark = critical_speeds(single)
    print(f"benchmark bicycle: weave {benchmark.weave_speed!r} (error {benchmark.weave_speed - WEAVE:+.1e}),"
          f" capsize {benchmark.capsize_speed!r} (error {benchmark.capsize_speed - CAPSIZE:+.1e}) m/s")

    narrow = best_time(lambda: critical_speeds_batch(model, 0.0, 10.0)) / count
    wide = best_time(lambda: critical_speeds_batch(model, 0.0, 1e6)) / count
    roots_narrow = sum(len(r.crossings) for r in critical_speeds_batch(model, 0.0, 10.0))
    roots_wide = sum(len(r.crossings) for r in critical_speeds_batch(model, 0.0, 1e6))
    narrow_one = best_time(lambda: critical_speeds(single, 0.0, 10.0), 20)
    wide_one = best_time(lambda: critical_speeds(single, 0.0, 1e6), 20)
    print(f"interval 0:1e6 vs 0:10 m/s: batch {wide * 1e6:.2f} vs {narrow * 1e6:.2f} us per bicycle"
          f" (ratio {wide / narrow:.2f}; {roots_wide} vs {roots_narrow} crossings: the cost follows"
          f" the crossings, not the width); one bicycle {wide_one * 1e6:.0f} vs"
          f" {narrow_one * 1e6:.0f} us (ratio {wide_one / narrow_one:.2f})")

if __name__ == "__main__":
    main()
