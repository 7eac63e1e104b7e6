"""Payloads, reflected steer inertia and the controller's actuator (gain, delay, lag): the model support.

Each extension is checked against an independent route: a payload against the rigid-body
composition of the point mass into its frame's benchmark parameters; the reflected inertia
against the model without it; the Pade-approximated delay against the exact characteristic
equation with ``exp(-s tau)`` solved by Newton's method.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from whipple.errors import InputError
from whipple.model.actuator import (
    PADE_ORDER,
    actuator_realisation,
    delay_eigenvalue,
    pade_denominator,
    with_actuator,
)
from whipple.model.assembly import (
    EXTENDED_PARAMETERS,
    EXTENSION_EFFECTS,
    MODEL_PARAMETERS,
    build_linear_model,
    extended_matrices,
    linear_model,
    model_matrices,
    whipple_matrices,
)
from whipple.model.bodies import Body, combine, frame_body
from whipple.model.casadi_model import casadi_state_function
from whipple.model.linear import second_order_model
from whipple.model.parameters import (
    Controller,
    Extensions,
    Payload,
    TyreCompliance,
    load_bicycle,
    read_bicycle_toml,
    write_bicycle_toml,
)
from whipple.simulation.nonlinear_bicycle import nonlinear_parameters
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run
from whipple.stability.critical import critical_speeds


def _composed(parameters: dict[str, float], letter: str, payload: Payload) -> dict[str, float]:
    """The frame's benchmark parameters with the point mass joined to it."""
    joined = combine(frame_body(parameters, letter), Body(payload.mass, payload.x, payload.z, 0.0, 0.0, 0.0, 0.0))
    result = dict(parameters)
    for field in ("mass", "x", "z"):
        result[{"mass": "m", "x": "x", "z": "z"}[field] + letter] = float(getattr(joined, field))
    for axes in ("xx", "zz", "xz"):
        result[f"I{letter}{axes}"] = float(getattr(joined, axes))
    return result


def _assert_matrices_equal(first, second) -> None:
    for name, a, b in zip(first._fields, first, second, strict=True):
        scale = max(np.abs(a).max(), np.abs(b).max(), 1.0)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)


@pytest.mark.parametrize("name", ["benchmark", "sbw2024"])
@pytest.mark.parametrize("frame, letter", [("payload", "B"), ("front_payload", "H")])
def test_payload_equals_rigid_body_composition(name, frame, letter):
    bicycle = load_bicycle(name)
    parameters = bicycle.parameters
    for payload in (Payload(7.0, 0.3 * parameters["w"], -0.9), Payload(2.5, parameters["w"] + 0.2, -1.1),
                    Payload(12.0, -0.25, -0.45)):
        with_payload = extended_matrices(parameters, Extensions(**{frame: payload}))
        composed = whipple_matrices(_composed(parameters, letter, payload))
        _assert_matrices_equal(with_payload, composed)


@pytest.mark.parametrize("name", ["benchmark", "sbw2024"])
def test_reflected_steer_inertia_adds_to_the_steer_mass_alone(name):
    bicycle = load_bicycle(name)
    base = extended_matrices(bicycle.parameters, bicycle.extensions)
    value = 0.37
    changed = extended_matrices(bicycle.parameters, dataclasses.replace(bicycle.extensions,
                                                                        reflected_steer_inertia=value))
    for field, a, b in zip(base._fields, base, changed, strict=True):
        difference = b - a
        if field == "M":
            assert difference[1, 1] == pytest.approx(value, rel=1e-13)
            difference[1, 1] = 0.0
        assert np.all(difference == 0.0), field
    # The rigid form J s s^T also couples roll and steer (the steer axis is tilted).
    rigid = extended_matrices(bicycle.parameters, dataclasses.replace(bicycle.extensions, steer_inertia=value))
    assert rigid.M[0, 1] != base.M[0, 1]


def test_unit_controller_settings_give_exactly_the_feedback_model():
    bicycle = load_bicycle("sbw2024")
    plain = Controller(steer=bicycle.controller.steer)
    explicit = Controller(steer=bicycle.controller.steer, gain_scale=1.0, delay=0.0, lag=0.0)
    m = model_matrices(bicycle.parameters, bicycle.extensions)
    raw = [np.zeros((2, 4)), np.zeros((2, 4))]
    raw[0][1, 2], raw[1][1, 2] = 13.0, -2.0
    by_hand = second_order_model(m.M, m.C1, m.K0, m.K2, damping=m.D, feedback=raw)
    for controller in (plain, explicit):
        model = linear_model(bicycle.with_controller(controller))
        assert np.array_equal(model.A, by_hand.A) and np.array_equal(model.B, by_hand.B)
        assert model.state_names == by_hand.state_names


def test_gain_scale_scales_the_commanded_torque():
    bicycle = load_bicycle("sbw2024")
    scaled = linear_model(bicycle.with_controller(dataclasses.replace(bicycle.controller, gain_scale=1.7)))
    doubled = linear_model(bicycle.with_controller(Controller(steer={"roll_rate": (13.0 * 1.7, -2.0 * 1.7)})))
    np.testing.assert_allclose(scaled.A, doubled.A, rtol=1e-14, atol=1e-12)


