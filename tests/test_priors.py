"""Priors of the causes' values and the evidence with them, checked against integrals and closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.priors import (
    Prior,
    default_uncertainty,
    gross_error_prior,
    laplace_evidence,
    parameter_prior,
    prior_shifts,
    robust_prior_residuals,
)
from whipple.diagnosis.registry import CALIBRATION
from whipple.model.parameters import load_bicycle


@pytest.mark.parametrize("prior", [Prior("normal", 2.0, 0.5), Prior("lognormal", 0.1, math.log(2.5)),
                                   Prior("halfnormal", 0.0, 3.0)])
def test_each_prior_is_a_density_and_its_residual_slope_is_its_derivative(prior):
    low = 0.0 if prior.kind != "normal" else -20.0
    total, _ = quad(lambda x: math.exp(prior.log_density(x)), low, 60.0, limit=200, points=[prior.centre])
    assert total == pytest.approx(1.0, abs=1e-6)
    for value in (0.3, 1.7, 4.0):
        step = 1e-6 * value
        slope = (prior.residual(value + step) - prior.residual(value - step)) / (2 * step)
        assert prior.slope(value) == pytest.approx(slope, rel=1e-6)


def test_a_prior_residual_costs_its_square_over_two_under_the_robust_loss():
    priors = [Prior("normal", 0.0, 1.0)] * 5
    values = [0.1, -1.0, 3.0, 7.5, -20.0]
    transformed = robust_prior_residuals(priors, values, f_scale=3.0)
    soft_l1 = 0.5 * 9.0 * 2.0 * (np.sqrt(1.0 + (transformed / 3.0) ** 2) - 1.0)
    np.testing.assert_allclose(soft_l1, 0.5 * np.square(values), rtol=1e-12)


def test_laplace_evidence_is_the_marginal_likelihood_of_a_linear_gaussian_model():
    # Residuals r(x) = J x - y with normal priors: log of the integral of exp(-|r|^2/2) p(x) dx
    # equals -chi2(map)/2 + the Laplace evidence at the maximum a posteriori, exactly.
    rng = np.random.default_rng(3)
    jacobian, target = rng.normal(size=(30, 2)), rng.normal(size=30)
    priors = [Prior("normal", 0.5, 0.8), Prior("normal", -1.0, 1.5)]
    centre, width = np.array([0.5, -1.0]), np.array([0.8, 1.5])
    posterior = jacobian.T @ jacobian + np.diag(1 / width**2)
    mode = np.linalg.solve(posterior, jacobian.T @ target + centre / width**2)
    chi2 = float(np.sum((jacobian @ mode - target) ** 2))
    grid = [np.linspace(m - 8 / math.sqrt(posterior[k, k]), m + 8 / math.sqrt(posterior[k, k]), 801)
            for k, m in enumerate(mode)]
    x, y = np.meshgrid(*grid, indexing="ij")
    points = np.stack([x.ravel(), y.ravel()], axis=1)
    misfit = np.sum((points @ jacobian.T - target) ** 2, axis=1)
    log_prior = sum(-0.5 * ((points[:, k] - centre[k]) / width[k]) ** 2 - math.log(width[k] * math.sqrt(2 * math.pi))
                    for k in range(2))
    integrand = np.exp(-0.5 * misfit + log_prior + 0.5 * chi2).reshape(x.shape)
    integral = np.trapezoid(np.trapezoid(integrand, grid[1], axis=1), grid[0])
    assert laplace_evidence(priors, mode, jacobian) == pytest.approx(math.log(integral), abs=1e-6)


def test_parameter_priors_take_the_stated_uncertainty_else_a_typical_one():
    browser = load_bicycle("tests/data/bicycleparameters/bicycles/BrowserBenchmark.txt")
    stated = next(iter(browser.uncertainty))
    assert parameter_prior(stated, browser.parameters, browser.uncertainty).scale == browser.uncertainty[stated]
    benchmark = load_bicycle("benchmark")
    assert parameter_prior("mB", benchmark.parameters, {}).scale == pytest.approx(0.02 * 85.0)
    assert default_uncertainty("IBxz", benchmark.parameters) == pytest.approx(0.1 * math.sqrt(9.2 * 2.8))
    gross = gross_error_prior("c", benchmark.parameters, {})
    assert gross.scale == pytest.approx(0.3 * 0.08) and gross.scale > 3 * parameter_prior("c", {"c": 0.08}, {}).scale


def test_the_calibration_is_a_candidate_only_with_priors_and_reports_what_moved():
    bicycle = load_bicycle("benchmark")
    assert CALIBRATION not in {c.name for c in DiagnosisOptions().candidates(bicycle)}
    calibration = next(c for c in DiagnosisOptions(occam="prior").candidates(bicycle) if c.name == CALIBRATION)
    assert len(calibration.parameters) == 23 and calibration.value_priors is not None
    values = list(calibration.start)
    values[calibration.parameters.index("IBxx")] += 2.5 * 0.92
    moved = prior_shifts(calibration.parameters, calibration.value_priors, values, calibration.units)
    assert [(m["name"], round(float(m["sigmas"]), 6)) for m in moved] == [("IBxx", 2.5)]
