"""Benchmark: regeneration time, and matrices evaluated per second.

Run on demand: ``python benchmarks/bench_derivation.py [--sets N]``. Every timing is printed
beside a baseline measured in the same run:

- the derivation of the Whipple model against SymPy's own bicycle test
  (``sympy.physics.mechanics.tests.test_kane3.test_bicycle``: the same bicycle by Kane's method
  with the full nonlinear equations, then linearized), and the regeneration of all models;
- matrices for N random parameter sets with the generated NumPy code (vectorised) against the
  Meijaard closed form evaluated one set at a time with plain floats, as BicycleParameters does.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from meijaard_oracle import meijaard_matrices_scalar, random_physical_parameters  # noqa: E402
from whipple.derivation.regenerate import generate  # noqa: E402

from whipple.model.assembly import whipple_matrices  # noqa: E402


def time_regeneration() -> float:
    started = time.perf_counter()
    generate()
    return time.perf_counter() - started


def time_whipple_derivation() -> float:
    from whipple.derivation.models import derive_whipple

    started = time.perf_counter()
    derive_whipple()
    return time.perf_counter() - started


def time_sympy_bicycle_test() -> float:
    from sympy.physics.mechanics.tests.test_kane3 import test_bicycle

    started = time.perf_counter()
    test_bicycle()
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sets", type=int, default=1_000_000, help="random parameter sets")
    parser.add_argument("--baseline-sets", type=int, default=20_000,
                        help="sets for the one-at-a-time baseline (its rate is extrapolated)")
    parser.add_argument("--skip-sympy", action="store_true", help="skip SymPy's bicycle test (about 100 s)")
    args = parser.parse_args()

    ours = time_whipple_derivation()
    print(f"Whipple model, first-order derivation:  {ours:8.2f} s")
    if not args.skip_sympy:
        theirs = time_sympy_bicycle_test()
        print(f"SymPy's own bicycle test (baseline):    {theirs:8.2f} s   speed-up {theirs / ours:.1f}x")
    seconds = time_regeneration()
    print(f"regeneration of all models (derive + emit): {seconds:.2f} s")

    parameters = random_physical_parameters(np.random.default_rng(1), args.sets)
    started = time.perf_counter()
    whipple_matrices(parameters)
    vectorised = time.perf_counter() - started
    rate = args.sets / vectorised

    count = min(args.baseline_sets, args.sets)
    rows = [{name: float(values[i]) for name, values in parameters.items()} for i in range(count)]
    started = time.perf_counter()
    for row in rows:
        meijaard_matrices_scalar(row)
    baseline_rate = count / (time.perf_counter() - started)

    print(f"generated NumPy code:       {rate:14,.0f} sets/s ({args.sets:,} sets in {vectorised:.2f} s)")
    print(f"closed form, one at a time: {baseline_rate:14,.0f} sets/s (baseline, {count:,} sets)")
    print(f"speed-up: {rate / baseline_rate:.1f}x")


if __name__ == "__main__":
    main()
