"""The nonlinear Whipple equations: derived, emitted, solved, simulated.

Independent references:
- Basu-Mandal, Chatterjee & Papadopoulos (2007), Table 1: a published state far from upright
  with its accelerations (whipple/data/reference/basu-mandal2007.toml);
- the linear model: the generated M, C1, K0, K2 (first-order Kane expansion) and the
  Meijaard et al. (2007) closed form (tests/meijaard_oracle.py), against the Jacobian of the
  nonlinear equations by automatic differentiation;
- mechanics: energy balance (the power of the inputs), the holonomic constraint's gradient
  equal to the vertical velocity constraint, ``C u' = b`` as the time derivative of ``C u = 0``.
"""

from __future__ import annotations

import json

import casadi
import numpy as np
import pytest
from meijaard_oracle import meijaard_matrices, random_physical_parameters
from scipy.linalg import expm
from whipple.generated import whipple_nonlinear_casadi, whipple_nonlinear_numpy, whipple_numpy

from whipple.cli import main
from whipple.errors import InputError, ParameterError
from whipple.measurement.weavefit import fit_weave
from whipple.model.nonlinear import (
    PARAMETERS,
    STATES,
    casadi_residual,
    casadi_state_derivative,
    energy,
    motion,
    parameter_vector,
    singularity_measure,
    solve_pitch,
    state_derivative,
    upright_state,
)
from whipple.model.nonlinear_verification import (
    BASU_MANDAL_TOLERANCE,
    check_linearization,
    compare_basu_mandal,
    jacobian_matrices,
    perturbed_parameters,
)
from whipple.model.parameters import load_bicycle
from whipple.simulation.nonlinear import simulate


@pytest.fixture(scope="module")
def benchmark() -> dict[str, float]:
    return dict(load_bicycle("benchmark").parameters)


def _random_states(rng: np.random.Generator, n: int) -> np.ndarray:
    """States with roll and steer up to about 45 degrees and rates up to a few rad/s."""
    states = np.zeros((n, len(STATES)))
    states[:, :3] = rng.uniform(-5, 5, (n, 3))
    states[:, 3] = rng.uniform(-0.8, 0.8, n)
    states[:, 4] = rng.uniform(-0.8, 0.8, n)
    states[:, 5:7] = rng.uniform(-3, 3, (n, 2))
    states[:, 7:9] = rng.uniform(-2, 2, (n, 2))
    states[:, 9] = rng.uniform(-30, 5, n)
    return states


def _one_set(parameters: dict[str, np.ndarray], k: int) -> dict[str, float]:
    return {name: float(values[k]) for name, values in parameters.items()}


# --- published state -------------------------------------------------------------------------

def test_basu_mandal_table_1_accelerations(benchmark):
    result = compare_basu_mandal(benchmark)
    assert len(result.accelerations) == 9
    worst = max(result.accelerations, key=lambda entry: entry.error)
    assert result.max_abs_error <= BASU_MANDAL_TOLERANCE, f"{worst.name}: error {worst.error:.2e}"


def test_basu_mandal_state_follows_from_the_independent_values(benchmark):
    # Pitch, dependent rates and the wheel centre's velocity are computed, not read.
    result = compare_basu_mandal(benchmark)
    assert {entry.name for entry in result.state} == {"z", "phi", "xd", "yd", "zd", "thetad", "phid", "betafd"}
    worst = max(result.state, key=lambda entry: entry.error)
    assert worst.error <= BASU_MANDAL_TOLERANCE, f"{worst.name}: error {worst.error:.2e}"


# --- against the linear model ----------------------------------------------------------------

def test_jacobian_equals_generated_linear_matrices(benchmark):
    sets = {"benchmark": benchmark, "kooijman2008": dict(load_bicycle("kooijman2008").parameters),
            **perturbed_parameters(benchmark, 3, seed=13)}
    check = check_linearization(sets, speeds=(0.5, 2.0, 4.0, 6.0, 10.0))
    assert check.max_error <= 1e-8, check.matrix_errors
    assert check.state_matrix_error <= 1e-8


def test_jacobian_equals_meijaard_closed_form_at_random_bicycles():
    parameters = random_physical_parameters(np.random.default_rng(1983), 8)
    oracle = meijaard_matrices(parameters)
    for k in range(8):
        one = _one_set(parameters, k)
        for speed in (1.0, 5.0):
            for name, computed, expected in zip(("M", "C1", "K0", "K2"), jacobian_matrices(one, speed),
                                                oracle, strict=True):
                scale = np.max(np.abs(expected[k]))
                assert np.max(np.abs(computed - expected[k])) <= 1e-10 * max(scale, 1.0), name


