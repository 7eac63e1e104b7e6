"""The closed-form sweep solver for models of the Whipple form against the general solver and eigenvalues.

``critical_speed_table`` solves models of the Whipple form (no steer damping, no controller) in
closed form where that settles their speeds (:mod:`whipple.stability.whipple_form`) and hands
the rest to the general solver, which the dense-grid property tests check. Here: the closed form
gives the general solver's speeds and ranges to rounding on many random bicycles (with and
without payloads and extra steer inertia, several speed intervals), its stable ranges agree with
the eigenvalues on a grid, and the benchmark speeds are exact to 1e-12 m/s.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_critical import CAPSIZE_SPEED, WEAVE_SPEED, benchmark
from test_critical_property import perturbed

from whipple.errors import InputError
from whipple.model.assembly import build_linear_model, whipple_form_matrices
from whipple.model.linear import LinearModel
from whipple.model.parameters import Controller, Extensions, TyreCompliance, load_bicycle, validate_rows
from whipple.stability.critical import (
    CHUNK_SIZE,
    CriticalSpeedTable,
    _general_table,
    critical_speed_table,
    whipple_speed_table,
)
from whipple.stability.whipple_form import is_whipple_form, whipple_form_table

INTERVALS = ((0.0, 10.0), (0.0, 1e6), (2.5, 7.0), (0.0, 3.0))


def random_models(seed: int, count: int, spread: float = 0.25) -> np.ndarray:
    """A's coefficients of `count` random bicycles, half with a rear or front payload and extra
    steer inertia (still of the Whipple form); `spread`: of the log-normal parameter factors."""
    model = build_linear_model(random_parameters(seed, count, spread))
    return model.A.reshape((-1,) + model.A.shape[-3:])


def random_parameters(seed: int, count: int, spread: float = 0.25) -> dict[str, np.ndarray]:
    """The parameters of :func:`random_models`."""
    rng = np.random.default_rng(seed)
    parameters = perturbed(rng, count, spread)
    parameters = {name: values[[not problem for problem in validate_rows(parameters)]]
                  for name, values in parameters.items()}
    count = parameters["w"].size
    half = rng.random(count) < 0.5
    parameters["payload_mass"] = np.where(half, rng.uniform(0.0, 30.0, count), 0.0)
    parameters["payload_x"] = rng.uniform(-0.2, 0.6, count)
    parameters["payload_z"] = rng.uniform(-1.2, -0.3, count)
    parameters["front_payload_mass"] = np.where(~half, rng.uniform(0.0, 8.0, count), 0.0)
    parameters["front_payload_x"] = rng.uniform(0.8, 1.2, count)
    parameters["front_payload_z"] = rng.uniform(-1.0, -0.5, count)
    parameters["steer_inertia"] = rng.uniform(0.0, 0.05, count)
    return parameters


def assert_tables_agree(closed: CriticalSpeedTable, general: CriticalSpeedTable) -> None:
    for name in ("weave_speed", "capsize_speed"):
        np.testing.assert_allclose(getattr(closed, name), getattr(general, name), rtol=1e-12,
                                   atol=0.0, equal_nan=True, err_msg=name)
    np.testing.assert_array_equal(closed.range_model, general.range_model)
    np.testing.assert_allclose(closed.range_low, general.range_low, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(closed.range_high, general.range_high, rtol=1e-12, atol=1e-300)


@pytest.mark.parametrize("low,high", INTERVALS)
def test_closed_form_equals_the_general_solver_on_random_bicycles(low: float, high: float) -> None:
    coefficients = random_models(11, 3000)
    assert is_whipple_form(coefficients)
    closed = whipple_form_table(coefficients, low, high)
    # The closed form must do most of the work (else it is no faster), and what it settles
    # must be what the general solver finds.
    assert closed.settled.mean() > 0.6, closed.settled.mean()
    settled = np.nonzero(closed.settled)[0]
    general = _general_table(coefficients[settled], low, high, True, CHUNK_SIZE)
    mine = np.isin(closed.range_model, settled)
    closed_settled = CriticalSpeedTable(closed.weave_speed[settled], closed.capsize_speed[settled],
                                   np.searchsorted(settled, closed.range_model[mine]),
                                   closed.range_low[mine], closed.range_high[mine])
    assert_tables_agree(closed_settled, general)
    # The public table (closed form plus the general solver for the rest) equals the general one.
    model = build_linear_model_from(coefficients)
    assert_tables_agree(critical_speed_table(model, low, high, chunk_size=700),
                        _general_table(coefficients, low, high, True, CHUNK_SIZE))


@pytest.mark.parametrize("low,high", INTERVALS + ((-1.0, 5.0),))
def test_table_from_the_matrices_is_the_table_of_the_models(low: float, high: float) -> None:
    # A sweep solves Whipple-form models from their matrices without forming the first-order
    # models: the same numbers, bit for bit.
    parameters = random_parameters(31, 2000)
    matrices = whipple_form_matrices(parameters)
    assert matrices is not None
    mine = whipple_speed_table(matrices.M, matrices.C1, matrices.K0, matrices.K2, low, high, chunk_size=700)
    theirs = critical_speed_table(build_linear_model(parameters), low, high, chunk_size=700)
    for name in CriticalSpeedTable.__dataclass_fields__:
        np.testing.assert_array_equal(getattr(mine, name), getattr(theirs, name), err_msg=name)


def test_models_of_other_forms_have_no_whipple_form_matrices() -> None:
    bicycle = load_bicycle("benchmark")
    assert whipple_form_matrices(bicycle.parameters, bicycle.extensions, bicycle.controller) is not None
    assert whipple_form_matrices(bicycle.parameters, Extensions(steer_damping=0.5)) is None
    assert whipple_form_matrices(bicycle.parameters, controller=Controller(steer={"roll_rate": [1.0]})) is None
    assert whipple_form_matrices(bicycle.parameters, Extensions(tyre_compliance=TyreCompliance(15.0, 1.0, 0.1))) is None


def test_bad_matrices_are_refused() -> None:
    M = np.eye(2)
    with pytest.raises(InputError, match="NaN or infinite"):
        whipple_speed_table(M, M, np.full((2, 2), np.nan), M)
    with pytest.raises(InputError, match="speed range"):
        whipple_speed_table(M, M, M, M, 5.0, 1.0)


def build_linear_model_from(coefficients: np.ndarray) -> LinearModel:
    return LinearModel(A=coefficients, B=np.zeros(coefficients.shape[:1] + (1, 4, 2)))


@pytest.mark.slow
def test_closed_form_equals_the_general_solver_on_many_random_bicycles() -> None:
    # 20,000 more bicycles, near the data set's bicycles and far from them (15-30 s).
    for seed, spread in zip(range(12, 16), (0.05, 0.25, 0.5, 1.0), strict=True):
        coefficients = random_models(seed, 5000, spread)
        model = build_linear_model_from(coefficients)
        for low, high in INTERVALS:
            assert_tables_agree(critical_speed_table(model, low, high),
                                _general_table(coefficients, low, high, True, CHUNK_SIZE))


def test_closed_form_stable_ranges_agree_with_eigenvalues_on_a_grid() -> None:
    coefficients = random_models(21, 1500)
    closed = whipple_form_table(coefficients, 0.0, 10.0)
    speeds = np.linspace(0.005, 9.995, 1000)
    A = sum(coefficients[:, None, k] * speeds[None, :, None, None] ** k
            for k in range(coefficients.shape[1]))
    largest = np.max(np.linalg.eigvals(A).real, axis=-1)
    checked = 0
    for index in np.nonzero(closed.settled)[0]:
        mine = closed.range_model == index
        inside = np.zeros(speeds.size, dtype=bool)
        ends = [0.0, 10.0]
        for low, high in zip(closed.range_low[mine], closed.range_high[mine], strict=True):
            inside |= (speeds > low) & (speeds < high)
            ends += [low, high]
        # Away from every range end and where the eigenvalues decide clearly.
        clear = (np.min(np.abs(speeds[:, None] - np.array(ends)[None, :]), axis=-1) > 1e-3) \
            & (np.abs(largest[index]) > 1e-9)
        np.testing.assert_array_equal(inside[clear], largest[index][clear] < 0, err_msg=str(index))
        checked += int(np.any(inside))
    assert checked > 300, checked


def test_benchmark_speeds_to_1e_12() -> None:
    table = critical_speed_table(benchmark())
    assert whipple_form_table(benchmark().A.reshape(1, 3, 4, 4), 0.0, 10.0).settled[0]
    assert abs(table.weave_speed[0] - WEAVE_SPEED) < 1e-12
    assert abs(table.capsize_speed[0] - CAPSIZE_SPEED) < 1e-12
    assert table.range_low.tolist() == [table.weave_speed[0]]
    assert table.range_high.tolist() == [table.capsize_speed[0]]


def test_damping_and_controllers_are_not_of_the_whipple_form() -> None:
    parameters = load_bicycle("benchmark").parameters
    plain = build_linear_model(parameters)
    damped = build_linear_model(parameters, Extensions(steer_damping=0.5))
    controlled = build_linear_model(parameters, None, Controller(steer={"roll_rate": (1.0,)}))
    assert is_whipple_form(plain.A.reshape(1, -1, 4, 4))
    assert not is_whipple_form(damped.A.reshape(1, -1, 4, 4))
    assert not is_whipple_form(controlled.A.reshape(1, -1, 4, 4))
