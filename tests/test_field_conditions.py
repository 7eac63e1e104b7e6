"""Field conditions of simulated runs: coasting on the ground, the acceleration terms, sensor faults.

Independent references:
- the coasting speed and distance: ``solve_ivp`` of ``v' = -(a + k v^2)`` and its limits;
- the linear time-varying simulation: a dense ``solve_ivp`` of the same system along v(t);
- the acceleration terms: their roll row against C1 of the linear derivation, and the whole
  ground run against the nonlinear model (prescribed speed) at small amplitude;
- treadmill runs and today's hidden-effect trials: the files written at the branch point
  (2c56f58), by their SHA-256;
- each sensor fault: the run without it, with the same seed (same noise).
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from whipple.cli import main
from whipple.measurement.noise import second_difference_noise
from whipple.measurement.runs import read_run
from whipple.model.assembly import linear_model, model_matrices
from whipple.model.parameters import Payload, load_bicycle
from whipple.model.speed_change import acceleration_stiffness
from whipple.simulation.coasting import coasting_distance, coasting_speed, stopping_time
from whipple.simulation.disturbance import disturbance_torque
from whipple.simulation.nonlinear_run import simulate_nonlinear_run
from whipple.simulation.scenario import PERFECT_SENSORS, RunScenario, ScenarioError, SensorFaults
from whipple.simulation.sensor_faults import BIAS_WALK_STREAM
from whipple.simulation.simulator import simulate_run, write_run_csv

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hidden_effects import (  # noqa: E402
    CONDITIONS,
    DISTURBANCE_STEER_SHARE,
    FieldConditions,
    trial_bicycle,
    trial_runs,
)

GYROS = ("roll_rate", "yaw_rate")


@pytest.fixture(scope="module")
def bike():
    return load_bicycle("benchmark")


def _sha(run, folder: Path) -> str:
    return hashlib.sha256(write_run_csv(run, folder / "run.csv").read_bytes()).hexdigest()


# --- treadmill runs and today's trials are unchanged --------------------------------------

#: SHA-256 of the run files written by the code at the branch point (2c56f58).
TREADMILL_FILES = {(0, 5.0): "1e613333ae29e5560674c9b25e11941ba191efc1cdf47b63cf340f1ad3446251",
                   (3, 4.5): "a0b544b31294a4d571fbd3b6eb5070306a0c0347c20209d326628c58cef12bc7",
                   (17, 6.0): "8fbb9a557f75b1aeb904cfee22c8092cbee20cd325cf353ff9ae28fed4dd647a"}
TRIAL_FILES = {("none", 0, "benchmark"): "557c25c4da565f48cdaf9a99e8dc88df9c5fad5628856c61298c69767039037b",
               ("rack", 3, "benchmark"): "491d91be56903f0996f0b2d4abfcaf6e4ecad4596947559d2b462436049e1bb9",
               ("none", 5, "sbw2024"): "9a17501f33afb3ecb193f4dda539cc295d04c401dfb0d19ac8d32522ad99440a"}


@pytest.mark.parametrize(("seed", "speed"), list(TREADMILL_FILES))
def test_treadmill_runs_are_bit_identical_to_before(bike, tmp_path, seed, speed):
    run = simulate_run(bike, RunScenario(speed=speed, seed=seed, n_pushes=2))
    assert _sha(run, tmp_path) == TREADMILL_FILES[seed, speed]


def test_treadmill_speedometer_and_nonlinear_runs_are_bit_identical_to_before(bike, tmp_path):
    columns = ("roll_rate", "yaw_rate", "steer_angle", "speedometer")
    speedometer = simulate_run(load_bicycle("kooijman2008"),
                               RunScenario(speed=5.5, seed=9, n_pushes=2, sample_rate=500, columns=columns))
    assert _sha(speedometer, tmp_path) == "40b340a6e915ce72ed46a47b4555abbe3b04b8ead8a752e841789f295378ea87"
    nonlinear = simulate_nonlinear_run(bike, RunScenario(speed=5.0, seed=2, n_pushes=1, duration=4.0))
    assert _sha(nonlinear, tmp_path) == "7ab73622a0004092c36f4ff5d9ccef8fa1a555bace69cd1811ca5ec7d10aea3a"


@pytest.mark.parametrize("key", list(TRIAL_FILES))
def test_default_trial_runs_are_todays(tmp_path, key):
    _, _, runs = trial_runs(*key)
    digest = hashlib.sha256("".join(_sha(run, tmp_path) for run in runs).encode()).hexdigest()
    assert digest == TRIAL_FILES[key]
    _, _, named = trial_runs(*key, conditions="treadmill")
    assert all(np.array_equal(a.signals["roll_rate"], b.signals["roll_rate"]) for a, b in zip(runs, named, strict=True))


# --- coasting ---------------------------------------------------------------------------------

@pytest.mark.parametrize(("a", "k"), [(0.05, 0.0), (0.0, 0.004), (0.03, 0.003), (0.08, 1e-9), (0.5, 0.05),
                                      (-0.05, 0.0), (-0.2, 0.003), (-0.08, 1e-9), (-0.5, 0.05)])
def test_coasting_speed_and_distance_solve_the_drag_law(a, k):
    v0, end = 6.0, min(20.0, 0.9 * stopping_time(6.0, a, k))
    t = np.linspace(0.0, end, 201)
    reference = solve_ivp(lambda _, y: [-(a + k * y[0] ** 2), y[0]], (0, end), [v0, 0.0], t_eval=t,
                          rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(coasting_speed(v0, a, k, t), reference.y[0], rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(coasting_distance(v0, a, k, t), reference.y[1], rtol=1e-9, atol=1e-9)


def test_coasting_limits_and_stopping_time():
    t = np.linspace(0, 10, 11)
    np.testing.assert_array_equal(coasting_speed(5.0, 0.05, 0.0, t), 5.0 - 0.05 * t)
    np.testing.assert_allclose(coasting_speed(5.0, 0.0, 0.01, t), 5.0 / (1 + 0.05 * t), rtol=1e-14)
    stop = stopping_time(5.0, 0.05, 0.01)
    assert abs(float(coasting_speed(5.0, 0.05, 0.01, stop))) < 1e-12
    assert stopping_time(5.0, 0.0, 0.01) == np.inf


def test_downhill_coasting_speeds_up_towards_the_drag_limit():
    # Down a slope the speed rises, and with drag it tends to sqrt(-a / k) from either side.
    assert stopping_time(5.0, -0.1, 0.004) == np.inf
    np.testing.assert_array_equal(coasting_speed(5.0, -0.05, 0.0, np.array([0.0, 10.0])), [5.0, 5.5])
    limit = np.sqrt(0.1 / 0.004)
    for start in (2.0, 8.0):
        late = coasting_speed(start, -0.1, 0.004, np.array([0.0, 1000.0]))
        assert late[0] == start and abs(late[1] - limit) < 1e-9


def test_ground_speed_with_drag_in_both_simulators(bike):
    scenario = RunScenario(speed=5.0, n_pushes=1, duration=4.0, setting="ground", deceleration=0.03, drag=0.004,
                           sensors=PERFECT_SENSORS)
    linear, nonlinear = simulate_run(bike, scenario), simulate_nonlinear_run(bike, scenario)
    expected = coasting_speed(5.0, 0.03, 0.004, linear.time)
    np.testing.assert_array_equal(linear.speed, expected)
    np.testing.assert_allclose(nonlinear.speed, expected, atol=1e-8)
    # Drag slows the bicycle by 0.03 + 0.004 v^2 m/s^2: 0.13 at the start, 0.116 after 4 s.
    assert 5.0 - 4 * 0.13 < float(expected[-1]) < 5.0 - 4 * 0.116
    assert linear.metadata["drag"] == "0.004" and nonlinear.metadata["drag"] == "0.004"


def test_downhill_ground_run_speeds_up_in_both_simulators(bike):
    scenario = RunScenario(speed=4.0, n_pushes=1, duration=4.0, setting="ground", deceleration=-0.1, drag=0.002,
                           sensors=PERFECT_SENSORS)
    linear, nonlinear = simulate_run(bike, scenario), simulate_nonlinear_run(bike, scenario)
    expected = coasting_speed(4.0, -0.1, 0.002, linear.time)
    np.testing.assert_array_equal(linear.speed, expected)
    np.testing.assert_allclose(nonlinear.speed, expected, atol=1e-8)
    # Gravity's pull of 0.1 m/s^2 less the drag of 0.002 v^2 (0.032 at 4 m/s, 0.037 at 4.3 m/s).
    assert 4.0 + 4 * (0.1 - 0.037) < float(expected[-1]) < 4.0 + 4 * (0.1 - 0.032)


def test_a_ground_run_without_deceleration_is_the_treadmill_run(bike):
    treadmill = simulate_run(bike, RunScenario(speed=5.0, n_pushes=1, duration=5.0, seed=3))
    ground = simulate_run(bike, RunScenario(speed=5.0, n_pushes=1, duration=5.0, seed=3, setting="ground",
                                            deceleration=0.0))
    np.testing.assert_array_equal(ground.states, treadmill.states)
    for name in treadmill.signals:
        np.testing.assert_array_equal(ground.signals[name], treadmill.signals[name])


# --- the linear time-varying simulation --------------------------------------------------------

def _coasts(run):
    """Index ranges of the free-coasting samples of a run."""
    fs = run.sample_rate
    return [np.arange(int(np.ceil(a * fs - 1e-6)), int(np.floor(b * fs + 1e-6)) + 1) for a, b in run.segments]


@pytest.mark.parametrize("terms", [False, True])
def test_ground_coasting_is_the_time_varying_system_along_the_speed(bike, terms):
    scenario = RunScenario(speed=5.5, setting="ground", deceleration=0.05, drag=0.003, n_pushes=2,
                           sensors=PERFECT_SENSORS)
    run = simulate_run(bike, scenario, acceleration_terms=terms)
    model, stiffness = linear_model(bike), acceleration_stiffness(bike)

    def derivative(t, x):
        v = float(scenario.true_speed(t))
        A = model.state_matrix(v)
        if terms:
            slowing = scenario.deceleration + scenario.drag * v**2
            A = A.copy()
            A[:, 0:2] += slowing * model.input_matrix(v) @ stiffness
        return A @ x

    for coast in _coasts(run):
        t = run.time[coast]
        reference = solve_ivp(derivative, (t[0], t[-1]), run.states[coast[0]], t_eval=t, method="DOP853",
                              rtol=1e-11, atol=1e-13).y.T
        error = np.abs(reference - run.states[coast]).max(axis=0) / np.abs(reference).max(axis=0)
        assert error.max() < 2e-5  # the midpoint rule at 100 Hz: measured 1.5e-6 to 8e-6
    # Held at one speed (the constant-speed model at the coast's start), the same coast is far off.
    t = run.time[coast]
    frozen = solve_ivp(lambda _, x: model.state_matrix(float(scenario.true_speed(t[0]))) @ x, (t[0], t[-1]),
                       run.states[coast[0]], t_eval=t, rtol=1e-10, atol=1e-12).y.T
    assert np.abs(frozen - run.states[coast]).max() > 0.05 * np.abs(run.states[coast]).max()


@pytest.mark.parametrize("name", ["benchmark", "kooijman2008", "browser", "sbw2024"])
def test_acceleration_stiffness_roll_row_is_c1_roll_steer(name):
    """From the nonlinear equations: the roll row is C1's roll-steer entry (all of it from momenta
    ``v P q``), with payloads folded in as the extended linear derivation adds them."""
    base = trial_bicycle(name)
    for bicycle in (base, base.with_extensions(payload=Payload(20.0, 0.3, -0.9)),
                    base.with_extensions(front_payload=Payload(5.0, 1.0, -0.8))):
        stiffness = acceleration_stiffness(bicycle)
        C1 = model_matrices(bicycle.parameters, bicycle.extensions).C1
        assert stiffness[0, 1] == pytest.approx(C1[0, 1], rel=1e-9)
        assert np.abs(stiffness[:, 0]).max() < 1e-9
        assert stiffness[1, 1] > 0


def test_acceleration_stiffness_of_point_wheels(bike):
    for changes in ({"rR": 0.0, "IRyy": 0.0}, {"rR": 0.0, "rF": 0.0, "IRyy": 0.0, "IFyy": 0.0}):
        skate = bike.with_parameters(**changes)
        C1 = model_matrices(skate.parameters, skate.extensions).C1
        assert acceleration_stiffness(skate)[0, 1] == pytest.approx(C1[0, 1], rel=1e-9)


def test_acceleration_terms_make_the_linear_ground_run_the_nonlinear_one(bike):
    """At small amplitude on the ground, the nonlinear run (speed prescribed by a hub torque) and the
    linear one with the acceleration terms agree as closely as on a treadmill; without them they
    differ by a few per cent (measured: 0.10 % against 3.3 % at 0.08 m/s^2; treadmill 0.08 %)."""
    scenario = RunScenario(speed=5.0, setting="ground", deceleration=0.08, n_pushes=1, push_roll_rate=0.05,
                           max_coast=4.0, sensors=PERFECT_SENSORS)
    nonlinear = simulate_nonlinear_run(bike, scenario).truth["roll_rate"]

    def difference(terms: bool) -> float:
        linear = simulate_run(bike, scenario, acceleration_terms=terms)
        coast = _coasts(linear)[0]
        return float(np.abs(nonlinear[coast] - linear.truth["roll_rate"][coast]).max()
                     / np.abs(linear.truth["roll_rate"][coast]).max())

    assert difference(True) < 0.003
    assert difference(False) > 0.02


# --- sensor faults --------------------------------------------------------------------------

def _faulty_pair(bike, faults, **changes):
    scenario = RunScenario(**{"speed": 5.0, "n_pushes": 1, "duration": 6.0, "seed": 5, "setting": "ground", **changes})
    return simulate_run(bike, scenario), simulate_run(bike, scenario.replace(faults=faults))


def _only_changed(clean, faulty, changed):
    np.testing.assert_array_equal(faulty.states, clean.states)
    for name in clean.truth:
        np.testing.assert_array_equal(faulty.truth[name], clean.truth[name])
    for name in clean.signals:
        if name not in changed:
            np.testing.assert_array_equal(faulty.signals[name], clean.signals[name])
    return {name: faulty.signals[name] - clean.signals[name] for name in changed}


def test_misalignment_mixes_the_yaw_rate_into_the_roll_gyro(bike):
    angle = np.radians(3.0)
    clean, faulty = _faulty_pair(bike, SensorFaults(misalignment=angle))
    change = _only_changed(clean, faulty, GYROS)
    roll, yaw = clean.truth["roll_rate"], clean.truth["yaw_rate"]
    np.testing.assert_allclose(change["roll_rate"], (np.cos(angle) - 1) * roll - np.sin(angle) * yaw, atol=1e-12)
    np.testing.assert_allclose(change["yaw_rate"], np.sin(angle) * roll + (np.cos(angle) - 1) * yaw, atol=1e-12)
    # The yaw rate mixed in is the Whipple model's: v delta cos(lambda) / w, plus the trail's term.
    p = bike.parameters
    steer, steer_rate = clean.truth["steer_angle"], clean.truth["steer_rate"]
    kinematic = (clean.speed * steer + p["c"] * steer_rate) * np.cos(p["lam"]) / p["w"]
    np.testing.assert_allclose(yaw, kinematic, atol=1e-12)


def test_gyro_scale_multiplies_both_gyros(bike):
    clean, faulty = _faulty_pair(bike, SensorFaults(gyro_scale=1.04))
    change = _only_changed(clean, faulty, GYROS)
    for name in GYROS:
        np.testing.assert_allclose(change[name], 0.04 * clean.truth[name], atol=1e-12)


def test_bias_drift_and_walk_change_the_roll_rate_alone(bike):
    clean, drifting = _faulty_pair(bike, SensorFaults(bias_drift=5e-4))
    np.testing.assert_allclose(_only_changed(clean, drifting, ("roll_rate",))["roll_rate"], 5e-4 * clean.time,
                               atol=1e-12)
    clean, walking = _faulty_pair(bike, SensorFaults(bias_walk=0.01), duration=60.0)
    walk = _only_changed(clean, walking, ("roll_rate",))["roll_rate"]
    assert walk[0] == 0.0
    steps = np.diff(walk)
    # Gaussian steps of 0.01 / sqrt(100 Hz) = 1e-3 rad/s: the spread of 6000 steps within 5 %.
    assert np.std(steps) == pytest.approx(1e-3, rel=0.05)
    assert abs(np.corrcoef(steps[:-1], steps[1:])[0, 1]) < 0.05
    again = simulate_run(bike, walking.scenario)
    np.testing.assert_array_equal(again.signals["roll_rate"], walking.signals["roll_rate"])
    assert BIAS_WALK_STREAM != 0


def test_steer_offset_shifts_the_steer_angle_alone(bike):
    clean, faulty = _faulty_pair(bike, SensorFaults(steer_offset=np.radians(0.8)))
    change = _only_changed(clean, faulty, ("steer_angle",))["steer_angle"]
    np.testing.assert_allclose(change, np.radians(0.8), atol=1e-15)


def test_no_steer_angle_leaves_the_other_columns_as_they_were(bike, tmp_path):
    full, _ = _faulty_pair(bike, SensorFaults())
    columns = ("roll_rate", "yaw_rate", "speed")
    without = simulate_run(bike, full.scenario.replace(columns=columns))
    assert tuple(without.signals) == columns
    for name in columns:
        np.testing.assert_array_equal(without.signals[name], full.signals[name])
    assert "steer_angle" not in read_run(write_run_csv(without, tmp_path / "run.csv")).signals


def test_faults_are_written_in_the_metadata_and_the_file_reads_back(bike, tmp_path):
    faults = SensorFaults(misalignment=0.03, gyro_scale=0.98, bias_drift=1e-4, bias_walk=1e-3, steer_offset=-0.01)
    _, faulty = _faulty_pair(bike, faults)
    assert {key: faulty.metadata[key] for key in ("imu_misalignment", "gyro_scale", "roll_rate_bias_drift",
                                                   "roll_rate_bias_walk", "steer_offset")} == {
        "imu_misalignment": "0.03", "gyro_scale": "0.98", "roll_rate_bias_drift": "0.0001",
        "roll_rate_bias_walk": "0.001", "steer_offset": "-0.01"}
    run = read_run(write_run_csv(faulty, tmp_path / "run.csv"))
    np.testing.assert_allclose(run.signals["roll_rate"], faulty.signals["roll_rate"], rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("changes", [
    {"misalignment": np.radians(21.0)}, {"gyro_scale": 1.6}, {"gyro_scale": float("nan")},
    {"bias_drift": 0.02}, {"bias_walk": -1e-3}, {"steer_offset": np.radians(-11.0)}, {"misalignment": True}])
def test_out_of_range_faults_are_one_line_errors(changes):
    with pytest.raises(ScenarioError) as error:
        SensorFaults(**changes)
    assert "\n" not in str(error.value) and next(iter(changes)) in str(error.value)


def test_drag_on_a_treadmill_and_a_speed_that_stops_are_refused():
    with pytest.raises(ScenarioError, match="ground setting only"):
        RunScenario(drag=0.001)
    with pytest.raises(ScenarioError, match="reaches 0"):
        RunScenario(speed=3.0, setting="ground", deceleration=0.05, drag=0.2)
    # Down a slope the speed at the run's end is the one checked against the reader's limit.
    RunScenario(speed=95.0, setting="ground", deceleration=-0.1, duration=10.0)
    with pytest.raises(ScenarioError, match="speeds up to 1"):
        RunScenario(speed=95.0, setting="ground", deceleration=-1.0, duration=10.0)


# --- the command line -------------------------------------------------------------------------

def test_cli_writes_ground_runs_with_faults(tmp_path, capsys):
    out = tmp_path / "run.csv"
    code = main(["simulate", "--bicycle", "benchmark", "--speed", "5", "--setting", "ground", "--drag", "0.002",
                 "--deceleration", "0.04", "--misalignment", "2", "--gyro-scale", "-3", "--bias-drift", "1e-4",
                 "--bias-walk", "1e-3", "--steer-offset", "0.5", "--no-steer-angle", "--seed", "3",
                 "--output", str(out)])
    assert code == 0 and str(out) in capsys.readouterr().out
    run = read_run(out)
    assert "steer_angle" not in run.signals
    m = run.metadata
    assert (m["deceleration"], m["drag"], m["gyro_scale"]) == ("0.04", "0.002", "0.97")
    assert float(m["imu_misalignment"]) == pytest.approx(np.radians(2.0))
    assert float(m["steer_offset"]) == pytest.approx(np.radians(0.5))
    assert m["roll_rate_bias_drift"] == "0.0001" and m["roll_rate_bias_walk"] == "0.001"
    # The speed column falls as the coasting law says (noise 0.02 m/s).
    expected = coasting_speed(5.0, 0.04, 0.002, run.time)
    assert np.abs(run.signals["speed"] - expected).mean() < 0.03


def test_cli_disturbance_needs_two_torques(tmp_path, capsys):
    with pytest.raises(SystemExit) as raised:
        main(["simulate", "--bicycle", "benchmark", "--speed", "5", "--disturbance", "2", "--output",
              str(tmp_path / "out")])
    error = capsys.readouterr().err
    assert raised.value.code == 2 and "expected two torques like 2,0.1" in error.splitlines()[-1]


@pytest.mark.parametrize(("arguments", "message"), [
    (["--deceleration", "0.05"], "--deceleration applies to --setting ground"),
    (["--drag", "0.001"], "--drag applies to --setting ground"),
    (["--setting", "ground", "--drag", "-0.001"], "drag must be"),
    (["--misalignment", "25"], "--misalignment must be within +/-20 degrees"),
    (["--gyro-scale", "60"], "--gyro-scale must be within +/-50 percent"),
    (["--bias-drift", "0.5"], "--bias-drift must be within"),
    (["--bias-walk", "-0.1"], "--bias-walk must be between 0 and"),
    (["--steer-offset", "12"], "--steer-offset must be within +/-10 degrees"),
    (["--steer-offset", "nan"], "--steer-offset must be within"),
    (["--disturbance", "2,-1"], "steer disturbance must be"),
    (["--disturbance", "2,0.1", "--disturbance-band", "50"], "below half the sample rate"),
    (["--disturbance", "2,0.1", "--nonlinear"], "on the linear model only"),
])
def test_cli_bad_field_options_exit_2_with_one_line(tmp_path, capsys, arguments, message):
    code = main(["simulate", "--bicycle", "benchmark", "--speed", "5", *arguments, "--output", str(tmp_path / "out")])
    error = capsys.readouterr().err
    assert code == 2 and error.count("\n") == 1 and message in error
    assert not (tmp_path / "out").exists()


# --- the hidden-effect trials' field conditions ---------------------------------------------------

def test_ground_trials_keep_the_effect_and_the_noise_and_draw_the_deceleration():
    base, truth, treadmill = trial_runs("rack", 3, "benchmark", speeds=(4.0, 6.0))
    _, ground_truth, ground = trial_runs("rack", 3, "benchmark", speeds=(4.0, 6.0), conditions="ground")
    assert ground_truth == truth
    for flat, coasting in zip(treadmill, ground, strict=True):
        assert coasting.metadata["seed"] == flat.metadata["seed"]
        assert coasting.metadata["setting"] == "ground"
        start = float(coasting.metadata["true_speed"])
        slowing = float(coasting.metadata["deceleration"]) + float(coasting.metadata.get("drag", 0)) * start**2
        assert 0.02 <= slowing <= 0.08
        assert "imu_misalignment" not in coasting.metadata and "steer_angle" in coasting.signals
    again = trial_runs("rack", 3, "benchmark", speeds=(4.0, 6.0), conditions="ground")[2]
    np.testing.assert_array_equal(again[1].signals["roll_rate"], ground[1].signals["roll_rate"])


def test_ground_trials_with_faults_draw_them_in_their_ranges():
    conditions = CONDITIONS["ground+faults"]
    without_steer = 0
    for seed in range(8):
        runs = trial_runs("none", seed, "benchmark", speeds=(5.0, 6.0), conditions="ground+faults")[2]
        metadata = [run.metadata for run in runs]
        for key in ("imu_misalignment", "gyro_scale", "steer_offset"):  # one instrument per trial
            assert metadata[0][key] == metadata[1][key]
        m = metadata[0]
        assert abs(float(m["imu_misalignment"])) <= conditions.misalignment
        assert 0.01 <= abs(float(m["gyro_scale"]) - 1) <= 0.05
        assert abs(float(m["steer_offset"])) <= conditions.steer_offset
        assert abs(float(m["roll_rate_bias_drift"])) <= conditions.bias_drift
        without_steer += "steer_angle" not in runs[0].signals
    assert 0 < without_steer < 8


def test_trials_at_another_sample_rate_keep_the_draws():
    """A sample rate in the field conditions changes the runs' rate and nothing drawn."""
    _, truth, runs = trial_runs("rack", 3, "benchmark", speeds=(4.0,), conditions="ground+faults")
    fast = FieldConditions("ground", faults=True, sample_rate=250.0)
    _, fast_truth, fast_runs = trial_runs("rack", 3, "benchmark", speeds=(4.0,), conditions=fast)
    assert fast_truth == truth
    assert fast_runs[0].sample_rate == pytest.approx(250.0)
    assert runs[0].sample_rate == pytest.approx(100.0)
    for key in ("seed", "deceleration", "imu_misalignment", "gyro_scale", "steer_offset"):
        assert fast_runs[0].metadata[key] == runs[0].metadata[key]
    _, _, treadmill = trial_runs("none", 0, "benchmark", speeds=(4.0,),
                                 conditions=FieldConditions(sample_rate=50.0))
    assert treadmill[0].sample_rate == pytest.approx(50.0)


