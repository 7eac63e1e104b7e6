"""Windows whose speed changes: the model follows the window's speed profile (issue 51, item 1).

The honest reference for a window of a coasting bicycle is the linear time-varying model's free
response along v(t), with the term ``v' Ka q``, fitted with the same weave fit as measured
windows. The window's model eigenvalue (:mod:`whipple.diagnosis.window_speed`, through
:func:`~whipple.diagnosis.observations.predicted_weave`) must match that fit; treadmill windows
(constant speed) must stay exactly as they were.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from whipple.diagnosis.observations import Observation, WindowSignals, mode_targets, observations, predicted_weave
from whipple.diagnosis.samples import SampleComparison
from whipple.diagnosis.window_speed import fit_weighted_offset, window_speeds
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import read_run
from whipple.measurement.weavefit import fit_weave
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.model.speed_change import acceleration_stiffness
from whipple.stability.nearest_modes import nearest_modes

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hidden_effects import run_trial, trial_runs  # noqa: E402

#: Largest distance [1/s] between the window model's eigenvalue and the weave fit of the time-varying
#: free response where the weave decays or barely grows (measured: 0.016 at most over the cases below;
#: the mean speed's frozen eigenvalue leaves up to 0.166).
TOLERANCE = 0.02
#: The same where the weave grows fast (real part near +1 1/s, 3.5 m/s): the eigenvector's drift
#: along v(t), which the frozen model leaves out, matters there (measured 0.057 and 0.077).
GROWING_TOLERANCE = 0.08


def _ltv_window(bicycle, mean_speed, acceleration, duration, rate=100.0):
    """Free response of ``x' = (A(v(t)) - v' B Ka) x`` along ``v = mean + v' (t - T/2)``, from the weave."""
    model, stiffness = linear_model(bicycle), acceleration_stiffness(bicycle)
    time = np.arange(0.0, duration + 1e-9, 1.0 / rate)
    middle = time[:-1] + 0.5 / rate
    speeds = mean_speed + acceleration * (middle - 0.5 * duration)
    A = model.state_matrix(speeds).copy()
    A[:, :, 0:2] -= acceleration * (model.input_matrix(speeds) @ stiffness)
    values, vectors = np.linalg.eig(A[0])
    weave = np.argmax(np.where(values.imag > 0, -np.abs(values.imag - 4.0), -np.inf))
    states = np.zeros((time.size, A.shape[-1]))
    states[0] = 0.2 * np.real(vectors[:, weave] / vectors[2, weave])
    for k in range(time.size - 1):
        # The exponential midpoint rule: at 100 Hz within 1e-6 of the amplitude (test_field_conditions).
        states[k + 1] = expm(A[k] / rate) @ states[k]
    return time, states


def _frozen_weave(bicycle, speed, near):
    values = np.linalg.eigvals(linear_model(bicycle).state_matrix(np.array([speed]))[0])
    values = values[values.imag > 0]
    return values[np.argmin(np.abs(values - near))]


@pytest.mark.parametrize("name", ["benchmark", "kooijman2008"])
def test_window_model_matches_the_fitted_time_varying_free_response(name):
    bicycle = load_bicycle(name)
    worst, worst_mean = 0.0, 0.0
    for speed, acceleration, duration in [(4.5, -0.05, 3.0), (5.5, -0.08, 4.0), (6.5, -0.03, 3.0),
                                          (7.0, -0.08, 2.5)]:
        time, states = _ltv_window(bicycle, speed, acceleration, duration)
        fit = fit_weave(time, np.array([states[:, 2], states[:, 1]]), ("roll_rate", "steer_angle"))
        window = Observation("run", 0.0, float(time[-1]), speed,
                             (speed - 0.5 * acceleration * duration, speed + 0.5 * acceleration * duration),
                             complex(fit.eigenvalue), np.eye(2) * 1e-4, acceleration=acceleration)
        predicted = predicted_weave(bicycle, [window])[0]
        worst = max(worst, abs(predicted - fit.eigenvalue))
        worst_mean = max(worst_mean, abs(_frozen_weave(bicycle, speed, fit.eigenvalue) - fit.eigenvalue))
    assert worst < TOLERANCE
    # The speed profile is what closes the gap: the mean speed alone leaves it at least twice as wide.
    assert worst_mean > 2 * worst
    time, states = _ltv_window(bicycle, 3.5, -0.08, 2.0)
    fit = fit_weave(time, np.array([states[:, 2], states[:, 1]]), ("roll_rate", "steer_angle"))
    window = Observation("run", 0.0, float(time[-1]), 3.5, (3.58, 3.42), complex(fit.eigenvalue), np.eye(2) * 1e-4,
                         acceleration=-0.08)
    assert fit.eigenvalue.real > 0.5
    assert abs(predicted_weave(bicycle, [window])[0] - fit.eigenvalue) < GROWING_TOLERANCE


def test_fit_weighted_offset_limits():
    # No damping: the window's centre; a decaying weave is read early, a growing one late.
    assert fit_weighted_offset(0.0, 3.0)[0] == pytest.approx(0.0, abs=1e-12)
    assert fit_weighted_offset(-1.0, 3.0)[0] < -0.5
    assert fit_weighted_offset(1.0, 3.0)[0] == pytest.approx(-fit_weighted_offset(-1.0, 3.0)[0])
    # Strong decay: the regression reads the first 1/(2|d|) or so of the window.
    assert fit_weighted_offset(-20.0, 3.0)[0] == pytest.approx(-1.5 + 0.05, abs=0.01)