def test_residual_inputs_enter_as_the_identity(benchmark):
    # The benchmark form has B = I: d residual / d torques = -I in the roll and steer rows.
    residual = casadi_residual()
    torques = casadi.MX.sym("torques", 2)
    value = residual(parameter_vector(benchmark), [0.1, -0.2], [0.3, 0.1, -10.0], [0.0, 0.0, 0.0], torques)
    jacobian = casadi.Function("j", [torques], [casadi.jacobian(value, torques)])
    np.testing.assert_allclose(np.array(jacobian([0.0, 0.0]))[:2], -np.eye(2), atol=1e-12)


# --- the generated pieces --------------------------------------------------------------------

def test_numpy_and_casadi_modules_agree_for_every_function():
    parameters = random_physical_parameters(np.random.default_rng(5), 3)
    rng = np.random.default_rng(6)
    for name, variables in whipple_nonlinear_numpy.VARIABLES.items():
        function = whipple_nonlinear_casadi.function(name)
        for k in range(3):
            p = [parameters[parameter][k] for parameter in PARAMETERS]
            values = rng.uniform(-1, 1, len(variables))
            numeric = whipple_nonlinear_numpy.__dict__[name](*p, *values)
            symbolic = function(p, values)
            symbolic = symbolic if isinstance(symbolic, tuple) else (symbolic,)
            for a, b in zip(numeric, symbolic, strict=True):
                b = np.array(b, dtype=float).reshape(np.shape(a))
                np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * max(1.0, np.max(np.abs(a))))


def test_vertical_constraint_is_the_rate_of_the_contact_height(benchmark):
    rng = np.random.default_rng(7)
    p = [benchmark[name] for name in PARAMETERS]
    roll, pitch, steer = rng.uniform(-0.8, 0.8, (3, 20))
    _, gradient = whipple_nonlinear_numpy.contact_height(*p, roll, pitch, steer)
    C = whipple_nonlinear_numpy.constraints(*p, roll, pitch, steer)[0]
    expected = np.zeros((20, 6))
    expected[:, [1, 2, 3]] = gradient
    np.testing.assert_allclose(C[:, 2, :], expected, atol=1e-13)


def test_constraint_bias_is_the_time_derivative_of_the_constraints(benchmark):
    # C(q) u = 0 along a motion, so C u' = -(dC/dt) u = b; dC/dt by automatic differentiation.
    angles, rates = casadi.SX.sym("angles", 3), casadi.SX.sym("rates", 6)
    p = parameter_vector(benchmark)
    C = whipple_nonlinear_casadi.constraints(p, angles)[0]
    angle_rates = rates[[1, 2, 3]]
    derivative = casadi.Function("d", [angles, rates], [casadi.jtimes(C @ rates, angles, angle_rates)])
    rng = np.random.default_rng(8)
    for _ in range(10):
        q, u = rng.uniform(-0.8, 0.8, 3), rng.uniform(-3, 3, 6)
        b = whipple_nonlinear_numpy.dynamics(*(benchmark[n] for n in PARAMETERS), *q, *u, 0.0, 0.0)[2]
        np.testing.assert_allclose(-np.array(derivative(q, u)).ravel(), b, atol=1e-12)


def test_energy_balance_equals_the_power_of_the_inputs():
    # dE/dt = roll torque * roll rate + steer torque * steer rate (the contact forces do no work).
    parameters = random_physical_parameters(np.random.default_rng(9), 4)
    angles, rates = casadi.SX.sym("angles", 3), casadi.SX.sym("rates", 6)
    angle_rates, accelerations = casadi.SX.sym("angle_rates", 3), casadi.SX.sym("accelerations", 6)
    rng = np.random.default_rng(10)
    for k in range(4):
        one = _one_set(parameters, k)
        kinetic, potential = whipple_nonlinear_casadi.energy(parameter_vector(one), casadi.vertcat(angles, rates))
        total = kinetic + potential
        rate = casadi.Function("rate", [angles, rates, angle_rates, accelerations],
                               [casadi.jtimes(total, angles, angle_rates) + casadi.jtimes(total, rates, accelerations)])
        state = _random_states(rng, 1)[0]
        torques = rng.uniform(-5, 5, 2)
        result = motion(one, state, torques)
        u, u_dot = result.rates, result.accelerations
        power = float(rate([state[3], result.pitch, state[4]], u, u[[1, 2, 3]], u_dot))
        kinetic_energy = float(energy(one, state)[0])
        expected = torques[0] * u[1] + torques[1] * u[3]
        assert abs(power - expected) <= 1e-10 * max(1.0, kinetic_energy), (power, expected)


