"""Eigen analysis at many speeds against a plain batched ``numpy.linalg.eigvals``, in one run.

Run:  python benchmarks/bench_eigen.py [--repeats 200]

For each case, ``whipple.stability.eigen.eigen_analysis`` without eigenvectors (eigenvalues,
tracking and mode labels: what ``whipple stability --plot``, the tables and the weave eigenvalue
use) and with them (``vectors=True``, for the record) against the bare
baseline: one ``numpy.linalg.eigvals`` call on the state matrices at the same speeds (building
them included), and for reference one ``numpy.linalg.eig`` call (eigenvectors too). The calls
are interleaved and the shortest of many repeats is kept, so that other load on the machine
affects both alike. The issue's target: eigen_analysis / eigvals within 2 (for the tables and
plots; eigenvectors at every speed cost ``eig``, itself about 1.5 times ``eigvals``).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np

from whipple.model.assembly import build_linear_model, linear_model
from whipple.model.linear import LinearModel
from whipple.model.parameters import load_bicycle
from whipple.stability.eigen import eigen_analysis


def interleaved_best(functions: dict[str, Callable[[], object]], repeats: int) -> dict[str, float]:
    """Shortest wall time [s] of each function over `repeats` rounds, calls interleaved."""
    best = dict.fromkeys(functions, np.inf)
    for _ in range(repeats):
        for name, function in functions.items():
            start = time.perf_counter()
            function()
            best[name] = min(best[name], time.perf_counter() - start)
    return best


def case(label: str, model: LinearModel, speeds: np.ndarray, repeats: int) -> float:
    functions = {
        "eigen_analysis": lambda: eigen_analysis(model, speeds, vectors=False),
        "with_vectors": lambda: eigen_analysis(model, speeds),
        "eigvals": lambda: np.linalg.eigvals(model.state_matrix(speeds)),
        "eig": lambda: np.linalg.eig(model.state_matrix(speeds)),
    }
    interleaved_best(functions, 3)  # warm up (the allocator settles on these array sizes)
    times = interleaved_best(functions, repeats)
    ratio = times["eigen_analysis"] / times["eigvals"]
    print(f"{label:44s} eigen_analysis {times['eigen_analysis'] * 1e3:7.2f} ms   eigvals "
          f"{times['eigvals'] * 1e3:6.2f} ms   eig {times['eig'] * 1e3:6.2f} ms   "
          f"eigen_analysis/eigvals {ratio:5.2f}   with vectors/eigvals "
          f"{times['with_vectors'] / times['eigvals']:5.2f}")
    return ratio


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=200)
    args = parser.parse_args()
    benchmark = linear_model(load_bicycle("benchmark"))
    rng = np.random.default_rng(1)
    parameters = load_bicycle("benchmark").parameters
    varied = {name: value * np.exp(0.1 * rng.standard_normal(20)) for name, value in parameters.items()}
    batch = build_linear_model(varied)
    ratios = [
        case("benchmark bicycle, 1000 speeds 0-10 m/s", benchmark, np.linspace(0.0, 10.0, 1000), args.repeats),
        case("benchmark bicycle, 10000 speeds 0-10 m/s", benchmark, np.linspace(0.0, 10.0, 10000),
             max(args.repeats // 10, 5)),
        case("sbw2024 (controller), 1000 speeds 0-10 m/s", linear_model(load_bicycle("sbw2024")),
             np.linspace(0.0, 10.0, 1000), args.repeats),
        case("20 random bicycles, 1000 speeds 0-10 m/s", batch, np.linspace(0.0, 10.0, 1000),
             max(args.repeats // 10, 5)),
    ]
    print(f"worst eigen_analysis/eigvals: {max(ratios):.2f} (target: within 2)")


if __name__ == "__main__":
    main()