def test_constant_speed_windows_are_unchanged():
    window = Observation("run", 1.0, 4.0, 5.0, (5.0, 5.0), complex(-0.8, 4.5), np.eye(2) * 1e-4)
    speeds, accelerations = window_speeds([window, replace(window, speed=4.0)])
    assert accelerations is None and speeds.tolist() == [5.0, 4.0]
    assert mode_targets([window])[5] is None
    bicycle = load_bicycle("benchmark")
    # The same solve as before windows carried a speed profile: the mean speed, nothing added.
    plain = nearest_modes(bicycle, np.array([5.0]), np.array([window.eigenvalue]), [None])[0]
    assert predicted_weave(bicycle, [window])[0] == plain[0]


def test_bundled_treadmill_windows_keep_a_constant_speed():
    # The bundled logs' speed column is an encoder's moving average whose slope is not zero: the
    # layout's `setting = treadmill` keeps their windows at constant speed, to the last bit.
    runs = [read_run(path) for path in bundled_runs()[:2]]
    found = [o for run in runs for o in observations(measure_run(run).windows)]
    assert found and all(o.acceleration == 0.0 for o in found)
    comparison = SampleComparison.of(found)
    assert comparison is not None and comparison.accelerations is None
    assert comparison.speeds.tolist() == [o.speed for o in found]


@pytest.mark.parametrize("conditions", ["ground", "downhill"])
def test_ground_windows_carry_their_measured_acceleration(conditions):
    # Slowing on level ground, speeding up down a slope (a negative deceleration).
    _, _, runs = trial_runs("none", 0, "benchmark", speeds=(5.0,), conditions=conditions)
    found = observations(measure_run(runs[0]).windows)
    assert found
    metadata = runs[0].metadata
    acceleration = -(float(metadata["deceleration"]) + float(metadata["drag"]) * 5.0**2)
    assert (acceleration > 0) == (conditions == "downhill")
    for o in found:
        assert 0.3 * abs(acceleration) < o.acceleration * np.sign(acceleration) < 2.5 * abs(acceleration)


def _sampled_window(bicycle, speed, acceleration, duration, noise, seed=0):
    """A window of the time-varying free response (roll rate, steer angle) with white noise of stated size."""
    time, states = _ltv_window(bicycle, speed, acceleration, duration)
    clean = np.array([states[:, 2], states[:, 1]])
    values = clean + np.asarray(noise)[:, None] * np.random.default_rng(seed).standard_normal(clean.shape)
    fit = fit_weave(time, values, ("roll_rate", "steer_angle"))
    return Observation("run", 0.0, float(time[-1]), speed,
                       (speed - 0.5 * acceleration * duration, speed + 0.5 * acceleration * duration),
                       complex(fit.eigenvalue), np.eye(2) * 1e-4, acceleration=acceleration,
                       signals=WindowSignals(time, values, ("roll_rate", "steer_angle"), "none",
                                             noise=np.asarray(noise, dtype=float)))


@pytest.mark.parametrize(("name", "acceleration"), [("benchmark", -0.08), ("kooijman2008", -0.08),
                                                   ("benchmark", 0.08)])
def test_sample_comparison_follows_the_speed_profile(name, acceleration):
    # The true model compared with a ground window's samples leaves only the noise when its
    # response follows the window's speed profile; frozen at one speed (the speed the weave fit
    # reads, with v' Ka q) it leaves the drift of the weave along v(t) on top.
    bicycle = load_bicycle(name)
    noise = (0.002, 0.0005)  # rad/s, rad: a 0.2 rad/s weave 100 times its noise
    window = _sampled_window(bicycle, 5.0, acceleration, 4.0, noise)
    comparison = SampleComparison.of([window])
    assert comparison is not None and comparison.profiles is not None
    followed = comparison.chi2_per_sample(bicycle)
    frozen = replace(comparison, profiles=None).chi2_per_sample(bicycle)
    spread = np.sqrt(2.0 / comparison.samples)
    assert abs(followed - 1.0) < 4 * spread
    assert frozen > 2.0  # measured 6.4-6.6 (benchmark), 2.3-2.6 (kooijman2008) over three noise seeds


def test_speed_profile_response_at_a_constant_speed_is_the_modal_one():
    # The initial state in place of the modal amplitudes spans the same responses: a window whose
    # acceleration is negligible gives the frozen model's residuals; a constant-speed window
    # beside changing ones keeps its residuals to the last bit.
    bicycle = load_bicycle("benchmark")
    window = _sampled_window(bicycle, 5.0, -0.08, 3.0, (0.02, 0.005), seed=1)
    still = replace(window, acceleration=1e-12)
    constant = replace(window, acceleration=0.0)
    followed = SampleComparison.of([still]).residuals([bicycle])[0]
    modal = SampleComparison.of([constant]).residuals([bicycle])[0]
    np.testing.assert_allclose(followed, modal, rtol=1e-7, atol=1e-7)
    mixed = SampleComparison.of([constant, window])
    alone = SampleComparison.of([constant])
    owner = mixed.window_of_residuals()
    assert np.array_equal(mixed.residuals([bicycle])[0][owner == 0], alone.residuals([bicycle])[0])


@pytest.mark.slow
def test_a_no_effect_ground_trial_is_diagnosed_none():
    # Ambiguous (reflected_steer_inertia) with windows at one speed, then (tyre_compliance) with
    # the speed the weave fit reads; none since the samples comparison follows the speed profile.
    trial = run_trial("none", 1, "kooijman2008", conditions="ground")
    assert trial.diagnosis.verdict == "none"
