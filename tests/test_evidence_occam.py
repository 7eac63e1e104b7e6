"""The evidence's Occam factor against the Bayes factor integrated numerically.

For residuals linear in the values, r(x) = r0 + J (x - x0), and a uniform prior over a box
wide enough to hold the likelihood, the Laplace approximation is exact: the log Bayes factor
against the base model (residuals r_base) is (chi2_base - chi2_min) / 2 + occam. A grid
integral of the likelihood over the box checks :func:`~whipple.diagnosis.evidence.occam_factor`,
with values that trade off against each other and without. Where the data barely set a value
the approximation fails, and each direction is charged at least the BIC's ln(n) / 2. The
Laplace form is an experiment (``DiagnosisOptions(occam="laplace")``); the default charges ln(n) / 2
per value.
"""

from __future__ import annotations

import numpy as np
import pytest

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.evidence import occam_factor
from whipple.diagnosis.fitting import CauseFit


def _cause(bounds):
    return Cause("test", tuple(f"x{k}" for k in range(len(bounds))), ("",) * len(bounds),
                 tuple(low for low, _ in bounds), tuple(bounds), lambda bicycle, values: bicycle)


def _fit(jacobian):
    k = jacobian.shape[1]
    return CauseFit("test", tuple(f"x{i}" for i in range(k)), ("",) * k, (0.0,) * k, (0.0,) * k, 0.0,
                    jacobian=jacobian)


def _log_integral(jacobian, bounds, n=801):
    """ln of the prior-averaged likelihood exp(-|J (x - centre)|^2 / 2) over the box (a grid)."""
    axes = [np.linspace(low, high, n) for low, high in bounds]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    centre = np.array([0.5 * (low + high) for low, high in bounds])
    chi2 = np.sum(((grid - centre) @ jacobian.T) ** 2, axis=-1)
    return float(np.log(np.mean(np.exp(-0.5 * chi2))))


@pytest.mark.parametrize("jacobian", [
    np.array([[30.0], [10.0], [-5.0]]),                      # one value, well set
    np.array([[20.0, 0.0], [0.0, 8.0], [3.0, 1.0]]),       # two nearly independent values
    np.array([[20.0, 17.0], [10.0, 12.0], [5.0, 4.0]]),    # two values that trade off (std 0.43 along)
])
def test_occam_factor_is_the_integrated_likelihood(jacobian):
    bounds = [(-2.0, 3.0)] * jacobian.shape[1]
    expected = _log_integral(jacobian, bounds, n=801 if jacobian.shape[1] == 1 else 401)
    assert occam_factor(_cause(bounds), _fit(jacobian), n=1, occam="laplace") == pytest.approx(expected, abs=0.02)


def test_a_value_set_twice_as_finely_costs_ln_2_more():
    bounds = [(-2.0, 3.0)] * 2
    jacobian = np.array([[20.0, 17.0], [10.0, 12.0], [5.0, 4.0]])
    once, twice = (occam_factor(_cause(bounds), _fit(scale * jacobian), n=1, occam="laplace") for scale in (1.0, 2.0))
    assert twice == pytest.approx(once - 2 * np.log(2.0))  # two values, each set twice as finely
    assert once < 0.0


def test_a_barely_informed_value_costs_the_bic_charge():
    bounds = [(0.0, 1.0), (0.0, 1.0)]
    held_at_bound = np.array([[40.0, 0.0], [10.0, 0.0]])  # the second value moves no residual
    n = 30
    one = occam_factor(_cause(bounds[:1]), _fit(held_at_bound[:, :1]), n, occam="laplace")
    assert one == pytest.approx(0.5 * np.log(2 * np.pi / (40.0**2 + 10.0**2)))  # finely set: Laplace
    assert occam_factor(_cause(bounds), _fit(held_at_bound), n, occam="laplace") == pytest.approx(one - 0.5 * np.log(n))
    barely = _fit(np.array([[1e-3, 0.0], [0.0, 1e-3]]))
    assert occam_factor(_cause(bounds), barely, n, occam="laplace") == pytest.approx(-np.log(n))
    assert occam_factor(_cause([]), _fit(np.zeros((3, 0))), n, occam="laplace") == 0.0


def test_the_default_charges_ln_n_over_2_per_value():
    jacobian = np.array([[20.0, 17.0], [10.0, 12.0], [5.0, 4.0]])
    assert occam_factor(_cause([(-2.0, 3.0)] * 2), _fit(jacobian), 40) == pytest.approx(-np.log(40))
