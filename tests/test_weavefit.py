"""Weave eigenvalue fits: exactness, calibration of the uncertainty, errors."""

from __future__ import annotations

import numpy as np
import pytest

from whipple.errors import AnalysisError, InputError
from whipple.measurement.weavefit import NoOscillationError, WeaveFit, fit_weave

# A window like the seed paper's run 1202: lambda = -1.32 +- 5.96i over 1.6 s at 100 Hz.
D, W = -1.32, 5.96
C = (0.05, 0.5, -0.2)


def damped(t, d=D, w=W, c=C, t0=None):
    tau = t - (t[0] if t0 is None else t0)
    return c[0] + np.exp(d * tau) * (c[1] * np.cos(w * tau) + c[2] * np.sin(w * tau))


def model_jacobian(tau, d, w, c):
    """Derivatives of the 5-parameter model with respect to (c1, c2, c3, d, w)."""
    e = np.exp(d * tau)
    cos, sin = e * np.cos(w * tau), e * np.sin(w * tau)
    return np.column_stack([
        np.ones_like(tau), cos, sin,
        tau * (c[1] * cos + c[2] * sin),
        tau * (c[2] * cos - c[1] * sin),
    ])


def test_noise_free_window_is_fitted_exactly():
    t = 9.4 + np.arange(161) / 100
    fit = fit_weave(t, damped(t))
    assert isinstance(fit, WeaveFit)
    assert fit.eigenvalue == pytest.approx(complex(D, W), abs=1e-7)
    np.testing.assert_allclose(fit.coefficients[0], C, atol=1e-7)
    assert fit.start == pytest.approx(9.4) and fit.n_samples == 161
    assert fit.r_squared == pytest.approx(1.0, abs=1e-10)
    # The curve is referred to the window start, at any times.
    later = np.linspace(9.4, 12.0, 7)
    np.testing.assert_allclose(fit.curve(later)[0], damped(later, t0=9.4), atol=1e-7)


@pytest.mark.parametrize(
    ("d", "w", "fs", "duration"),
    [(-1.32, 5.96, 100, 1.6), (1.4, 2.2, 500, 2.0), (-0.3, 12.0, 500, 4.0), (-4.0, 8.0, 100, 0.9)],
)
def test_stable_unstable_short_and_long_windows(d, w, fs, duration):
    rng = np.random.default_rng(1)
    t = np.arange(0, duration, 1 / fs)
    y = damped(t, d, w) + 0.002 * rng.standard_normal(t.size)
    fit = fit_weave(t, y)
    assert abs(fit.damping - d) < 5 * fit.eigenvalue_std[0]
    assert abs(fit.frequency - w) < 5 * fit.eigenvalue_std[1]
    assert fit.eigenvalue_std[0] < 0.05 and fit.eigenvalue_std[1] < 0.05


def calibration_runs(n_runs, sigma=0.02, seed=7):
    rng = np.random.default_rng(seed)
    t = np.arange(0, 1.6, 0.01)
    clean = damped(t)
    estimates, stds = [], []
    for _ in range(n_runs):
        fit = fit_weave(t, clean + sigma * rng.standard_normal(t.size))
        estimates.append((fit.damping, fit.frequency))
        stds.append(fit.eigenvalue_std)
    jac = model_jacobian(t, D, W, C)
    crb = np.sqrt(np.diag(np.linalg.inv(jac.T @ jac)))[3:] * sigma
    return np.array(estimates), np.array(stds), crb


def test_uncertainty_is_calibrated_and_spread_near_cramer_rao():
    estimates, stds, crb = calibration_runs(200)
    inside = np.abs(estimates - (D, W)) < 2 * stds
    coverage = inside.mean(axis=0)
    assert ((coverage >= 0.90) & (coverage <= 0.99)).all(), coverage
    ratio = estimates.std(axis=0) / crb
    assert (ratio < 1.5).all(), ratio
    # The reported std itself estimates the CRB.
    np.testing.assert_allclose(stds.mean(axis=0) / crb, 1.0, atol=0.15)


@pytest.mark.slow
def test_calibration_with_many_windows():
    estimates, stds, crb = calibration_runs(2000, seed=11)
    coverage = (np.abs(estimates - (D, W)) < 2 * stds).mean(axis=0)
    np.testing.assert_allclose(coverage, 0.954, atol=0.02)
    assert (estimates.std(axis=0) / crb < 1.15).all()


def ar1(rng, n, rho, sigma):
    noise = np.empty(n)
    noise[0] = sigma * rng.standard_normal()
    shocks = sigma * np.sqrt(1 - rho**2) * rng.standard_normal(n)
    for k in range(1, n):
        noise[k] = rho * noise[k - 1] + shocks[k]
    return noise


