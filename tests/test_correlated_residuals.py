"""Residuals correlated in time: the evidence read from the samples shrinks by their correlation.

Runs of the benchmark simulated with and without random road torques
(:mod:`whipple.simulation.disturbance`); the true model's residual on their windows is white
noise without them and the response to the torques with them.
"""

from __future__ import annotations

import numpy as np
import pytest

from whipple.diagnosis.correlated_residuals import correlation_factor, model_change_columns
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.observations import observations
from whipple.diagnosis.samples import SampleComparison
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import run_from_simulation
from whipple.model.parameters import load_bicycle
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

BIKE = load_bicycle("benchmark")


def _windows(disturbance, seed, speeds=(4.5, 5.5, 6.5)):
    found = []
    for k, speed in enumerate(speeds):
        scenario = RunScenario(speed=speed, seed=seed + k, disturbance=disturbance)
        found += observations(measure_run(run_from_simulation(simulate_run(BIKE, scenario))).windows)
    return found


def _true_factor(windows):
    samples = SampleComparison.of(windows, bicycle=BIKE)
    return correlation_factor(samples, samples.residuals([BIKE])[0], windows)


def test_the_columns_are_a_shifted_eigenvalue_s_change():
    # d/d(lambda) of e^{lambda t} is t e^{lambda t}: a small change of the eigenvalue moves a
    # window within the columns' span.
    tau = np.linspace(0.0, 3.0, 76)
    columns = model_change_columns(tau, -0.8 + 4.5j)
    changed = np.real(np.exp((-0.8 + 4.502j) * tau)) - np.real(np.exp((-0.8 + 4.5j) * tau))
    fitted = columns @ np.linalg.lstsq(columns, changed, rcond=None)[0]
    assert np.max(np.abs(fitted - changed)) < 1e-2 * np.max(np.abs(changed))


def test_white_noise_leaves_the_evidence_as_it_is():
    # Without torques the true model leaves the noise: the factor is 1 (it exceeds 1 by chance
    # in at most 1 of 20 data sets, by little).
    factors = [_true_factor(_windows((0.0, 0.0), seed)) for seed in (0, 10, 20, 30)]
    assert max(factors) < 1.2 and sum(f > 1.0 for f in factors) <= 1


def test_random_torques_shrink_the_evidence():
    # With random torques of 3 N m (roll) and 0.15 N m (steer), the true model's residual in
    # the directions of a changed eigenvalue is several times the noise's.
    factors = [_true_factor(_windows((3.0, 0.15), seed)) for seed in (0, 10)]
    assert min(factors) > 2.0


@pytest.mark.slow
def test_a_disturbed_bicycle_without_effect_is_diagnosed_none():
    # Before the factor, such runs gave leads of 30-130 in evidence to model terms and loads.
    windows = _windows((3.0, 0.15), 40, speeds=(3.5, 4.5, 5.5, 6.5, 7.5))
    assert diagnose_observations(BIKE, windows).verdict == "none"
