"""Simulated runs of the nonlinear model: the same procedure as the linear simulator, energy, eigenvalues.

Independent references:
- mechanics: the energy balance E - E(0) = work of every torque (integrated along the run) and,
  with a free rear wheel, no controller and no push acting, conservation of energy while
  coasting; the power of each torque from the energy's rate of change (finite differences of
  the generated NumPy energy);
- the linear model: at small amplitude, the package's window finder and weave fit on the
  nonlinear run give the linear weave eigenvalue (controller and steer damping included);
- the linear simulator: same samples, pushes, windows and catches for the same scenario.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from whipple.cli import main
from whipple.errors import AnalysisError, InputError
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import read_run, run_from_simulation
from whipple.model.assembly import linear_model
from whipple.model.nonlinear import casadi_reduced_equations, casadi_state_derivative, energy, parameter_vector
from whipple.model.parameters import (
    Controller,
    Payload,
    TyreCompliance,
    load_bicycle,
    write_bicycle_toml,
)
from whipple.simulation.nonlinear import with_diagnostics
from whipple.simulation.nonlinear_bicycle import ForcedBicycle, coast, nonlinear_parameters
from whipple.simulation.nonlinear_run import simulate_nonlinear_run
from whipple.simulation.scenario import PERFECT_SENSORS, RunScenario, ScenarioError
from whipple.simulation.simulator import simulate_run


@pytest.fixture(scope="module")
def bike():
    return load_bicycle("benchmark")


@pytest.fixture(scope="module")
def free_run(bike):
    """Benchmark at 5 m/s, rear wheel free, no controller: energy only changes by the torques' work."""
    scenario = RunScenario(speed=5.0, n_pushes=1, sensors=PERFECT_SENSORS)
    return simulate_nonlinear_run(bike, scenario, speed_control="free")


def _random_state(rng: np.random.Generator) -> np.ndarray:
    state = np.zeros(10)
    state[:3] = rng.uniform(-2, 2, 3)
    state[3:5] = rng.uniform(-0.5, 0.5, 2)
    state[5:7] = rng.uniform(-3, 3, 2)
    state[7:9] = rng.uniform(-1.5, 1.5, 2)
    state[9] = rng.uniform(-25, -5)
    return state


def test_reduced_equations_take_each_torque_in_its_own_row(bike):
    """mass @ a = force + tau: roll and steer torques as in the state derivative; the hub torque's power."""
    parameters = dict(bike.parameters)
    p = parameter_vector(parameters)
    reduced, full = casadi_reduced_equations(), casadi_state_derivative()
    rng = np.random.default_rng(3)
    for _ in range(4):
        state, torques = _random_state(rng), rng.uniform(-5, 5, 3)
        kinematics, mass, force, _ = (np.asarray(v, dtype=float) for v in reduced(p, state))
        kinematics, force = kinematics.ravel(), force.ravel()
        without_hub = np.linalg.solve(mass, force + np.append(torques[:2], 0.0))
        expected = np.asarray(full(p, state, torques[:2])[0], dtype=float).ravel()
        np.testing.assert_allclose(np.append(kinematics, without_hub), expected, rtol=1e-12, atol=1e-12)
        # dE/dt along the motion (central differences) is the power of the three torques.
        derivative = np.append(kinematics, np.linalg.solve(mass, force + torques))
        h = 1e-6
        ahead, behind = energy(parameters, state + h * derivative), energy(parameters, state - h * derivative)
        rate = (sum(ahead) - sum(behind)) / (2 * h)
        assert rate == pytest.approx(torques @ state[7:10], rel=1e-6, abs=1e-6)


def test_free_coasting_conserves_energy_and_the_balance_holds_throughout(free_run):
    checks = free_run.checks
    assert checks is not None
    # E - E(0) - W over the whole run (hand, push): integration error only.
    assert checks.energy_error_relative < 1e-10
    samples = with_diagnostics(dict(load_bicycle("benchmark").parameters), free_run.time, free_run.states, 0, "")
    (start, stop), = free_run.segments
    coasting = (free_run.time >= start) & (free_run.time <= stop)
    lateral = float(np.ptp(samples.energy))  # the energy the push and the hand put in and take out [J]
    assert lateral > 1.0
    drift = np.ptp(samples.energy[coasting])
    assert drift < 1e-9 * checks.energy_scale and drift < 1e-8 * lateral
    assert checks.holonomic_drift < 1e-12 and checks.velocity_drift < 1e-12
    # With a free rear wheel the speed exchanges energy with the lateral motion.
    assert np.ptp(free_run.speed[coasting]) > 1e-4