# --- the library -----------------------------------------------------------------------------

def test_pitch_is_zero_upright_and_even_in_roll_and_steer(benchmark):
    assert float(solve_pitch(benchmark, 0.0, 0.0)) == pytest.approx(0.0, abs=1e-15)
    roll, steer = np.array([0.3, 0.5, -0.2]), np.array([0.4, -0.9, 0.1])
    np.testing.assert_allclose(solve_pitch(benchmark, roll, steer), solve_pitch(benchmark, -roll, -steer),
                               atol=1e-14)
    p = [benchmark[name] for name in PARAMETERS]
    pitch = solve_pitch(benchmark, roll, steer)
    assert np.max(np.abs(whipple_nonlinear_numpy.contact_height(*p, roll, pitch, steer)[0])) <= 1e-15


def test_numpy_and_casadi_state_derivatives_agree():
    parameters = random_physical_parameters(np.random.default_rng(11), 5)
    rng = np.random.default_rng(12)
    function = casadi_state_derivative()
    for k in range(5):
        one = _one_set(parameters, k)
        for state in _random_states(rng, 4):
            torques = rng.uniform(-3, 3, 2)
            numeric = state_derivative(one, state, torques)
            symbolic, pitch = function(parameter_vector(one), state, torques)
            scale = max(1.0, np.max(np.abs(numeric)))
            np.testing.assert_allclose(np.array(symbolic).ravel(), numeric, rtol=0, atol=1e-11 * scale)
            assert float(pitch) == pytest.approx(float(motion(one, state).pitch), abs=1e-14)


def test_state_derivative_broadcasts_over_states_and_parameters(benchmark):
    states = _random_states(np.random.default_rng(14), 6)
    parameters = dict(benchmark)
    parameters["mB"] = np.linspace(60.0, 100.0, 6)
    together = state_derivative(parameters, states)
    assert together.shape == (6, len(STATES))
    for k in range(6):
        single = state_derivative({**benchmark, "mB": parameters["mB"][k]}, states[k])
        np.testing.assert_allclose(together[k], single, rtol=1e-13, atol=1e-13)


def test_upright_straight_motion_is_steady(benchmark):
    derivative = state_derivative(benchmark, upright_state(benchmark, 5.0))
    assert derivative[0] == pytest.approx(5.0, rel=1e-14)
    np.testing.assert_allclose(derivative[1:5], 0.0, atol=1e-14)
    np.testing.assert_allclose(derivative[7:], 0.0, atol=1e-12)


def test_contact_force_carries_the_front_share_of_the_weight_at_rest(benchmark):
    # Upright at rest, the ground's vertical forces are the static wheel loads (moments about
    # the rear contact): the front wheel carries g * sum(m x) / w, pointing up (negative z).
    result = motion(benchmark, upright_state(benchmark, 0.0))
    moment = sum(benchmark[f"m{b}"] * x for b, x in (("R", 0.0), ("B", benchmark["xB"]), ("H", benchmark["xH"]),
                                                      ("F", benchmark["w"])))
    np.testing.assert_allclose(result.contact_force, [0.0, 0.0, -benchmark["g"] * moment / benchmark["w"]],
                               atol=1e-10)


def test_singularity_measure_is_one_upright_and_changes_sign_near_90_degrees_of_steer(benchmark):
    assert float(singularity_measure(benchmark, 0.0, 0.0, 0.0)) == pytest.approx(1.0, abs=1e-14)
    steer = np.array([1.4, 1.8])
    measure = singularity_measure(benchmark, 0.0, solve_pitch(benchmark, 0.0, steer), steer)
    assert measure[0] > 0 > measure[1]


def test_missing_pitch_inertia_is_a_parameter_error(benchmark):
    parameters = {name: value for name, value in benchmark.items() if name != "IByy"}
    with pytest.raises(ParameterError, match="IByy"):
        state_derivative(parameters, upright_state(benchmark, 5.0))


def test_bad_state_shape_is_an_input_error(benchmark):
    with pytest.raises(InputError, match="10 entries"):
        state_derivative(benchmark, np.zeros(8))


