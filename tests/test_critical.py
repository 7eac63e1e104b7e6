"""Critical speeds, stable speed ranges and their uncertainty: whipple.stability.critical.

Published values used (facts, not code):

* benchmark bicycle: Meijaard, Papadopoulos, Ruina & Schwab (2007), Proc. R. Soc. A 463,
  1955-1982 — matrices of Appendix A (K0 without g) and the weave and capsize speeds of
  Table 2(a), as reproduced in src/whipple/data/reference/meijaard2007-benchmark.toml;
* seed bicycle: Kooijman & Schwab (2009), DETC2009-86965, matrices of eq. (2) (K0 with g) and
  the weave (about 4.0 m/s) and capsize (about 7.9 m/s) speeds of Figure 6.
"""

from __future__ import annotations

import casadi
import numpy as np
import pytest
from grid_critical import dense_check

from whipple.errors import AnalysisError, InputError
from whipple.model.linear import LinearModel, second_order_model
from whipple.stability.characteristic import (
    condition_functions,
    hopf_condition,
    real_condition,
    sparsity_pattern,
)
from whipple.stability.critical import critical_speeds, critical_speeds_batch
from whipple.stability.polynomial import evaluate
from whipple.stability.polyroots import real_roots
from whipple.stability.uncertainty import critical_speed_uncertainty

G = 9.81
M = np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]])
C1 = np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]])
K0 = np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]) * G
K2 = np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]])
WEAVE_SPEED = 4.29238253634111
CAPSIZE_SPEED = 6.02426201538837


def benchmark() -> LinearModel:
    return second_order_model(M, C1, K0, K2)


def test_benchmark_weave_and_capsize_speeds_to_1e_12() -> None:
    # Measured from the published matrices: |error| 2.1e-14 (weave) and 5.4e-14 (capsize).
    result = critical_speeds(benchmark())
    assert abs(result.weave_speed - WEAVE_SPEED) < 1e-12
    assert abs(result.capsize_speed - CAPSIZE_SPEED) < 1e-12
    assert result.weave_speeds == (result.weave_speed,)
    assert result.capsize_speeds == (result.capsize_speed,)
    assert result.stable_speed_ranges == ((result.weave_speed, result.capsize_speed),)
    weave, capsize = result.crossings
    assert (weave.kind, weave.mode, weave.direction) == ("hopf", "weave", "stabilising")
    assert (capsize.kind, capsize.mode, capsize.direction) == ("real", "capsize",
                                                               "destabilising")
    # The Whipple conditions are quadratics in v^2: closed form, then Newton.
    assert weave.method.startswith("closed-form") and capsize.method.startswith("closed-form")
    # Table 2(a): weave eigenvalues at the weave speed are +/- 3.43503384866144 i.
    assert weave.eigenvalue.imag == pytest.approx(3.43503384866144, abs=1e-12)
    assert abs(weave.eigenvalue.real) < 1e-12 and abs(capsize.eigenvalue) < 1e-12


def test_unpolished_roots_agree_with_polished_ones() -> None:
    polished = critical_speeds(benchmark())
    bisected = critical_speeds(benchmark(), polish=False)
    assert {c.method for c in bisected.crossings} == {"closed-form"}
    assert abs(polished.weave_speed - bisected.weave_speed) < 1e-12
    assert abs(polished.capsize_speed - bisected.capsize_speed) < 1e-12


def test_seed_bicycle_is_stable_between_about_4_and_7_9() -> None:
    seed = second_order_model(
        [[7.98981, 0.89569], [0.89569, 0.29857]], [[0.0, 7.17025], [-0.59389, 1.32610]],
        [[-109.91168, -13.45745], [-13.45745, -4.82272]], [[0.0, 11.19798], [0.0, 1.42200]])
    result = critical_speeds(seed)
    assert result.weave_speed == pytest.approx(4.0, abs=0.05)
    assert result.capsize_speed == pytest.approx(7.9, abs=0.05)
    assert result.stable_speed_ranges == ((result.weave_speed, result.capsize_speed),)


def test_casadi_conditions_are_orlando_products() -> None:
    rng = np.random.default_rng(2)
    for n in (2, 3, 4, 5, 6):
        coefficients = rng.standard_normal((3, n, n))
        function = condition_functions(sparsity_pattern(coefficients))
        for speed in (0.0, 0.7, 3.0):
            A = coefficients[0] + speed * coefficients[1] + speed**2 * coefficients[2]
            hopf, real = (float(x) for x in function(speed, coefficients.ravel()))
            eigenvalues = np.linalg.eigvals(A)
            assert hopf == pytest.approx(hopf_condition(eigenvalues), rel=1e-10)
            assert real == pytest.approx(real_condition(eigenvalues), rel=1e-10)