def test_pushes_do_the_work_the_energy_shows(free_run, bike):
    push = free_run.pushes[0]
    before, after = np.searchsorted(free_run.time, [push.time - 0.05, push.time + push.duration + 0.01])
    samples = with_diagnostics(dict(bike.parameters), free_run.time, free_run.states, 0, "")
    gained = samples.energy[after] - samples.energy[before]
    assert gained > 0.5  # J: the push's kinetic energy, and hardly anything of the hand's wobble


def test_same_procedure_as_the_linear_simulator(bike):
    scenario = RunScenario(speed=5.0, push_roll_rate=0.01, hold_std=0.0, sensors=PERFECT_SENSORS, n_pushes=2)
    nonlinear, linear = simulate_nonlinear_run(bike, scenario), simulate_run(bike, scenario)
    np.testing.assert_array_equal(nonlinear.time, linear.time)
    assert nonlinear.pushes == linear.pushes
    assert nonlinear.segments == linear.segments and nonlinear.catches == linear.catches
    scale = np.abs(linear.truth["roll_rate"]).max()
    # At a roll rate of 0.01 rad/s the motions agree to the linear simulator's discretisation of the push.
    np.testing.assert_allclose(nonlinear.truth["roll_rate"], linear.truth["roll_rate"], atol=1e-3 * scale)
    np.testing.assert_allclose(nonlinear.truth["yaw_rate"], linear.truth["yaw_rate"], atol=2e-3 * scale)
    np.testing.assert_allclose(nonlinear.speed, 5.0, rtol=1e-12)
    assert nonlinear.checks.energy_error_relative < 1e-10


def test_the_catch_comes_at_the_first_sample_beyond_the_limit(bike):
    run = simulate_nonlinear_run(bike, RunScenario(speed=2.0, n_pushes=1, sensors=PERFECT_SENSORS))
    (catch,) = run.catches
    k = int(np.searchsorted(run.time, catch))
    assert abs(run.state("roll")[k]) > 0.25 or abs(run.state("roll_rate")[k]) > 1.5
    free = (run.time > run.segments[0][0]) & (run.time < catch - 1e-9)
    assert np.abs(run.state("roll")[free]).max() <= 0.25 and np.abs(run.state("roll_rate")[free]).max() <= 1.5


def test_ground_speed_follows_the_deceleration(bike):
    scenario = RunScenario(speed=5.0, n_pushes=1, setting="ground", deceleration=0.1, sensors=PERFECT_SENSORS)
    run = simulate_nonlinear_run(bike, scenario)
    np.testing.assert_allclose(run.speed, 5.0 - 0.1 * run.time, atol=1e-9)
    assert run.checks.energy_error_relative < 1e-10
    with pytest.raises(ScenarioError, match="free rear wheel"):
        simulate_nonlinear_run(bike, scenario, speed_control="free")


@pytest.mark.parametrize("name, speed, settle, changes", [
    ("benchmark", 6.0, 0.5, {}),
    ("benchmark", 6.0, 0.5, {"steer_damping": 0.5}),
    ("sbw2024", 5.0, 0.8, {}),
])
def test_small_amplitude_run_fitted_gives_the_linear_weave(name, speed, settle, changes):
    bicycle = load_bicycle(name).with_extensions(**changes)
    scenario = RunScenario(speed=speed, n_pushes=1, push_roll_rate=0.01, hold_std=0.0, sensors=PERFECT_SENSORS)
    run = simulate_nonlinear_run(bicycle, scenario)
    fits = [m.fit for m in measure_run(run_from_simulation(run), settle=settle, baseline="quadratic") if m.usable]
    # The window finder's first window starts after the push (later ones hold the tail of the motion).
    assert fits and fits[0].start - run.segments[0][0] < settle + 0.5
    eigenvalues = np.linalg.eigvals(linear_model(bicycle).state_matrix(speed))
    weave = eigenvalues[np.argmax(eigenvalues.imag)]
    assert abs(fits[0].eigenvalue - weave) < 1e-3
    # The controller and the damping really act: without them the weave is elsewhere.
    bare = load_bicycle(name).with_controller(Controller())
    if changes or not load_bicycle(name).controller.is_empty():
        others = np.linalg.eigvals(linear_model(bare).state_matrix(speed))
        assert np.min(np.abs(others - fits[0].eigenvalue)) > 0.05