def test_autocorrelated_residuals_widen_the_uncertainty():
    rng = np.random.default_rng(3)
    t = np.arange(0, 2.5, 0.01)
    errors, white, reported = [], [], []
    for _ in range(60):
        fit = fit_weave(t, damped(t) + ar1(rng, t.size, 0.8, 0.02))
        assert fit.noise_model.startswith("newey-west")
        assert fit.residual_correlation > 0.5
        errors.append((fit.damping - D, fit.frequency - W))
        white.append(np.sqrt(np.diag(fit.covariance_white)))
        reported.append(fit.eigenvalue_std)
    errors, white, reported = map(np.array, (errors, white, reported))
    # The white-noise formula is far too optimistic; the corrected one is not.
    assert (np.abs(errors) < 2 * white).mean() < 0.7
    assert (np.abs(errors) < 2 * reported).mean() > 0.85
    fit = fit_weave(t, damped(t) + ar1(rng, t.size, 0.8, 0.02), noise="white")
    assert fit.noise_model == "white"


def test_joint_fit_shares_the_eigenvalue():
    rng = np.random.default_rng(5)
    t = np.arange(0, 2.0, 0.01)
    roll = damped(t) + 0.02 * rng.standard_normal(t.size)
    yaw = damped(t, c=(0.0, -0.3, 0.4)) + 0.01 * rng.standard_normal(t.size)
    joint = fit_weave(t, [roll, yaw], names=("roll_rate", "yaw_rate"))
    alone = fit_weave(t, roll)
    assert joint.signal_names == ("roll_rate", "yaw_rate")
    assert joint.coefficients.shape == (2, 3)
    np.testing.assert_allclose(joint.coefficients[1], (0.0, -0.3, 0.4), atol=0.02)
    assert abs(joint.damping - D) < 4 * joint.eigenvalue_std[0]
    assert joint.eigenvalue_std[0] < alone.eigenvalue_std[0]
    assert joint.eigenvalue_std[1] < alone.eigenvalue_std[1]


def test_less_than_half_a_period_is_no_oscillation():
    t = np.arange(0, 0.3, 0.01)  # a fifth of a period
    with pytest.raises(NoOscillationError, match="half a period") as caught:
        fit_weave(t, damped(t, d=0.0, w=4.0))
    assert isinstance(caught.value, InputError) and isinstance(caught.value, AnalysisError)


@pytest.mark.parametrize(
    ("values", "message"),
    [(np.full(100, 0.3), "constant"), (np.zeros(5), "too short")],
)
def test_degenerate_windows(values, message):
    with pytest.raises(NoOscillationError, match=message):
        fit_weave(np.arange(values.size) / 100, values)


def test_bad_input():
    t = np.arange(150) / 100
    y = damped(t)
    y[7] = np.nan
    with pytest.raises(InputError, match="non-finite"):
        fit_weave(t, y)
    with pytest.raises(InputError, match="do not match"):
        fit_weave(t, damped(t)[:-1])
    with pytest.raises(InputError, match="noise model"):
        fit_weave(t, damped(t), noise="pink")


def test_cycles_above_noise_stop_where_the_envelope_meets_the_noise():
    """A strongly damped oscillation in noise counts its periods until its envelope falls to the
    noise's RMS (ln(A / sigma) / |d|), not over the whole window; a growing one over all of it."""
    rng = np.random.default_rng(4)
    time = np.arange(0.0, 3.0, 0.01)
    amplitude, sigma, d, w = 1.0, 0.01, -3.0, 6.0
    values = amplitude * np.exp(d * time) * np.cos(w * time) + rng.normal(0.0, sigma, time.size)
    fit = fit_weave(time, values)
    expected = w * np.log(amplitude / sigma) / -d / (2 * np.pi)
    assert fit.cycles_above_noise == pytest.approx(expected, rel=0.05)
    assert fit.cycles_above_noise < 0.6 * fit.cycles
    growing = fit_weave(time, 0.01 * np.exp(0.5 * time) * np.cos(w * time) + rng.normal(0.0, 1e-4, time.size))
    assert growing.cycles_above_noise == pytest.approx(growing.cycles)


def test_the_window_check_leaves_out_a_window_mostly_noise():
    """By default it turns down a window whose oscillation sinks into the noise within half a
    period, though the window itself spans almost three; 0 turns the check off."""
    from whipple.measurement import experiment

    rng = np.random.default_rng(5)
    time = np.arange(0.0, 3.0, 0.01)
    fit = fit_weave(time, np.exp(-8.0 * time) * np.cos(6.0 * time) + rng.normal(0.0, 0.01, time.size))
    assert fit.cycles > 2.5 and fit.cycles_above_noise < 0.75
    assert "above the noise" in experiment._quality(fit, experiment.FitOptions().min_cycles_above_noise)
    assert experiment._quality(fit, 0.0) is None


@pytest.mark.parametrize("cycles", [-0.5, float("nan"), 1e3])
def test_a_check_of_cycles_above_the_noise_out_of_range_is_refused(cycles):
    from whipple.measurement import experiment

    with pytest.raises(InputError, match="cycles above the noise"):
        experiment.FitOptions(min_cycles_above_noise=cycles)