def test_trials_with_noisier_sensors_keep_the_draws():
    """A noise scale in the field conditions multiplies every sensor's noise and changes nothing drawn."""
    _, truth, runs = trial_runs("rack", 3, "benchmark", speeds=(4.0,), conditions="ground+faults")
    noisy = FieldConditions("ground", faults=True, noise_scale=3.0)
    _, noisy_truth, noisy_runs = trial_runs("rack", 3, "benchmark", speeds=(4.0,), conditions=noisy)
    assert noisy_truth == truth
    for key in ("seed", "deceleration", "imu_misalignment", "gyro_scale", "steer_offset"):
        assert noisy_runs[0].metadata[key] == runs[0].metadata[key]
    # The noise read from the samples (second differences) grows threefold. The steer angle's:
    # the roll rate's second differences also hold the held bicycle's wobble, which is motion.
    ratio = float(second_difference_noise(noisy_runs[0].signals["steer_angle"])[0]
                  / second_difference_noise(runs[0].signals["steer_angle"])[0])
    assert ratio == pytest.approx(3.0, rel=0.1)


def test_trials_with_disturbances_keep_the_draws():
    """Random torques drawn per trial leave the effect, the field's draws and the runs' seeds as they were."""
    for conditions, disturbed in (("ground+faults", "ground+faults+disturbance"),
                                  ("treadmill", "treadmill+disturbance")):
        _, truth, runs = trial_runs("rack", 3, "benchmark", speeds=(4.0, 5.0), conditions=conditions)
        _, disturbed_truth, disturbed_runs = trial_runs("rack", 3, "benchmark", speeds=(4.0, 5.0),
                                                        conditions=disturbed)
        assert disturbed_truth == truth
        levels = set()
        for run, disturbed_run in zip(runs, disturbed_runs, strict=True):
            for key in ("seed", "deceleration", "imu_misalignment", "gyro_scale", "steer_offset"):
                assert disturbed_run.metadata.get(key) == run.metadata.get(key)
            levels.add(disturbed_run.metadata["disturbance"])
        roll, steer = (float(x) for x in levels.pop().split(","))
        assert not levels and 1.0 <= roll <= 5.0 and steer == pytest.approx(DISTURBANCE_STEER_SHARE * roll, rel=1e-5)