def test_coast_holds_the_speed_and_keeps_an_upright_bicycle_upright(bike):
    forced = ForcedBicycle(bike)
    times = np.linspace(0, 2, 201)
    states = coast(forced, forced.upright(4.0), times)
    np.testing.assert_allclose(states[:, 3:5], 0.0, atol=1e-14)
    np.testing.assert_allclose(states[:, 0], 4.0 * times, rtol=1e-9)


def test_coast_agrees_with_an_independent_integration_of_the_same_equations(bike):
    # CVODES (Adams) on the CasADi function against SciPy's DOP853 calling it from Python,
    # much tighter: a weave of 0.5 rad/s roll rate at 5 m/s over three seconds.
    forced = ForcedBicycle(bike)
    start = forced.upright(5.0, roll_rate=0.5, steer_rate=-0.2)
    times = np.linspace(0.0, 3.0, 301)
    reference = solve_ivp(lambda t, y: forced.free(y, np.zeros(2))[:10], (0.0, 3.0), start, method="DOP853",
                          t_eval=times, rtol=1e-12, atol=1e-14).y.T
    states = coast(forced, start, times, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(states[:, 3:5])) > 0.05  # it leans and steers
    np.testing.assert_allclose(states[:, 3:10], reference[:, 3:10], rtol=0, atol=1e-8)


def test_coast_of_a_bicycle_that_falls_over_is_an_analysis_error(bike):
    forced = ForcedBicycle(bike)
    with pytest.raises(AnalysisError, match="falls over"):
        coast(forced, forced.upright(1.0, roll_rate=3.0), np.linspace(0.0, 10.0, 1001))
    with pytest.raises(InputError, match="must increase"):
        coast(forced, forced.upright(4.0), np.array([0.0, 0.2, 0.1]))


def test_absent_pitch_inertias_are_estimated_and_reported(tmp_path):
    parameters, estimated = nonlinear_parameters(load_bicycle("sbw2024"))
    assert estimated == ("IByy", "IHyy")
    assert parameters["IByy"] == pytest.approx(parameters["IBxx"] + parameters["IBzz"])
    assert nonlinear_parameters(load_bicycle("benchmark"))[1] == ()
    run = simulate_nonlinear_run(load_bicycle("sbw2024"), RunScenario(speed=4.0, n_pushes=1))
    assert run.metadata["estimated_parameters"].startswith("IByy = ")


@pytest.mark.parametrize("changes", [{"payload": Payload(5.0, 0.3, -0.9)}, {"steer_inertia": 0.01},
                                     {"tyre_compliance": TyreCompliance(10.0, 1.0, 0.1)}])
def test_extensions_the_nonlinear_model_lacks_are_refused_in_one_line(bike, changes):
    with pytest.raises(InputError) as caught:
        simulate_nonlinear_run(bike.with_extensions(**changes), RunScenario(n_pushes=1))
    assert "\n" not in str(caught.value) and "nonlinear model has no" in str(caught.value)


def test_cli_simulates_the_nonlinear_model_and_reports_the_drift(tmp_path, capsys):
    out = tmp_path / "run.csv"
    assert main(["simulate", "--bicycle", "sbw2024", "--speed", "4", "--pushes", "1", "--nonlinear",
                 "--output", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "constraint drift" in printed and "energy balance error" in printed
    run = read_run(out)
    assert run.metadata["model"] == "nonlinear" and run.metadata["speed_control"] == "driven"
    assert float(run.metadata["holonomic_drift"].split()[0]) < 1e-12
    assert len(run.metadata["true_windows"].split(";")) == 1

    bicycle = tmp_path / "heavy.toml"
    write_bicycle_toml(load_bicycle("benchmark").with_extensions(payload=Payload(5.0, 0.3, -0.9)), bicycle)
    code = main(["simulate", "--bicycle", str(bicycle), "--speed", "4", "--nonlinear",
                 "--output", str(tmp_path / "x.csv")])
    error = capsys.readouterr().err
    assert code == 2 and error.count("\n") == 1 and "heavy.toml" in error and "payload" in error
    assert not (tmp_path / "x.csv").exists()