# --- simulation ------------------------------------------------------------------------------

def test_energy_is_conserved_without_inputs(benchmark):
    # Benchmark at 4.6 m/s with a roll rate kick (Meijaard et al. 2007, Fig. 4): 5 s.
    result = simulate(benchmark, upright_state(benchmark, 4.6, roll_rate=0.5), duration=5.0)
    assert result.stop_reason == "duration" and result.time[-1] == pytest.approx(5.0)
    assert result.energy_drift <= 1e-9
    assert result.holonomic_drift <= 1e-12 and result.velocity_drift <= 1e-12
    assert np.max(np.abs(result.states[:, 3])) < 0.2


def test_energy_changes_by_the_work_of_a_constant_steer_torque(benchmark):
    # With a steer torque T the energy changes by T times the change of steer angle.
    result = simulate(benchmark, upright_state(benchmark, 5.0), duration=1.0, inputs=[0.0, 0.5])
    work = 0.5 * (result.states[:, 4] - result.states[0, 4])
    gain = result.energy - result.energy[0]
    assert np.max(np.abs(gain - work)) <= 1e-8 * result.energy[0]


@pytest.mark.parametrize("speed", [4.0, 6.0])
def test_small_weave_reproduces_the_linear_eigenvalue(benchmark, speed):
    M, C1, K0, K2 = whipple_numpy.matrices(*(benchmark[name] for name in whipple_numpy.PARAMETERS))
    A = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.linalg.solve(M, K0 + speed**2 * K2), -speed * np.linalg.solve(M, C1)]])
    eigenvalues, vectors = np.linalg.eig(A)
    weave = int(np.argmax(eigenvalues.imag))
    start = 1e-4 * (vectors[:, weave] / vectors[0, weave]).real  # weave mode only, 1e-4 rad of roll
    state = upright_state(benchmark, speed, roll=start[0], steer=start[1], roll_rate=start[2], steer_rate=start[3])
    result = simulate(benchmark, state, duration=5.0)
    fit = fit_weave(result.time, result.states[:, 7], noise="white")
    assert abs(fit.eigenvalue - eigenvalues[weave]) <= 1e-3
    linear = np.array([(expm(A * t) @ start)[2] for t in result.time])
    assert np.max(np.abs(result.states[:, 7] - linear)) <= 1e-3 * np.max(np.abs(linear))


def test_simulation_stops_at_the_singular_steer_angle(benchmark):
    # Slow and leaning: the bicycle falls and steers towards 90 degrees, where the rolling
    # constraints demand an unbounded yaw rate.
    result = simulate(benchmark, upright_state(benchmark, 1.0, roll=0.05), duration=5.0)
    assert result.stop_reason == "singular" and result.time[-1] < 5.0
    assert abs(result.states[-1, 4]) > 1.3


def test_simulation_rejects_bad_input(benchmark):
    state = upright_state(benchmark, 5.0)
    with pytest.raises(InputError, match="duration"):
        simulate(benchmark, state, duration=-1.0)
    with pytest.raises(InputError, match="finite"):
        simulate(benchmark, np.full(10, np.nan), duration=1.0)
    with pytest.raises(InputError, match="torques"):
        simulate(benchmark, state, duration=1.0, inputs=[1.0, 2.0, 3.0])


def test_verify_json_reports_the_nonlinear_checks(capsys):
    assert main(["verify", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)["nonlinear"]
    assert report["passed"]
    assert report["max_abs_error"] <= 1e-10 and report["linearization_max_error"] <= 1e-8


# --- long runs -------------------------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("bicycle, speed", [("benchmark", 5.0), ("benchmark", 8.0), ("kooijman2008", 5.0)])
def test_energy_is_conserved_over_a_long_run(bicycle, speed):
    # The benchmark at 8 m/s capsizes (above its capsize speed): the run ends at the singular
    # steer angle, and the energy is conserved up to there.
    parameters = dict(load_bicycle(bicycle).parameters)
    result = simulate(parameters, upright_state(parameters, speed, roll=0.1, steer=0.05, roll_rate=0.3),
                      duration=30.0)
    assert result.energy_drift <= 1e-8


@pytest.mark.slow
@pytest.mark.parametrize("speed", [4.5, 5.0, 5.5, 7.0])
def test_small_weave_eigenvalue_at_more_speeds(benchmark, speed):
    test_small_weave_reproduces_the_linear_eigenvalue(benchmark, speed)