def test_pade_denominators_and_all_pass():
    np.testing.assert_allclose(pade_denominator(1), [1, 1 / 2])
    np.testing.assert_allclose(pade_denominator(3), [1, 1 / 2, 1 / 10, 1 / 120])
    # The realisation's transfer function is Q(-s tau) / Q(s tau): all-pass, and exp(-s tau) at low s.
    tau = 0.08
    for order in (1, 2, 3, 4):
        actuator = actuator_realisation(tau, 0.0, order)
        for s in (0.3j, 2.0j, 1.0 + 5.0j):
            value = (actuator.c @ np.linalg.solve(s * np.eye(order) - actuator.a, actuator.b))[0, 0] + actuator.d
            q = pade_denominator(order)
            numerator = (q * (-1.0) ** np.arange(order + 1))[::-1]
            expected = np.polyval(numerator, s * tau) / np.polyval(q[::-1], s * tau)
            assert value == pytest.approx(expected, rel=1e-12)
            assert value == pytest.approx(np.exp(-s * tau), abs=abs(s * tau) ** (2 * order + 1))
            if s.real == 0:
                assert abs(value) == pytest.approx(1.0, rel=1e-12)


def _weave(model, speed, near):
    values = np.linalg.eigvals(model.state_matrix(speed))
    values = values[values.imag > 0]
    return values[np.argmin(np.abs(values - near))]


@pytest.mark.parametrize("delay, lag", [(0.05, 0.0), (0.1, 0.0), (0.2, 0.0), (0.1, 0.05)])
def test_pade_weave_converges_to_the_exact_delay_root(delay, lag):
    bicycle = load_bicycle("sbw2024")
    controller = dataclasses.replace(bicycle.controller, delay=delay, lag=lag)
    plant = build_linear_model(bicycle.parameters, bicycle.extensions, None)
    speed = 3.0
    undelayed = _weave(linear_model(bicycle), speed, 9j)
    errors = []
    for order in (1, 2, 3, 4):
        guess = _weave(with_actuator(plant, controller, order), speed, undelayed)
        exact = delay_eigenvalue(plant, controller, speed, guess)
        errors.append(abs(guess - exact))
    # Measured (3 m/s): order 1..4 errors 5e-2, 2e-4, 4e-7, 4e-10 1/s at 0.05 s; 2.6e-1, 3.4e-3, 2.0e-5,
    # 6e-8 at 0.1 s; 7e-1, 2.1e-2, 3.1e-4, 2.6e-6 at 0.2 s; bound each with a factor of ~3 margin.
    assert all(later < earlier / 10 for earlier, later in zip(errors, errors[1:], strict=False))
    assert errors[PADE_ORDER - 1] < {0.05: 1.2e-6, 0.1: 6e-5, 0.2: 1e-3}[delay]
    # The delay changes the weave by far more than the approximant's error.
    assert abs(exact - undelayed) > 1e3 * errors[PADE_ORDER - 1]


def test_lag_alone_is_exact():
    bicycle = load_bicycle("sbw2024")
    controller = dataclasses.replace(bicycle.controller, lag=0.04)
    plant = build_linear_model(bicycle.parameters, bicycle.extensions, None)
    model = linear_model(bicycle.with_controller(controller))
    assert model.state_names[4:] == ("steer_torque_lag",) and model.state_units[4:] == ("N m",)
    for speed in (2.0, 4.5):
        weave = _weave(model, speed, 9j)
        assert abs(delay_eigenvalue(plant, controller, speed, weave) - weave) < 1e-10


def test_actuator_states_per_torque_row_in_use():
    bicycle = load_bicycle("benchmark").with_controller(
        Controller(steer={"roll": (4.0,)}, roll={"steer_rate": (0.0, 0.5)}, delay=0.02, lag=0.01))
    model = linear_model(bicycle)
    assert model.n_states == 4 + 2 * (PADE_ORDER + 1)
    assert model.state_names[4] == "roll_torque_delay1" and model.state_names[-1] == "steer_torque_lag"
    assert model.A.shape[-3] == 3  # still quadratic in v
    # CasADi's exact expression is the same assembly.
    function, p0 = casadi_state_function(bicycle)
    for speed in (0.0, 3.0, 7.0):
        np.testing.assert_allclose(np.array(function(speed, p0)), model.state_matrix(speed), rtol=1e-13, atol=1e-10)


def test_critical_speeds_see_the_actuator_states():
    bicycle = load_bicycle("sbw2024")
    delayed = bicycle.with_controller(dataclasses.replace(bicycle.controller, delay=0.03, lag=0.01))
    model = linear_model(delayed)
    result = critical_speeds(model, 0.5, 8.0)
    speeds = np.linspace(0.5, 8.0, 1501)
    stable = np.linalg.eigvals(model.state_matrix(speeds)).real.max(axis=-1) < 0
    changes = speeds[1:][stable[1:] != stable[:-1]]
    found = sorted(crossing.speed for crossing in result.crossings)
    assert len(found) == len(changes) > 0
    np.testing.assert_allclose(found, changes, atol=0.01)


