"""The fitting function's bias (whipple.diagnosis.fit_bias): a model's prediction of a window's fit."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest
from synthetic_windows import synthetic_observations

from whipple.cli import main
from whipple.diagnosis.candidate_fits import fit_all, refit_through_bias
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.fit_bias import debiased, fitting_bias
from whipple.diagnosis.fitting import model_residuals, robust_chi2, window_whitening
from whipple.diagnosis.observations import observations, predicted_weave
from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.registry import candidate_causes
from whipple.measurement.experiment import measure_run
from whipple.measurement.refit import refit_weave, refit_weaves
from whipple.measurement.runs import run_from_simulation
from whipple.measurement.weavefit import NoOscillationError, fit_weave, response_with_eigenvalue
from whipple.model.parameters import load_bicycle
from whipple.simulation.scenario import RunScenario, Sensor, Sensors
from whipple.simulation.simulator import simulate_run, write_run_csv

#: Sensors without noise worth the name (exactly zero noise would leave no residual to scale).
QUIET = Sensors(*[Sensor(1e-6, 0.0)] * 7)


def _observations(bicycle, speeds, sensors=QUIET, seed=3):
    runs = [run_from_simulation(simulate_run(bicycle, RunScenario(speed=speed, seed=seed + k, n_pushes=3,
                                                                  sensors=sensors), name=f"run{k}"))
            for k, speed in enumerate(speeds)]
    return observations([m for run in runs for m in measure_run(run, baseline="auto")])


@pytest.fixture(scope="module")
def steer_damper():
    """Noise-free windows at 5, 6 and 8 m/s of kooijman2008 with a steer damper: the base
    bicycle, the damped one, and the windows."""
    base = load_bicycle("kooijman2008")
    bicycle = base.with_extensions(steer_damping=1.1)
    return base, bicycle, _observations(bicycle, (5.0, 6.0, 8.0))


def _misfit(model, found, amplitudes="own", start="measured"):
    """Median |measured - model weave - model's bias| [1/s] over the windows whose eigenvalue the model's weave
    matches within 30%."""
    measured = np.array([o.eigenvalue for o in found])
    deviation = measured - predicted_weave(model, found)
    keep = np.abs(deviation) < 0.3 * np.abs(measured)
    return np.median(np.abs(deviation - fitting_bias(model, found, amplitudes=amplitudes, start=start))[keep])


def test_the_bias_of_the_true_model_explains_the_fitted_eigenvalues(steer_damper):
    # Noise-free runs of a bicycle with a steer damper: the fitted weave eigenvalues differ from
    # the model's by the fitting function's bias alone, which the model's own response predicts.
    _, bicycle, found = steer_damper
    weave = predicted_weave(bicycle, found)
    deviation = np.array([o.eigenvalue for o in found]) - weave
    weave_windows = np.abs(deviation) < 0.3 * np.abs(weave)
    assert weave_windows.sum() >= 6
    bias = fitting_bias(bicycle, found)[weave_windows]
    deviation = deviation[weave_windows]
    assert np.median(np.abs(deviation)) > 1e-3  # there is a bias to explain
    assert np.median(np.abs(deviation - bias)) < 0.1 * np.median(np.abs(deviation))


def test_the_bias_depends_on_the_model():
    # The base model's bias is no correction for a bicycle with a steer damper: why each
    # candidate is compared through its own.
    base = load_bicycle("kooijman2008")
    bicycle = base.with_extensions(steer_damping=1.1)
    found = _observations(bicycle, (6.0,))
    deviation = np.array([o.eigenvalue for o in found]) - predicted_weave(bicycle, found)
    own, other = fitting_bias(bicycle, found), fitting_bias(base, found)
    assert np.median(np.abs(deviation - other)) > 10 * np.median(np.abs(deviation - own))


def test_amplitudes_at_the_model_weave_are_exact_for_the_truth_and_swallow_a_wrong_model_error(steer_damper):
    # Why the diagnosis fits the modal amplitudes at the window's own weave, and what that costs:
    # at the model's weave the truth's bias is exact, but a wrong model's error is partly taken
    # for bias by the other modes.
    base, bicycle, found = steer_damper
    assert _misfit(bicycle, found, "model") < 0.1 * _misfit(bicycle, found, "own")
    assert _misfit(base, found, "model") < 0.8 * _misfit(base, found, "own")
    with pytest.raises(ValueError, match="amplitudes"):
        fitting_bias(bicycle, found, amplitudes="window")


def test_the_experimental_start_of_the_fixed_point_from_the_model_weave(steer_damper):
    # Started from the model's weave, the fixed point leaves the truth closer to its windows and
    # keeps nearly all of a wrong model's error (97% here; amplitudes fitted at the model's
    # weave keep two thirds of it).
    base, bicycle, found = steer_damper
    from_measured = _misfit(bicycle, found), _misfit(base, found)
    from_model = _misfit(bicycle, found, start="model"), _misfit(base, found, start="model")
    assert from_model[0] < from_measured[0]
    assert from_model[1] >= 0.9 * from_measured[1]


def test_windows_without_samples_have_no_bias():
    bicycle = load_bicycle("benchmark")
    listed = synthetic_observations(bicycle, 1, [3.0, 5.0, 7.0])
    assert all(o.signals is None for o in listed)
    assert np.all(fitting_bias(bicycle, listed) == 0)
    assert debiased(listed, np.zeros(len(listed))) == list(listed)


def test_debiased_shifts_each_eigenvalue():
    bicycle = load_bicycle("benchmark")
    listed = synthetic_observations(bicycle, 1, [3.0, 5.0])
    shifted = debiased(listed, np.array([0.1 - 0.2j, 0.0]))
    assert shifted[0].eigenvalue == pytest.approx(listed[0].eigenvalue - (0.1 - 0.2j))
    assert shifted[1] is listed[1]


def test_refit_weave_finds_a_damped_sinusoid_and_refuses_no_oscillation():
    time = np.arange(0.0, 3.0, 0.01)
    signal = 0.2 + np.exp(-0.8 * time) * np.cos(5.0 * time + 0.3)
    assert refit_weave(time, signal, complex(-0.7, 5.2)) == pytest.approx(complex(-0.8, 5.0), abs=1e-6)
    with pytest.raises(NoOscillationError):
        refit_weave(time, np.zeros(time.size), complex(-0.7, 5.2))


@pytest.mark.parametrize("baseline", ["constant", "quadratic"])
def test_refit_weave_reaches_the_full_fits_optimum(baseline):
    # A weave with a castering-like fast mode, a capsize-like drift and noise: the function does
    # not fit exactly, and the refit's Gauss-Newton steps must land where the full fit does.
    rng = np.random.default_rng(3)
    time = np.arange(0.0, 4.0, 0.005)
    signal = (np.exp(-0.6 * time) * np.sin(4.1 * time + 0.4) + 0.5 * np.exp(-9.0 * time)
              + 0.05 * np.exp(0.2 * time) + 0.01 * rng.standard_normal(time.size))
    full = fit_weave(time, signal, baseline=baseline).eigenvalue
    assert abs(full - complex(-0.6, 4.1)) > 1e-3  # the extra modes bias the fit: a real test
    refit = refit_weave(time, signal, complex(-0.5, 4.3), baseline)
    # The full fit stops at SciPy's default tolerances, a few 1e-6 1/s from the optimum here;
    # the refit must agree to that and fit at least as well.
    assert refit == pytest.approx(full, abs=1e-5)
    fitted = {z: response_with_eigenvalue(time, signal, z, baseline)[0] for z in (full, refit)}
    assert np.sum((signal - fitted[refit]) ** 2) <= np.sum((signal - fitted[full]) ** 2)


def test_refitting_many_windows_at_once_gives_each_windows_own_refit():
    # Windows of different lengths, baselines and signal counts, one without oscillation:
    # stacked, each must reach the optimum it reaches alone, and the failure stays its own.
    rng = np.random.default_rng(5)
    times, values, starts, baselines = [], [], [], []
    for n, (size, baseline) in enumerate([(300, "constant"), (180, "quadratic"), (520, "constant"),
                                          (240, "quadratic"), (400, "constant")]):
        time = np.arange(size) * 0.01
        weave = np.exp(-0.4 * time) * np.sin((3.5 + 0.3 * n) * time + 0.2 * n)
        signal = weave + 0.3 * np.exp(-8.0 * time) + 0.01 * rng.standard_normal(size)
        values.append(np.vstack([signal, 0.5 * signal + 0.02 * rng.standard_normal(size)]) if n == 2 else signal)
        times.append(time)
        starts.append(complex(-0.3, 3.4 + 0.3 * n))
        baselines.append(baseline)
    values[4] = np.full(400, 0.7)
    together, failures = refit_weaves(times, values, np.array(starts), baselines)
    for n in range(4):
        alone = refit_weave(times[n], values[n], starts[n], baselines[n])
        assert together[n] == pytest.approx(alone, abs=1e-12)
        if n != 2:  # the full fit weighs two signals by their residuals (the test above)
            assert together[n] == pytest.approx(fit_weave(times[n], values[n], baseline=baselines[n]).eigenvalue,
                                                abs=1e-5)
        assert failures[n] is None
    assert np.isnan(together[4]) and "constant" in failures[4]


def test_a_refit_of_several_signals_with_the_fits_weights_reaches_the_fits_optimum():
    # Two signals of different noise, the second with more of a fast mode: the full fit weighs
    # them by their residuals, so a refit weighing them by their spreads lands elsewhere.
    rng = np.random.default_rng(11)
    time = np.arange(0.0, 3.0, 0.01)
    weave = np.exp(-0.5 * time) * np.sin(4.0 * time + 0.3)
    signals = np.vstack([weave + 0.2 * np.exp(-10.0 * time) + 0.01 * rng.standard_normal(time.size),
                         0.4 * np.exp(-0.5 * time) * np.sin(4.0 * time + 1.1) + 0.3 * np.exp(-10.0 * time)
                         + 0.05 * rng.standard_normal(time.size)])
    fit = fit_weave(time, signals, ("roll_rate", "steer_angle"))
    assert len(fit.signal_weights) == 2
    start = fit.eigenvalue + complex(0.05, -0.1)
    assert refit_weave(time, signals, start, weights=fit.signal_weights) == pytest.approx(fit.eigenvalue, abs=1e-5)
    assert abs(refit_weave(time, signals, start) - fit.eigenvalue) > 1e-3


# Slow (many diagnoses of simulated runs): run with `pytest -m slow`.
@pytest.mark.slow
def test_diagnosis_through_the_fitting_function_estimates_the_truth_better():
    # Realistic sensors: compared through the fitting function, the true cause's value is
    # nearer the truth (the windows' bias is predicted, not fitted by the cause's value); compared
    # with the samples (no fitting function at all), nearer still (1.1002 against 1.112 and 1.164).
    base = load_bicycle("kooijman2008")
    truth = 1.1
    found = _observations(base.with_extensions(steer_damping=truth), (4.0, 5.0, 6.0, 7.0, 8.0), sensors=Sensors(),
                          seed=11)
    error = {}
    for comparison in ("eigenvalues", "fitting-function", "samples"):
        diagnosis = diagnose_observations(base, found, options=DiagnosisOptions(comparison=comparison),
                                          estimate_spread=False)
        assert diagnosis.comparison == comparison
        error[comparison] = abs({fit.cause: fit.values for fit in diagnosis.fits}["steer_damping"][0] - truth)
    assert error["samples"] < error["fitting-function"] < error["eigenvalues"]


# Slow (a whole diagnosis of the bundled runs by the command (over 1 minute)): run with `pytest -m slow`.
@pytest.mark.slow
def test_diagnose_cli_compares_with_the_samples_by_default(tmp_path, capsys):
    truth = load_bicycle("benchmark").with_extensions(steer_damping=0.8)
    paths = []
    for k, speed in enumerate((4.0, 5.0, 6.0, 7.0)):
        run = simulate_run(truth, RunScenario(speed=speed, seed=10 + k), name=f"run{k}")
        paths.append(str(write_run_csv(run, tmp_path / f"run{k}.csv")))
    spread = {}
    roll_rate_alone = ["--signals", "roll_rate"]
    for option, applied in (([], "samples"), (["--compare", "fitting-function"], "fitting-function"),
                            (["--compare", "eigenvalues"], "eigenvalues"), (roll_rate_alone, "samples")):
        out = tmp_path / "d.json"
        assert main(["diagnose", *paths, "--bicycle", "benchmark", *option, "--json", str(out)]) == 0
        data = json.loads(out.read_text())
        assert data["comparison"] == applied
        assert data["verdict"] == "named" and data["cause"] == "steer_damping"
        assert abs(data["estimate"]["steer_damping"]["value"] - 0.8) < 0.2
        spread[" ".join(option)] = data["estimate"]["steer_damping"]["std"]
        fitted = "roll_rate" if option == roll_rate_alone else "roll_rate and steer_angle jointly"
        assert f"(4 runs; fitted {fitted}, baseline auto)" in capsys.readouterr().out
    # The runs measure the steer angle, so by default its weave is fitted jointly with the roll
    # rate, which sharpens every eigenvalue.
    assert spread[""] < spread[" ".join(roll_rate_alone)]
    for signals, problem in ((",", "--signals names no signal"), ("roll_rate,steer_rat", "no steer_rat signal")):
        assert main(["diagnose", *paths, "--bicycle", "benchmark", "--signals", signals]) == 2
        assert problem in capsys.readouterr().err


def test_observations_without_samples_are_compared_directly():
    # A table of eigenvalues has no samples to refit: the default changes nothing there.
    base = load_bicycle("benchmark")
    listed = synthetic_observations(base.with_extensions(steer_damping=0.8), 2, (3.0, 4.0, 5.0, 6.0))
    by_default = diagnose_observations(base, listed, estimate_spread=False)
    directly = diagnose_observations(base, listed, options=DiagnosisOptions(comparison="eigenvalues"),
                                     estimate_spread=False)
    assert by_default.comparison == "eigenvalues"
    assert by_default.ranking() == directly.ranking()


def test_only_causes_near_the_best_are_refitted_with_their_own_bias():
    # The screen of the bias (evidence.BIAS_SCREEN): a cause near the best is refitted with its
    # own model's bias exactly as without the screen; one far behind is its direct fit,
    # evaluated with the base model's bias, and its chi-square is that evaluation's.
    base = load_bicycle("kooijman2008")
    found = _observations(base.with_extensions(steer_damping=1.1), (5.0, 7.0), sensors=Sensors(), seed=5)
    causes = [cause for cause in candidate_causes(base) if cause.name in ("steer_damping", "speed_scale")]
    whitening = window_whitening(found, base)
    _, fits = fit_all(base, causes, found, whitening)
    base_bias = fitting_bias(base, found)
    screened_base, screened, biases = refit_through_bias(base, causes, fits, found, whitening, base_bias, [True, False])
    own = fitting_bias(causes[0].apply(base, list(fits[0].values)), found)
    unscreened_base, unscreened = fit_all(base, causes[:1], found, whitening, [[fits[0].values]], [base_bias, own])
    assert screened[0].values == unscreened[0].values and screened[0].chi2 == unscreened[0].chi2
    assert screened_base.chi2 == unscreened_base.chi2
    assert np.array_equal(biases[0], own) and biases[1] is base_bias
    assert screened[1].values == fits[1].values
    far = model_residuals(causes[1].apply(base, list(fits[1].values)), found, replace(whitening, bias=base_bias))[0]
    assert screened[1].chi2 == robust_chi2(far) != fits[1].chi2
