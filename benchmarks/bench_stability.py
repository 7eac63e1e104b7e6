"""Benchmark of the stability analysis against what users do today, measured in the same run.

Run:  python benchmarks/bench_stability.py [--bicycles N]

Cases, per bicycle (benchmark bicycle of Meijaard et al. 2007, matrices of Appendix A):

1. eigenvalues at 1000 speeds from 0 to 10 m/s
   - ours: whipple.stability.eigen.eigen_analysis (batched eig, tracking and mode labels included)
   - baseline: a Python loop over speeds building A(v) and calling numpy.linalg.eig
2. weave and capsize speeds
   - ours: whipple.stability.critical.critical_speeds (exact polynomial conditions, no grid)
   - baseline: loop over a 0.01 m/s grid for the largest real part, then scipy brentq in
     every cell where it changes sign
3. a batch of random bicycles (whipple sweep): critical_speeds_batch per bicycle, with and
   without Newton polishing, against baseline 2 (see bench_critical.py for the full comparison).

Ratios are baseline time / our time (> 1: we are faster). Precision is the distance to the
published weave and capsize speeds (Table 2(a)).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
from scipy.optimize import brentq

from whipple.model.linear import second_order_model
from whipple.stability.critical import critical_speeds, critical_speeds_batch
from whipple.stability.eigen import eigen_analysis

G = 9.81
M = np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]])
C1 = np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]])
K0 = np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]) * G
K2 = np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]])
WEAVE, CAPSIZE = 4.29238253634111, 6.02426201538837


def best_time(function: Callable[[], object], repeats: int = 5) -> float:
    """Shortest wall time [s] of `repeats` calls."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def state_matrix(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray,
                 speed_stiffness: np.ndarray, speed: float) -> np.ndarray:
    """A(v) the way a user script builds it, one speed at a time."""
    inverse = np.linalg.inv(mass)
    A = np.zeros((4, 4))
    A[:2, 2:] = np.eye(2)
    A[2:, :2] = -inverse @ (stiffness + speed**2 * speed_stiffness)
    A[2:, 2:] = -inverse @ (speed * damping)
    return A


Matrices = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def baseline_eigenvalues(matrices: Matrices, speeds: np.ndarray) -> list:
    return [np.linalg.eig(state_matrix(*matrices, speed)) for speed in speeds]


def baseline_critical(matrices: Matrices) -> list[float]:
    """Grid scan of the largest real part at 0.01 m/s, brentq in each sign-change cell."""
    def largest(speed: float) -> float:
        return float(np.max(np.linalg.eigvals(state_matrix(*matrices, speed)).real))

    grid = np.linspace(0.0, 10.0, 1001)
    values = np.array([largest(speed) for speed in grid])
    cells = np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)
    return [brentq(largest, grid[i], grid[i + 1], xtol=1e-14) for i in cells]


def random_bicycles(count: int, seed: int = 1) -> Matrices:
    rng = np.random.default_rng(seed)

    def factor() -> np.ndarray:
        return np.exp(0.2 * rng.standard_normal((count, 2, 2)))

    mass = M * factor()
    mass[:, 1, 0] = mass[:, 0, 1]
    stiffness = K0 * factor()
    stiffness[:, 1, 0] = stiffness[:, 0, 1]
    return mass, C1 * factor(), stiffness, K2 * factor()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bicycles", type=int, default=1000, help="batch size of case 3")
    args = parser.parse_args()
    model = second_order_model(M, C1, K0, K2)
    matrices: Matrices = (M, C1, K0, K2)
    speeds = np.linspace(0.0, 10.0, 1000)

    print("1. eigenvalues at 1000 speeds, one bicycle")
    ours = best_time(lambda: eigen_analysis(model, speeds))
    base = best_time(lambda: baseline_eigenvalues(matrices, speeds))
    print(f"   ours (eig + tracking + labels) {ours * 1e3:8.2f} ms   "
          f"per-speed eig loop {base * 1e3:8.2f} ms   ratio {base / ours:6.2f}")

    print("2. weave and capsize speeds, one bicycle")
    ours = best_time(lambda: critical_speeds(model))
    base = best_time(lambda: baseline_critical(matrices))
    result = critical_speeds(model)
    found = baseline_critical(matrices)
    assert result.weave_speed is not None and result.capsize_speed is not None
    print(f"   ours (critical_speeds)         {ours * 1e3:8.2f} ms   "
          f"grid 0.01 + brentq {base * 1e3:8.2f} ms   ratio {base / ours:6.2f}")
    print(f"   error vs published: ours weave {abs(result.weave_speed - WEAVE):.1e} m/s, "
          f"capsize {abs(result.capsize_speed - CAPSIZE):.1e} m/s; baseline weave "
          f"{abs(found[0] - WEAVE):.1e} m/s, capsize {abs(found[1] - CAPSIZE):.1e} m/s")

    count = args.bicycles
    print(f"3. batch of {count} random bicycles (time per bicycle)")
    batch = random_bicycles(count)
    batch_model = second_order_model(*batch)
    subset = min(count, 50)
    base = best_time(lambda: [baseline_critical((batch[0][i], batch[1][i], batch[2][i],
                                                 batch[3][i])) for i in range(subset)],
                     repeats=1) / subset
    print(f"   baseline grid 0.01 + brentq    {base * 1e3:8.2f} ms (on {subset} bicycles)")
    for polish in (True, False):
        start = time.perf_counter()
        critical_speeds_batch(batch_model, polish=polish)
        ours = (time.perf_counter() - start) / count
        label = "polynomial, Newton polish" if polish else "polynomial, unpolished"
        print(f"   ours {label:27s}{ours * 1e3:8.3f} ms   ratio {base / ours:8.1f}")


if __name__ == "__main__":
    main()
