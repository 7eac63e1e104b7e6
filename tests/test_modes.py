"""Tracking eigenvalues over speed and naming the modes: whipple.stability.modes.

Benchmark matrices: Meijaard, Papadopoulos, Ruina & Schwab (2007), Proc. R. Soc. A 463,
Appendix A (K0 published without g), as reproduced in
src/whipple/data/reference/meijaard2007-benchmark.toml.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from whipple.model.assembly import linear_model
from whipple.model.linear import LinearModel, second_order_model
from whipple.model.parameters import load_bicycle
from whipple.stability import modes
from whipple.stability.critical import critical_speeds
from whipple.stability.eigen import eigen_analysis

G = 9.81
M = [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]]
C1 = [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]]
K0 = [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]
K2 = [[0.0, 76.59734589573222], [0.0, 2.65431523794604]]
DOUBLE_ROOT = 0.68428307889246  # [m/s], Table 2(a); the double eigenvalue is 3.78290405129320


def benchmark() -> LinearModel:
    return second_order_model(M, C1, np.array(K0) * G, K2)


def assert_continuous(values: np.ndarray) -> None:
    """Each column moves to its own nearest eigenvalue at the next speed: no hidden swap."""
    step = np.abs(values[..., 1:, :] - values[..., :-1, :])
    cross = np.abs(values[..., 1:, None, :] - values[..., :-1, :, None])
    n = values.shape[-1]
    cross[..., np.arange(n), np.arange(n)] = np.inf
    assert np.all(step <= np.min(cross, axis=-1) + 1e-12)


def test_labels_never_swap_on_the_benchmark() -> None:
    speeds = np.linspace(0.0, 10.0, 10001)
    result = eigen_analysis(benchmark(), speeds)
    labels, values = result.labels, result.eigenvalues
    before = speeds < DOUBLE_ROOT
    # Columns: the two weave-forming modes, then capsize, then castering.
    assert set(labels[before, 0]) == {"weave_real_upper"}
    assert set(labels[before, 1]) == {"weave_real_lower"}
    assert set(labels[~before, 0]) == set(labels[~before, 1]) == {"weave"}
    assert set(labels[:, 2]) == {"capsize"} and set(labels[:, 3]) == {"castering"}
    assert_continuous(values)
    # The capsize eigenvalue passes through zero at the capsize speed without a relabel.
    capsize = values[:, 2].real
    assert capsize[0] < 0 < capsize[-1]


def test_merge_into_weave_at_the_published_double_root() -> None:
    result = eigen_analysis(benchmark(), [DOUBLE_ROOT - 1e-6, DOUBLE_ROOT + 1e-6])
    assert list(result.labels[0, :2]) == ["weave_real_upper", "weave_real_lower"]
    assert list(result.labels[1, :2]) == ["weave", "weave"]
    # Near a double root eigenvalues are only resolved to the square root of round-off.
    np.testing.assert_allclose(result.eigenvalues[:, :2].real, 3.78290405129320, atol=1e-2)
    assert result.mode("weave")[1].imag > 0


def test_track_undoes_any_shuffle() -> None:
    rng = np.random.default_rng(4)
    speeds = np.linspace(0.0, 10.0, 400)
    model = second_order_model(np.stack([M] * 3), C1, np.array(K0) * G, K2)
    values = np.linalg.eigvals(model.state_matrix(speeds))
    shuffled = np.take_along_axis(values, rng.permuted(np.broadcast_to(
        np.arange(4), values.shape), axis=-1), axis=-1)
    tracked = np.take_along_axis(shuffled, modes.track(shuffled), axis=-1)
    np.testing.assert_array_equal(np.sort_complex(tracked), np.sort_complex(values))
    assert_continuous(tracked)
    # Branches start sorted by real part at the first speed.
    assert np.all(np.diff(tracked[:, 0].real, axis=-1) >= 0)


def test_labels_do_not_depend_on_the_requested_speeds() -> None:
    model = benchmark()
    alone = eigen_analysis(model, [2.0])
    among = eigen_analysis(model, np.linspace(0.0, 10.0, 11))
    np.testing.assert_array_equal(alone.labels[0], among.labels[2])
    np.testing.assert_array_equal(alone.eigenvalues[0], among.eigenvalues[2])


def test_negative_speeds_mirror_the_spectrum() -> None:
    result = eigen_analysis(benchmark(), [-3.0, 3.0])
    np.testing.assert_allclose(np.sort_complex(-result.eigenvalues[0]),
                               np.sort_complex(result.eigenvalues[1]), atol=1e-12)


def extended_model(coupling: float = 1.0) -> LinearModel:
    """Whipple benchmark with two extra first-order states (a steer-torque lag with relaxation
    rate 20 + 5 v [1/s] and a fast lateral state), weakly coupled: a stand-in for extensions
    with extra real modes, built from polynomial coefficients only."""
    base = benchmark()
    A = np.zeros((3, 6, 6))
    A[:, :4, :4] = base.A
    A[0, 4, 4], A[1, 4, 4] = -20.0, -5.0
    A[0, 4, 1] = 2.0 * coupling          # lag driven by the steer angle
    A[0, 3, 4] = 0.5 * coupling          # and feeding the steer acceleration
    A[0, 5, 5] = -60.0
    A[0, 5, 0] = 1.0 * coupling
    A[0, 2, 5] = 0.2 * coupling
    names = base.state_names + ("lag", "lateral")
    return LinearModel(A, np.zeros((1, 6, 2)), names, base.state_units + ("N m", "m/s"))


def test_extended_model_keeps_the_whipple_labels() -> None:
    speeds = np.linspace(0.0, 10.0, 2001)
    result = eigen_analysis(extended_model(), speeds)
    labels = result.labels
    assert set(labels[speeds > 1.0, 0]) == {"weave"}
    assert set(labels[:, 2]) == {"capsize"} and set(labels[:, 3]) == {"castering"}
    assert set(labels[:, 4]) == {"mode_5"} and set(labels[:, 5]) == {"mode_6"}
    # Without coupling the Whipple modes are exactly the benchmark's.
    uncoupled = eigen_analysis(extended_model(0.0), [5.0])
    whipple = eigen_analysis(benchmark(), [5.0])
    for name in ("weave", "capsize", "castering"):
        assert uncoupled.mode(name)[0] == pytest.approx(whipple.mode(name)[0], abs=1e-12)
    critical = critical_speeds(extended_model())
    assert critical.weave_speed is not None and critical.capsize_speed is not None
    assert abs(critical.weave_speed - 4.29) < 0.5 and abs(critical.capsize_speed - 6.02) < 0.5


def test_controller_with_speed_dependent_gain_keeps_labels_consistent() -> None:
    # Steer torque += (8 - 1 v) * roll rate [N m s/rad]: gains polynomial in v.
    gain0, gain1 = np.zeros((2, 4)), np.zeros((2, 4))
    gain0[1, 2], gain1[1, 2] = 8.0, -1.0
    model = second_order_model(M, C1, np.array(K0) * G, K2, feedback=[gain0, gain1])
    speeds = np.linspace(0.0, 10.0, 2001)
    labels = eigen_analysis(model, speeds).labels
    for column in range(4):
        changes = np.flatnonzero(labels[1:, column] != labels[:-1, column])
        # At most one change per column: a weave-forming real mode joining the weave.
        assert changes.size <= 1
        for index in changes:
            assert labels[index + 1, column] == "weave"
            assert labels[index, column].startswith("weave_real")


def test_assignment_is_optimal_and_breaks_ties_like_scipy() -> None:
    # Independent check of the assignment used at ambiguous tracking steps: brute force over
    # all permutations for the optimum, and SciPy's solver for the choice among equal optima.
    linear_sum_assignment = pytest.importorskip("scipy.optimize").linear_sum_assignment
    rng = np.random.default_rng(7)
    for n in (1, 2, 3, 4, 5):
        permutations = np.array(list(itertools.permutations(range(n))))
        for _ in range(200):
            cost = rng.random((n, n)) ** 2
            if rng.random() < 0.5:  # equal rows: two equal eigenvalues at a double root
                cost = np.round(cost * 3) / 3
                cost[1 % n] = cost[0]
            chosen = modes.assignment(cost)
            totals = cost[np.arange(n), permutations].sum(axis=-1)
            assert cost[np.arange(n), chosen].sum() == pytest.approx(totals.min(), abs=1e-12)
            np.testing.assert_array_equal(chosen, linear_sum_assignment(cost)[1])


def test_track_of_eigenvalues_whose_squared_distances_overflow() -> None:
    # Eigenvalues of about 1e159 (a controller polynomial of 160 terms in the speed): their
    # squared distances are infinite, on which the assignment never ended (whipple check hung).
    # Both of the first speed's eigenvalues are nearest the second's first: an ambiguous step.
    values = np.array([[[0.0, 1e159], [4e159, 6e159]]], dtype=complex)
    np.testing.assert_array_equal(modes.track(values)[0, 1], [0, 1])
    np.testing.assert_array_equal(modes.track(values[..., ::-1])[0, 1], [1, 0])


def test_labels_that_cannot_all_be_right_are_not_given() -> None:
    # A nearly massless rear frame with its inertia (mB = 1e-3 kg, IBxx = 9.2 kg m^2): the
    # oscillation passes from one pair of branches to another over speed, and the weave group
    # then held all four branches (three labelled weave_real_lower at v = 0).
    bicycle = load_bicycle("benchmark").with_parameters(mB=1e-3)
    result = eigen_analysis(linear_model(bicycle), np.linspace(0.0, 10.0, 201), vectors=False)
    labels = result.labels
    for row, values in zip(labels.reshape(-1, labels.shape[-1]), result.eigenvalues.reshape(-1, labels.shape[-1]),
                           strict=True):
        row = list(row)
        assert row.count("weave") in (0, 2)
        assert row.count(modes.WEAVE_UPPER) <= 1 and row.count(modes.WEAVE_LOWER) <= 1
        weave = values[[k for k, name in enumerate(row) if name == "weave"]]
        assert np.allclose(weave, np.conj(weave[::-1]))
    at_rest = list(labels.reshape(-1, labels.shape[-1])[0])
    assert at_rest.count(modes.WEAVE_UPPER) == 1 and at_rest.count(modes.WEAVE_LOWER) == 1
