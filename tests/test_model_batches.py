"""Several models evaluated at once: the same residuals, the same fits, as one at a time.

A fit's finite-difference Jacobian evaluates its points together
(:func:`whipple.diagnosis.fitting.models_residuals`); the independent reference is the
evaluation of each model alone, and SciPy's own finite differences for the whole fit.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares as scipy_least_squares
from synthetic_windows import synthetic_observations

from whipple.diagnosis import fitting
from whipple.diagnosis.families import combined_cause
from whipple.diagnosis.fitting import fit_cause, model_residuals, models_residuals, window_whitening
from whipple.diagnosis.registry import candidate_causes
from whipple.model.parameters import Payload, TyreCompliance, load_bicycle

SPEEDS = (3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 7.0)


def _causes(bicycle):
    return {f"{cause.name}/{len(cause.parameters)}": cause for cause in candidate_causes(bicycle)}


@pytest.mark.parametrize("name", ["benchmark", "sbw2024"])
def test_models_together_give_each_models_own_residuals(name):
    base = load_bicycle(name)
    truth = base.with_extensions(payload=Payload(6.0, 0.2, -0.7))
    observations = synthetic_observations(truth, 1, SPEEDS)
    whitening = window_whitening(observations, base)
    models = [base, truth, base.with_extensions(steer_damping=0.4), base.with_parameters(c=0.09)]
    residuals, predicted, chi2 = models_residuals(models, observations, whitening)
    for k, model in enumerate(models):
        alone, alone_predicted, alone_chi2 = model_residuals(model, observations, whitening)
        np.testing.assert_array_equal(residuals[k], alone)
        np.testing.assert_array_equal(predicted[k], alone_predicted)
        assert chi2[k] == alone_chi2
    # A model with more states (tyre lag) among them: solved on its own, the same again.
    tyres = TyreCompliance(cornering_stiffness=20.0, camber_stiffness=1.0, relaxation_length=0.3)
    mixed = [models[1], base.with_extensions(tyre_compliance=tyres)]
    together = models_residuals(mixed, observations, whitening)[0]
    for k, model in enumerate(mixed):
        np.testing.assert_array_equal(together[k], model_residuals(model, observations, whitening)[0])


def test_fits_with_the_jacobian_evaluated_together_equal_scipys_own():
    base = load_bicycle("benchmark")
    truth = base.with_extensions(payload=Payload(8.0, 0.3, -0.8), steer_damping=0.3)
    observations = synthetic_observations(truth, 2, SPEEDS)
    causes = _causes(base)
    pair = combined_cause(causes["payload/3"], causes["steer_damping/1"])
    for cause in (causes["payload/3"], pair):
        batched = fit_cause(base, cause, observations)
        original = fitting.least_squares
        try:
            # SciPy's finite differences, one evaluation at a time.
            fitting.least_squares = lambda *args, workers=None, **kwargs: scipy_least_squares(*args, **kwargs)
            serial = fit_cause(base, cause, observations)
        finally:
            fitting.least_squares = original
        np.testing.assert_allclose(batched.values, serial.values, rtol=1e-12, atol=1e-12)
        assert batched.chi2 == pytest.approx(serial.chi2, rel=1e-12)
        np.testing.assert_allclose(batched.jacobian, serial.jacobian, rtol=1e-9, atol=1e-9)
    # And the fit does at least as well as the hidden pair's own values.
    assert pair.parameters == ("payload_mass", "payload_x", "payload_z", "steer_damping")
    at_truth = model_residuals(pair.apply(base, [8.0, 0.3, -0.8, 0.3]), observations,
                               window_whitening(observations, base))[0]
    assert batched.chi2 <= fitting.robust_chi2(at_truth)