def test_disturbance_torques_are_the_filtered_noise_asked_for():
    torque = disturbance_torque((3.0, 0.2), 2.0, 100.0, 200_000, seed=5)
    np.testing.assert_allclose(torque.std(axis=0), [3.0, 0.2], rtol=0.03)
    memory = np.exp(-2 * np.pi * 2.0 / 100.0)
    lag = [np.corrcoef(torque[:-1, k], torque[1:, k])[0, 1] for k in range(2)]
    np.testing.assert_allclose(lag, memory, atol=0.005)
    assert abs(np.corrcoef(torque[:, 0], torque[:, 1])[0, 1]) < 0.02
    assert not disturbance_torque((0.0, 0.0), 2.0, 100.0, 10, seed=5).any()


def test_a_disturbed_run_keeps_the_noise_and_pushes_of_the_undisturbed_one(bike):
    calm = simulate_run(bike, RunScenario(speed=5.0, n_pushes=1, duration=4.0, seed=3))
    disturbed = simulate_run(bike, RunScenario(speed=5.0, n_pushes=1, duration=4.0, seed=3,
                                               disturbance=(3.0, 0.15)))
    assert disturbed.segments == calm.segments and disturbed.pushes == calm.pushes
    # The sensors' noise is the same draw: the difference of the measured and the true roll rate.
    np.testing.assert_allclose(disturbed.signals["roll_rate"] - disturbed.truth["roll_rate"],
                               calm.signals["roll_rate"] - calm.truth["roll_rate"], rtol=0, atol=1e-12)
    # The motion differs: the torques move the bicycle by more than the noise.
    coast = slice(int(1.2 * 100), int(3.9 * 100))
    moved = disturbed.truth["roll_rate"][coast] - calm.truth["roll_rate"][coast]
    assert np.sqrt(np.mean(moved**2)) > 0.02
    assert disturbed.metadata["disturbance"] == "3,0.15" and "disturbance" not in calm.metadata


def test_field_conditions_are_checked():
    with pytest.raises(ValueError, match="ground"):
        FieldConditions("treadmill", faults=True)
    with pytest.raises(ValueError, match="conditions must be"):
        trial_runs("none", 0, conditions="moon")