def polynomial(roots: list[float], factor: float) -> np.ndarray:
    """Coefficients, constant first, of factor * prod (v - root)."""
    return factor * np.polynomial.polynomial.polyfromroots(roots)


def synthetic_model() -> LinearModel:
    """A complex pair s(v) +/- i (2 + v) and real eigenvalues r(v), q(v) with known zeros:
    s = -(v - 1)(v - 1.003)(v - 6): two Hopf crossings 3 mm/s apart, inside one grid cell;
    r = -(v - 7)^2: touches zero at 7 m/s; q = v - 8: crosses at 8 m/s."""
    s = polynomial([1.0, 1.003, 6.0], -1.0)
    r = polynomial([7.0, 7.0], -1.0)
    q = polynomial([8.0], 1.0)
    A = np.zeros((4, 4, 4))
    A[: s.size, 0, 0] = A[: s.size, 1, 1] = s
    A[:2, 0, 1] = [2.0, 1.0]
    A[:2, 1, 0] = [-2.0, -1.0]
    A[: r.size, 2, 2] = r
    A[: q.size, 3, 3] = q
    return LinearModel(A, np.zeros((1, 4, 2)))


def test_all_crossings_close_pairs_touches_and_several_stable_ranges() -> None:
    result = critical_speeds(synthetic_model(), step=0.01)
    found = [(c.kind, c.direction) for c in result.crossings]
    assert found == [("hopf", "stabilising"), ("hopf", "destabilising"),
                     ("hopf", "stabilising"), ("real", "touch"), ("real", "destabilising")]
    speeds = [c.speed for c in result.crossings]
    np.testing.assert_allclose(speeds[:3] + speeds[4:], [1.0, 1.003, 6.0, 8.0], atol=1e-12)
    # A tangential root is located by a minimum search: to about sqrt(round-off).
    assert speeds[3] == pytest.approx(7.0, abs=1e-6)
    ranges = result.stable_speed_ranges
    assert len(ranges) == 3
    np.testing.assert_allclose(np.array(ranges), [[1.0, 1.003], [6.0, speeds[3]],
                                                  [speeds[3], 8.0]], atol=1e-12)


def test_no_crossing_and_ranges_reaching_the_ends() -> None:
    always_stable = LinearModel(np.array([[[-1.0, 2.0], [-2.0, -1.0]]]), np.zeros((1, 2, 1)))
    result = critical_speeds(always_stable, 0.5, 3.0)
    assert result.crossings == () and result.stable_speed_ranges == ((0.5, 3.0),)
    assert result.weave_speed is None and result.capsize_speed is None
    never = critical_speeds(benchmark(), 0.0, 4.0)
    assert never.stable_speed_ranges == () and never.weave_speed is None


def test_batch_keeps_order_and_reports_progress() -> None:
    scale = np.linspace(0.8, 1.2, 6).reshape(2, 3, 1, 1)
    batch = second_order_model(M, C1, K0 * scale, K2)
    finished: list[int] = []
    results = critical_speeds_batch(batch, chunk_size=4, progress=finished.append)
    assert len(results) == 6 and finished == [4, 6]
    for index, result in enumerate(results):
        alone = critical_speeds(batch.select(np.unravel_index(index, (2, 3))))
        assert result == alone
    with pytest.raises(ValueError):
        critical_speeds(batch)


def test_bad_ranges_raise_input_error() -> None:
    for low, high in ((3.0, 1.0), (0.0, np.nan), (1.0, 1.0)):
        with pytest.raises(InputError):
            critical_speeds(benchmark(), low, high)


# --- property test against an independent dense sweep ------------------------------------

def random_models(rng: np.random.Generator, count: int, flip: float) -> LinearModel:
    """Random bicycles around the benchmark: entries scaled by log-normal factors (sd 0.35),
    M kept symmetric positive definite and K0 symmetric, and a fraction `flip` of the entries
    of C1, K0 and K2 with their sign flipped (to reach unusual stability patterns)."""
    def factor() -> np.ndarray:
        return np.exp(0.35 * rng.standard_normal((count, 2, 2)))

    mass = M * factor()
    mass[:, 1, 0] = mass[:, 0, 1]
    determinant = mass[:, 0, 0] * mass[:, 1, 1] - mass[:, 0, 1] ** 2
    small = determinant <= 0.05 * mass[:, 0, 0] * mass[:, 1, 1]
    mass[small, 0, 1] = mass[small, 1, 0] = 0.5 * np.sqrt(mass[small, 0, 0] * mass[small, 1, 1])
    matrices = []
    for base in (C1, K0, K2):
        matrix = base * factor() * np.where(rng.random((count, 2, 2)) < flip, -1.0, 1.0)
        matrices.append(matrix)
    matrices[1][:, 1, 0] = matrices[1][:, 0, 1]
    return second_order_model(mass, *matrices)


