"""Property tests: the polynomial critical-speed solver against the dense-grid check.

Three families of random bicycles, each a perturbation of the bicycles of the BicycleParameters
data set (tests/data/bicycleparameters) and of the benchmark and Kooijman (2008) bicycles:

* Whipple models: every benchmark parameter scaled by a log-normal factor;
* the same with a controller whose gains are polynomials in v (steer torque on roll, roll rate
  and steer rate; roll torque on roll rate), random signs and sizes;
* the tyre-compliance model (8 states), tyre values scaled too.

For each, every crossing, stable range and missed crossing is checked by
:func:`grid_critical.dense_check` (a plain eigenvalue scan and bisection). The default suite
runs a few hundred bicycles; the slow test runs more than 10^4.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from grid_critical import dense_check

from whipple.model.assembly import build_linear_model
from whipple.model.linear import second_order_model
from whipple.model.parameters import Controller, Extensions, TyreCompliance, load_bicycle
from whipple.stability.critical import critical_speed_table, critical_speeds_batch
from whipple.stability.eigen import eigen_analysis

DATA = Path(__file__).parent / "data" / "bicycleparameters" / "bicycles"
#: M, C1, K0 (with g) and K2 of the benchmark bicycle (Meijaard et al. 2007, Appendix A).
BENCHMARK = (np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]]),
             np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]]),
             np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]) * 9.81,
             np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]]))
SEEDS = {"whipple": 1, "controller": 2, "tyre": 3}
CHECKS = ("unsound", "unexplained", "missed", "wrong_range")


def base_parameters() -> list[dict[str, float]]:
    """Benchmark parameters of every bicycle of the data set and the two built-in ones."""
    bicycles = [load_bicycle("benchmark"), load_bicycle("kooijman2008")]
    bicycles += [load_bicycle(path) for path in sorted(DATA.glob("*Benchmark.txt"))]
    return [{key: float(value) for key, value in b.parameters.items()} for b in bicycles]


def perturbed(rng: np.random.Generator, count: int, spread: float, wheels: bool = False
              ) -> dict[str, np.ndarray]:
    """`count` parameter sets: a random base bicycle, each parameter times exp(spread N(0,1)).

    With `wheels`, only bases with wheels of positive radius and mass (tyres need a contact
    load and a rolling wheel).
    """
    bases = base_parameters()
    if wheels:
        bases = [b for b in bases if min(b["rR"], b["rF"], b["mR"], b["mF"]) > 0]
    pick = rng.integers(len(bases), size=count)
    names = list(bases[0])
    values = {name: np.array([bases[i][name] for i in pick]) for name in names}
    for name in names:
        if name in ("g",):
            continue
        values[name] = values[name] * np.exp(spread * rng.standard_normal(count))
    return values


def controller(rng: np.random.Generator) -> Controller:
    """Gains polynomial in v (up to quadratic), random signs and sizes [N m per state unit]."""
    return Controller(
        steer={"roll": tuple(rng.normal(0.0, 20.0, 2)),
               "roll_rate": tuple(rng.normal(0.0, [8.0, 2.0, 0.3])),
               "steer_rate": tuple(rng.normal(0.0, 1.0, 1))},
        roll={"roll_rate": tuple(rng.normal(0.0, 5.0, 2))})


def run_family(family: str, rng: np.random.Generator, count: int, points: int
               ) -> dict[str, float]:
    """Solve `count` random bicycles of one family and compare with the dense check."""
    if family == "controller":
        # One controller per batch of bicycles (the Controller applies to a whole batch).
        totals: dict[str, float] = {}
        for _ in range(max(1, count // 50)):
            part = run_models(build_linear_model(perturbed(rng, 50, 0.15), None, controller(rng)),
                              points)
            for key, value in part.items():
                totals[key] = totals.get(key, 0) + value
        return totals
    if family == "tyre":
        tyres = TyreCompliance(11.5 * np.exp(0.3 * rng.standard_normal()),
                               0.57 * np.exp(0.3 * rng.standard_normal()),
                               0.15 * np.exp(0.3 * rng.standard_normal()))
        extensions = Extensions(tyre_compliance=tyres)
        return run_models(build_linear_model(perturbed(rng, count, 0.15, wheels=True), extensions), points)
    return run_models(build_linear_model(perturbed(rng, count, 0.25)), points)


def run_models(model, points: int) -> dict[str, float]:
    coefficients = model.A.reshape((-1,) + model.A.shape[-3:])
    results = critical_speeds_batch(model, 0.0, 10.0)
    report = dense_check(results, coefficients, 0.0, 10.0, points)
    report["with_crossings"] = sum(bool(r.crossings) for r in results)
    return report


@pytest.mark.parametrize("family,count", [("whipple", 300), ("controller", 150), ("tyre", 60)])
def test_random_bicycles_agree_with_the_dense_check(family: str, count: int) -> None:
    report = run_family(family, np.random.default_rng(SEEDS[family]), count, 501)
    assert report["models"] == count
    assert report["with_crossings"] > count // 3, report
    for key in CHECKS:
        assert report[key] == 0, report


@pytest.mark.slow
@pytest.mark.parametrize("family,count", [("whipple", 6000), ("controller", 3000),
                                          ("tyre", 1200)])
def test_many_random_bicycles_agree_with_the_dense_check(family: str, count: int) -> None:
    rng = np.random.default_rng(len(family))
    for _ in range(count // 300 if family != "controller" else count // 300):
        report = run_family(family, rng, 300, 1001)
        for key in CHECKS:
            assert report[key] == 0, report


def test_crossing_modes_match_the_grid_labels_on_benchmark_like_bicycles() -> None:
    # Labels are decided at the roots alone; on bicycles within +/-5 % of the benchmark (entry
    # by entry) they must equal those of eigen_analysis, which tracks branches over 0-10 m/s.
    # (On exotic bicycles the two can differ, e.g. a capsize branch that merges with castering
    # into an oscillatory pair above the capsize speed is `mode_3` on the grid: docs/stability.md.)
    rng = np.random.default_rng(5)
    base = second_order_model(*BENCHMARK)
    factors = 1.0 + 0.05 * rng.uniform(-1.0, 1.0, (4, 80, 2, 2))
    matrices = [X * f for X, f in zip(BENCHMARK, factors, strict=True)]
    for X in (matrices[0], matrices[2]):
        X[:, 1, 0] = X[:, 0, 1]
    model = second_order_model(*matrices)
    assert base.n_states == 4
    checked = 0
    for index, result in enumerate(critical_speeds_batch(model)):
        speeds = [c.speed for c in result.crossings]
        grid = eigen_analysis(model.select(index), speeds)
        for k, crossing in enumerate(result.crossings):
            column = np.argmin(np.abs(grid.eigenvalues[k] - crossing.eigenvalue))
            assert crossing.mode == grid.labels[k][column], (index, crossing)
            checked += 1
    assert checked > 120


@pytest.mark.parametrize("damping", [0.0, 0.3])
def test_the_array_table_equals_the_result_objects(damping: float) -> None:
    # Without damping the models have the Whipple form, which the table solves in closed form
    # (tests/test_whipple_form.py): equal to rounding. With damping it runs the objects' solver:
    # equal exactly.
    rng = np.random.default_rng(9)
    model = build_linear_model(perturbed(rng, 120, 0.25), Extensions(steer_damping=damping))
    results = critical_speeds_batch(model, 0.0, 12.0, chunk_size=40)
    table = critical_speed_table(model, 0.0, 12.0, chunk_size=40)
    rtol = 1e-12 if damping == 0.0 else 0.0
    for index, result in enumerate(results):
        for name in ("weave_speed", "capsize_speed"):
            value = getattr(result, name)
            if value is None:
                assert np.isnan(getattr(table, name)[index])
            else:
                assert getattr(table, name)[index] == pytest.approx(value, rel=rtol, abs=0.0)
        mine = table.range_model == index
        ranges = np.array(result.stable_speed_ranges).reshape(-1, 2)
        np.testing.assert_allclose(table.range_low[mine], ranges[:, 0], rtol=rtol, atol=0.0)
        np.testing.assert_allclose(table.range_high[mine], ranges[:, 1], rtol=rtol, atol=0.0)


def test_negative_speeds_and_the_crossing_at_rest() -> None:
    # Whipple models are odd in v (lambda(-v) = -lambda(v)): a weave that is a pure imaginary
    # pair at v = 0 crosses there, where a1 = a3 = 0 and the closed form is undefined. The
    # dense grid avoids v = 0 itself, where the count of unstable eigenvalues is not defined.
    model = build_linear_model(perturbed(np.random.default_rng(4), 200, 0.25))
    coefficients = model.A.reshape((-1,) + model.A.shape[-3:])
    results = critical_speeds_batch(model, -10.0, 10.0)
    report = dense_check(results, coefficients, -10.0, 10.0, 1000)
    assert sum(c.speed == 0.0 for r in results for c in r.crossings) > 20
    for key in CHECKS:
        assert report[key] == 0, report