def test_linear_simulator_runs_a_delayed_lagging_controller():
    bicycle = load_bicycle("sbw2024")
    delayed = bicycle.with_controller(dataclasses.replace(bicycle.controller, delay=0.01, lag=0.005))
    run = simulate_run(delayed, RunScenario(speed=4.0, sample_rate=100, n_pushes=1))
    assert np.isfinite(run.states).all() and run.states.shape[1] == 4 + PADE_ORDER + 1
    plain = simulate_run(bicycle, RunScenario(speed=4.0, sample_rate=100, n_pushes=1))
    assert not np.allclose(run.state("roll_rate"), plain.state("roll_rate"), atol=1e-4)


def test_nonlinear_model_refuses_what_it_does_not_hold():
    bicycle = load_bicycle("sbw2024")
    for changed in (bicycle.with_controller(dataclasses.replace(bicycle.controller, delay=0.05)),
                    bicycle.with_controller(dataclasses.replace(bicycle.controller, lag=0.05)),
                    bicycle.with_extensions(front_payload=Payload(1.0, 1.0, -0.8)),
                    bicycle.with_extensions(reflected_steer_inertia=0.1)):
        with pytest.raises(InputError, match="linear model"):
            nonlinear_parameters(changed)
    scaled = bicycle.with_controller(dataclasses.replace(bicycle.controller, gain_scale=0.8))
    assert nonlinear_parameters(scaled)[0]["w"] == bicycle.parameters["w"]


def test_bicycle_file_round_trip_of_the_new_keys(tmp_path):
    bicycle = load_bicycle("sbw2024")
    changed = bicycle.with_extensions(front_payload=Payload(1.5, 1.1, -0.9), reflected_steer_inertia=0.21)
    changed = changed.with_controller(dataclasses.replace(bicycle.controller, gain_scale=0.8, delay=0.04, lag=0.02))
    write_bicycle_toml(changed, tmp_path / "b.toml")
    text = (tmp_path / "b.toml").read_text()
    assert "[extensions.front_payload]" in text and "delay = 0.04" in text
    assert read_bicycle_toml(tmp_path / "b.toml") == changed
    # Defaults are not written.
    write_bicycle_toml(bicycle, tmp_path / "plain.toml")
    assert "delay" not in (tmp_path / "plain.toml").read_text()


def test_zero_gain_scale_leaves_the_bicycle_uncontrolled():
    bicycle = load_bicycle("sbw2024")
    off = bicycle.with_controller(dataclasses.replace(bicycle.controller, gain_scale=0.0, delay=0.05, lag=0.01))
    plant = build_linear_model(bicycle.parameters, bicycle.extensions, None)
    model = linear_model(off)
    np.testing.assert_array_equal(model.state_matrix(3.0), plant.state_matrix(3.0))
    function, p0 = casadi_state_function(off)
    np.testing.assert_allclose(np.array(function(3.0, p0)), plant.state_matrix(3.0), rtol=1e-14, atol=1e-12)


def test_tyre_model_takes_the_actuator_states_too():
    bicycle = load_bicycle("sbw2024").with_extensions(tyre_compliance=TyreCompliance(12.0, 0.57, 0.15))
    bicycle = bicycle.with_controller(dataclasses.replace(bicycle.controller, delay=0.03, lag=0.01))
    model = linear_model(bicycle)
    assert model.state_names[4:8] == ("lateral_speed", "yaw_rate", "rear_lateral_force", "front_lateral_force")
    assert model.state_names[8:] == tuple(f"steer_torque_delay{k}" for k in (1, 2, 3)) + ("steer_torque_lag",)
    function, p0 = casadi_state_function(bicycle)
    for speed in (1.0, 3.0, 6.0):
        expected = model.state_matrix(speed)
        np.testing.assert_allclose(np.array(function(speed, p0)), expected, rtol=1e-12,
                                   atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("name", ["benchmark", "kooijman2008", "sbw2024"])
def test_models_without_an_effective_extension_use_the_plain_whipple_code(name):
    # Every extension value either changes the matrices on its own or is a payload position.
    added = set(EXTENDED_PARAMETERS) - set(MODEL_PARAMETERS)
    assert all(value.endswith(("_x", "_z")) for value in added - set(EXTENSION_EFFECTS))
    parameters = dict(load_bicycle(name).parameters)
    parked = {**parameters, "payload_mass": 0.0, "payload_x": 0.4, "payload_z": -1.0}
    plain, extended = model_matrices(parked), extended_matrices(parked)
    for key in ("M", "C1", "K0", "K2", "D"):
        assert np.array_equal(getattr(plain, key), getattr(whipple_matrices(parameters), key))
        np.testing.assert_allclose(getattr(plain, key), getattr(extended, key), rtol=1e-12,
                                   atol=1e-12 * np.max(np.abs(getattr(extended, key))))
    loaded = {**parked, "payload_mass": 2.0}
    assert np.array_equal(model_matrices(loaded).M, extended_matrices(loaded).M)