def check_against_sweep(model: LinearModel, step: float, points: int) -> dict[str, float]:
    """Compare critical_speeds_batch with a dense eigenvalue sweep on [0, 10] m/s.

    The sweep (``grid_critical.dense_check``) counts unstable eigenvalues on `points` speeds and
    bisects every change of the count; it uses nothing from whipple but the model's matrices.
    """
    results = critical_speeds_batch(model, 0.0, 10.0, step=step)
    report = dense_check(results, model.A.reshape((-1,) + model.A.shape[-3:]), 0.0, 10.0, points)
    report["safety_net"] = sum(c.method == "eigenvalue-bisection" for r in results for c in r.crossings)
    return report


def assert_agrees(report: dict[str, float]) -> None:
    for key in ("unsound", "unexplained", "missed", "wrong_range", "safety_net"):
        assert report[key] == 0, report


def test_random_bicycles_agree_with_a_dense_sweep() -> None:
    # 2000 random bicycles, half with sign flips; grid step 0.05 m/s (coarser than the default)
    # so that close crossings fall in one cell; sweep on 0.01 m/s.
    rng = np.random.default_rng(20240607)
    for flip in (0.0, 0.1):
        report = check_against_sweep(random_models(rng, 1000, flip), step=0.05, points=1001)
        assert report["crossings"] > 700
        assert_agrees(report)


@pytest.mark.slow
def test_many_random_bicycles_agree_with_a_dense_sweep() -> None:
    # 15000 random bicycles at the default grid step, sweep on 0.005 m/s (about 4 minutes).
    rng = np.random.default_rng(7)
    for flip in (0.0, 0.05, 0.2):
        for _ in range(2):
            report = check_against_sweep(random_models(rng, 2500, flip), step=0.01, points=2001)
            assert_agrees(report)


def test_controlled_bicycles_agree_with_a_dense_sweep() -> None:
    # Steer torque += (k0 + k1 v) * roll rate + k2 * roll: gains polynomial in v.
    rng = np.random.default_rng(11)
    count = 200
    gain0, gain1 = np.zeros((count, 2, 4)), np.zeros((count, 2, 4))
    gain0[:, 1, 2] = rng.uniform(-5.0, 15.0, count)
    gain1[:, 1, 2] = rng.uniform(-2.0, 1.0, count)
    gain0[:, 1, 0] = rng.uniform(-20.0, 20.0, count)
    model = second_order_model(M, C1, K0, K2, feedback=[gain0, gain1])
    assert_agrees(check_against_sweep(model, step=0.05, points=1001))


# --- uncertainty -------------------------------------------------------------------------

def toy_state_function(kind: str) -> casadi.Function:
    """A(v, p) of the benchmark with p scaling K0[0,0], C1[0,1], K2[0,1] and M[1,1]; built
    with a linear solve (MX only) or an explicit inverse (SX)."""
    symbol = casadi.MX if kind == "MX" else casadi.SX
    v, p = symbol.sym("v"), symbol.sym("p", 4)
    mass = symbol(casadi.DM(M))
    mass[1, 1] = M[1, 1] * p[3]
    damping = symbol(casadi.DM(C1))
    damping[0, 1] = C1[0, 1] * p[1]
    stiffness = symbol(casadi.DM(K0))
    stiffness[0, 0] = K0[0, 0] * p[0]
    speed_stiffness = symbol(casadi.DM(K2))
    speed_stiffness[0, 1] = K2[0, 1] * p[2]
    inverse = casadi.inv(mass) if kind == "MX" else casadi.inv_minor(mass)
    A = casadi.vertcat(
        casadi.horzcat(symbol.zeros(2, 2), symbol.eye(2)),
        casadi.horzcat(-inverse @ (stiffness + v**2 * speed_stiffness),
                       -inverse @ (v * damping)))
    return casadi.Function("A", [v, p], [A])


def toy_models(parameters: np.ndarray) -> LinearModel:
    count = parameters.shape[0]
    mass, damping, stiffness, speed_stiffness = (
        np.broadcast_to(X, (count, 2, 2)).copy() for X in (M, C1, K0, K2))
    stiffness[:, 0, 0] *= parameters[:, 0]
    damping[:, 0, 1] *= parameters[:, 1]
    speed_stiffness[:, 0, 1] *= parameters[:, 2]
    mass[:, 1, 1] *= parameters[:, 3]
    return second_order_model(mass, damping, stiffness, speed_stiffness)


