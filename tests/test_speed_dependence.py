"""The speed-dependence check: a cause whose best values drift with speed is not named.

Synthetic weave eigenvalues of the benchmark bicycle with a steer damping that is the same at
every speed (the cause's own form) or that jumps between the low and the high speeds (a form no
candidate has): only the second must show values that depend on speed.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from whipple.diagnosis.consistency import jackknife_std, speed_dependence, speed_group_sums
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.fitting import fit_cause, window_whitening
from whipple.diagnosis.observations import Observation, predicted_weave
from whipple.diagnosis.options import VerdictRules
from whipple.diagnosis.registry import cause_by_name
from whipple.model.parameters import load_bicycle

SPEEDS = np.repeat([3.0, 4.0, 5.0, 6.0, 7.0, 8.0], 3)  # m/s
STD = 0.05  # 1/s, of both parts of each eigenvalue


def _observations(damping_at_speed, seed=5, shared=0.0, std=STD, true_speed=lambda v: v):
    """Windows whose true steer damping [N m s/rad] at speed v is ``damping_at_speed(v)``.

    ``shared``: std [1/s] of an error common to all windows of one speed (a fitting bias);
    ``std``: of both parts of each eigenvalue [1/s]; ``true_speed(v)``: the speed [m/s] at which
    the windows measured at v ran (a speed error).
    """
    bicycle = load_bicycle("benchmark")
    rng = np.random.default_rng(seed)
    covariance = np.eye(2) * std**2
    observations = []
    bias = {v: complex(*rng.normal(0.0, shared, 2)) for v in np.unique(SPEEDS)}
    for v in SPEEDS:
        ran = true_speed(v)
        guess = Observation("r", 0.0, 1.0, ran, (ran, ran), complex(-1.0, 5.0), covariance)
        truth = bicycle.with_extensions(steer_damping=damping_at_speed(v))
        eigenvalue = predicted_weave(truth, [guess])[0] + complex(*rng.normal(0.0, std, 2)) + bias[v]
        observations.append(Observation("r", 0.0, 1.0, v, (v, v), eigenvalue, covariance))
    return bicycle, observations


def _dependence(damping_at_speed, **noise):
    bicycle, observations = _observations(damping_at_speed, **noise)
    cause = cause_by_name(bicycle, "steer_damping")
    fit = fit_cause(bicycle, cause, observations)
    return speed_dependence(bicycle, cause, observations, fit.values, (1.0, 1.0))


def test_a_cause_of_its_own_form_has_the_same_values_at_low_and_high_speeds():
    dependence = _dependence(lambda v: 0.8)
    assert dependence is not None
    assert dependence.evidence < VerdictRules().speed_dependence
    assert abs(dependence.low[0] - 0.8) < 0.1 and abs(dependence.high[0] - 0.8) < 0.1
    assert 5.0 < dependence.split < 6.0  # between the third and the fourth speed


def test_values_that_drift_with_speed_are_found():
    dependence = _dependence(lambda v: 0.3 if v < 5.5 else 1.3)
    assert dependence is not None
    assert dependence.evidence > VerdictRules().speed_dependence
    assert abs(dependence.low[0] - 0.3) < 0.15 and abs(dependence.high[0] - 1.3) < 0.15


# Slow (a diagnosis refitted per speed range): run with `pytest -m slow`.
@pytest.mark.slow
def test_a_drifting_cause_is_not_named():
    bicycle, observations = _observations(lambda v: 0.3 if v < 5.5 else 1.3)
    diagnosis = diagnose_observations(bicycle, observations)
    assert not (diagnosis.verdict == "named" and diagnosis.cause == "steer_damping")
    if diagnosis.cause == "steer_damping":
        assert any("change with speed" in reason for reason in diagnosis.reasons)


def test_a_constant_cause_is_still_named():
    bicycle, observations = _observations(lambda v: 0.8)
    diagnosis = diagnose_observations(bicycle, observations)
    assert (diagnosis.verdict, diagnosis.cause) == ("named", "steer_damping")
    assert diagnosis.speed_dependence is not None
    assert diagnosis.speed_dependence.evidence < VerdictRules().speed_dependence


def test_too_few_windows_for_a_half_give_no_check():
    bicycle, observations = _observations(lambda v: 0.8)
    cause = cause_by_name(bicycle, "payload")  # three values: a half of two windows cannot hold them
    few = [observations[0], observations[-1], observations[-2]]
    assert speed_dependence(bicycle, cause, few, (1.0, 0.3, -0.9), (1.0, 1.0)) is None


def test_errors_shared_by_a_speed_make_the_design_effect_large():
    bicycle, observations = _observations(lambda v: 0.8)
    whitening = window_whitening(observations, bicycle)
    one_per_speed = np.repeat([[2.0, -1.0]], len(observations), axis=0).ravel()
    squares, count = speed_group_sums(one_per_speed, observations, whitening)
    # Three windows per speed that move together: each group's sum is 3x a window's residual.
    assert np.isclose(squares / count, 3.0 * (4.0 + 1.0) / 2.0)
    alternating = one_per_speed * np.repeat(np.tile([1.0, -1.0, 0.0], len(SPEEDS) // 3), 2)
    assert speed_group_sums(alternating, observations, whitening)[0] == 0.0


def test_a_bias_shared_by_each_speed_is_not_taken_for_a_drift():
    independent = [_dependence(lambda v: 0.8, seed=seed) for seed in range(6)]
    shared = [_dependence(lambda v: 0.8, seed=seed, shared=4 * STD) for seed in range(6)]
    assert all(d is not None and d.design_effect < 2.0 for d in independent)
    assert all(d is not None and d.design_effect > 2.0 for d in shared)
    assert all(d.evidence < VerdictRules().speed_dependence for d in shared)
    # Without the discount, the same chi-square differences would read as a drift.
    penalty = 0.5 * np.log(2 * len(SPEEDS))
    assert any((d.evidence + penalty) * d.design_effect - penalty > VerdictRules().speed_dependence for d in shared)


def _jackknife_and_fit_std(**noise):
    bicycle, observations = _observations(lambda v: 0.8, **noise)
    cause = cause_by_name(bicycle, "steer_damping")
    fit = fit_cause(bicycle, cause, observations)
    return jackknife_std(bicycle, cause, observations, fit.values)[0], fit.std[0], fit.values[0]


def test_the_jackknife_sees_errors_shared_by_a_speeds_windows():
    # Independent window noise only: the jackknife spread and the fit's own std agree roughly.
    alone, fit_std, value = _jackknife_and_fit_std()
    assert abs(value - 0.8) < 0.1
    assert 0.3 * fit_std < alone < 3.0 * fit_std
    # An error common to the windows of each speed (10x the window noise): the fit's std, which
    # counts every window as independent, misses it; the spread over left-out speeds does not.
    shared, fit_std, _ = _jackknife_and_fit_std(shared=0.5)
    assert shared > 3.0 * fit_std


def test_the_jackknife_of_exact_data_is_zero():
    bicycle, observations = _observations(lambda v: 0.8)
    exact = [dataclasses.replace(o, eigenvalue=predicted_weave(bicycle.with_extensions(steer_damping=0.8), [o])[0])
             for o in observations]
    cause = cause_by_name(bicycle, "steer_damping")
    fit = fit_cause(bicycle, cause, exact)
    assert abs(fit.values[0] - 0.8) < 1e-6
    assert jackknife_std(bicycle, cause, exact, fit.values)[0] < 1e-6


def test_evidence_that_one_speed_s_error_gives_names_nothing():
    """The windows of one speed measured at a speed 8 % off: no cause, though the speed scale gains evidence.

    Fitted to every window as if independent, a speed scale of about 0.985 leads with evidence
    above the threshold; refitted with each speed's windows left out, its values spread over
    more than twice its distance from 1 (no effect).
    """
    bicycle, observations = _observations(lambda v: 0.0, std=0.01, true_speed=lambda v: v * 1.08 if v == 4.0 else v)
    diagnosis = diagnose_observations(bicycle, observations)
    leader = max(diagnosis.fits, key=lambda fit: fit.evidence)
    assert leader.cause == "speed_scale" and leader.evidence > VerdictRules().named_threshold
    assert diagnosis.verdict == "none"
    assert any("value lies within 2 standard deviations of no effect" in reason for reason in diagnosis.reasons)
    assert abs(leader.values[0] - 1.0) < VerdictRules().null_distance * leader.std[0]
