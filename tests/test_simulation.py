"""Simulated runs: exact coasting, speed profiles, speedometer, file round trip, bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.linalg import expm

from whipple.cli import main
from whipple.errors import InputError
from whipple.measurement.runs import read_run, run_from_simulation
from whipple.measurement.speedometer import speed_regression, speedometer_speed
from whipple.model.assembly import linear_model
from whipple.model.linear import LinearModel
from whipple.model.parameters import load_bicycle
from whipple.simulation.discretization import expm_batch
from whipple.simulation.procedure import cut_run
from whipple.simulation.run_writer import format_true_windows
from whipple.simulation.scenario import (
    PERFECT_SENSORS,
    SIGNALS,
    Push,
    RunScenario,
    ScenarioError,
    Sensor,
    Sensors,
)
from whipple.simulation.simulator import parse_true_windows, simulate_run, write_run_csv


@pytest.fixture(scope="module")
def bike():
    return load_bicycle("benchmark")


@pytest.fixture(scope="module")
def clean_run(bike):
    """Benchmark bicycle at 5 m/s (stable weave), noise-free, 500 Hz."""
    return simulate_run(bike, RunScenario(speed=5.0, sample_rate=500, sensors=PERFECT_SENSORS,
                                               hold_std=0.0))


def _window(run, segment):
    start, stop = segment
    return np.flatnonzero((run.time >= start) & (run.time <= stop))


def test_deterministic_given_seed(bike):
    scenario = RunScenario(speed=4.0, n_pushes=1, duration=4.0, seed=7)
    first, second = simulate_run(bike, scenario), simulate_run(bike, scenario)
    for name in first.signals:
        np.testing.assert_array_equal(first.signals[name], second.signals[name])
    other = simulate_run(bike, scenario.replace(seed=8))
    assert not np.array_equal(first.signals["roll_rate"], other.signals["roll_rate"])


def test_coasting_is_the_exact_free_response(bike, clean_run):
    A = linear_model(bike).state_matrix(5.0)
    assert len(clean_run.segments) == 3
    for segment in clean_run.segments:
        index = _window(clean_run, segment)[::10]
        tau = clean_run.time[index] - clean_run.time[index[0]]
        exact = np.einsum("tij,j->ti", expm(A * tau[:, None, None]), clean_run.states[index[0]])
        scale = np.abs(exact).max()
        assert scale > 0.1  # a real motion, not a resting bicycle
        assert np.abs(exact - clean_run.states[index]).max() < 1e-9 * scale


def test_roll_rate_decays_with_the_weave_eigenvalue(bike, clean_run):
    eigenvalues = np.linalg.eigvals(linear_model(bike).state_matrix(5.0))
    weave = eigenvalues[np.argmax(eigenvalues.imag)]
    others = eigenvalues[np.abs(eigenvalues.imag) < 1e-9].real
    index = _window(clean_run, clean_run.segments[0])
    tau = clean_run.time[index] - clean_run.time[index[0]]
    y = clean_run.truth["roll_rate"][index]

    def misfit(lam: complex) -> float:
        basis = [np.exp(lam.real * tau) * np.cos(lam.imag * tau),
                 np.exp(lam.real * tau) * np.sin(lam.imag * tau)]
        basis += [np.exp(r * tau) for r in others]
        coefficients, *_ = np.linalg.lstsq(np.column_stack(basis), y, rcond=None)
        return float(np.linalg.norm(np.column_stack(basis) @ coefficients - y) / np.linalg.norm(y))

    assert weave.real < 0 and misfit(weave) < 1e-9
    assert misfit(weave * 1.01) > 1e-4  # the decay really pins the eigenvalue


def test_push_gives_a_realistic_roll_rate_and_the_hold_keeps_upright(bike):
    run = simulate_run(bike, RunScenario(speed=5.0, sensors=PERFECT_SENSORS))
    push = run.pushes[0]
    after = (run.time > push.time) & (run.time < push.time + 2.0)
    assert 0.3 <= np.abs(run.truth["roll_rate"][after]).max() <= 1.0
    held = run.time < run.scenario.release
    assert np.abs(run.state("roll")[held]).max() < 0.01
    assert [np.sign(p.roll_impulse) for p in run.pushes] == [1, -1, 1]
    # after each catch the state is back near zero within the catch duration
    for catch in run.catches:
        later = np.searchsorted(run.time, catch + 2 * run.scenario.catch_duration)
        assert abs(run.state("roll")[later]) < 0.01


def test_catch_comes_early_at_unstable_speed(bike):
    run = simulate_run(bike, RunScenario(speed=2.0, sensors=PERFECT_SENSORS))
    assert run.segments and all(stop - start < run.scenario.max_coast
                                for start, stop in run.segments)
    assert np.abs(run.state("roll")).max() < 1.2 * run.scenario.roll_limit


def test_treadmill_speed_is_constant_and_ground_speed_decays(bike):
    tread = simulate_run(bike, RunScenario(speed=4.0, sensors=PERFECT_SENSORS))
    np.testing.assert_array_equal(tread.signals["speed"], 4.0)
    ground = simulate_run(bike, RunScenario(speed=4.0, setting="ground", deceleration=0.05,
                                                 sensors=PERFECT_SENSORS))
    np.testing.assert_allclose(ground.speed, 4.0 - 0.05 * ground.time, rtol=0, atol=1e-12)
    assert ground.signals["speed"][-1] < ground.signals["speed"][0] - 0.5


def test_speed_scale_applies_to_measurements_only(bike):
    scaled = bike.with_extensions(speed_scale=1.05)
    scenario = RunScenario(speed=5.0, n_pushes=1, sensors=PERFECT_SENSORS,
                           columns=("roll_rate", "speed"))
    plain, measured = simulate_run(bike, scenario), simulate_run(scaled, scenario)
    np.testing.assert_allclose(measured.signals["speed"], 1.05 * plain.speed)
    np.testing.assert_array_equal(measured.states, plain.states)


@pytest.mark.parametrize(("rate", "setting"), [(500, "ground"), (100, "treadmill")])
def test_speedometer_crossings_are_twentieths_of_a_revolution(bike, rate, setting):
    scenario = RunScenario(speed=5.0, sample_rate=rate, setting=setting,
                           columns=("roll_rate", "speedometer"), n_pushes=2)
    run = simulate_run(bike, scenario)
    clean = run.truth["speedometer"]
    crossings = np.count_nonzero(np.sign(clean[1:]) != np.sign(clean[:-1]))
    rolled = np.trapezoid(run.speed, run.time)
    expected = rolled / (2 * np.pi * bike.parameters["rR"]) * 20
    assert abs(crossings - expected) <= 1
    # the noisy signal, read as the seed paper did, gives the speed over each window within 1 %
    staircase = speedometer_speed(run.time, run.signals["speedometer"],
                                  bike.parameters["rR"], 20)
    measured = staircase.sampled(run.time)
    for start, stop in run.segments:
        estimate = speed_regression(run.time, measured, start, stop).mean
        truth = speed_regression(run.time, run.speed, start, stop).mean
        assert abs(estimate / truth - 1) < 0.01


def test_round_trip_through_read_run(bike, tmp_path):
    scenario = RunScenario(speed=3.0, sample_rate=500, n_pushes=2, seed=3,
                           columns=("roll_rate", "yaw_rate", "steer_angle", "steer_rate",
                                    "roll_angle", "speedometer"))
    run = simulate_run(bike, scenario)
    path = write_run_csv(run, tmp_path / "run.csv")
    read = read_run(path)
    assert list(read.signals) == list(scenario.columns)
    for name, values in run.signals.items():
        np.testing.assert_allclose(read.signals[name], values, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(read.time, run.time, atol=1e-12)
    assert read.sample_rate == pytest.approx(500)
    assert read.metadata["bicycle"] == "benchmark"
    assert read.metadata["pulses_per_revolution"] == "20"
    assert float(read.metadata["wheel_radius"]) == bike.parameters["rR"]
    np.testing.assert_allclose(parse_true_windows(read.metadata["true_windows"]), run.segments,
                               rtol=1e-5)
    direct = run_from_simulation(run)
    np.testing.assert_allclose(direct.speed(), read.speed(), rtol=1e-6)
    assert direct.metadata == read.metadata


def test_treadmill_without_speed_column_writes_speed_metadata(bike, tmp_path):
    run = simulate_run(bike.with_extensions(speed_scale=0.98),
                       RunScenario(speed=4.0, n_pushes=1, columns=("roll_rate",)))
    read = read_run(write_run_csv(run, tmp_path / "r.csv"))
    np.testing.assert_allclose(read.speed(), 0.98 * 4.0)


def test_sensor_noise_and_bias(bike):
    sensors = PERFECT_SENSORS.scaled()
    sensors = dataclasses.replace(sensors, roll_rate=Sensor(0.02, 0.01))
    run = simulate_run(bike, RunScenario(speed=5.0, sensors=sensors, sample_rate=500))
    error = run.signals["roll_rate"] - run.truth["roll_rate"]
    assert error.mean() == pytest.approx(0.01, abs=0.001)
    assert error.std() == pytest.approx(0.02, rel=0.05)
    np.testing.assert_array_equal(run.signals["steer_angle"], run.truth["steer_angle"])


def test_yaw_rate_from_kinematics_or_from_a_state(bike):
    p = bike.parameters
    run = simulate_run(bike, RunScenario(speed=5.0, n_pushes=1, sensors=PERFECT_SENSORS))
    expected = ((5.0 * run.state("steer") + p["c"] * run.state("steer_rate"))
                * np.cos(p["lam"]) / p["w"])
    np.testing.assert_allclose(run.signals["yaw_rate"], expected, atol=1e-15)

    # A model with its own (lagging) yaw-rate state: the simulator must use that state.
    base = linear_model(bike)
    degree = base.A.shape[0]
    A = np.zeros((degree, 5, 5))
    A[:, :4, :4] = base.A
    tau, factor = 0.05, np.cos(p["lam"]) / p["w"]
    A[0, 4, 3], A[1, 4, 1], A[0, 4, 4] = factor * p["c"] / tau, factor / tau, -1 / tau
    B = np.concatenate([base.B, np.zeros((base.B.shape[0], 1, 2))], axis=1)
    model = LinearModel(A, B, base.state_names + ("yaw_rate",), base.state_units + ("rad/s",))
    lagged = simulate_run(bike, RunScenario(speed=5.0, n_pushes=1, sensors=PERFECT_SENSORS),
                          model=model)
    np.testing.assert_array_equal(lagged.signals["yaw_rate"], lagged.state("yaw_rate"))
    np.testing.assert_allclose(lagged.states[:, :4], run.states, atol=1e-12)
    assert not np.allclose(lagged.signals["yaw_rate"], run.signals["yaw_rate"], atol=1e-3)


@pytest.mark.parametrize("speed", [2.0, 3.0, 4.0, 5.0])
def test_sbw2024_with_its_controller_stays_in_the_linear_range(speed):
    bicycle = load_bicycle("sbw2024")
    assert not bicycle.controller.is_empty()
    run = simulate_run(bicycle, RunScenario(speed=speed, sample_rate=100))
    assert np.isfinite(run.states).all()
    assert np.abs(run.state("roll")).max() < 0.3
    assert len(run.segments) == 3 and all(stop - start >= 2.0 for start, stop in run.segments)


def test_explicit_pushes(bike):
    pushes = (Push(1.5, roll_impulse=8.0), Push(6.0, roll_impulse=-8.0, steer_impulse=0.05))
    run = simulate_run(bike, RunScenario(speed=5.5, pushes=pushes, duration=10.0))
    assert run.pushes == pushes
    assert run.segments[0][0] == pytest.approx(1.6) and run.segments[1][0] == pytest.approx(6.1)
    assert run.segments[1][1] == pytest.approx(run.time[-1])
    assert run.time[-1] == pytest.approx(10.0)


def test_expm_batch_matches_scipy(bike):
    A = linear_model(bike).state_matrix(np.linspace(0.5, 10, 12))
    for dt in (0.002, 0.01, 0.5):
        expected = np.array([expm(a * dt) for a in A])
        np.testing.assert_allclose(expm_batch(A * dt), expected, rtol=0,
                                   atol=1e-13 * np.abs(expected).max())


@pytest.mark.parametrize(
    "changes",
    [
        {"speed": -1.0},
        {"speed": float("nan")},
        {"sample_rate": 0.0},
        {"duration": -2.0},
        {"setting": "moon"},
        {"columns": ("yaw_rate", "speed")},
        {"columns": ("roll_rate", "pressure")},
        {"n_pushes": 0},
        {"seed": -1},
        {"pushes": (Push(0.5),)},
        {"pushes": (Push(2.0), Push(2.5))},
        {"pushes": (Push(2.0),), "duration": 1.5},
        {"setting": "ground", "speed": 0.5, "deceleration": 0.1},
        {"sensors": Sensors(roll_rate=Sensor(-0.1))},
        {"setting": "ground", "columns": ("roll_rate", "yaw_rate")},
        {"pushes": (Push(2.0),), "n_pushes": 1},
        {"push_signs": "sometimes"},
        {"push_spread": 1.0},
        {"coast_spread": -0.1},
        {"coast_spread": float("nan")},
    ],
)
def test_bad_scenarios_raise_one_line_input_errors(changes):
    with pytest.raises(InputError) as caught:
        RunScenario(**changes)
    assert isinstance(caught.value, ScenarioError) and "\n" not in str(caught.value)


def test_bad_simulations_raise_input_errors(bike):
    with pytest.raises(ScenarioError, match="alias"):
        simulate_run(bike, RunScenario(speed=12.0, columns=("roll_rate", "speedometer")))
    batch = linear_model(bike)
    stacked = LinearModel(np.stack([batch.A, batch.A]), np.stack([batch.B, batch.B]))
    with pytest.raises(ScenarioError, match="batch"):
        simulate_run(bike, RunScenario(), model=stacked)
    with pytest.raises(InputError):
        parse_true_windows("1.0-2.0")


def test_every_signal_name_is_a_run_file_column():
    from whipple.measurement.layouts import SPEC_COLUMNS

    assert set(SIGNALS) <= set(SPEC_COLUMNS)


def test_cli_writes_one_file_per_speed(tmp_path, capsys):
    out = tmp_path / "runs"
    code = main(["simulate", "--bicycle", "benchmark", "--speeds", "3,5", "--pushes", "1",
                 "--speedometer", "--sample-rate", "500", "--seed", "4", "--output", str(out)])
    assert code == 0
    files = sorted(out.iterdir())
    assert [f.name for f in files] == ["benchmark_treadmill_3.00ms.csv",
                                       "benchmark_treadmill_5.00ms.csv"]
    runs = [read_run(f) for f in files]
    assert [r.metadata["seed"] for r in runs] == ["4", "5"]
    assert "speedometer" in runs[0].signals
    assert str(files[0]) in capsys.readouterr().out


@pytest.mark.parametrize(
    "arguments",
    [
        ["--speed", "-1"],
        ["--speed", "3", "--sample-rate", "0"],
        ["--speeds", "3,x"],
        ["--speeds", "3,4", "--output", "one.csv"],
        ["--speed", "3", "--pushes", "0"],
        ["--speed", "3", "--noise", "-1"],
        ["--speed", "3", "--setting", "ground", "--duration", "100"],
    ],
)
def test_cli_bad_arguments_exit_2_with_one_line(tmp_path, capsys, arguments):
    if "--output" not in arguments:
        arguments = [*arguments, "--output", str(tmp_path / "out")]
    try:
        code = main(["simulate", "--bicycle", "benchmark", *arguments])
    except SystemExit as exited:  # argparse rejects a malformed value itself
        code = exited.code
    assert code == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "error" in error
    assert not (tmp_path / "out").exists()


def test_cli_refuses_to_overwrite_its_input(tmp_path, capsys):
    bicycle_file = tmp_path / "bike.csv"
    text = "contents that must survive\n"
    bicycle_file.write_text(text)
    code = main(["simulate", "--bicycle", str(bicycle_file), "--speed", "3",
                 "--output", str(bicycle_file)])
    assert code == 2 and bicycle_file.read_text() == text
    assert "input" in capsys.readouterr().err


def test_procedure_options_off_draw_nothing_and_on_draw_their_own_stream(bike):
    # Defaults give the run they always gave: the options' own stream is not touched.
    plain = simulate_run(bike, RunScenario(speed=5.0, seed=4))
    spelled = simulate_run(bike, RunScenario(speed=5.0, seed=4, push_signs="alternate", push_spread=0.0,
                                             coast_spread=0.0))
    for name, values in plain.signals.items():
        np.testing.assert_array_equal(values, spelled.signals[name])
    assert [np.sign(p.roll_impulse) for p in plain.pushes] == [1.0, -1.0, 1.0]
    # With them, the sizes and coasts change, and the hand's wobble and the noise do not.
    drawn = simulate_run(bike, RunScenario(speed=5.0, seed=4, push_signs="random", push_spread=0.4,
                                           coast_spread=0.5))
    sizes = np.abs([p.roll_impulse for p in drawn.pushes]) / abs(plain.pushes[0].roll_impulse)
    assert np.all((sizes >= 0.6 - 1e-9) & (sizes <= 1.4 + 1e-9)) and np.ptp(sizes) > 0.01
    coasting = np.diff(drawn.segments, axis=1).ravel()
    assert np.all((coasting >= 2.5 - 0.011) & (coasting <= 5.0 + 0.011))
    np.testing.assert_array_equal(plain.state("roll")[:90], drawn.state("roll")[:90])  # held until the push


def test_a_cut_keeps_times_and_clips_the_truth(bike):
    run = simulate_run(bike, RunScenario(speed=5.0, seed=1))
    first, second = run.segments[:2]
    cut = cut_run(run, first[1] - 1.0, second[0] + 1.0)
    assert cut.time[0] == pytest.approx(first[1] - 1.0) and cut.time[-1] == pytest.approx(second[0] + 1.0)
    assert cut.segments == ((cut.time[0], first[1]), (second[0], cut.time[-1]))
    assert cut.metadata["true_windows"] == format_true_windows(cut.segments)
    assert cut.catches == (first[1],) and len(cut.pushes) == 1
    k = int(np.searchsorted(run.time, cut.time[0]))
    np.testing.assert_array_equal(cut.signals["roll_rate"], run.signals["roll_rate"][k:k + cut.time.size])
    with pytest.raises(ScenarioError, match="fewer than 3 samples"):
        cut_run(run, 100.0, 101.0)
