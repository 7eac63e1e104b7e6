"""Dense-grid critical speeds: the independent check of whipple.stability.critical (tests only).

Nothing here uses whipple but a model's coefficient arrays ``A_k`` (N, T, n, n):

* :func:`dense_check` compares the solver's results with a plain eigenvalue scan: the number of
  unstable eigenvalues on a dense speed grid, every change of that number bisected to
  1e-15 m/s, and the stable ranges read off the grid;
* :func:`grid_critical_speeds` is the method the solver replaced (eigenvalues on a 0.01 m/s grid,
  sign changes of the Hopf and real conditions, bisection), kept for the benchmark;
* :func:`grid_brentq_speeds` is what a user script does (a loop over bicycles and the grid of the
  largest real part, ``scipy.optimize.brentq`` in every cell where it changes sign).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def state_matrices(coefficients: np.ndarray, speed: np.ndarray) -> np.ndarray:
    """A of each model (N, T, n, n) at one speed each (N,) [m/s]."""
    A = np.zeros(coefficients.shape[:1] + coefficients.shape[2:])
    for power in range(coefficients.shape[1] - 1, -1, -1):
        A = A * speed[:, None, None] + coefficients[:, power]
    return A


def unstable_count(coefficients: np.ndarray, speed: np.ndarray) -> np.ndarray:
    """Number of eigenvalues with positive real part, per model (N, T, n, n) and speed (N,)."""
    return np.sum(np.linalg.eigvals(state_matrices(coefficients, speed)).real > 0, axis=-1)


def dense_check(results: list, coefficients: np.ndarray, low: float, high: float,
                points: int) -> dict[str, float]:
    """Compare critical-speed results with a dense eigenvalue sweep on [low, high] m/s.

    Returns counts of disagreements (all must be 0): ``unsound`` (a crossing that does not
    change the unstable count as its kind and direction say), ``unexplained`` (a sweep cell whose
    count changes differently from the crossings found in it), ``missed`` (a change located by
    bisection with no crossing within 1e-9 m/s), ``wrong_range`` (grid speeds inside a stable
    range that are unstable, or the reverse, away from crossings).
    """
    count = coefficients.shape[0]
    speeds = np.linspace(low, high, points)
    counts = unstable_count(np.repeat(coefficients, points, axis=0),
                            np.tile(speeds, count)).reshape(count, points)
    crossing_model = np.array([i for i, r in enumerate(results) for _ in r.crossings], dtype=int)
    crossing = [c for r in results for c in r.crossings]
    crossing_speed = np.array([c.speed for c in crossing])
    # Ends of the range (e.g. a pure imaginary pair exactly at v = 0) are not compared.
    interior = (crossing_speed > low + 1e-6) & (crossing_speed < high - 1e-6)

    jump = np.array([{"destabilising": 1, "stabilising": -1, "touch": 0}[c.direction]
                     * (2 if c.kind == "hopf" else 1) for c in crossing], dtype=int)
    delta = 1e-7
    change = (unstable_count(coefficients[crossing_model], crossing_speed + delta)
              - unstable_count(coefficients[crossing_model], crossing_speed - delta))
    unsound = int(np.sum((change != jump) & interior))

    net = np.zeros_like(counts)
    cell = np.clip(np.searchsorted(speeds, crossing_speed), 1, points - 1)
    np.add.at(net, (crossing_model[interior], cell[interior]), jump[interior])
    unexplained = int(np.sum(np.any(net[:, 2:] != np.diff(counts, axis=1)[:, 1:], axis=1)))

    model_index, index = np.nonzero(counts[:, 1:] != counts[:, :-1])
    a, b = speeds[index], speeds[index + 1]
    below = counts[model_index, index]
    for _ in range(55):
        middle = 0.5 * (a + b)
        same = unstable_count(coefficients[model_index], middle) == below
        a, b = np.where(same, middle, a), np.where(same, b, middle)
    located = 0.5 * (a + b)
    keep = located > low + 1e-6
    worst, missed = 0.0, 0
    order = np.lexsort((crossing_speed, crossing_model))
    sorted_model, sorted_speed = crossing_model[order], crossing_speed[order]
    for model_id, speed in zip(model_index[keep], located[keep], strict=True):
        lo, hi = np.searchsorted(sorted_model, [model_id, model_id + 1])
        distance = np.min(np.abs(sorted_speed[lo:hi] - speed), initial=np.inf)
        worst = max(worst, distance)
        missed += int(distance > 1e-9)

    inside = np.zeros_like(counts, dtype=bool)
    near = np.zeros_like(inside)
    for i, result in enumerate(results):
        for a_, b_ in result.stable_speed_ranges:
            inside[i] |= (speeds > a_) & (speeds < b_) | ((speeds == b_) & (b_ == high))
        for c in result.crossings:
            near[i] |= np.abs(speeds - c.speed) < 1e-9
    wrong_range = int(np.sum(((inside != (counts == 0)) & ~near)[:, 1:]))
    return {"models": count, "crossings": len(crossing), "unsound": unsound,
            "unexplained": unexplained, "missed": missed, "wrong_range": wrong_range,
            "worst_difference": worst,
            "several_ranges": sum(len(r.stable_speed_ranges) > 1 for r in results)}


def _conditions(eigenvalues: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    first, second = np.triu_indices(eigenvalues.shape[-1], 1)
    hopf = np.prod(eigenvalues[..., first] + eigenvalues[..., second], axis=-1).real
    return hopf, np.prod(eigenvalues, axis=-1).real


def grid_critical_speeds(coefficients: np.ndarray, low: float, high: float, step: float = 0.01
                         ) -> list[tuple[list[float], list[tuple[float, float]]]]:
    """The replaced method: conditions from eigenvalues on a grid, sign changes, bisection.

    Returns, per model, the roots of both conditions [m/s] (unverified) and the stable ranges.
    """
    count, _, n, _ = coefficients.shape
    grid = np.linspace(low, high, int(round((high - low) / step)) + 1)
    lam = np.linalg.eigvals(state_matrices(np.repeat(coefficients, grid.size, axis=0),
                                           np.tile(grid, count))).reshape(count, grid.size, n)
    roots: list[list[float]] = [[] for _ in range(count)]
    for kind, values in enumerate(_conditions(lam)):
        model, index = np.nonzero(np.sign(values[:, :-1]) * np.sign(values[:, 1:]) < 0)
        a, b = grid[index], grid[index + 1]
        fa = values[model, index]
        for _ in range(45):
            middle = 0.5 * (a + b)
            fm = _conditions(np.linalg.eigvals(state_matrices(coefficients[model], middle)))[kind]
            left = np.sign(fm) == np.sign(fa)
            a, b, fa = np.where(left, middle, a), np.where(left, b, middle), np.where(left, fm, fa)
        for m, speed in zip(model, 0.5 * (a + b), strict=True):
            roots[m].append(float(speed))
    results = []
    for m in range(count):
        knots = sorted([low, high] + roots[m])
        mids = np.array([0.5 * (x + y) for x, y in zip(knots[:-1], knots[1:], strict=True)])
        stable = np.max(np.linalg.eigvals(state_matrices(coefficients[[m] * mids.size], mids)).real,
                        axis=-1) < 0
        results.append((sorted(roots[m]), [(x, y) for x, y, s in zip(knots[:-1], knots[1:], stable,
                                                                      strict=True) if s]))
    return results


def grid_brentq_speeds(coefficients: np.ndarray, low: float, high: float, step: float = 0.01
                       ) -> list[list[float]]:
    """Per bicycle: the largest real part on a grid, brentq in every cell where it changes sign."""
    out = []
    grid = np.linspace(low, high, int(round((high - low) / step)) + 1)
    for c in coefficients:
        def largest(v: float, c: np.ndarray = c) -> float:
            return float(np.max(np.linalg.eigvals(state_matrices(c[None], np.array([v]))[0]).real))
        values = [largest(v) for v in grid]
        roots = [brentq(largest, grid[i], grid[i + 1], xtol=1e-14)
                 for i in range(grid.size - 1) if values[i] * values[i + 1] < 0]
        out.append(roots)
    return out
