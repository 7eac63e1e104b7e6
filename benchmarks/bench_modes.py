"""The diagnosis' nearest modes: the characteristic quartic against numpy.linalg.eig, in one run.

Run: ``python benchmarks/bench_modes.py [--windows 67] [--repeat 200]``

A diagnosis fit evaluates, thousands of times for one parameter set, the model's mode nearest
each window's measured weave (eigenvalue and mode shape, at the window's speed). Timed per
evaluation, for the benchmark bicycle with a steer damping (the extended model's code) at
``--windows`` speeds between 2 and 8 m/s:

* ``eig`` (the baseline): the first-order model's state matrices at the speeds and one
  batched ``numpy.linalg.eig``, as the diagnosis did before 2026-11-26 (tests/eig_modes.py);
* ``quartic``: :func:`whipple.stability.nearest_modes.nearest_modes`, which takes M, C(v), K(v)
  and the roots of ``det(M s^2 + C s + K)`` (:mod:`whipple.stability.quartic`);
* the parts of each: building the model, and the eigen-solve alone.

Also prints the largest difference between the two routes' eigenvalues and mode shapes.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from eig_modes import nearest_modes_by_eig  # noqa: E402

from whipple.model.assembly import linear_model, second_order_matrices  # noqa: E402
from whipple.model.parameters import load_bicycle  # noqa: E402
from whipple.stability.nearest_modes import nearest_modes  # noqa: E402
from whipple.stability.quartic import second_order_eigenvalues  # noqa: E402


def _interleaved(functions: dict, repeat: int, rounds: int = 7) -> dict:
    """Best time per call of each function, the functions timed in turn in every round.

    This machine's speed drifts by tens of per cent within minutes; timing the functions one
    after another inside each round lets every ratio compare like with like.
    """
    best = {label: np.inf for label in functions}
    for _ in range(rounds):
        for label, function in functions.items():
            start = time.perf_counter()
            for _ in range(repeat):
                function()
            best[label] = min(best[label], (time.perf_counter() - start) / repeat)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--windows", type=int, default=67)
    parser.add_argument("--repeat", type=int, default=200)
    args = parser.parse_args()

    base = load_bicycle("benchmark")
    bicycle = dataclasses.replace(base, extensions=dataclasses.replace(base.extensions, steer_damping=0.8))
    speeds = np.linspace(2.0, 8.0, args.windows)
    signals = [("steer_angle", "roll_rate")] * args.windows
    weave, _ = nearest_modes_by_eig(bicycle, speeds, np.full(args.windows, 1.0 + 4.0j), signals)
    targets = weave + 0.2 * np.random.default_rng(0).normal(size=args.windows)

    expected = nearest_modes_by_eig(bicycle, speeds, targets, signals)
    found = nearest_modes(bicycle, speeds, targets, signals)
    eigen_error = np.max(np.abs(found[0] - expected[0]) / np.abs(expected[0]))
    shape_error = np.max(np.abs(found[1] - expected[1]) / np.abs(expected[1]))

    A = linear_model(bicycle).state_matrix(speeds)
    M, C, K = second_order_matrices(bicycle, speeds)  # type: ignore[misc]
    times = _interleaved({
        "eig: whole evaluation (baseline)": lambda: nearest_modes_by_eig(bicycle, speeds, targets, signals),
        "eig: model and state matrices": lambda: linear_model(bicycle).state_matrix(speeds),
        "eig: numpy.linalg.eig alone": lambda: np.linalg.eig(A),
        "quartic: whole evaluation": lambda: nearest_modes(bicycle, speeds, targets, signals),
        "quartic: M, C(v), K(v)": lambda: second_order_matrices(bicycle, speeds),
        "quartic: eigenvalues alone": lambda: second_order_eigenvalues(M, C, K),
    }, args.repeat)
    baseline = times["eig: whole evaluation (baseline)"]
    print(f"{args.windows} windows, one parameter set (benchmark bicycle with steer damping)")
    for label, seconds in times.items():
        print(f"  {label:36s} {seconds * 1e6:8.1f} us   {seconds / baseline:5.2f} x baseline")
    print(f"largest relative difference, quartic against eig: eigenvalue {eigen_error:.1e}, "
          f"mode shape {shape_error:.1e}")


if __name__ == "__main__":
    main()
