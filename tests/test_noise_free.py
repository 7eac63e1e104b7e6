"""Observations without noise: what windows of given speeds and uncertainties could tell at best.

The trials' "right given the data" counts an ambiguous verdict as right only where the same
windows without noise are ambiguous too; these tests check the twin itself.
"""

from __future__ import annotations

import numpy as np
from synthetic_windows import synthetic_observations

from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.fitting import model_residuals, window_whitening
from whipple.diagnosis.observations import noise_free, observations, predicted_modes
from whipple.diagnosis.registry import cause_by_name
from whipple.diagnosis.samples import SampleComparison, noise_free_samples
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import run_from_simulation
from whipple.model.parameters import load_bicycle
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

SPEEDS = np.repeat([3.5, 4.5, 5.5, 6.5, 7.5], 4)


def simulated_observations(bicycle, speeds):
    """The usable windows of simulated runs (three pushes each), fitted to roll rate and steer angle."""
    runs = [run_from_simulation(simulate_run(bicycle, RunScenario(speed=speed, seed=k), name=f"run{k}"))
            for k, speed in enumerate(speeds)]
    return observations([m for run in runs for m in measure_run(run, signals=("roll_rate", "steer_angle"))])


def test_the_true_model_fits_its_noise_free_twin_exactly_and_the_windows_keep_their_uncertainties():
    bicycle = load_bicycle("benchmark")
    truth = bicycle.with_extensions(steer_damping=0.6)
    measured = synthetic_observations(truth, 3, SPEEDS)
    twin = noise_free(truth, measured)
    eigenvalues, shapes = predicted_modes(truth, measured)
    assert np.array_equal([o.eigenvalue for o in twin], eigenvalues)
    assert np.array_equal([o.shape for o in twin], shapes)
    assert all(np.array_equal(o.covariance, m.covariance) and o.speed == m.speed and o.signals is None
               for o, m in zip(twin, measured, strict=True))
    # The noise is gone: the true model's whitened residuals vanish, the base model's do not.
    whitening = window_whitening(twin, bicycle)
    assert np.max(np.abs(model_residuals(truth, twin, whitening)[0])) < 1e-8
    assert np.max(np.abs(model_residuals(bicycle, twin, whitening)[0])) > 1.0


def test_a_twin_of_the_samples_is_the_true_models_response_at_the_windows_noise():
    # The twin's samples are what of each window the true model explains: the true model leaves
    # no residual on them, the base model does, and each window keeps its measured noise.
    bicycle = load_bicycle("benchmark")
    truth = bicycle.with_extensions(steer_damping=0.6)
    measured = simulated_observations(truth, (4.0, 6.0))
    twins = noise_free_samples(truth, measured)
    noisy, twin = SampleComparison.of(measured), SampleComparison.of(twins)
    assert np.array_equal(twin.noise, noisy.noise)
    assert twin.chi2_per_sample(truth) < 1e-12 < 1.0 < twin.chi2_per_sample(bicycle)
    assert 0.8 < noisy.chi2_per_sample(truth) < 1.2
    assert [o.eigenvalue for o in twins] == [o.eigenvalue for o in noise_free(truth, measured)]


def test_a_twin_tells_what_no_luck_in_the_noise_could_single_out():
    # A steer inertia and the front wheel's diametral inertia IFxx predict the benchmark's weave
    # alike (tests/test_ambiguity_gain.py): without noise the windows still cannot tell them
    # apart. A steer damping, on the same windows, is singled out.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name)
              for name in ("steer_inertia", "parameter:IFxx", "steer_damping", "speed_scale", "parameter:c")]
    inertia = bicycle.with_extensions(steer_inertia=0.04)
    twin = diagnose_observations(bicycle, noise_free(inertia, synthetic_observations(inertia, 0, SPEEDS)), causes)
    assert twin.verdict == "ambiguous" and {twin.cause, *twin.rivals} == {"steer_inertia", "parameter:IFxx"}
    damping = bicycle.with_extensions(steer_damping=0.6)
    twin = diagnose_observations(bicycle, noise_free(damping, synthetic_observations(damping, 0, SPEEDS)), causes)
    assert twin.verdict == "named" and twin.cause == "steer_damping"