def test_first_order_uncertainty_matches_monte_carlo() -> None:
    nominal, std = np.ones(4), np.full(4, 0.0025)
    function = toy_state_function("MX")
    weave = critical_speed_uncertainty(function, nominal, std, WEAVE_SPEED, "weave")
    capsize = critical_speed_uncertainty(function, nominal, std, CAPSIZE_SPEED, "capsize")
    assert abs(weave.speed - WEAVE_SPEED) < 1e-12 and abs(capsize.speed - CAPSIZE_SPEED) < 1e-12
    assert weave.kind == "hopf" and capsize.kind == "real"
    # C1 does not enter det(K0 + v^2 K2): the capsize speed cannot depend on it.
    assert capsize.sensitivity[1] == 0.0
    rng = np.random.default_rng(5)
    samples = nominal + std * rng.standard_normal((2000, 4))
    results = critical_speeds_batch(toy_models(samples), step=0.05)
    weave_mc = np.array([r.weave_speed for r in results], dtype=float)
    capsize_mc = np.array([r.capsize_speed for r in results], dtype=float)
    # Sampling error of a standard deviation from 2000 samples is about 1.6 %.
    assert np.std(weave_mc, ddof=1) == pytest.approx(weave.std, rel=0.05)
    assert np.std(capsize_mc, ddof=1) == pytest.approx(capsize.std, rel=0.05)
    # The sensitivities agree with finite differences of the solved speeds.
    step = 1e-6
    for index in range(4):
        shifted = nominal.copy()
        shifted[index] += step
        moved = critical_speeds(toy_models(shifted[None]).select(0))
        assert (moved.weave_speed - WEAVE_SPEED) / step == pytest.approx(
            weave.sensitivity[index], rel=1e-4, abs=1e-6)


def test_uncertainty_accepts_sx_functions_and_a_covariance() -> None:
    covariance = np.diag(np.full(4, 0.0025**2))
    covariance[0, 2] = covariance[2, 0] = 0.5 * 0.0025**2
    with_mx = critical_speed_uncertainty(toy_state_function("MX"), np.ones(4), covariance,
                                         4.3, "weave")
    with_sx = critical_speed_uncertainty(toy_state_function("SX"), np.ones(4), covariance,
                                         4.3, "hopf")
    assert with_mx.std == pytest.approx(with_sx.std, rel=1e-10)
    assert abs(with_sx.speed - WEAVE_SPEED) < 1e-12


def test_uncertainty_rejects_bad_input() -> None:
    function = toy_state_function("SX")
    with pytest.raises(InputError):
        critical_speed_uncertainty(function, np.ones(4), np.ones(3), 4.3, "weave")
    with pytest.raises(InputError):
        critical_speed_uncertainty(function, np.ones(4), -np.ones(4), 4.3, "weave")
    with pytest.raises(InputError):
        critical_speed_uncertainty(function, np.ones(4), np.ones(4), 4.3, "wobble")
    with pytest.raises(AnalysisError):
        # The real condition has no root near 1 m/s: Newton cannot converge there.
        critical_speed_uncertainty(function, np.ones(4), np.ones(4), 1.0, "capsize")


def test_close_real_roots_that_the_companion_matrix_splits_into_a_pair_are_found() -> None:
    # The Hopf condition of a tyre-model bicycle (a perturbed data-set bicycle, in u = v^2, from
    # the slow property test): two real roots 1 % apart, v = 1.1098 (an opposite real pair) and
    # v = 1.1221 (the crossing), which the companion matrix returns as a complex pair 2.6 % off
    # the axis; the coefficients span 51 orders of magnitude.
    even = [0.0, 0.0, -2.662127200046332e+34, 3.9174163946606523e+34, -1.1399084791032017e+34,
            -2.331371588756532e+33, 8.73764875821775e+30, 4.591288313090395e+28,
            -1.7355925813410037e+26, -4.5763293449840943e+21, 3401.017420078646,
            -7.235369327468175e-17]
    hopf = np.zeros((1, 2 * len(even) - 1))
    hopf[0, ::2] = even
    roots = real_roots(hopf, 0.0, 10.0)
    inside = roots.speed[roots.speed > 0]
    assert inside.size == 2
    # Each is a sign change of the polynomial itself, to rounding.
    below, _ = evaluate(np.repeat(hopf, 2, axis=0), inside * (1 - 1e-9))
    above, _ = evaluate(np.repeat(hopf, 2, axis=0), inside * (1 + 1e-9))
    assert np.all(np.sign(below) != np.sign(above))
    assert inside[1] == pytest.approx(1.12213351204528, rel=1e-12)
    assert all(method.startswith("companion+scan") for method in roots.method[roots.speed > 0])
